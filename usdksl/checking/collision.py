"""First contacts of animated meshes: the Python face of the native core.

``find_contacts`` hands the loader's arrays to the core and returns the first
contact of every triangle pair; ``CollisionResult.face_contacts`` collapses
those to authored faces, which is what every report names.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from typing import Callable, Dict, Iterable, List, Optional, Sequence, Tuple

import numpy as np

from .. import _native
from .memory_windows import plan_memory_windows, window_of
from ..ccd_defaults import DEFAULT_MAX_ITERATIONS, DEFAULT_THICKNESS, DEFAULT_TOLERANCE
from ..contacts.table import ContactTable

#: Broad phases of the core: kinetic separation lists, the swept-volume BVH baseline, per-sample
#: (discrete) checks, and all pairs (the brute-force reference).
METHODS = ("ksl", "swept", "discrete", "brute")
#: Work counter: memory windows the range was handed to the core in (absent when it was handed whole).
MEMORY_WINDOWS_COUNTER = "memory_windows"


def default_threads() -> int:
    """Cores this process may run on (its CPU affinity), at least 1."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # platforms without affinity masks
        return max(1, os.cpu_count() or 1)


def mesh_arrays(meshes: Sequence) -> List[tuple]:
    """(times, points, triangles, triangle_face) per mesh, as every binding of the core reads a mesh (no copy
    when the arrays already have its dtypes and layout; float32 points, as the loader keeps authored
    world-space points, are read as the same doubles without a float64 copy)."""
    return [(np.ascontiguousarray(m.times, dtype=np.float64),
             np.ascontiguousarray(m.points, dtype=np.float32 if m.points.dtype == np.float32 else np.float64),
             np.ascontiguousarray(m.triangles, dtype=np.int32), np.ascontiguousarray(m.triangle_face, dtype=np.int32))
            for m in meshes]


def _row_order(time, mesh_a, face_a, mesh_b, face_b) -> np.ndarray:
    return np.lexsort((face_b, mesh_b, face_a, mesh_a, time))


@dataclass
class CollisionResult:
    """First contact per triangle pair (time codes), sorted by (time, mesh_a, tri_a, mesh_b, tri_b), plus work
    counters."""

    time: np.ndarray
    mesh_a: np.ndarray
    tri_a: np.ndarray
    mesh_b: np.ndarray
    tri_b: np.ndarray
    feature: np.ndarray
    undecided: np.ndarray
    counters: Dict[str, int]

    def __len__(self) -> int:
        return int(self.time.shape[0])

    def face_contacts(self, meshes: Sequence) -> ContactTable:
        """Collapse triangle contacts to authored faces: the first contact per face pair, in canonical
        order for the meshes' prim paths (mesh index order for meshes without a ``path``)."""
        offsets = np.zeros(len(meshes) + 1, dtype=np.int64)
        offsets[1:] = np.cumsum([m.triangle_face.shape[0] for m in meshes])
        all_faces = (np.concatenate([m.triangle_face for m in meshes]).astype(np.int64)
                     if meshes else np.zeros(0, np.int64))
        face_a = all_faces[offsets[self.mesh_a] + self.tri_a]
        face_b = all_faces[offsets[self.mesh_b] + self.tri_b]
        paths = [getattr(m, "path", None) for m in meshes]
        return ContactTable.from_rows(None if None in paths else paths, self.time, self.mesh_a, face_a,
                                      self.mesh_b, face_b, self.feature)


