"""The ``<stem>.usdksl.usda`` (or ``.usdc``) override layer: the results of a check written back into USD.

The layer sublayers the input by a relative path (so the pair of files can move together) and copies the
input's stage metadata (timeCodesPerSecond, framesPerSecond, start/end time codes, upAxis,
metersPerUnit, defaultPrim): without them the sublayered cache's samples would be rescaled (docs/contracts.md,
Outputs). On the cache's prims it only authors ``over`` opinions (it defines nothing but its review
material, under ``/UsdkslReview``); the input file is never opened for writing.

Per checked mesh it authors:

``int usdksl:contactFaceCount``
    how many of the mesh's authored faces touch anything (0 when clean);
``rel usdksl:contactsWith``
    the meshes it touches (itself included for self contacts), sorted; no targets when clean;
``double usdksl:firstContactTime``
    its first contact in time codes; **absent when the mesh is clean**, so ``Get()`` returns None;
``double[] primvars:usdksl:firstContactTime`` (interpolation uniform)
    one value per authored face: that face's first contact time, **NaN for faces that never touch**
    (time codes may be negative, so no sentinel number is safe);
``color3f[] primvars:displayColor`` (interpolation uniform, indexed) and ``int[] primvars:displayColor:indices``
    the colours grey and red, and per face an index into them **sampled in time**: a face is red from
    its first contact on (usdview shows where and when). Integer arrays are held between samples, never
    interpolated, so a face turns red exactly at the sample of its first contact and no sample "just
    before" is needed; the first sample, at the start of the checked range, holds the state before any
    contact (faces touching at the start are red there). One sample per distinct first-contact time,
    unless a mesh has more than :data:`MAX_EXACT_COLOR_SAMPLES`: then its samples fall on whole time
    codes (a face turns red at the first whole time code at or after its first contact: exact at whole
    frames, up to one time code late in between). The default value (no time) marks every face that ever
    touches. Any ``primvars:displayColor:indices`` of the input is replaced by these.
``rel material:binding:preview`` (with ``MaterialBindingAPI``; also on ``materialBind`` GeomSubsets)
    the review material ``/UsdkslReview/ContactColors``: a UsdPreviewSurface whose diffuse colour reads
    the ``displayColor`` primvar, so the colours show in usdview (which renders the preview purpose)
    with scene materials on. Renders of the ``full`` purpose keep the scene's materials.

Its ``customLayerData`` holds one dictionary, ``usdksl``, saying what produced it (docs/contracts.md,
Outputs): ``string shotSha256`` (SHA-256 of the shot's root layer
file, as the farm manifest names it) and ``dictionary settings`` (the check's settings, as the JSON report
has them: a setting that is None is left out, lists of strings are ``string[]``, of numbers ``double[]``).

The layer is written as text (``.usdksl.usda``) unless it authors more than :data:`USDA_MAX_ARRAY_ELEMENTS`
array elements; then as a binary crate file (``.usdksl.usdc``), which is smaller and much faster to
open.

Meshes inside instances are made visible to these opinions by authoring ``instanceable = false`` on
their instances in this layer (the input keeps its instancing).

PointInstancer instances (``/World/scatter[3]/box``, :mod:`usdksl.reading.instancing`) are not prims, and all
instances share their prototype's faces, so nothing is authored per instance mesh or per face. Their results
go on the instancer prim instead:

``double[] usdksl:instanceFirstContactTime``
    one value per instance index (the instancer's protoIndices order): that instance's first contact, NaN
    when it never touches anything or was not checked;
``int usdksl:contactInstanceCount``, ``rel usdksl:contactsWith``, ``double usdksl:firstContactTime``
    as for a mesh, over all its instances. A mesh touched by an instance lists the instancer in its
    ``usdksl:contactsWith``.
"""

from __future__ import annotations

import os
import tempfile
from dataclasses import dataclass
from pathlib import Path
from typing import Dict, Iterable, List, Optional, Sequence, Tuple, Union

import numpy as np

from ..unmasked import distinct_sorted

CONTACT_COLOR = (1.0, 0.1, 0.1)
CLEAN_COLOR = (0.6, 0.6, 0.6)

