"""Assets a stage asks for that do not resolve, so that what they hold is silently missing from the check.

USD composes what it can and only warns about the rest: a character whose body file was renamed
composes without a body, and a check of it finds no contact with the body. :func:`unresolved_assets`
lists every such asset of an open stage (docs/contracts.md, "Bad input"):

* references and payloads: the PcpErrors of ``stage.GetCompositionErrors()`` (what OpenUSD's
  ``usdValidation:CompositionErrorTest`` flags) that leave a prim without an arc: an asset that does not
  resolve or does not open, or one without the prim the arc names (``ErrorUnresolvedPrimPath``). The
  asset path as authored comes from the specs of the prim the error is about;
* sublayers, at any depth and in layers brought in by references (``ErrorInvalidSublayerPath``), each
  named with the layer that lists it;
* value clips: pxr reports no composition error for them and only warns once a value is read, so each
  ``clips`` set (``assetPaths`` and ``manifestAssetPath``) is resolved here.

:func:`open_stage_trapping_asset_warnings` opens a stage the way usdksl does, with pxr's own warnings about
exactly those errors kept off the console (the loader reports them in one line). It needs
``Tf.DiagnosticTrap`` (usd-core 26.11 has it): an older pxr offers Python no way to hold a warning back
(``Tf.Error.Mark`` holds errors only, and no diagnostic delegate can be installed from Python), so there the
warnings are printed as before.

Clip sets given by ``templateAssetPath`` are not checked: USD itself keeps only the template's paths that
resolve.

A stage handed over open (:func:`usdksl.pipeline.stage.check_stage`, a DCC's stage) may also have payloads it
has not loaded (``Usd.Stage.Open(..., Usd.Stage.LoadNone)``, or ``stage.Unload``): what they hold is missing
from the composed stage as surely as a file that does not resolve, so :func:`unresolved_assets` names each
too (problem :data:`NOT_LOADED`). A stage usdksl opens itself loads every payload and has none.
:func:`trapping_clip_warnings` holds back pxr's warnings about value clips while such a stage is read.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import Dict, Iterator, List, Optional, Set, Tuple

from pxr import Ar, Pcp, Sdf, Tf, Usd

from .file_formats import missing_format_note

#: What asked for an asset (:attr:`UnresolvedAsset.kind`).
REFERENCE = "reference"
PAYLOAD = "payload"
SUBLAYER = "sublayer"
CLIP = "clip"

#: :attr:`UnresolvedAsset.problem` of an asset path the resolver finds nothing for.
DOES_NOT_RESOLVE = "does not resolve"
#: ... of one it resolves that does not open as a layer (not a USD file, unreadable).
DOES_NOT_OPEN = "resolves but does not open"
#: ... of a payload the open stage has not loaded (its prims compose without what it holds).
NOT_LOADED = "is not loaded on the stage (stage.Load loads it)"

#: Composition errors that leave a prim without (part of) what an asset holds.
_ARC_ERRORS = (Pcp.ErrorType_InvalidAssetPath, Pcp.ErrorType_UnresolvedPrimPath)
_SUBLAYER_ERRORS = (Pcp.ErrorType_InvalidSublayerPath,)

#: The asset paths a PcpError's text names, between @ signs.
_AT_PATH = re.compile(r"@([^@]*)@")
#: The arc a PcpError's text is about.
_ARC_WORD = re.compile(r"\b(reference|payload)\b")


@dataclass(frozen=True)
class UnresolvedAsset:
    """One asset a stage asks for that does not compose.

    ``asset_path`` as authored; ``requester`` the prim that asked for it (a sublayer: the identifier of the
    layer that lists it); ``kind`` one of REFERENCE, PAYLOAD, SUBLAYER, CLIP; ``layer`` the identifier of
    the layer the asset path is authored in; ``problem`` what is wrong with it; ``target`` the prim a
    reference or payload names, when authored; ``manifest`` True for a value clip set's manifest."""

    kind: str
    asset_path: str
    requester: str
    layer: str
    problem: str = DOES_NOT_RESOLVE
    target: str = ""
    manifest: bool = False

    def describe(self) -> str:
        """``reference @./body_v2.usd@ does not resolve``: what, which asset (as USD writes an arc), what is
        wrong."""
        what = "value clip manifest" if self.manifest else "value clip" if self.kind == CLIP else self.kind
        target = f"<{self.target}>" if self.target else ""
        return f"{what} @{self.asset_path}@{target} {self.problem}" + (
            missing_format_note(self.asset_path) if self.problem == DOES_NOT_OPEN else "")


#: The option that checks what composes anyway, named by :func:`refusal`.
ALLOW_OPTION = "--allow-missing-assets"


