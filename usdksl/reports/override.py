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
Outputs): ``string version`` (the usdksl that wrote it), ``string shotSha256`` (SHA-256 of the shot's root layer
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

With the check's contact regions (a :class:`~usdksl.regions.table.RegionTable` over the same contact rows,
docs/contracts.md, Regions), every checked mesh that has contacts also gets:

``int[] primvars:usdksl:region`` (interpolation uniform)
    one value per authored face: the id of the region of that face's earliest contact (the contact row
    whose time ``primvars:usdksl:firstContactTime`` holds; of rows at the same time, the first in the
    table's canonical order), **0 for a face in no region** (ids start at 1). Like the first contact times,
    per segment for a mesh whose topology changes;
``int[] usdksl:regions``
    the ids of the regions the mesh is a side of, ascending, and beside it one value per region, in that
    order: ``double[] usdksl:regionFirstFrame``, ``double[] usdksl:regionLastFrame`` (frames on the stage's
    clock, as regions.csv has them), ``double[] usdksl:regionMaxDepth`` (scene units),
    ``token[] usdksl:regionDepthMeasure`` (``penetration`` or ``intersection_length``: what the depth
    measures) and ``string[] usdksl:regionWith`` (the region's other side: a prim path, or an instance
    path such as ``/World/scatter[3]/box``; the mesh itself for a self region).

These are attributes rather than ``customData``: usdview lists a selected prim's attributes with their
values in its attribute view (and shows a whole array in the value viewer), while ``customData`` only
shows as raw metadata text; attributes also keep their types (``Get()`` returns ints and doubles) and
read the same in every DCC. A face the user picks in usdview (its ``primvars:usdksl:region``) is looked up
in ``usdksl:regions`` of its mesh to read when and how deep that problem is.

A PointInstancer's instances share their prototype's faces, so no region is written per face of an
instance: the instancer gets ``int[] usdksl:instanceRegion`` (one value per instance index: the region of
that instance's earliest contact, 0 for none) and the region arrays above over all its instances (in
``usdksl:regionWith`` the side that is not one of its instances; side b when both are).
"""

from __future__ import annotations

import os
import tempfile
from dataclasses import dataclass
from pathlib import Path
from typing import Dict, Iterable, List, Optional, Sequence, Tuple, Union

import numpy as np

from ..clock import StageClock
from ..regions.table import FIRST_REGION_ID, RegionTable
from ..unmasked import distinct_sorted

CONTACT_COLOR = (1.0, 0.1, 0.1)
CLEAN_COLOR = (0.6, 0.6, 0.6)

ATTR_FIRST_CONTACT_TIME = "usdksl:firstContactTime"
ATTR_CONTACT_FACE_COUNT = "usdksl:contactFaceCount"
REL_CONTACTS_WITH = "usdksl:contactsWith"
ATTR_INSTANCE_FIRST_CONTACT_TIME = "usdksl:instanceFirstContactTime"
ATTR_CONTACT_INSTANCE_COUNT = "usdksl:contactInstanceCount"
PRIMVAR_FIRST_CONTACT_TIME = "primvars:usdksl:firstContactTime"
PRIMVAR_REGION = "primvars:usdksl:region"
ATTR_REGIONS = "usdksl:regions"
ATTR_REGION_FIRST_FRAME = "usdksl:regionFirstFrame"
ATTR_REGION_LAST_FRAME = "usdksl:regionLastFrame"
ATTR_REGION_MAX_DEPTH = "usdksl:regionMaxDepth"
ATTR_REGION_DEPTH_MEASURE = "usdksl:regionDepthMeasure"
ATTR_REGION_WITH = "usdksl:regionWith"
ATTR_INSTANCE_REGION = "usdksl:instanceRegion"
#: primvars:usdksl:region (and usdksl:instanceRegion) of a face (instance) in no region: region ids start above it.
NO_REGION_ID = FIRST_REGION_ID - 1
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


def face_regions(table, row_ids: np.ndarray, mesh_index: int, face_count: int) -> np.ndarray:
    """int32[face_count]: the region id (``row_ids``, one per row of ``table``) of each face's earliest contact
    as either side of a row, NO_REGION_ID when it never touches. Of rows at that same time the first in the
    table's order wins, so the face's region is the one of the row its first contact time comes from."""
    chosen = [np.flatnonzero(side == mesh_index) for side in (table.mesh_a, table.mesh_b)]
    rows = np.concatenate(chosen)
    faces = np.concatenate([table.face_a[chosen[0]], table.face_b[chosen[1]]]).astype(np.int64)
    return _earliest_region(faces, rows, table, row_ids, face_count)


def _earliest_region(keys: np.ndarray, rows: np.ndarray, table, row_ids: np.ndarray, count: int) -> np.ndarray:
    """int32[count]: for each key (a face, an instance) the region id of its earliest row among ``rows`` (one
    key per row), of rows at the same time the first in the table's order; NO_REGION_ID for a key with none."""
    result = np.full(count, NO_REGION_ID, np.int32)
    if rows.size:
        order = np.lexsort((rows, table.time[rows], keys))
        keys, rows = keys[order], rows[order]
        first = np.flatnonzero(np.concatenate([[True], keys[1:] != keys[:-1]]))
        result[keys[first]] = np.asarray(row_ids)[rows[first]]
    return result


