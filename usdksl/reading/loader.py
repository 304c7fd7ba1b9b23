"""USD stage -> world-space arrays the native core checks.

Every ``UsdGeom.Mesh`` of the stage becomes a :class:`MeshData`: its world-space
points at each of its time samples (the union of the ``points`` samples and of the
xformOp samples of the mesh and of its ancestors up to a ``resetXformStack``), a fan
triangulation of its authored polygons with a triangle -> face map, and a
classification (static / rigid / deforming).

Two kinds of mesh take their points from OpenUSD instead of ``points`` x transform:

* meshes skinned by UsdSkel (bound to a Skeleton under a SkelRoot): :mod:`usdksl.reading.skinning`;
* each instance of a mesh prototype of a ``UsdGeom.PointInstancer``, named
  ``<instancer>[<index>]/<prototype>/...``: :mod:`usdksl.reading.instancing`. Meshes below a
  PointInstancer are its prototypes and are never loaded on their own (UsdImaging and
  UsdGeomBBoxCache prune them the same way).

Empty meshes (no points, no faces, or only degenerate faces) are skipped with a warning
in :attr:`Shot.warnings`; a shot with nothing else left is an input error.

Python loops over prims and time samples only; points, faces and triangles are
handled by numpy. The points of one mesh go straight into one preallocated
``float64[K, N, 3]`` array, so loading holds little more than the result.

:func:`load_shot` opens the file and loads it. A check does it in two steps on one open stage:
:func:`find_mesh_sources` opens it and finds the meshes and their sample times (what the memory estimate
counts), :func:`load_sources` reads their points (once, or once per piece of a shot cut at gaps).
:func:`find_mesh_sources` also takes a stage open already (a DCC's, usdksl.pipeline.stage): then nothing is
opened, and what that stage composes (its session layer, variant selections, population mask and loaded
payloads) is what is read.

The input file is opened read-only and never saved.
"""

from __future__ import annotations

import fnmatch
import os
import re
from contextlib import contextmanager
from dataclasses import dataclass
from typing import Callable, Dict, Iterator, List, Optional, Sequence, Tuple, Union

import numpy as np
from pxr import Tf, Usd, UsdGeom

from ..errors import UsdkslEmptyMeshError, UsdkslGapError, UsdkslInputError, UsdkslUsageError
from ..warning_kinds import EMPTY_MESH, NOT_A_SURFACE, UNMESHED_SOLID, UNRESOLVED_ASSET
from ..unmasked import distinct_sorted
from .file_formats import require_file_format
from .segments import mesh_stretches
# What the rest of the package reads from the loader; one mesh is read in .meshes.
from .meshes import (DEFORMING, RIGID, STATIC, NOT_SURFACES, MeshData, Shot, UncheckedGeometry, _MatrixCache, rendered,
                     unmeshed_solid_kind, not_surface_kind, _window, load_mesh,  # noqa: F401
                     mesh_sample_times, topology_segments)

IncludeFilter = Union[None, Callable[[str], bool], str, Sequence[str]]


# --------------------------------------------------------------------------- opening

_PXR_NAMESPACE = re.compile(r"pxrInternal_v\w*?__pxrReserved__::")


#: Stands for a diagnostic USD could not hand to Python: its text is not UTF-8 (the text parser quotes
#: the bytes it stopped at).
NOT_UTF8_DIAGNOSTIC = "bytes that are not UTF-8 text"


def _diagnostic_entries(error: Exception) -> List[str]:
    try:
        return re.split(r"\n\s*Error in ", str(error))
    except UnicodeDecodeError:   # one diagnostic quotes bytes that are not UTF-8: keep the others
        entries = []
        for diagnostic in getattr(error, "args", ()):
            try:
                entries.append(str(diagnostic))
            except UnicodeDecodeError:
                entries.append(NOT_UTF8_DIAGNOSTIC)
        return entries