ATTR_FIRST_CONTACT_TIME = "usdksl:firstContactTime"
ATTR_CONTACT_FACE_COUNT = "usdksl:contactFaceCount"
REL_CONTACTS_WITH = "usdksl:contactsWith"
ATTR_INSTANCE_FIRST_CONTACT_TIME = "usdksl:instanceFirstContactTime"
ATTR_CONTACT_INSTANCE_COUNT = "usdksl:contactInstanceCount"
PRIMVAR_FIRST_CONTACT_TIME = "primvars:usdksl:firstContactTime"
PRIMVAR_DISPLAY_COLOR = "primvars:displayColor"
PRIMVAR_DISPLAY_COLOR_INDICES = PRIMVAR_DISPLAY_COLOR + ":indices"
#: Index of each colour in primvars:displayColor.
CLEAN_INDEX = 0
CONTACT_INDEX = 1

#: The review material and the binding that shows it in usdview with scene materials on.
REVIEW_SCOPE = "/UsdkslReview"
REVIEW_MATERIAL = REVIEW_SCOPE + "/ContactColors"
REVIEW_BINDING = "material:binding:preview"
#: familyName of GeomSubsets that bind materials to some faces (they need the review binding too).
MATERIAL_BIND_FAMILY = "materialBind"

#: A matte surface, so the review colours read the same from every side.
REVIEW_ROUGHNESS = 0.8
#: More distinct first-contact times than this on one mesh: colour samples on whole time codes.
MAX_EXACT_COLOR_SAMPLES = 256
#: The customLayerData key of the provenance dictionary (module docstring).
PROVENANCE_KEY = "usdksl"
#: A layer with more array elements than this is written as a binary crate (.usdc) instead of text.
USDA_MAX_ARRAY_ELEMENTS = 100_000
TEXT_SUFFIX = ".usdksl.usda"
BINARY_SUFFIX = ".usdksl.usdc"

_COPIED_LAYER_FIELDS = ("timeCodesPerSecond", "framesPerSecond", "startTimeCode", "endTimeCode")
_COPIED_STAGE_FIELDS = ("upAxis", "metersPerUnit")


def relative_sublayer_path(input_path: Union[str, os.PathLike], layer_directory: Union[str, os.PathLike]) -> str:
    """The input as seen from the override layer's directory, always anchored ('./' or '../')."""
    relative = os.path.relpath(os.path.abspath(input_path), os.path.abspath(layer_directory))
    relative = relative.replace(os.sep, "/")
    if not relative.startswith("../"):
        relative = "./" + relative
    return relative


def face_first_contact_times(table, mesh_index: int, face_count: int) -> np.ndarray:
    """float64[face_count]: each face's earliest contact as either side of a row; NaN when never."""
    first = np.full(face_count, np.inf)
    for mesh_side, face_side in ((table.mesh_a, table.face_a), (table.mesh_b, table.face_b)):
        rows = mesh_side == mesh_index
        if rows.any():
            np.minimum.at(first, face_side[rows], table.time[rows])
    first[np.isinf(first)] = np.nan
    return first


def touched_meshes(table, mesh_index: int) -> np.ndarray:
    """Indices of meshes sharing a contact row with ``mesh_index`` (itself for self contacts)."""
    other = np.concatenate([table.mesh_b[table.mesh_a == mesh_index], table.mesh_a[table.mesh_b == mesh_index]])
    return distinct_sorted(other)


@dataclass
class OverrideLayer:
    """A built override layer: the anonymous Sdf.Layer and how many array elements it authors."""

    layer: object
    array_elements: int

    @property
    def binary(self) -> bool:
        """Whether it is written as a crate file (.usdc) rather than text."""
        return self.array_elements > USDA_MAX_ARRAY_ELEMENTS

    @property
    def suffix(self) -> str:
        return BINARY_SUFFIX if self.binary else TEXT_SUFFIX

    def data(self) -> Union[str, bytes]:
        """The file's content: usda text, or the bytes of a crate file."""
        if not self.binary:
            return self.layer.ExportToString()
        with tempfile.TemporaryDirectory(prefix="usdksl-layer-") as folder:
            target = os.path.join(folder, "layer" + BINARY_SUFFIX)
            if not self.layer.Export(target):
                raise RuntimeError("USD could not write the override layer as a crate file")
            with open(target, "rb") as handle:
                return handle.read()


