"""Contact regions: the problems a person fixes, each a group of contacting face pairs (docs/contracts.md,
Regions).

A :class:`RegionTable` holds one row per region, column by column (numpy arrays, no Python object per
region), and for every row of the check's :class:`~usdksl.contacts.table.ContactTable` the region it
belongs to. A region is the face pairs of one mesh pair that are connected on the meshes (their faces
share a vertex, on either side) and overlap in time (see :func:`usdksl.regions.grouping.group_regions`).
Regions are numbered from 1 in the order of their earliest contact row: the canonical row order of the
contact table, so the numbers are the same on every run of the same shot and settings.

Depth (:mod:`usdksl.regions.depth`): at the measured samples of a region's span (its first and last, and
the samples on whole frames between them), how far one surface goes through the other. Where a side is a
closed (watertight) mesh it is the penetration depth: the largest distance from that mesh's surface of a
point of the other mesh's region faces inside it (scene units). Where neither side is closed (cloth on
cloth, a self region) it is the length of the two surfaces' intersection curve within the region (scene
units). ``depth_measure`` says which.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import List, Optional, Sequence

import numpy as np

from ..unmasked import distinct_sorted

#: depth_measure of a region with a closed side: penetration depth into the closed mesh.
PENETRATION = "penetration"
#: depth_measure of a region with no closed side: length of the intersection curve.
INTERSECTION_LENGTH = "intersection_length"
#: Region ids start here (id = row index + FIRST_REGION_ID).
FIRST_REGION_ID = 1
#: row_region of a contact row that belongs to no region (never in a finished table).
NO_REGION = -1


@dataclass
class DepthSamples:
    """Depth at the measured samples of each region's span (:mod:`usdksl.regions.depth`): one row per
    (region, measured sample), sorted by region, then time. Lengths in scene units, times in time codes."""

    region: np.ndarray               # int32[S], row index into the RegionTable
    time: np.ndarray                 # float64[S]
    penetration: np.ndarray          # float64[S]; NaN where neither side is closed
    intersection_length: np.ndarray  # float64[S]; length of the intersection curve at that sample
    box_min: np.ndarray              # float64[S, 3]; world-space box of the intersection at that sample
    box_max: np.ndarray              # float64[S, 3]; (NaN rows where nothing intersects at that sample)

    @property
    def count(self) -> int:
        return int(self.time.shape[0])


@dataclass
class RegionTable:
    """One row per region of a check, plus the region of each contact row."""

    paths: Optional[List[str]]
    mesh_a: np.ndarray            # int32[R], index into paths (canonical side a, as the contact rows)
    mesh_b: np.ndarray            # int32[R]
    first_time: np.ndarray        # float64[R]: the continuous first contact of its earliest face pair
    last_time: np.ndarray         # float64[R]: the last sample at which it is still in contact (>= first_time);
                                  #   with last contacts, the latest continuous last contact of its face pairs
    face_pairs: np.ndarray        # int64[R]
    depth_measure: np.ndarray     # object[R]: PENETRATION or INTERSECTION_LENGTH
    max_depth: np.ndarray         # float64[R]: largest depth over its measured samples (0 when nothing crosses
                                  #   at any of them)
    max_depth_time: np.ndarray    # float64[R]: the measured sample where it is largest (first_time when it is 0)
    max_intersection_length: np.ndarray  # float64[R]
    center: np.ndarray            # float64[R, 3]: world-space centre of box_min..box_max
    box_min: np.ndarray           # float64[R, 3]: world-space box of the region at max_depth_time
    box_max: np.ndarray           # float64[R, 3]
    row_region: np.ndarray        # int32[C]: per contact row, its region's row index here
    samples: Optional[DepthSamples] = None

    @property
    def count(self) -> int:
        return int(self.first_time.shape[0])

    def __len__(self) -> int:
        return self.count

    @property
    def ids(self) -> np.ndarray:
        """int64[R]: the stable region ids written in the reports."""
        return np.arange(self.count, dtype=np.int64) + FIRST_REGION_ID

    @property
    def row_ids(self) -> np.ndarray:
        """int64[C]: the region id of each contact row."""
        return self.row_region.astype(np.int64) + FIRST_REGION_ID

    @property
    def is_self(self) -> np.ndarray:
        return self.mesh_a == self.mesh_b

    def faces(self, region: int, table) -> tuple:
        """(faces of mesh_a, faces of mesh_b) of region row ``region`` (its contact rows in ``table``): sorted
        unique authored faces (for a self region both sides are faces of the one mesh)."""
        rows = np.flatnonzero(self.row_region == region)
        return distinct_sorted(table.face_a[rows]), distinct_sorted(table.face_b[rows])

    def known_regions(self, known: np.ndarray) -> np.ndarray:
        """bool[R]: a region is known when every one of its contact rows is (``known`` bool per contact row,
        from a contacts or a region baseline): the regions.csv ``baseline`` column."""
        unknown = np.zeros(self.count, bool)
        rows = (~np.asarray(known, bool)) & (self.row_region != NO_REGION)
        unknown[self.row_region[rows]] = True
        return ~unknown

    def worst_first(self) -> np.ndarray:
        """int64[R]: region rows worst first: penetrations (a surface through a closed mesh) by depth, then
        the regions measured by intersection length, by length (the two are different lengths: a 1 cm pass
        into a body outranks a 5 cm crease of cloth through itself); ties by first time, then row."""
        measure_rank = np.where(self.depth_measure == PENETRATION, 0, 1)
        return np.lexsort((np.arange(self.count), self.first_time, -self.max_depth, measure_rank))

    @classmethod
    def empty(cls, paths: Optional[Sequence[str]], contact_rows: int = 0) -> "RegionTable":
        ints = np.zeros(0, np.int32)
        floats = np.zeros(0)
        boxes = np.zeros((0, 3))
        return cls(paths=None if paths is None else list(paths), mesh_a=ints, mesh_b=ints.copy(),
                   first_time=floats, last_time=floats.copy(), face_pairs=np.zeros(0, np.int64),
                   depth_measure=np.zeros(0, object), max_depth=floats.copy(), max_depth_time=floats.copy(),
                   max_intersection_length=floats.copy(), center=boxes, box_min=boxes.copy(),
                   box_max=boxes.copy(), row_region=np.full(contact_rows, NO_REGION, np.int32))
