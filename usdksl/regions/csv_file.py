"""regions.csv: one line per contact region (docs/contracts.md, Regions).

Columns, in this order: ``region,prim_a,prim_b,kind,first_time,last_time,first_frame,last_frame,
face_pairs,max_depth,max_depth_time,center_x,center_y,center_z`` then ``depth_measure,max_depth_frame,
max_intersection_length,min_x,min_y,min_z,max_x,max_y,max_z,faces_a,faces_b`` (faces_a, faces_b: how many
authored faces of each side the region holds) and, with a baseline, ``baseline`` (new or known). Rows in
region id order. Times in time codes, frames by the stage's clock, lengths in scene units (world space).
"""

from __future__ import annotations

from typing import List, Optional

import numpy as np

from ..clock import StageClock
from ..contacts.csv_file import KNOWN, NEW, STATUS_COLUMN
from ..contacts.table import KIND_INTER, KIND_SELF
from ..unmasked import distinct_sorted
from .table import RegionTable

#: The columns every regions.csv starts with, in this order.
REGION_COLUMNS = ("region", "prim_a", "prim_b", "kind", "first_time", "last_time", "first_frame", "last_frame",
                  "face_pairs", "max_depth", "max_depth_time", "center_x", "center_y", "center_z")
#: The columns that follow them.
REGION_DETAIL_COLUMNS = ("depth_measure", "max_depth_frame", "max_intersection_length", "min_x", "min_y", "min_z",
                         "max_x", "max_y", "max_z", "faces_a", "faces_b")
#: The JSON report's lists of each region's faces on side a and side b (regions.csv has their counts).
FACE_LIST_KEYS = ("face_ids_a", "face_ids_b")


def region_faces(regions: RegionTable, faces: np.ndarray) -> List[np.ndarray]:
    """Per region, the sorted distinct authored faces of one side (``faces``: the table's face_a or face_b
    column, one per contact row)."""
    stride = int(faces.max(initial=0)) + 1
    keys = distinct_sorted(regions.row_region.astype(np.int64) * stride + faces.astype(np.int64))
    bounds = np.searchsorted(keys // stride, np.arange(1, regions.count))
    return np.split(keys % stride, bounds)


def region_records(regions: RegionTable, table, clock: StageClock, known: Optional[np.ndarray] = None,
                   with_face_lists: bool = False) -> List[dict]:
    """One dict per region (the regions.csv columns, in id order); ``known`` bool per contact row. With
    ``with_face_lists`` (the JSON report) also the faces of each side (FACE_LIST_KEYS)."""
    if regions.count == 0:
        return []
    names = np.array(table.mesh_names(), dtype=object)
    faces_a, faces_b = region_faces(regions, table.face_a), region_faces(regions, table.face_b)
    status = None if known is None else regions.known_regions(known)
    columns = {
        "region": regions.ids.tolist(), "prim_a": names[regions.mesh_a].tolist(),
        "prim_b": names[regions.mesh_b].tolist(),
        "kind": np.where(regions.is_self, KIND_SELF, KIND_INTER).tolist(),
        "first_time": regions.first_time.tolist(), "last_time": regions.last_time.tolist(),
        "first_frame": clock.frames(regions.first_time).tolist(), "last_frame": clock.frames(regions.last_time).tolist(),
        "face_pairs": regions.face_pairs.tolist(), "max_depth": regions.max_depth.tolist(),
        "max_depth_time": regions.max_depth_time.tolist(),
        "center_x": regions.center[:, 0].tolist(), "center_y": regions.center[:, 1].tolist(),
        "center_z": regions.center[:, 2].tolist(), "depth_measure": regions.depth_measure.tolist(),
        "max_depth_frame": clock.frames(regions.max_depth_time).tolist(),
        "max_intersection_length": regions.max_intersection_length.tolist(),
        "min_x": regions.box_min[:, 0].tolist(), "min_y": regions.box_min[:, 1].tolist(),
        "min_z": regions.box_min[:, 2].tolist(), "max_x": regions.box_max[:, 0].tolist(),
        "max_y": regions.box_max[:, 1].tolist(), "max_z": regions.box_max[:, 2].tolist(),
        "faces_a": [len(faces) for faces in faces_a], "faces_b": [len(faces) for faces in faces_b],
    }
    if status is not None:
        columns[STATUS_COLUMN] = np.where(status, KNOWN, NEW).tolist()
    if with_face_lists:
        columns[FACE_LIST_KEYS[0]] = [faces.tolist() for faces in faces_a]
        columns[FACE_LIST_KEYS[1]] = [faces.tolist() for faces in faces_b]
    keys = list(columns)
    return [dict(zip(keys, values)) for values in zip(*(columns[key] for key in keys))]


def regions_csv(regions: RegionTable, table, clock: StageClock, known: Optional[np.ndarray] = None) -> str:
    """regions.csv: the header, then one line per region in id order (numbers as repr, so they read back
    exactly); ``known`` (bool per contact row, from a baseline) adds the ``baseline`` column."""
    header = REGION_COLUMNS + REGION_DETAIL_COLUMNS + ((STATUS_COLUMN,) if known is not None else ())
    lines = [",".join(header)]
    for record in region_records(regions, table, clock, known):
        lines.append(",".join(value if isinstance(value, str) else repr(value)
                              for value in (record[column] for column in header)))
    return "\n".join(lines) + "\n"