def first_non_utf8_line(file: str) -> Optional[int]:
    """The line (1-based) of the first byte sequence of ``file`` that is not UTF-8; None when all is."""
    try:
        with open(file, "rb") as handle:
            data = handle.read()
    except OSError:
        return None
    try:
        data.decode("utf-8")
    except UnicodeDecodeError as error:
        return data.count(b"\n", 0, error.start) + 1
    return None


def _pxr_error_text(error: Exception, file: Optional[str] = None) -> str:
    """The diagnostics of a Tf.ErrorException on one line, without C++ function/file noise. A diagnostic
    whose text is not UTF-8 is named as such, with the line of ``file`` where such bytes first occur."""
    messages = []
    for entry in _diagnostic_entries(error):
        if entry == NOT_UTF8_DIAGNOSTIC and file:
            line = first_non_utf8_line(file)
            messages.append(f"{NOT_UTF8_DIAGNOSTIC}" + (f" (first at line {line})" if line else ""))
            continue
        _, separator, message = entry.partition(" : '")
        text = message.strip().rstrip("'") if separator else entry
        text = " ".join(_PXR_NAMESPACE.sub("", text).split())
        if text:
            messages.append(text)
    return "; ".join(messages) or type(error).__name__


def open_stage(path: Union[str, os.PathLike]) -> Usd.Stage:
    """Open ``path`` read-only with all payloads loaded; one-line UsdkslInputError on failure.

    A local file is checked first (missing, a directory, unreadable: one line each). Anything that is not a
    local file but that the asset resolver resolves (a package-relative path such as
    ``shot.usdz[scene.usdc]``, or a path a studio resolver understands) is opened through Usd.Stage.Open.
    """
    file = os.fspath(path)
    if not os.path.exists(file):
        if not _resolves(file):
            raise UsdkslInputError("no such file", file=file)
    elif not os.path.isfile(file):
        raise UsdkslInputError("not a file", file=file)
    elif not os.access(file, os.R_OK):
        raise UsdkslInputError("file is not readable", file=file)
    require_file_format(file)   # an Alembic shot on a USD build without usdAbc: one line saying how to convert
    from .composition import open_stage_trapping_asset_warnings   # the loader names unresolved assets itself

    try:
        stage = open_stage_trapping_asset_warnings(file)
    except Tf.ErrorException as error:
        raise UsdkslInputError(f"cannot open as USD: {_pxr_error_text(error, file)}", file=file) from None
    if stage is None:
        raise UsdkslInputError("cannot open as USD", file=file)
    return stage


def _resolves(asset_path: str) -> bool:
    """True when the asset resolver finds ``asset_path`` (not a plain local file)."""
    from pxr import Ar

    try:
        return bool(str(Ar.GetResolver().Resolve(asset_path)))
    except Tf.ErrorException:
        return False


def stage_metadata(stage: Usd.Stage) -> Dict[str, object]:
    """Stage metadata an override layer must copy so the cache's samples keep their meaning."""
    root = stage.GetRootLayer()
    metadata: Dict[str, object] = {
        "timeCodesPerSecond": float(stage.GetTimeCodesPerSecond()),
        "framesPerSecond": float(stage.GetFramesPerSecond()),
    }
    if root.HasStartTimeCode():
        metadata["startTimeCode"] = float(stage.GetStartTimeCode())
    if root.HasEndTimeCode():
        metadata["endTimeCode"] = float(stage.GetEndTimeCode())
    metadata["upAxis"] = str(UsdGeom.GetStageUpAxis(stage))
    metadata["metersPerUnit"] = float(UsdGeom.GetStageMetersPerUnit(stage))
    if root.HasDefaultPrim():
        metadata["defaultPrim"] = str(root.defaultPrim)
    return metadata


# --------------------------------------------------------------------------- finding meshes