def segment_row_ids(segments: Sequence[tuple], row_ids: np.ndarray) -> List[np.ndarray]:
    """Per segment ((range, Shot, ContactTable) as :func:`override_layer` takes them), int64[rows of its
    table]: the region id of each row, given ``row_ids`` per row of the shot's one table. That table is
    :meth:`ContactTable.concatenate` of the segments' tables over their topology epochs, which keeps a face
    pair found again in a later segment with the same faces once, at its first row: the same grouping is
    made here, so a row that was merged away takes the region of the row that was kept."""
    from ..reading.segments import topology_epochs

    tables = [segment_table for _, _, segment_table in segments]
    counts = [segment_table.count for segment_table in tables]
    row_ids = np.asarray(row_ids, dtype=np.int64)
    if not sum(counts):
        return [np.zeros(0, np.int64) for _ in tables]
    epochs = topology_epochs([segment_shot for _, segment_shot, _ in segments])
    piece = np.repeat(np.arange(len(tables)), counts)
    mesh_a = np.concatenate([segment_table.mesh_a for segment_table in tables]).astype(np.int64)
    mesh_b = np.concatenate([segment_table.mesh_b for segment_table in tables]).astype(np.int64)
    face_a = np.concatenate([segment_table.face_a for segment_table in tables]).astype(np.int64)
    face_b = np.concatenate([segment_table.face_b for segment_table in tables]).astype(np.int64)
    key = np.stack([mesh_a, face_a, epochs[piece, mesh_a], mesh_b, face_b, epochs[piece, mesh_b]], axis=1)
    _, first, group = np.unique(key, axis=0, return_index=True, return_inverse=True)
    kept = np.sort(first)           # the one table's rows: the first row of each group, in segment order
    if kept.size != row_ids.size:
        raise ValueError(f"the regions are of a table of {row_ids.size} rows, the segments make {kept.size}")
    joined_row = np.searchsorted(kept, first)[group.reshape(-1)]
    return np.split(row_ids[joined_row], np.cumsum(counts)[:-1])


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


