"""The ``<stem>.usdksl.usda`` override layer: the results of a check written back into USD.

The layer sublayers the input by a relative path (so the pair of files can move together) and copies the
input's stage metadata (timeCodesPerSecond, framesPerSecond, start/end time codes, upAxis,
metersPerUnit, defaultPrim): without them the sublayered cache's samples would be rescaled (docs/contracts.md,
Outputs). It only authors ``over`` opinions; the input file is never opened for writing.

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
``color3f[] primvars:displayColor`` (interpolation uniform)
    red for faces that touch, neutral grey for the others, so usdview shows where. Any
    ``primvars:displayColor:indices`` the input authors is blocked, or it would re-index the colours.

Meshes inside instances are made visible to these opinions by authoring ``instanceable = false`` on
their instances in this layer (the input keeps its instancing).

PointInstancer instances (``/World/scatter[3]/box``, :mod:`usdksl.instancing`) are not prims, and all
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
from pathlib import Path
from typing import Dict, Iterable, Optional, Sequence, Union

import numpy as np

CONTACT_COLOR = (1.0, 0.1, 0.1)
CLEAN_COLOR = (0.6, 0.6, 0.6)

ATTR_FIRST_CONTACT_TIME = "usdksl:firstContactTime"
ATTR_CONTACT_FACE_COUNT = "usdksl:contactFaceCount"
REL_CONTACTS_WITH = "usdksl:contactsWith"
ATTR_INSTANCE_FIRST_CONTACT_TIME = "usdksl:instanceFirstContactTime"
ATTR_CONTACT_INSTANCE_COUNT = "usdksl:contactInstanceCount"
PRIMVAR_FIRST_CONTACT_TIME = "primvars:usdksl:firstContactTime"
PRIMVAR_DISPLAY_COLOR = "primvars:displayColor"

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
    return np.unique(other)


def build_override_layer(shot, checked_meshes: Iterable[int], table,
                         layer_path: Union[str, os.PathLike], segments: Optional[Sequence[tuple]] = None) -> str:
    """The override layer's usda text for ``shot`` (usdksl.loader.Shot) and its ContactTable.

    ``checked_meshes``: indices into shot.meshes that took part in at least one checked pair.
    ``layer_path``: where the layer will live (only its directory matters, for the relative sublayer).
    ``segments``: for a shot checked in constant-topology stretches (usdksl.segments), a list of
    ((start, end), segment Shot, segment ContactTable). A mesh whose topology differs between segments gets
    its per-face primvars as time samples at each segment's start and end (held within the segment, one
    value per face of the topology in force); the mesh-level values cover all segments, and
    ``usdksl:contactFaceCount`` then adds up the touching faces of every segment.
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

    paths = [mesh.path for mesh in shot.meshes]
    targets = [_result_prim(mesh) for mesh in shot.meshes]
    instancers: Dict[str, list] = {}
    for index in sorted(set(int(i) for i in checked_meshes), key=paths.__getitem__):
        mesh = shot.meshes[index]
        if getattr(mesh, "instancer", None):
            instancers.setdefault(mesh.instancer, []).append(index)
            continue
        # (time range or None for the default value, face times) per authored value
        if segments and len(segments) > 1 and not _same_topology_everywhere(segments, index):
            values = [(span, face_first_contact_times(segment_table, index, segment_shot.meshes[index].face_count))
                      for span, segment_shot, segment_table in segments]
        else:
            values = [(None, face_first_contact_times(table, index, mesh.face_count))]
        touching_faces = sum(int((~np.isnan(times)).sum()) for _, times in values)
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
        for span, face_times in values:
            colors = np.where(~np.isnan(face_times)[:, None], np.array(CONTACT_COLOR, np.float32),
                              np.array(CLEAN_COLOR, np.float32)).astype(np.float32)
            if span is None:
                primvar.default = Vt.DoubleArray.FromNumpy(face_times)
                display.default = Vt.Vec3fArray.FromNumpy(colors)
                continue
            for time in sorted(set(span)):
                layer.SetTimeSample(primvar.path, float(time), Vt.DoubleArray.FromNumpy(face_times))
                layer.SetTimeSample(display.path, float(time), Vt.Vec3fArray.FromNumpy(colors))
        if _input_authors(shot.stage, mesh.path, PRIMVAR_DISPLAY_COLOR + ":indices"):
            indices = Sdf.AttributeSpec(spec, PRIMVAR_DISPLAY_COLOR + ":indices", Sdf.ValueTypeNames.IntArray)
            indices.default = Sdf.ValueBlock()
    for instancer, indices in sorted(instancers.items()):
        _author_instancer(layer, shot, instancer, indices, table, targets)
    return layer.ExportToString()


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


def _input_authors(stage, prim_path: str, attribute_name: str) -> bool:
    prim = stage.GetPrimAtPath(prim_path) if stage is not None else None
    if not prim:
        return False
    attribute = prim.GetAttribute(attribute_name)
    return bool(attribute) and (attribute.HasAuthoredValue() or attribute.GetNumTimeSamples() > 0)


def override_layer_name(shot_path: Union[str, os.PathLike]) -> str:
    return f"{shot_stem(shot_path)}.usdksl.usda"


def shot_stem(shot_path: Union[str, os.PathLike]) -> str:
    """``shot.usd`` -> ``shot``; ``shot.usdc`` -> ``shot``; the package-relative ``pkg.usdz[scene.usdc]`` ->
    ``pkg.scene``."""
    text = os.fspath(shot_path)
    if text.endswith("]") and "[" in text:
        package, inner = text[:-1].split("[", 1)
        return f"{Path(package).stem}.{Path(inner).stem}"
    return Path(text).stem


__all__ = ["build_override_layer", "face_first_contact_times", "touched_meshes", "relative_sublayer_path",
           "override_layer_name", "shot_stem"]