def refusal(assets: List[UnresolvedAsset]) -> str:
    """The message of the input error for a stage with unresolved ``assets`` (its file and the first
    asset's requester go before it): the first asset, how many more, and the option."""
    more = len(assets) - 1
    others = f", and {more} more unresolved asset{'s' if more > 1 else ''}" if more else ""
    return f"{assets[0].describe()}{others}; nothing checked ({ALLOW_OPTION} checks what composes)"


def not_checked(asset: UnresolvedAsset) -> str:
    """Why what ``asset`` holds is missing from a check of what composes (an unchecked entry's reason)."""
    return f"{asset.describe()}: what it brings in is not checked"


def summary(assets: List[UnresolvedAsset]) -> str:
    """``2 assets do not resolve, the first @./body_v2.usd@ (reference of /World/Body)``."""
    first = assets[0]
    count = f"{len(assets)} assets do not" if len(assets) > 1 else "an asset does not"
    return f"{count} resolve, the first @{first.asset_path}@ ({first.kind} of {first.requester})"


def unresolved_assets(stage: Usd.Stage) -> List[UnresolvedAsset]:
    """Every asset of ``stage`` that does not compose (module docstring): references and payloads by prim
    path, then sublayers, then value clips, then payloads the stage has not loaded. Empty when everything
    resolves and is loaded."""
    with Ar.ResolverContextBinder(stage.GetPathResolverContext()):
        errors = stage.GetCompositionErrors()
        found = _arc_assets(stage, [error for error in errors if error.errorType in _ARC_ERRORS])
        found += _sublayer_assets(stage, [error for error in errors if error.errorType in _SUBLAYER_ERRORS])
        found += _clip_assets(stage)
    found += unloaded_payloads(stage)
    return list(dict.fromkeys(found))


def unloaded_payloads(stage: Usd.Stage) -> List[UnresolvedAsset]:
    """One UnresolvedAsset (problem :data:`NOT_LOADED`) per payload authored on a prim whose payloads
    ``stage`` has not loaded, by prim path; a payload without an asset path (one inside the same layer
    stack) is named by the prim it targets."""
    found = []
    for path in sorted(str(loadable) for loadable in stage.FindLoadable()):
        prim = stage.GetPrimAtPath(path)
        if not prim or prim.IsLoaded():
            continue
        payloads = [(item.assetPath, str(item.primPath) if not item.primPath.isEmpty else "", spec.layer.identifier)
                    for spec in prim.GetPrimStack() for item in spec.payloadList.GetAddedOrExplicitItems()]
        for asset_path, target, layer in dict.fromkeys(payloads) or [("", "", "")]:
            found.append(UnresolvedAsset(kind=PAYLOAD, asset_path=asset_path, requester=path, layer=layer,
                                         problem=NOT_LOADED, target=target))
    return found


def _covered_error_texts(stage: Usd.Stage) -> List[str]:
    """The text of each composition error :func:`unresolved_assets` reports (pxr prints it as a warning)."""
    return [str(error) for error in stage.GetCompositionErrors()
            if error.errorType in _ARC_ERRORS + _SUBLAYER_ERRORS]


def open_stage_trapping_asset_warnings(file: str) -> Usd.Stage:
    """``Usd.Stage.Open(file, Usd.Stage.LoadAll)``, without pxr's warnings about the composition errors
    :func:`unresolved_assets` reports; any other diagnostic is printed as usual. Raises what Usd.Stage.Open
    raises."""
    trap_type = getattr(Tf, "DiagnosticTrap", None)
    if trap_type is None:   # an older pxr cannot hold a warning back from Python
        return Usd.Stage.Open(file, Usd.Stage.LoadAll)
    with trap_type() as trap:
        stage = Usd.Stage.Open(file, Usd.Stage.LoadAll)
        if stage is not None:
            _erase_asset_warnings(trap, _covered_error_texts(stage) + _read_missing_clips(stage))
    return stage


def trapping_clip_warnings(stage: Usd.Stage) -> Usd.Stage:
    """``stage`` (open already, its composition warnings printed when it was composed) with the value clips
    :func:`unresolved_assets` reports read once, so that pxr's warning about each, which it prints on a clip's
    first read, is held back here instead of being printed while usdksl reads the stage. Without
    ``Tf.DiagnosticTrap`` nothing is read and pxr warns as before."""
    trap_type = getattr(Tf, "DiagnosticTrap", None)
    if trap_type is not None:
        with trap_type() as trap:
            _erase_asset_warnings(trap, _read_missing_clips(stage))
    return stage