def build_override_layer(shot, checked_meshes: Iterable[int], table, layer_path: Union[str, os.PathLike],
                         segments: Optional[Sequence[tuple]] = None, span: Optional[Tuple[float, float]] = None,
                         provenance: Optional[dict] = None) -> str:
    """The override layer's usda text (see :func:`override_layer`)."""
    return override_layer(shot, checked_meshes, table, layer_path, segments, span,
                          provenance).layer.ExportToString()


def provenance_data(shot_sha256: str, settings: dict) -> dict:
    """The ``usdksl`` customLayerData dictionary (module docstring) from the check's settings
    (CheckOptions.settings()): only values a USD dictionary can hold. The usdksl version is not in it: looking it
    up (importlib.metadata) costs every check tens of milliseconds of start-up."""
    return {"shotSha256": str(shot_sha256), "settings": _usd_dictionary(settings)}


def _usd_dictionary(values: dict) -> dict:
    """``values`` with None left out (a USD dictionary has no null) and lists as typed VtArrays."""
    from pxr import Vt

    result = {}
    for key, value in values.items():
        if value is None:
            continue
        if isinstance(value, dict):
            value = _usd_dictionary(value)
        elif isinstance(value, (list, tuple)):
            # an empty list has no element type to go by; the settings' lists of paths are strings
            numeric = bool(value) and all(isinstance(item, (int, float)) and not isinstance(item, bool)
                                          for item in value)
            value = (Vt.DoubleArray([float(item) for item in value]) if numeric
                     else Vt.StringArray([str(item) for item in value]))
        result[str(key)] = value
    return result