def _include_predicate(include: IncludeFilter) -> Callable[[str], bool]:
    if include is None:
        return lambda path: True
    if callable(include):
        return include
    patterns = [include] if isinstance(include, str) else list(include)

    def matches(path: str) -> bool:
        for pattern in patterns:
            pattern = str(pattern).rstrip("/") or "/"
            if (fnmatch.fnmatchcase(path, pattern) or path.startswith(pattern + "/")
                    or path.startswith(pattern + "[")):   # instances: <instancer>[<index>]/...
                return True
        return False

    return matches


def mesh_prims(stage: Usd.Stage, include: IncludeFilter = None) -> List[Usd.Prim]:
    """Every defined, active UsdGeom.Mesh (instance proxies included), in traversal order.

    Meshes below a UsdGeom.PointInstancer are its prototypes: they are left out here and
    loaded once per instance (:mod:`usdksl.reading.instancing`).
    ``include``: None (all), a callable on the prim path, or fnmatch patterns; a pattern
    also selects every mesh below the prim it names.
    """
    wanted = _include_predicate(include)
    predicate = Usd.TraverseInstanceProxies(Usd.PrimDefaultPredicate)
    found = []
    prims = iter(Usd.PrimRange.Stage(stage, predicate))
    for prim in prims:
        if prim.IsA(UsdGeom.PointInstancer):
            prims.PruneChildren()
        elif prim.IsA(UsdGeom.Mesh) and wanted(str(prim.GetPath())):
            found.append(prim)
    return found


def unmeshed_solids(stage: Usd.Stage, include: IncludeFilter = None,
                    in_prototypes: Sequence[Tuple[str, str]] = ()) -> List[UncheckedGeometry]:
    """One UncheckedGeometry per kind of solid non-mesh gprim (:func:`usdksl.reading.meshes.unmeshed_solid_kind`)
    that is visible, not a guide (left out as for meshes) and not below a PointInstancer, plus
    ``in_prototypes`` ((kind, path) found in prototypes with instances): geometry a contact could be
    with that usdksl reads past, with its first prim and how many there are. Curves, points and volumes
    (:data:`usdksl.reading.meshes.NOT_SURFACES`) come as one item per kind too, with the kind NOT_A_SURFACE:
    geometry, but not a surface a contact is defined on."""
    wanted = _include_predicate(include)
    found: Dict[str, List[str]] = {}
    prims = iter(Usd.PrimRange.Stage(stage, Usd.TraverseInstanceProxies(Usd.PrimDefaultPredicate)))
    for prim in prims:
        if prim.IsA(UsdGeom.PointInstancer):
            prims.PruneChildren()
            continue
        if not prim.IsA(UsdGeom.Boundable) or prim.IsA(UsdGeom.Mesh):
            continue
        kind = unmeshed_solid_kind(prim) or not_surface_kind(prim)
        if kind and wanted(str(prim.GetPath())) and rendered(prim):
            found.setdefault(kind, []).append(str(prim.GetPath()))
    for kind, path in in_prototypes:
        found.setdefault(kind, []).append(path)
    items = []
    for kind, paths in found.items():
        prims_named = f"{len(paths)} UsdGeom.{kind} prim{'s' if len(paths) > 1 else ''} (first {paths[0]})"
        if kind in NOT_SURFACES:
            items.append(UncheckedGeometry(prim=paths[0], kind=NOT_A_SURFACE, reason=(
                f"{prims_named}: not a surface; usdksl checks surfaces (UsdGeom.Mesh) only")))
        else:
            items.append(UncheckedGeometry(prim=paths[0], kind=UNMESHED_SOLID, reason=(
                f"{prims_named} not checked: usdksl checks UsdGeom.Mesh surfaces only; export colliders as meshes")))
    return items


# --------------------------------------------------------------------------- whole shot