def _read_missing_clips(stage: Usd.Stage) -> List[str]:
    """Read the values of every prim whose value clips do not resolve (pxr warns about a clip on its first
    read) and return the text of those warnings."""
    with Ar.ResolverContextBinder(stage.GetPathResolverContext()):
        clips = _clip_assets(stage)
    for path in dict.fromkeys(asset.requester for asset in clips):
        _read_clip_values(stage.GetPrimAtPath(path))
    return [f"clip layer @{asset.asset_path}@" for asset in clips]


def _erase_asset_warnings(trap, texts: List[str]) -> None:
    """Drop the warnings ``trap`` holds whose text names one of ``texts``; every other diagnostic is printed."""
    if texts:
        trap.EraseMatching(lambda diagnostic: isinstance(diagnostic, Tf.Warning)
                           and any(text in diagnostic.commentary for text in texts))


def _read_clip_values(prim: Usd.Prim) -> None:
    """Ask for the time samples of every attribute at and below ``prim``: USD opens a value clip's layers on
    the first such read and warns there, once per stage, about each that does not open."""
    if not prim:
        return
    for below in Usd.PrimRange(prim, Usd.TraverseInstanceProxies(Usd.PrimDefaultPredicate)):
        for attribute in below.GetAttributes():
            attribute.GetTimeSamples()


# --------------------------------------------------------------------------- references and payloads

def _arc_assets(stage: Usd.Stage, errors: list) -> List[UnresolvedAsset]:
    """The references and payloads behind ``errors`` (PcpErrors about prims), read from the specs of
    each prim; an error whose asset cannot be found there is named by its own text."""
    by_prim: Dict[str, list] = {}
    for error in errors:
        by_prim.setdefault(str(error.rootSite.path), []).append(error)
    found: List[UnresolvedAsset] = []
    for path in sorted(by_prim):
        prim = stage.GetPrimAtPath(path)
        wants_prims = any(error.errorType == Pcp.ErrorType_UnresolvedPrimPath for error in by_prim[path])
        assets = list(_failing_arcs(prim, path, wants_prims)) if prim else []
        found += assets or [_from_error_text(error, path) for error in by_prim[path]]
    return found


def _failing_arcs(prim: Usd.Prim, path: str, wants_prims: bool) -> Iterator[UnresolvedAsset]:
    """The references and payloads authored on ``prim``'s specs whose asset has not opened, or (when
    ``wants_prims``) whose asset lacks the prim they name."""
    resolver = Ar.GetResolver()
    for spec in prim.GetPrimStack():
        for kind, list_op in ((REFERENCE, spec.referenceList), (PAYLOAD, spec.payloadList)):
            for item in list_op.GetAddedOrExplicitItems():
                if not item.assetPath:   # an arc inside the same layer stack: no asset to resolve
                    continue
                identifier = Sdf.ComputeAssetPathRelativeToLayer(spec.layer, item.assetPath)
                opened = Sdf.Layer.Find(identifier)
                problem = None
                if opened is None:
                    problem = DOES_NOT_OPEN if str(resolver.Resolve(identifier)) else DOES_NOT_RESOLVE
                elif wants_prims:
                    problem = _missing_target(opened, item.primPath)
                if problem:
                    yield UnresolvedAsset(kind=kind, asset_path=item.assetPath, requester=path,
                                          layer=spec.layer.identifier, problem=problem,
                                          target=str(item.primPath) if not item.primPath.isEmpty else "")


def _missing_target(layer: Sdf.Layer, target: Sdf.Path) -> Optional[str]:
    """What is wrong with the prim an arc names in ``layer`` (its default prim when ``target`` is empty),
    looked for in ``layer`` and its sublayers; None when it is there."""
    if target.isEmpty:
        name = layer.defaultPrim
        if not name:
            return f"{DOES_NOT_RESOLVE}: its asset has no default prim"
        target = Sdf.Path(name) if name.startswith("/") else Sdf.Path.absoluteRootPath.AppendChild(name)
    if _layer_stack_has(layer, target, set()):
        return None
    return f"{DOES_NOT_RESOLVE}: its asset has no prim <{target}>"


def _layer_stack_has(layer: Sdf.Layer, path: Sdf.Path, seen: Set[str]) -> bool:
    if layer.identifier in seen:
        return False
    seen.add(layer.identifier)
    if layer.GetPrimAtPath(path):
        return True
    for sublayer_path in layer.subLayerPaths:
        sublayer = Sdf.Layer.Find(Sdf.ComputeAssetPathRelativeToLayer(layer, sublayer_path))
        if sublayer is not None and _layer_stack_has(sublayer, path, seen):
            return True
    return False


