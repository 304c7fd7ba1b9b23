"""Where a mesh's vertices are at a time: linear between its samples, held before the first and after the
last (docs/contracts.md, Motion), the way the continuous check moves them.

:func:`points_at` gives every vertex at one time (the cross-check's frames, a region's picture);
:func:`vertex_points_at` gives chosen vertices each at its own time (where a contact row's faces were at its
first contact). Both take the loader's MeshData or anything with ``times`` and ``points`` (float64, or float32
as the loader keeps authored world-space points: read as the same doubles). :func:`samples_all_alike` tells
whether a mesh's points ever change.
"""

from __future__ import annotations

import numpy as np

#: Values (samples x points x 3) compared at a time by :func:`samples_all_alike` (32 MB of float64 at most).
SAMPLE_BLOCK_VALUES = 1 << 22


def points_at(mesh, time: float) -> np.ndarray:
    """float64[N, 3]: the world-space points of ``mesh`` at ``time`` (a sample's own points at a sample time)."""
    times = mesh.times
    if len(times) == 1 or time <= times[0]:
        return _doubles(mesh.points[0])
    if time >= times[-1]:
        return _doubles(mesh.points[-1])
    upper = int(np.searchsorted(times, time, side="right"))
    lower = upper - 1
    if times[lower] == time:
        return _doubles(mesh.points[lower])
    weight = (time - times[lower]) / (times[upper] - times[lower])
    return (1.0 - weight) * _doubles(mesh.points[lower]) + weight * _doubles(mesh.points[upper])


def _doubles(points: np.ndarray) -> np.ndarray:
    """``points`` as float64 (no copy when they are)."""
    return points.astype(np.float64, copy=False)


def vertex_points_at(mesh, vertices: np.ndarray, times: np.ndarray) -> np.ndarray:
    """float64[V, 3]: vertex ``vertices[i]`` of ``mesh`` at ``times[i]``."""
    sample_times = mesh.times
    if sample_times.size == 1:
        return _doubles(mesh.points[0][vertices])
    clamped = np.clip(times, sample_times[0], sample_times[-1])
    upper = np.clip(np.searchsorted(sample_times, clamped, side="right"), 1, sample_times.size - 1)
    lower = upper - 1
    weight = ((clamped - sample_times[lower]) / (sample_times[upper] - sample_times[lower]))[:, None]
    return (1.0 - weight) * _doubles(mesh.points[lower, vertices]) + weight * _doubles(mesh.points[upper, vertices])


def samples_all_alike(points: np.ndarray) -> bool:
    """Whether every sample of ``points`` [K, N, 3] equals the first, exactly. Compared a block of samples at a
    time (SAMPLE_BLOCK_VALUES values), stopping at the first that differs: no [K, N, 3] temporary, which on a
    long shot would be a quarter of the points' own memory."""
    if points.ndim != 3 or points.shape[0] < 2:
        return True
    samples_per_block = max(1, SAMPLE_BLOCK_VALUES // max(1, points[0].size))
    for start in range(1, points.shape[0], samples_per_block):
        if not bool(np.all(points[start:start + samples_per_block] == points[:1])):
            return False
    return True
