"""Memory windows: a long shot handed to the core one stretch of time after another.

The core copies the points it is given and builds flightplans (merged and raw) over every sample it gets:
about ten times what the loader's own float64 points take. Handed the whole shot, its memory grows with
the shot's length. Handed one window of samples at a time, with the windows cut at time codes where every
animated mesh has a sample, it holds one window: memory is set by the window and the triangles, and the
answer is the one of the whole shot, bit for bit (docs/contracts.md, Windows and merging: a run over
[a, b] and one over [b, c], merged by the earliest time per triangle pair, are one run over [a, c]).

:func:`plan_memory_windows` cuts a checked range into windows of at most a number of sample steps;
:func:`window_of` is a mesh's samples inside one window (numpy views, no copy: the core copies only them).
The core starts every window afresh (its front is built again at each cut, the cost of one more time
window of its own threads) and :func:`usdksl.checking.collision.find_contacts` joins the windows' rows.
"""

from __future__ import annotations

import copy
import dataclasses
from typing import Iterable, List, Optional, Sequence, Tuple

import numpy as np

from ..unmasked import distinct_sorted

TimeRange = Tuple[float, float]

#: Fewest sample steps a memory window spans (a shorter one costs its rebuild for little work); the
#: last window of a range may be shorter only when the range is.
MIN_STEPS_PER_WINDOW = 8


def used_meshes(meshes: Sequence, pairs: Iterable[Tuple[int, int]]) -> List[int]:
    """Indices of the meshes that appear in ``pairs``, in order."""
    used = sorted({int(index) for pair in pairs for index in pair})
    return [index for index in used if 0 <= index < len(meshes)]


def plan_memory_windows(meshes: Sequence, pairs: Iterable[Tuple[int, int]], time_range: TimeRange,
                        steps_per_window: Optional[int]) -> List[TimeRange]:
    """Windows (time codes) covering ``time_range`` in order, each ending where the next begins, each of at
    most about ``steps_per_window`` steps between consecutive sample times of the meshes in ``pairs`` (at
    least MIN_STEPS_PER_WINDOW), cut only at time codes where every animated one of them (more than one
    sample) has a sample. One window, the range itself, when ``steps_per_window`` is None or the range is
    not longer, or when no time fits a cut."""
    start, end = float(time_range[0]), float(time_range[1])
    if steps_per_window is None or end <= start:
        return [(start, end)]
    steps_per_window = max(int(steps_per_window), MIN_STEPS_PER_WINDOW)
    animated = [meshes[index] for index in used_meshes(meshes, pairs) if len(meshes[index].times) > 1]
    if not animated:
        return [(start, end)]
    times = distinct_sorted(np.concatenate([np.asarray(mesh.times, np.float64) for mesh in animated]
                                           + [np.array([start, end])]))
    times = times[(times >= start) & (times <= end)]
    if times.size - 1 <= steps_per_window:
        return [(start, end)]
    shared = times
    for mesh in animated:
        shared = shared[_is_in(shared, np.asarray(mesh.times, np.float64))]
    cut_index = np.searchsorted(times, shared)          # each shared time's step index
    last = times.size - 1
    cuts: List[int] = []
    at = 0
    while last - at > steps_per_window:
        # the latest shared time within reach that leaves the minimum on both sides, else the earliest beyond
        fits = cut_index[(cut_index > at + MIN_STEPS_PER_WINDOW - 1) & (cut_index <= at + steps_per_window)
                         & (cut_index <= last - MIN_STEPS_PER_WINDOW)]
        beyond = cut_index[(cut_index > at + steps_per_window) & (cut_index <= last - MIN_STEPS_PER_WINDOW)]
        if fits.size:
            at = int(fits[-1])
        elif beyond.size:
            at = int(beyond[0])
        else:
            break
        cuts.append(at)
    bounds = [start] + [float(times[index]) for index in cuts] + [end]
    return list(zip(bounds[:-1], bounds[1:]))


def _is_in(values: np.ndarray, sorted_values: np.ndarray) -> np.ndarray:
    """bool per value: whether it occurs in ``sorted_values`` (np.isin imports numpy.ma, which a plain
    check does not load)."""
    at = np.minimum(np.searchsorted(sorted_values, values), max(sorted_values.size - 1, 0))
    return sorted_values[at] == values if sorted_values.size else np.zeros(values.size, bool)


def window_of(mesh, window: TimeRange):
    """``mesh`` (anything with ``times`` and ``points[K, N, 3]``) over ``window`` only: its samples inside
    the window, both ends included (views, no copy). A still mesh (one sample) is itself. Raises
    ValueError when the window starts or ends strictly between two of its samples (the window would
    re-sample its motion: plan_memory_windows never cuts there)."""
    times = np.asarray(mesh.times)
    if times.size <= 1:
        return mesh
    start, end = window
    first = int(np.searchsorted(times, start, side="left"))
    stop = int(np.searchsorted(times, end, side="right"))
    for bound, index in ((start, first), (end, stop - 1)):
        inside = times[0] < bound < times[-1]
        if inside and not (0 <= index < times.size and times[index] == bound):
            raise ValueError(f"a memory window bound {bound:g} falls between two samples of a mesh")
    first = min(first, times.size - 1)        # a window after the last sample holds it
    stop = max(stop, first + 1)               # a window before the first sample holds it
    if dataclasses.is_dataclass(mesh):
        return dataclasses.replace(mesh, times=mesh.times[first:stop], points=mesh.points[first:stop])
    sliced = copy.copy(mesh)
    sliced.times, sliced.points = mesh.times[first:stop], mesh.points[first:stop]
    return sliced


__all__ = ["MIN_STEPS_PER_WINDOW", "plan_memory_windows", "used_meshes", "window_of"]