def _from_error_text(error, requester: str) -> UnresolvedAsset:
    """An UnresolvedAsset named by a PcpError's own text (the asset as pxr prints it), for an error whose
    authored asset path the specs do not show."""
    text = " ".join(str(error).split())
    paths = _AT_PATH.findall(text)
    arc = _ARC_WORD.search(text)
    return UnresolvedAsset(kind=arc.group(1) if arc else REFERENCE, asset_path=paths[0] if paths else "",
                           requester=requester, layer=paths[-1] if len(paths) > 1 else "",
                           problem=f"does not compose ({text})")


# --------------------------------------------------------------------------- sublayers

def _sublayer_assets(stage: Usd.Stage, errors: list) -> List[UnresolvedAsset]:
    """The sublayers that did not open, listed by every layer the stage uses (its own layer stack and the
    layer stacks of its references and payloads); the errors' own text when none is found."""
    if not errors:
        return []
    resolver = Ar.GetResolver()
    found = []
    for layer in sorted(stage.GetUsedLayers(), key=lambda used: used.identifier):
        for sublayer_path in layer.subLayerPaths:
            identifier = Sdf.ComputeAssetPathRelativeToLayer(layer, sublayer_path)
            if Sdf.Layer.Find(identifier) is None:
                found.append(UnresolvedAsset(
                    kind=SUBLAYER, asset_path=sublayer_path, requester=layer.identifier, layer=layer.identifier,
                    problem=DOES_NOT_OPEN if str(resolver.Resolve(identifier)) else DOES_NOT_RESOLVE))
    if found:
        return found
    fallback = []
    for error in errors:
        text = " ".join(str(error).split())
        paths = _AT_PATH.findall(text)
        fallback.append(UnresolvedAsset(kind=SUBLAYER, asset_path=paths[0] if paths else "",
                                        requester=paths[-1] if len(paths) > 1 else str(error.rootSite),
                                        layer=paths[-1] if len(paths) > 1 else "",
                                        problem=f"does not compose ({text})"))
    return fallback


# --------------------------------------------------------------------------- value clips

def _clip_assets(stage: Usd.Stage) -> List[UnresolvedAsset]:
    """The clip and manifest asset paths of every prim's value clip sets that do not resolve."""
    resolver = Ar.GetResolver()
    found = []
    for prim, path in _prims_with_clips(stage):
        for (_, field), (value, layer) in sorted(_clip_values(prim).items(), key=lambda item: item[0]):
            manifest = field == "manifestAssetPath"
            for asset in ([value] if manifest else list(value)):
                authored = getattr(asset, "path", asset)
                if authored and not str(resolver.Resolve(Sdf.ComputeAssetPathRelativeToLayer(layer, authored))):
                    found.append(UnresolvedAsset(kind=CLIP, asset_path=authored, requester=path,
                                                 layer=layer.identifier, manifest=manifest))
    return found


def _prims_with_clips(stage: Usd.Stage) -> Iterator[Tuple[Usd.Prim, str]]:
    """(prim, path as the stage shows it) of each prim the loader could read that authors ``clips``: the
    stage's prims, then those of each instancing prototype, named below the prototype's first instance."""
    for prim in Usd.PrimRange.Stage(stage, Usd.PrimDefaultPredicate):
        if prim.HasAuthoredMetadata("clips"):
            yield prim, str(prim.GetPath())
    for prototype in stage.GetPrototypes():
        instances = prototype.GetInstances()
        for prim in Usd.PrimRange(prototype, Usd.PrimDefaultPredicate):
            if prim.HasAuthoredMetadata("clips"):
                path = prim.GetPath()
                if instances:
                    path = path.ReplacePrefix(prototype.GetPath(), instances[0].GetPath())
                yield prim, str(path)


def _clip_values(prim: Usd.Prim) -> Dict[Tuple[str, str], tuple]:
    """{(clip set, "assetPaths" or "manifestAssetPath"): (value, layer it is authored in)} of the clip sets
    ``prim`` uses (all, or those its ``clipSets`` names), each from its strongest opinion: asset paths are
    anchored to the layer that authors them."""
    values: Dict[Tuple[str, str], tuple] = {}
    for spec in prim.GetPrimStack():
        clips = spec.GetInfo("clips") if spec.HasInfo("clips") else None
        for set_name, clip_set in (clips or {}).items():
            for field in ("assetPaths", "manifestAssetPath"):
                if field in clip_set and (set_name, field) not in values:
                    values[(set_name, field)] = (clip_set[field], spec.layer)
    clip_sets = prim.GetMetadata("clipSets") if prim.HasAuthoredMetadata("clipSets") else None
    if clip_sets is not None:
        used = set(clip_sets.ApplyOperations(sorted({set_name for set_name, _ in values})))
        values = {key: value for key, value in values.items() if key[0] in used}
    return values