def _check_time_range(file: str, time_range) -> Optional[Tuple[float, float]]:
    if time_range is None:
        return None
    try:
        start, end = (float(value) for value in time_range)
    except (TypeError, ValueError):
        raise UsdkslUsageError(f"time range must be two numbers, got {time_range!r}",
                               file=file) from None
    if not (np.isfinite(start) and np.isfinite(end)) or start > end:
        raise UsdkslUsageError(f"time range [{start:g}, {end:g}] is empty or not finite",
                               file=file)
    return (start, end)


@dataclass
class MeshSources:
    """A shot's stage, opened once, and what :func:`load_shot` loads from it, found once: the memory estimate
    (usdksl.pipeline.memory_budget) counts these sources before any motion is read, and :func:`load_sources`
    loads them, once or once per piece of a shot cut at gaps (usdksl.pipeline.loading)."""

    file: str
    stage: Usd.Stage
    metadata: Dict[str, object]
    #: The authored UsdGeom.Mesh prims (:func:`mesh_prims`), in order: the first ``len(prims)`` sources.
    prims: List[Usd.Prim]
    #: A skinned, authored or instanced mesh each, with ``sample_times()`` and ``load()``.
    sources: list
    #: float64[K_i] per source: the time codes at which it has a sample, sorted (empty for a still one).
    sample_times: List[np.ndarray]
    #: What was found unchecked on the stage (unresolved assets, nested instancers, solid non-meshes) with
    #: a warning line each; every load starts from a copy of both.
    unchecked: List[UncheckedGeometry]
    warnings: List[str]


def find_mesh_sources(path: Union[str, os.PathLike], include: IncludeFilter = None,
                      allow_missing_assets: bool = False, skin_keys_only: bool = False,
                      stage: Optional[Usd.Stage] = None) -> MeshSources:
    """Open ``path`` and find the meshes :func:`load_shot` would load (``include``, ``allow_missing_assets``,
    ``skin_keys_only`` as there) with their sample times, reading no points. ``stage``: read this open stage
    instead of opening ``path`` (which then names it in messages, and is the file the reports name: the
    file of its root layer). Raises :class:`usdksl.errors.UsdkslInputError` with a one-line message on bad
    input."""
    file = os.fspath(path)
    with _errors_name_file(file):
        return _find_mesh_sources(file, include, allow_missing_assets, skin_keys_only, stage)


def load_sources(found: MeshSources, time_range: Optional[Tuple[float, float]] = None,
                 absent: Optional[Dict[str, float]] = None) -> Shot:
    """:func:`load_shot` of the stage and sources ``found`` already (``time_range``, ``absent`` as there):
    no second open of the stage, no second search for its meshes."""
    with _errors_name_file(found.file):
        return _load_sources(found, _check_time_range(found.file, time_range), absent or {})


def load_shot(path: Union[str, os.PathLike], time_range: Optional[Tuple[float, float]] = None,
              include: IncludeFilter = None, allow_missing_assets: bool = False,
              skin_keys_only: bool = False, absent: Optional[Dict[str, float]] = None) -> Shot:
    """Load every mesh of a USD shot in world space (see module docstring).

    ``time_range=(a, b)``: each animated mesh keeps its samples inside (a, b) plus its
    values evaluated exactly at a and b. ``include``: see :func:`mesh_prims`.
    ``allow_missing_assets``: load what composes when an asset does not resolve (each is listed in
    :attr:`Shot.unchecked`) instead of raising. ``skin_keys_only``: pose skinned meshes at their keys only
    (:mod:`usdksl.reading.skinning`). ``absent``: {mesh path: time} of meshes loaded still at that one time
    and listed in :attr:`Shot.absent` (a piece of a shot where they have no points: usdksl.reading.segments).
    Raises :class:`usdksl.errors.UsdkslInputError` with a one-line message on bad input, and
    :class:`usdksl.errors.UsdkslGapError` when a mesh has empty or blocked samples between samples with points.
    """
    file = os.fspath(path)
    with _errors_name_file(file):
        time_range = _check_time_range(file, time_range)
        found = _find_mesh_sources(file, include, allow_missing_assets, skin_keys_only)
        return _load_sources(found, time_range, absent or {})