def override_layer(shot, checked_meshes: Iterable[int], table, layer_path: Union[str, os.PathLike],
                   segments: Optional[Sequence[tuple]] = None,
                   span: Optional[Tuple[float, float]] = None, provenance: Optional[dict] = None) -> OverrideLayer:
    """The override layer for ``shot`` (usdksl.reading.loader.Shot) and its ContactTable.

    ``checked_meshes``: indices into shot.meshes that took part in at least one checked pair.
    ``layer_path``: where the layer will live (only its directory matters, for the relative sublayer).
    ``span``: the checked range in time codes, where the colour samples start (default: the shot's samples).
    ``segments``: for a shot checked in constant-topology stretches (usdksl.reading.segments), a list of
    ((start, end), segment Shot, segment ContactTable). A mesh whose topology differs between segments gets
    its per-face primvars as time samples per segment (one value per face of the topology in force);
    the mesh-level values cover all segments, and ``usdksl:contactFaceCount`` then adds up the touching
    faces of every segment.
    ``provenance``: the ``usdksl`` customLayerData dictionary (:func:`provenance_data`); None: none written.
    """
    from pxr import Sdf, Vt

    layer = Sdf.Layer.CreateAnonymous("usdksl.usda")
    layer.subLayerPaths.append(relative_sublayer_path(shot.path, Path(layer_path).parent))
    metadata: Dict[str, object] = dict(shot.metadata)
    for key in _COPIED_LAYER_FIELDS:
        if key in metadata:
            setattr(layer, key, float(metadata[key]))
    for key in _COPIED_STAGE_FIELDS:
        if key in metadata:
            value = metadata[key]
            layer.pseudoRoot.SetInfo(key, float(value) if key == "metersPerUnit" else str(value))
    if metadata.get("defaultPrim"):
        layer.defaultPrim = str(metadata["defaultPrim"])
    layer.comment = "usdksl check results: override layer over the cache it sublayers"
    if provenance is not None:
        layer.customLayerData = {PROVENANCE_KEY: provenance}
    if span is None:
        times = np.asarray(shot.times, dtype=np.float64)
        span = (float(times.min()), float(times.max())) if times.size else (0.0, 0.0)

    paths = [mesh.path for mesh in shot.meshes]
    targets = [_result_prim(mesh) for mesh in shot.meshes]
    instancers: Dict[str, list] = {}
    elements = 0
    reviewed = []
    for index in sorted(set(int(i) for i in checked_meshes), key=paths.__getitem__):
        mesh = shot.meshes[index]
        if getattr(mesh, "instancer", None):
            instancers.setdefault(mesh.instancer, []).append(index)
            continue
        # (time range, face times, whether the range is one segment of several) per authored value
        if segments and len(segments) > 1 and not _same_topology_everywhere(segments, index):
            values = [(segment_span, face_first_contact_times(segment_table, index,
                                                              segment_shot.meshes[index].face_count), True)
                      for segment_span, segment_shot, segment_table in segments]
        else:
            values = [(span, face_first_contact_times(table, index, mesh.face_count), False)]
        touching_faces = sum(int((~np.isnan(times)).sum()) for _, times, _ in values)
        for instance_path in _enclosing_instances(shot.stage, mesh.path):
            # opinions below an instance are ignored; de-instance it in this review layer only
            instance = Sdf.CreatePrimInLayer(layer, Sdf.Path(instance_path))
            instance.specifier = Sdf.SpecifierOver
            instance.instanceable = False
        spec = Sdf.CreatePrimInLayer(layer, Sdf.Path(mesh.path))
        spec.specifier = Sdf.SpecifierOver

        count = Sdf.AttributeSpec(spec, ATTR_CONTACT_FACE_COUNT, Sdf.ValueTypeNames.Int, declaresCustom=True)
        count.default = touching_faces
        relationship = Sdf.RelationshipSpec(spec, REL_CONTACTS_WITH, custom=True)
        relationship.targetPathList.explicitItems = [
            Sdf.Path(other) for other in sorted({targets[i] for i in touched_meshes(table, index).tolist()})]
        rows = (table.mesh_a == index) | (table.mesh_b == index)
        if rows.any():
            first = Sdf.AttributeSpec(spec, ATTR_FIRST_CONTACT_TIME, Sdf.ValueTypeNames.Double,
                                      declaresCustom=True)
            first.default = float(table.time[rows].min())

        primvar = Sdf.AttributeSpec(spec, PRIMVAR_FIRST_CONTACT_TIME, Sdf.ValueTypeNames.DoubleArray)
        primvar.SetInfo("interpolation", "uniform")
        display = Sdf.AttributeSpec(spec, PRIMVAR_DISPLAY_COLOR, Sdf.ValueTypeNames.Color3fArray)
        display.SetInfo("interpolation", "uniform")
        display.default = Vt.Vec3fArray([CLEAN_COLOR, CONTACT_COLOR])
        indices = Sdf.AttributeSpec(spec, PRIMVAR_DISPLAY_COLOR_INDICES, Sdf.ValueTypeNames.IntArray)
        for value_span, face_times, segmented in values:
            if not segmented:
                primvar.default = Vt.DoubleArray.FromNumpy(face_times)
                indices.default = Vt.IntArray.FromNumpy(_color_indices(face_times, np.inf))
                elements += 2 * face_times.size
            else:
                for time in sorted(set(value_span)):
                    layer.SetTimeSample(primvar.path, float(time), Vt.DoubleArray.FromNumpy(face_times))
                    elements += face_times.size
            for time in color_sample_times(face_times, value_span[0]):
                layer.SetTimeSample(indices.path, float(time),
                                    Vt.IntArray.FromNumpy(_color_indices(face_times, time)))
                elements += face_times.size
        reviewed.append(spec)
        _bind_review_material(spec, _material_subsets(shot.stage, mesh.path))
    if reviewed:
        _define_review_material(layer)
    for instancer, indices in sorted(instancers.items()):
        _author_instancer(layer, shot, instancer, indices, table, targets)
    return OverrideLayer(layer=layer, array_elements=elements)


def color_sample_times(face_times: np.ndarray, start: float) -> List[float]:
    """Times of the colour index samples of one mesh (module docstring): ``start``, then each distinct first
    contact after it, or, past MAX_EXACT_COLOR_SAMPLES of them, the whole time codes at or after them."""
    touched = face_times[~np.isnan(face_times)]
    later = distinct_sorted(touched[touched > start])
    if later.size > MAX_EXACT_COLOR_SAMPLES:
        later = distinct_sorted(np.maximum(np.ceil(later), start))
        later = later[later > start]
    return [float(start)] + later.tolist()