def provenance_data(shot_sha256: str, settings: dict, version: str) -> dict:
    """The ``usdksl`` customLayerData dictionary (module docstring): the usdksl ``version`` that wrote the layer,
    the shot's hash and the check's settings (CheckOptions.settings()), only values a USD dictionary can hold."""
    return {"version": str(version), "shotSha256": str(shot_sha256), "settings": _usd_dictionary(settings)}


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
                   span: Optional[Tuple[float, float]] = None, provenance: Optional[dict] = None,
                   regions: Optional[RegionTable] = None, clock: Optional[StageClock] = None) -> OverrideLayer:
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
    ``regions``: the check's :class:`~usdksl.regions.table.RegionTable` over the rows of ``table`` (the one
    table of all segments); None: no region is written and the layer is what it was without regions.
    """
    from pxr import Sdf, Vt

    row_ids = None
    segment_ids: Optional[List[np.ndarray]] = None   # region id per row of each segment's table, when needed
    if regions is not None:
        if regions.row_region.shape[0] != table.count:
            raise ValueError(f"regions of {regions.row_region.shape[0]} contact rows for a table of {table.count}")
        row_ids = regions.row_ids

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
    if regions is not None and clock is None:   # the region arrays' frames: the shot's clock
        clock = StageClock.from_metadata(shot.metadata)
    instancers: Dict[str, list] = {}
    elements = 0
    reviewed = []
    for index in sorted(set(int(i) for i in checked_meshes), key=paths.__getitem__):
        mesh = shot.meshes[index]
        if getattr(mesh, "instancer", None):
            instancers.setdefault(mesh.instancer, []).append(index)
            continue
        # (time range, face times, whether the range is one segment of several) per authored value
        segmented = bool(segments and len(segments) > 1 and not _same_topology_everywhere(segments, index))
        if segmented:
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
        if regions is not None and rows.any():
            if segmented:
                segment_ids = segment_ids if segment_ids is not None else segment_row_ids(segments, row_ids)
                face_values = [(segment_span, face_regions(segment_table, ids, index,
                                                           segment_shot.meshes[index].face_count))
                               for (segment_span, segment_shot, segment_table), ids in zip(segments, segment_ids)]
            else:
                face_values = [(None, face_regions(table, row_ids, index, mesh.face_count))]
            elements += _author_face_regions(spec, face_values)
            elements += _author_region_list(spec, [index], regions, clock, paths)
        reviewed.append(spec)
        _bind_review_material(spec, _material_subsets(shot.stage, mesh.path))
    if reviewed:
        _define_review_material(layer)
    for instancer, indices in sorted(instancers.items()):
        elements += _author_instancer(layer, shot, instancer, indices, table, targets, regions, paths, clock)
    return OverrideLayer(layer=layer, array_elements=elements)


def _author_face_regions(spec, face_values: Sequence[tuple]) -> int:
    """primvars:usdksl:region from [(segment range or None, int32[F] region per face)]: the default value, or
    for a mesh whose topology changes a sample at each end of every segment, as the first contact times.
    Returns the array elements authored."""
    from pxr import Sdf, Vt

    primvar = Sdf.AttributeSpec(spec, PRIMVAR_REGION, Sdf.ValueTypeNames.IntArray)
    primvar.SetInfo("interpolation", "uniform")
    elements = 0
    for segment_span, face_ids in face_values:
        value = Vt.IntArray.FromNumpy(np.ascontiguousarray(face_ids, dtype=np.int32))
        if segment_span is None:
            primvar.default = value
            elements += face_ids.size
            continue
        for time in sorted(set(segment_span)):
            spec.layer.SetTimeSample(primvar.path, float(time), value)
            elements += face_ids.size
    return elements


def _author_region_list(spec, own: Sequence[int], regions: RegionTable, clock: StageClock,
                        paths: Sequence[str]) -> int:
    """usdksl:regions and the per-region arrays beside it (module docstring) for the regions that a mesh of
    ``own`` (indices into the shot's meshes) is a side of. Returns the array elements authored."""
    from pxr import Sdf, Vt

    mine_a, mine_b = np.isin(regions.mesh_a, own), np.isin(regions.mesh_b, own)
    chosen = np.flatnonzero(mine_a | mine_b)           # ascending rows: ascending ids
    other = np.where(mine_a[chosen], regions.mesh_b[chosen], regions.mesh_a[chosen])
    names = np.array(list(paths), dtype=object)
    values = ((ATTR_REGIONS, Sdf.ValueTypeNames.IntArray, Vt.IntArray.FromNumpy(
                  regions.ids[chosen].astype(np.int32))),
              (ATTR_REGION_FIRST_FRAME, Sdf.ValueTypeNames.DoubleArray, Vt.DoubleArray.FromNumpy(
                  np.asarray(clock.frames(regions.first_time[chosen]), dtype=np.float64))),
              (ATTR_REGION_LAST_FRAME, Sdf.ValueTypeNames.DoubleArray, Vt.DoubleArray.FromNumpy(
                  np.asarray(clock.frames(regions.last_time[chosen]), dtype=np.float64))),
              (ATTR_REGION_MAX_DEPTH, Sdf.ValueTypeNames.DoubleArray, Vt.DoubleArray.FromNumpy(
                  np.asarray(regions.max_depth[chosen], dtype=np.float64))),
              (ATTR_REGION_DEPTH_MEASURE, Sdf.ValueTypeNames.TokenArray, Vt.TokenArray(
                  [str(measure) for measure in regions.depth_measure[chosen].tolist()])),
              (ATTR_REGION_WITH, Sdf.ValueTypeNames.StringArray, Vt.StringArray(
                  [str(name) for name in names[other].tolist()])))
    for name, value_type, value in values:
        attribute = Sdf.AttributeSpec(spec, name, value_type, declaresCustom=True)
        attribute.default = value
    return len(values) * int(chosen.size)


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


def _author_instancer(layer, shot, instancer: str, indices: Sequence[int], table, targets,
                      regions: Optional[RegionTable] = None, paths: Sequence[str] = (),
                      clock: Optional[StageClock] = None) -> int:
    """Per-instance first contact times and instancer-level totals (module docstring); with ``regions`` the
    region of each instance's first contact and the instancer's region arrays. Returns the array elements
    authored with regions (the rest is not counted, as before regions)."""
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
    if regions is None or np.isnan(first).all():
        return 0
    instance_regions = _instance_regions(table, regions.row_ids, indices, [mesh.instance_index for mesh in meshes],
                                         count)
    per_instance = Sdf.AttributeSpec(spec, ATTR_INSTANCE_REGION, Sdf.ValueTypeNames.IntArray, declaresCustom=True)
    per_instance.default = Vt.IntArray.FromNumpy(instance_regions)
    return count + _author_region_list(spec, list(indices), regions, clock, paths)


def _instance_regions(table, row_ids: np.ndarray, indices: Sequence[int], instance_indices: Sequence[int],
                      count: int) -> np.ndarray:
    """int32[count]: per instance index the region id of the earliest contact of any of its meshes (shot
    mesh ``indices``, instance ``instance_indices``), NO_REGION_ID for an instance that never touches; of rows
    at the same time the first in the table's order."""
    instance_of = np.full(max(indices) + 1, -1, np.int64)
    instance_of[np.asarray(indices, dtype=np.int64)] = np.asarray(instance_indices, dtype=np.int64)
    rows = np.concatenate([np.flatnonzero(np.isin(side, indices)) for side in (table.mesh_a, table.mesh_b)])
    instances = np.concatenate([instance_of[table.mesh_a[np.isin(table.mesh_a, indices)]],
                                instance_of[table.mesh_b[np.isin(table.mesh_b, indices)]]])
    return _earliest_region(instances, rows, table, row_ids, count)


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
           "override_layer_name", "shot_stem", "face_regions", "segment_row_ids"]