@contextmanager
def _errors_name_file(file: str) -> Iterator[None]:
    """Readers below the loader know the prim but not the file: their input errors get ``file``."""
    try:
        yield
    except UsdkslInputError as error:
        if error.file:
            raise
        raise type(error)(error.message, file=file, prim=error.prim, time=error.time) from None


def _find_mesh_sources(file: str, include: IncludeFilter, allow_missing_assets: bool = False,
                       skin_keys_only: bool = False, stage: Optional[Usd.Stage] = None) -> MeshSources:
    from . import composition

    # a stage handed over open was composed (and warned about) by its owner: only its clips warn on first read
    stage = open_stage(file) if stage is None else composition.trapping_clip_warnings(stage)
    missing = composition.unresolved_assets(stage)   # composed without them, a contact with them goes unseen
    root = stage.GetRootLayer().identifier   # a sublayer of it is asked for by the file every line names already
    if missing and not allow_missing_assets:
        requester = missing[0].requester
        raise UsdkslInputError(composition.refusal(missing), file=file, prim=None if requester == root else requester)
    metadata = stage_metadata(stage)
    unchecked: List[UncheckedGeometry] = [
        UncheckedGeometry(prim=asset.requester, reason=composition.not_checked(asset), kind=UNRESOLVED_ASSET)
        for asset in missing]
    warnings: List[str] = [f"{file}: {item.reason}" if item.prim == root else f"{file}: {item.prim}: {item.reason}"
                           for item in unchecked]
    try:
        prims, sources = _mesh_sources(stage, include, file, warnings, unchecked, skin_keys_only)
    except UsdkslInputError as error:
        if not missing:
            raise
        raise type(error)(f"{error.message} ({composition.summary(missing)})", file=error.file or file,
                          prim=error.prim, time=error.time) from None
    return MeshSources(file=file, stage=stage, metadata=metadata, prims=prims, sources=sources,
                       sample_times=_source_sample_times(sources, file), unchecked=unchecked, warnings=warnings)


def _load_sources(found: MeshSources, time_range: Optional[Tuple[float, float]],
                  absent: Dict[str, float]) -> Shot:
    from . import layer_rates   # it builds on this module

    file, stage, metadata, sources = found.file, found.stage, found.metadata, found.sources
    unchecked = list(found.unchecked)
    warnings = list(found.warnings)
    for source in sources:   # an instancer warns while it loads: into this load's lines, once per load
        instancer = getattr(source, "instancer", None)
        if instancer is not None:
            instancer.start_load(warnings)
    sample_times = found.sample_times
    per_mesh_times = [_window(times, time_range) for times in sample_times]
    animated = [times for times in per_mesh_times if times.size]
    if animated:
        reference_time = float(min(times[0] for times in animated))
    elif time_range is not None:
        reference_time = time_range[0]
    else:
        reference_time = float(metadata.get("startTimeCode", 0.0))

    matrices = _MatrixCache()
    meshes = []
    empty: List[UsdkslEmptyMeshError] = []
    for source, times in zip(sources, per_mesh_times):
        if times.size == 0:
            times = np.array([reference_time], dtype=np.float64)
        if source.path in absent:
            times = np.array([absent[source.path]], dtype=np.float64)
        try:
            loaded = source.load(times, file, matrices)
        except UsdkslEmptyMeshError as error:
            # an instancer's prototype mesh is source.mesh.prim; its gaps are not cut around (exit 2 below)
            prim = getattr(source, "prim", None) or getattr(getattr(source, "mesh", None), "prim", None)
            if not error.degenerate and _shows_surface_within(prim, times):
                raise UsdkslGapError(f"points are empty or blocked here ({error.message})", file=file,
                                     prim=error.prim, time=error.time) from None
            empty.append(error)
            warnings.append(f"{error}; skipped")
            unchecked.append(UncheckedGeometry(prim=error.prim or source.path, reason=f"{error.message}; skipped",
                                               kind=EMPTY_MESH))
            continue
        except Tf.ErrorException as error:
            raise UsdkslInputError(f"cannot read mesh: {_pxr_error_text(error)}", file=file,
                                   prim=source.path) from None
        meshes.extend(loaded if isinstance(loaded, list) else [loaded])
    if not meshes and empty:
        first = empty[0]
        others = f" and {len(empty) - 1} more empty meshes" if len(empty) > 1 else ""
        raise UsdkslInputError(f"{first.message}{others}; nothing else to check", file=file,
                               prim=first.prim, time=first.time)
    if not meshes:
        raise UsdkslInputError("nothing to check: no mesh and no visible PointInstancer instance",
                               file=file)
    warnings.extend(layer_rates.rescaled_layer_warnings(
        stage, [prim for source in sources for prim in source.motion_prims()], file))
    present = [mesh for mesh in meshes if mesh.path not in absent] or meshes
    shot_times = distinct_sorted(np.concatenate([mesh.times for mesh in present]))
    return Shot(path=file, meshes=meshes, times=shot_times, metadata=metadata, stage=stage, absent=frozenset(absent),
                sample_span=_sample_span(sample_times),
                warnings=warnings, unchecked=unchecked, notes=_sparse_skin_notes(sources, time_range, file))


