"""How deep each region goes, at every sample of its span: the length of its intersection curve, the
penetration depth into a closed side, and where.

For each region, at each sample from the first sample at or after its earliest row to the last sample of its
rows' spans (:mod:`.grouping`):

* ``intersection_length``: the summed length of the segments where a triangle of a row's face_a crosses a
  triangle of its face_b (each face pair once; the thickness plays no part; coplanar overlaps add 0; a segment
  along an edge lying in the other surface is found by both triangles of that edge, each counting half; for a
  mesh with itself, triangles sharing an edge, or meeting only at a shared corner, add nothing);
* ``penetration``, for a region of two meshes at least one of which is closed (:mod:`.closed`): for a closed
  side X and the other side Y, the largest distance to X's whole surface of a point of Y's region faces (the
  faces of Y the region's rows name) that lies inside X; the larger of the two when both are closed; NaN for a
  self region and when neither side is closed. Every point of the faces counts, not only their vertices: cloth
  draped over a table edge cuts the box with every cloth vertex outside. The depth d reported satisfies
  d <= true depth <= d + DEPTH_RELATIVE_ACCURACY x the longest edge of the Y triangle where the deepest point
  lies (plus the rounding of the distance arithmetic): a branch and bound over each triangle, the inside
  test by the angle-weighted pseudonormal of the closest surface feature (usdksl/regions/closed_surface.hpp in
  the native core says why);
* ``box_min``, ``box_max``: the world-space box of the intersection segments' endpoints and of the inside
  points the depth search found; NaN rows where there are none.

Only the regions' own samples are evaluated, one sample per thread at a time.
"""

from __future__ import annotations

from typing import Optional, Sequence

import numpy as np

from .. import _native
from ..checking.collision import default_threads, mesh_arrays
from .grouping import Grouping, contact_columns
from .table import DepthSamples

#: Accuracy of the penetration depth, as a fraction of the longest edge of the penetrating triangle where the
#: deepest point lies (dimensionless; the native core's DEPTH_RELATIVE_ACCURACY).
DEPTH_RELATIVE_ACCURACY = float(_native.DEPTH_RELATIVE_ACCURACY)


def region_depths(meshes: Sequence, table, grouping: Grouping, sample_times: np.ndarray, closed: np.ndarray,
                  threads: Optional[int] = None) -> DepthSamples:
    """The depth samples of every region of ``grouping`` (see the module), one row per (region, sample), sorted
    by region, then time. ``sample_times``: the grouping's sample times; ``closed``: bool per mesh
    (:func:`usdksl.regions.closed.closed_meshes`). ``threads`` (default: every core this process may run on)
    splits the samples; the answer does not depend on it."""
    sample_times = np.ascontiguousarray(sample_times, dtype=np.float64).reshape(-1)
    closed = np.ascontiguousarray(closed, dtype=bool).reshape(-1)
    threads = default_threads() if threads is None else int(threads)
    span = np.asarray(grouping.row_span).reshape(-1, 2)
    raw = _native.region_depths(mesh_arrays(meshes), *contact_columns(table),
                                np.ascontiguousarray(grouping.row_region, dtype=np.int32),
                                np.ascontiguousarray(span[:, 1], dtype=np.int32), int(grouping.region_count),
                                sample_times, closed, max(threads, 1))
    return DepthSamples(region=raw["region"], time=sample_times[raw["sample"]], penetration=raw["penetration"],
                        intersection_length=raw["intersection_length"], box_min=raw["box_min"],
                        box_max=raw["box_max"])