def _color_indices(face_times: np.ndarray, time: float) -> np.ndarray:
    """int32[F]: CONTACT_INDEX for faces whose first contact is at or before ``time``, else CLEAN_INDEX."""
    return np.where(face_times <= time, CONTACT_INDEX, CLEAN_INDEX).astype(np.int32)   # NaN <= time is False


def _material_subsets(stage, mesh_path: str) -> List[str]:
    """Paths of the mesh's GeomSubsets that bind materials to some of its faces."""
    from pxr import UsdGeom

    prim = stage.GetPrimAtPath(mesh_path) if stage is not None else None
    if not prim or not prim.IsA(UsdGeom.Mesh):
        return []
    subsets = UsdGeom.Subset.GetGeomSubsets(UsdGeom.Imageable(prim), UsdGeom.Tokens.face, MATERIAL_BIND_FAMILY)
    return sorted(str(subset.GetPath()) for subset in subsets)


def _bind_review_material(spec, subset_paths: Sequence[str]) -> None:
    """Bind the review material for the preview purpose on the mesh and its material subsets."""
    from pxr import Sdf

    for target in [spec] + [Sdf.CreatePrimInLayer(spec.layer, Sdf.Path(path)) for path in subset_paths]:
        if target is not spec:
            target.specifier = Sdf.SpecifierOver
        target.SetInfo("apiSchemas", Sdf.TokenListOp.Create(prependedItems=["MaterialBindingAPI"]))
        binding = Sdf.RelationshipSpec(target, REVIEW_BINDING, custom=False)
        binding.targetPathList.explicitItems = [Sdf.Path(REVIEW_MATERIAL)]


def _define_review_material(layer) -> None:
    """/UsdkslReview/ContactColors: UsdPreviewSurface, diffuse colour from the displayColor primvar."""
    from pxr import Sdf

    scope = Sdf.PrimSpec(layer.pseudoRoot, REVIEW_SCOPE.lstrip("/"), Sdf.SpecifierDef, "Scope")
    material = Sdf.PrimSpec(scope, REVIEW_MATERIAL.rsplit("/", 1)[1], Sdf.SpecifierDef, "Material")
    surface = Sdf.PrimSpec(material, "Surface", Sdf.SpecifierDef, "Shader")
    reader = Sdf.PrimSpec(material, "DisplayColor", Sdf.SpecifierDef, "Shader")

    def attribute(prim, name, value_type, value=None, connect=None, uniform=False):
        spec = Sdf.AttributeSpec(prim, name, value_type,
                                 Sdf.VariabilityUniform if uniform else Sdf.VariabilityVarying)
        if value is not None:
            spec.default = value
        if connect is not None:
            spec.connectionPathList.explicitItems = [Sdf.Path(connect)]
        return spec

    attribute(reader, "info:id", Sdf.ValueTypeNames.Token, "UsdPrimvarReader_float3", uniform=True)
    attribute(reader, "inputs:varname", Sdf.ValueTypeNames.String, "displayColor")
    attribute(reader, "inputs:fallback", Sdf.ValueTypeNames.Float3, CLEAN_COLOR)
    attribute(reader, "outputs:result", Sdf.ValueTypeNames.Float3)
    attribute(surface, "info:id", Sdf.ValueTypeNames.Token, "UsdPreviewSurface", uniform=True)
    attribute(surface, "inputs:diffuseColor", Sdf.ValueTypeNames.Color3f,
              connect=f"{reader.path}.outputs:result")
    attribute(surface, "inputs:roughness", Sdf.ValueTypeNames.Float, REVIEW_ROUGHNESS)
    attribute(surface, "outputs:surface", Sdf.ValueTypeNames.Token)
    attribute(material, "outputs:surface", Sdf.ValueTypeNames.Token, connect=f"{surface.path}.outputs:surface")


def _result_prim(mesh) -> str:
    """The prim a mesh's results are written on (and that other meshes' contactsWith target)."""
    return getattr(mesh, "instancer", None) or mesh.path