def _mesh_sources(stage: Usd.Stage, include: IncludeFilter, file: str, warnings: List[str],
                  unchecked: Optional[List[UncheckedGeometry]] = None,
                  skin_keys_only: bool = False) -> Tuple[List[Usd.Prim], list]:
    """(the authored mesh prims, what load_shot loads): in its order a skinned mesh, an authored mesh or a
    PointInstancer's prototype mesh, each with ``sample_times()`` and ``load()``, the first ones one per prim.
    Geometry read past without a check (nested instancers, solid non-meshes) goes to ``unchecked``, each with a
    line in ``warnings``.
    ``skin_keys_only``: skinned meshes are posed at their keys only (:mod:`usdksl.reading.skinning`).
    Raises UsdkslInputError when there is nothing to load."""
    from . import instancing   # it builds on this module

    unchecked = unchecked if unchecked is not None else []
    in_prototypes: List[Tuple[str, str]] = []     # (kind, path) of solid non-meshes in instanced prototypes
    try:
        prims = mesh_prims(stage, include)
        skinned = _skinned_meshes(stage, skin_keys_only)
        sources = [skinned.get(str(prim.GetPath())) or _AuthoredMesh(prim) for prim in prims]
        sources += instancing.find_instanced_meshes(stage, _include_predicate(include), file, warnings,
                                                     skinned, unchecked, in_prototypes)
        for item in unmeshed_solids(stage, include, in_prototypes):
            unchecked.append(item)
            if item.kind != NOT_A_SURFACE:
                warnings.append(f"{file}: {item.reason}")
    except Tf.ErrorException as error:
        raise UsdkslInputError(f"cannot read the stage: {_pxr_error_text(error)}", file=file) from None
    if not sources:
        what = "no UsdGeom.Mesh prims" if include is None else "no UsdGeom.Mesh prims match the selection"
        raise UsdkslInputError(f"{what} on the stage", file=file)
    return prims, sources


#: The schema UsdSkel poses meshes under (UsdSkel.Root), named so that a stage can be searched for it before
#: pxr.UsdSkel is imported: most caches have no skeleton, and that import costs about 8 ms.
SKEL_ROOT_SCHEMA = "SkelRoot"


