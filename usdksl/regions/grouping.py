"""Contact rows grouped into regions: the face pairs of one mesh pair that are connected on the meshes and
overlap in time.

A person fixes a poke-through, not 400 face pairs: the rows of one problem share vertices (the cloth faces
around a collider's corner, the collider faces under the cloth) and happen together. Two rows of one mesh pair
are in one region when a face of one shares a vertex with a face of the other (on side a, on side b, or, for a
mesh with itself, on any side; a face shares its vertices with itself) and their spans in sample steps
intersect; regions are the connected components.

A row's span is [i0, i1]: i0 the last sample at or before its time (0 when none), i1 = max(i0 + 1, the sample of
its last sampled contact), at most the last sample, so contacts in consecutive steps overlap. The last sampled
contact: when the row's faces are in contact at s0, the first sample at or after its time (a triangle of one
within ``thickness`` of a triangle of the other, the check's static test), the last sample of the run from s0
on during which they stay in contact; otherwise (a graze, gone by the next sample) the row's own time.

Because a shared vertex joins, one large face joins everything on it at the same time: a table top of two
triangles touched by the cloth at two far-apart places at once is one region, the same places on a finely
tessellated top are two (unless the cloth faces touching them share vertices). The same place touched again
after its first contacts have ended starts a new region.

The native core does the work (contact walks on threads, then a union-find in which each vertex's rows,
in span order, join the row that reaches furthest so far: no pair of rows is compared directly).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Optional, Sequence

import numpy as np

from .. import _native
from ..checking.collision import default_threads, mesh_arrays


@dataclass
class Grouping:
    """The region of each contact row and the spans it was grouped by."""

    row_region: np.ndarray        # int32[C]: 0..region_count-1, numbered in the order of each region's first row
    region_count: int
    row_last_sampled: np.ndarray  # float64[C]: last sample still in contact (time codes); a graze's own time
    row_span: np.ndarray          # int32[C, 2]: first and last sample index (into sample_times) of the row's span


def contact_columns(table) -> tuple:
    """The table's (time, mesh_a, face_a, mesh_b, face_b) as the core reads them."""
    return (np.ascontiguousarray(table.time, dtype=np.float64), np.ascontiguousarray(table.mesh_a, dtype=np.int32),
            np.ascontiguousarray(table.face_a, dtype=np.int32), np.ascontiguousarray(table.mesh_b, dtype=np.int32),
            np.ascontiguousarray(table.face_b, dtype=np.int32))


def group_regions(meshes: Sequence, table, sample_times: np.ndarray, thickness: float,
                  threads: Optional[int] = None) -> Grouping:
    """Regions of the rows of ``table`` (a ContactTable of ``meshes``; see the module for the rules).

    ``sample_times``: float64[S], sorted, the check's sample times (the union of the meshes' sample times in the
    checked range); ``thickness``: the check's contact distance (scene units). ``threads`` (default: every core
    this process may run on) splits the contact walks; the answer does not depend on it.
    """
    sample_times = np.ascontiguousarray(sample_times, dtype=np.float64).reshape(-1)
    threads = default_threads() if threads is None else int(threads)
    raw = _native.group_regions(mesh_arrays(meshes), *contact_columns(table), sample_times, float(thickness),
                                max(threads, 1))
    return Grouping(row_region=raw["row_region"], region_count=int(raw["region_count"]),
                    row_last_sampled=raw["row_last_sampled"],
                    row_span=np.stack([raw["row_span_first"], raw["row_span_last"]], axis=1).astype(np.int32))