def _instance_count(stage, instancer: str, time: float, fallback: int) -> int:
    from pxr import UsdGeom

    prim = stage.GetPrimAtPath(instancer) if stage is not None else None
    indices = UsdGeom.PointInstancer(prim).GetProtoIndicesAttr().Get(time) if prim else None
    return max(len(indices) if indices is not None else 0, fallback)


def _author_instancer(layer, shot, instancer: str, indices: Sequence[int], table, targets) -> None:
    """Per-instance first contact times and instancer-level totals (module docstring)."""
    from pxr import Sdf, Vt

    meshes = [shot.meshes[i] for i in indices]
    count = _instance_count(shot.stage, instancer, float(meshes[0].times[0]),
                            max(mesh.instance_index for mesh in meshes) + 1)
    first = np.full(count, np.inf)
    touched = set()
    for index, mesh in zip(indices, meshes):
        rows = (table.mesh_a == index) | (table.mesh_b == index)
        if rows.any():
            first[mesh.instance_index] = min(first[mesh.instance_index], float(table.time[rows].min()))
        touched.update(targets[i] for i in touched_meshes(table, index).tolist())
    first[np.isinf(first)] = np.nan
    for instance_path in _enclosing_instances(shot.stage, instancer):
        instance = Sdf.CreatePrimInLayer(layer, Sdf.Path(instance_path))
        instance.specifier = Sdf.SpecifierOver
        instance.instanceable = False
    spec = Sdf.CreatePrimInLayer(layer, Sdf.Path(instancer))
    spec.specifier = Sdf.SpecifierOver
    times = Sdf.AttributeSpec(spec, ATTR_INSTANCE_FIRST_CONTACT_TIME, Sdf.ValueTypeNames.DoubleArray,
                              declaresCustom=True)
    times.default = Vt.DoubleArray.FromNumpy(first)
    touching = Sdf.AttributeSpec(spec, ATTR_CONTACT_INSTANCE_COUNT, Sdf.ValueTypeNames.Int, declaresCustom=True)
    touching.default = int((~np.isnan(first)).sum())
    relationship = Sdf.RelationshipSpec(spec, REL_CONTACTS_WITH, custom=True)
    relationship.targetPathList.explicitItems = [Sdf.Path(other) for other in sorted(touched)]
    if not np.isnan(first).all():
        earliest = Sdf.AttributeSpec(spec, ATTR_FIRST_CONTACT_TIME, Sdf.ValueTypeNames.Double, declaresCustom=True)
        earliest.default = float(np.nanmin(first))


def _enclosing_instances(stage, prim_path: str):
    """Paths of the instances a mesh lives under (outermost first), so their overs can take effect."""
    prim = stage.GetPrimAtPath(prim_path) if stage is not None else None
    found = []
    while prim and prim.IsInstanceProxy():
        prim = prim.GetParent()
        if prim.IsInstance():
            found.append(str(prim.GetPath()))
    return list(reversed(found))


def _same_topology_everywhere(segments, index: int) -> bool:
    reference = segments[0][1].meshes[index]
    for _, segment_shot, _ in segments[1:]:
        other = segment_shot.meshes[index]
        if (other.face_count != reference.face_count or not np.array_equal(other.triangles, reference.triangles)
                or not np.array_equal(other.triangle_face, reference.triangle_face)):
            return False
    return True


def override_layer_name(shot_path: Union[str, os.PathLike], binary: bool = False) -> str:
    return f"{shot_stem(shot_path)}{BINARY_SUFFIX if binary else TEXT_SUFFIX}"


def shot_stem(shot_path: Union[str, os.PathLike]) -> str:
    """``shot.usd`` -> ``shot``; ``shot.usdc`` -> ``shot``; the package-relative ``pkg.usdz[scene.usdc]`` ->
    ``pkg.scene``."""
    text = os.fspath(shot_path)
    if text.endswith("]") and "[" in text:
        package, inner = text[:-1].split("[", 1)
        return f"{Path(package).stem}.{Path(inner).stem}"
    return Path(text).stem


__all__ = ["OverrideLayer", "override_layer", "provenance_data", "color_sample_times", "build_override_layer", "face_first_contact_times", "touched_meshes", "relative_sublayer_path",
           "override_layer_name", "shot_stem"]