def _skinned_meshes(stage: Usd.Stage, keys_only: bool = False) -> dict:
    """:func:`usdksl.reading.skinning.find_skinned_meshes`, or {} when no prim it would visit is a SkelRoot
    (then UsdSkel is not imported). A USD that cannot name the schema's type asks UsdSkel itself."""
    skel_root = Usd.SchemaRegistry.GetTypeFromSchemaTypeName(SKEL_ROOT_SCHEMA)
    if not skel_root.isUnknown:
        predicate = Usd.TraverseInstanceProxies(Usd.PrimDefaultPredicate)   # what find_skinned_meshes visits
        if not any(prim.IsA(skel_root) for prim in Usd.PrimRange.Stage(stage, predicate)):
            return {}
    from . import skinning   # it builds on this module

    return skinning.find_skinned_meshes(stage, keys_only=keys_only)


def _sparse_skin_notes(sources: Sequence, time_range: Optional[Tuple[float, float]], file: str) -> List[str]:
    """:func:`usdksl.reading.skinning.sparse_key_notes` on the skinned meshes among ``sources`` (instanced
    prototypes included), each line led by ``file``."""
    # duck-typed: the skinning module is imported only when the stage has a SkelRoot
    skinned = [getattr(source, "skinned", None) or source for source in sources]
    skinned = [mesh for mesh in skinned if hasattr(mesh, "frames_between_keys")]
    if not skinned:
        return []
    from . import skinning   # it builds on this module

    return [f"{file}: {line}" for line in skinning.sparse_key_notes(skinned, time_range)]


def _source_sample_times(sources: Sequence, file: str) -> List[np.ndarray]:
    try:
        return [np.asarray(sorted(source.sample_times()), dtype=np.float64) for source in sources]
    except Tf.ErrorException as error:
        raise UsdkslInputError(f"cannot read time samples: {_pxr_error_text(error)}",
                               file=file) from None


def shot_sample_times(path: Union[str, os.PathLike], include: IncludeFilter = None,
                      skin_keys_only: bool = False) -> List[np.ndarray]:
    """float64[K_i] per mesh source of :func:`load_shot` (a skinned, authored or instanced mesh): the time
    codes at which it has a sample, empty for a still one; a skinned mesh's include the frames it is posed at
    between sparse keys unless ``skin_keys_only`` (:mod:`usdksl.reading.skinning`). Reads time samples only,
    never points, so it is cheap on any cache. Raises UsdkslInputError like load_shot."""
    file = os.fspath(path)
    stage = open_stage(file)   # held while the sources' prims are read: they die with it
    return _source_sample_times(_mesh_sources(stage, include, file, [], skin_keys_only=skin_keys_only)[1], file)


def _sample_span(sample_times: Sequence[np.ndarray]) -> Optional[Tuple[float, float]]:
    """First and last sample of the animated sources (more than one sample), or None."""
    animated = [times for times in sample_times if times.size > 1]
    if not animated:
        return None
    return (min(float(times[0]) for times in animated), max(float(times[-1]) for times in animated))


def _shows_surface_within(prim: Optional[Usd.Prim], times: np.ndarray) -> bool:
    """Whether a UsdGeom.Mesh ``prim`` has a stretch of samples with points and faces within ``times``' span: then
    an empty sample is a gap in the mesh, not an empty mesh."""
    if prim is None or not prim.IsA(UsdGeom.Mesh) or times.size == 0:
        return False
    first, last = float(times[0]), float(times[-1])
    return any(stretch.valid and stretch.first <= last and stretch.last >= first
               for stretch in mesh_stretches(prim))


class _AuthoredMesh:
    """A mesh whose world points are its authored points through its transforms (no UsdSkel, no instancer)."""

    def __init__(self, prim: Usd.Prim):
        self.prim = prim
        self.path = str(prim.GetPath())

    def sample_times(self) -> np.ndarray:
        return mesh_sample_times(self.prim)

    def motion_prims(self) -> List[Usd.Prim]:
        return [self.prim]

    def load(self, times: np.ndarray, file: str, matrices: _MatrixCache) -> MeshData:
        return load_mesh(self.prim, times, file, matrices)
