"""How deep each region goes, at the samples of its span a person looks at: the length of its intersection
curve, the penetration depth into a closed side, and where.

A region's span runs from the first sample at or after its earliest row to the last sample of its rows' spans
(:mod:`.grouping`). It is measured at its first and last samples and, between them, at the samples
:func:`depth_sample_flags` flags: those on whole frames of the stage's clock, and a sample between frames only
where the whole frame before it is not a sample. People review frames as usdview shows them; sub-frame samples
(motion blur) would cost as much as frames each without changing what a person fixes, while the first and last
samples keep a contact that begins or ends between frames measured there. A deeper moment strictly between two
measured samples is not reported as the region's largest. At each measured sample:

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

Only the regions' own measured samples are evaluated, one sample per thread at a time.
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
#: How far (in frames) a sample's frame may lie from an integer and still be on a whole frame: far below any
#: sub-frame step a cache is written with, far above the rounding of time code x frames per time code.
WHOLE_FRAME_TOLERANCE = 1e-6


def depth_sample_flags(sample_times: np.ndarray, frames_per_time_code: float = 1.0) -> np.ndarray:
    """bool[K]: which of ``sample_times`` (sorted time codes, the samples of one piece) a region's depth is
    measured at between its first and last samples. A sample is flagged when its frame (time code x
    ``frames_per_time_code``, :attr:`usdksl.clock.StageClock.frames_per_time_code`) lies within
    :data:`WHOLE_FRAME_TOLERANCE` of an integer, or when the whole frame just before it (the floor of its frame)
    is no sample: a shot sampled only between frames keeps every sample, one sampled once a frame is
    unchanged."""
    frames = np.asarray(sample_times, dtype=np.float64).reshape(-1) * float(frames_per_time_code)
    nearest = np.round(frames)
    whole = np.abs(frames - nearest) <= WHOLE_FRAME_TOLERANCE
    return whole | ~np.isin(np.floor(frames), nearest[whole])


def region_depths(meshes: Sequence, table, grouping: Grouping, sample_times: np.ndarray, closed: np.ndarray,
                  threads: Optional[int] = None, measured: Optional[np.ndarray] = None) -> DepthSamples:
    """The depth samples of every region of ``grouping`` (see the module), one row per (region, measured
    sample), sorted by region, then time. ``sample_times``: the grouping's sample times; ``closed``: bool per
    mesh (:func:`usdksl.regions.closed.closed_meshes`); ``measured``: bool per sample time, the samples measured
    between a region's first and last (:func:`depth_sample_flags`; default: every sample). ``threads``
    (default: every core this process may run on) splits the samples; the answer does not depend on it."""
    sample_times = np.ascontiguousarray(sample_times, dtype=np.float64).reshape(-1)
    closed = np.ascontiguousarray(closed, dtype=bool).reshape(-1)
    measured = (np.ones(sample_times.size, bool) if measured is None
                else np.ascontiguousarray(measured, dtype=bool).reshape(-1))
    threads = default_threads() if threads is None else int(threads)
    span = np.asarray(grouping.row_span).reshape(-1, 2)
    raw = _native.region_depths(mesh_arrays(meshes), *contact_columns(table),
                                np.ascontiguousarray(grouping.row_region, dtype=np.int32),
                                np.ascontiguousarray(span[:, 1], dtype=np.int32), int(grouping.region_count),
                                sample_times, measured, closed, max(threads, 1))
    return DepthSamples(region=raw["region"], time=sample_times[raw["sample"]], penetration=raw["penetration"],
                        intersection_length=raw["intersection_length"], box_min=raw["box_min"],
                        box_max=raw["box_max"])