def find_contacts(meshes: Sequence, pairs: Iterable[Tuple[int, int]], method: str = "ksl",
                  time_range: Optional[Tuple[float, float]] = None, tolerance: float = DEFAULT_TOLERANCE,
                  thickness: float = DEFAULT_THICKNESS, max_iterations: int = DEFAULT_MAX_ITERATIONS,
                  discrete_substeps: int = 1,
                  progress: Optional[Callable[[float, int], None]] = None,
                  threads: Optional[int] = None, steps_per_window: Optional[int] = None,
                  settled: Optional[np.ndarray] = None, frames_per_time_code: float = 0.0) -> CollisionResult:
    """First contact of every triangle pair of the given mesh pairs ((i, i) is a self check).

    ``meshes`` are loader MeshData (or anything with times, points, triangles,
    triangle_face). ``time_range`` defaults to the union of the meshes' sample
    times. A contact whose conservative time falls just before the range start
    (its flightplan step straddles the start) is reported at the range start.
    ``threads`` (default: every core this process may run on) splits the range
    into time windows checked in parallel; the result is identical for any count.
    ``steps_per_window`` (None: the whole range at once) hands the core the range in memory windows of
    about that many sample steps, one after another (usdksl.checking.memory_windows), so that it holds
    one window of the samples at a time; the result is identical for any value.
    ``settled`` (int32[N, 4]: mesh_a, tri_a, mesh_b, tri_b) are triangle pairs whose first contact is known to
    come at or before the range start (a run over an earlier range found them): the core does not look for
    them again, and they are not in the result.
    ``frames_per_time_code`` (the stage's clock, :attr:`usdksl.clock.StageClock.frames_per_time_code`; 0:
    unknown) lets ``ksl`` and ``swept`` step over the samples between whole frames (a simulator's sub-frame
    samples) with their distance from the frames' chords as slack; the raw samples confirm every contact, so
    the result is the same, only found at about the cost of the whole frames.
    """
    if method not in METHODS:
        raise ValueError(f"unknown method {method!r}; expected one of {', '.join(METHODS)}")
    if threads is None:
        threads = default_threads()
    if int(threads) < 1:
        raise ValueError(f"threads must be at least 1, got {threads!r}")
    pair_array = np.asarray(list(pairs), dtype=np.int32).reshape(-1, 2)
    if time_range is None:
        starts = [float(m.times[0]) for m in meshes]
        ends = [float(m.times[-1]) for m in meshes]
        time_range = (min(starts), max(ends)) if meshes else (0.0, 0.0)
    t_begin, t_end = float(time_range[0]), float(time_range[1])
    windows = plan_memory_windows(meshes, pair_array.tolist(), (t_begin, t_end), steps_per_window)
    if len(windows) > 1:
        return _find_contacts_in_windows(meshes, pair_array, windows, progress,
                                         dict(method=method, tolerance=tolerance, thickness=thickness,
                                              max_iterations=max_iterations, discrete_substeps=discrete_substeps,
                                              threads=threads, frames_per_time_code=frames_per_time_code))
    native_meshes = mesh_arrays(meshes)
    options = _native.CheckOptions(method=method, t_begin=t_begin, t_end=t_end, tolerance=float(tolerance),
                                   thickness=float(thickness), max_iterations=int(max_iterations),
                                   discrete_substeps=int(discrete_substeps), threads=int(threads),
                                   frames_per_time_code=float(frames_per_time_code))
    if settled is not None and len(settled):
        options.settle(np.ascontiguousarray(settled, dtype=np.int32).reshape(-1, 4))
    raw = _native.find_contacts(native_meshes, pair_array, options, progress)
    time = raw["time"]
    columns = {name: raw[name] for name in ("mesh_a", "tri_a", "mesh_b", "tri_b", "feature", "undecided")}
    # The core returns its rows in _row_order already; only times it clamps to the range start (the
    # earliest rows) can need re-ordering among themselves.
    if time.size and time[0] < t_begin:
        time = np.maximum(time, t_begin)
        order = _row_order(time, columns["mesh_a"], columns["tri_a"], columns["mesh_b"], columns["tri_b"])
        time = time[order]
        columns = {name: column[order] for name, column in columns.items()}
    return CollisionResult(time=time, counters=dict(raw["counters"]), **columns)


def found_pairs(results: Sequence[CollisionResult]) -> np.ndarray:
    """int32[N, 4]: the triangle pairs (mesh_a, tri_a, mesh_b, tri_b) that ``results`` found."""
    if not results:
        return np.zeros((0, 4), np.int32)
    return np.stack([np.concatenate([getattr(result, name) for result in results]).astype(np.int32)
                     for name in ("mesh_a", "tri_a", "mesh_b", "tri_b")], axis=1)


def _find_contacts_in_windows(meshes: Sequence, pair_array: np.ndarray, windows: Sequence[Tuple[float, float]],
                              progress: Optional[Callable[[float, int], None]], settings: dict) -> CollisionResult:
    """find_contacts over consecutive ``windows``, each with the meshes' samples inside it only, joined as
    the core joins its own time windows: the earliest row per triangle pair (the earlier window on a tie).
    A window leaves alone the pairs the windows before it found (their first contacts come first), so a
    contact that goes on across a cut is found and confirmed once."""
    parts: List[CollisionResult] = []
    found_before = 0
    for window in windows:
        report = None if progress is None else (
            lambda reached, count, before=found_before: progress(reached, before + count))
        part = find_contacts([window_of(mesh, window) for mesh in meshes], pair_array, time_range=window,
                             progress=report, settled=found_pairs(parts), **settings)
        parts.append(part)
        found_before += len(part)
    names = ("time", "mesh_a", "tri_a", "mesh_b", "tri_b", "feature", "undecided")
    joined = {name: np.concatenate([getattr(part, name) for part in parts]) for name in names}
    window_index = np.repeat(np.arange(len(parts)), [len(part) for part in parts])
    by_pair = np.lexsort((window_index, joined["time"], joined["tri_b"], joined["mesh_b"], joined["tri_a"],
                          joined["mesh_a"]))
    key = [joined[name][by_pair] for name in ("mesh_a", "tri_a", "mesh_b", "tri_b")]
    first = np.ones(by_pair.size, bool)
    first[1:] = np.any([column[1:] != column[:-1] for column in key], axis=0)
    kept = by_pair[first]
    kept = kept[_row_order(*(joined[name][kept] for name in ("time", "mesh_a", "tri_a", "mesh_b", "tri_b")))]
    counters: Dict[str, int] = {}
    for part in parts:
        for name, value in part.counters.items():
            counters[name] = counters.get(name, 0) + int(value)
    counters[MEMORY_WINDOWS_COUNTER] = len(parts)
    return CollisionResult(counters=counters, **{name: joined[name][kept] for name in names})
