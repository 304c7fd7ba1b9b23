"""First contacts of animated meshes: the Python face of the native core.

``find_contacts`` hands the loader's arrays to the core and returns the first
contact of every triangle pair; ``CollisionResult.face_contacts`` collapses
those to authored faces, which is what every report names.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Dict, Iterable, Optional, Sequence, Tuple

import numpy as np

from .. import _native

METHODS = ("ksl", "swept", "discrete", "brute")

#: Default CCD tolerance: width of the time interval, as a fraction of one
#: flightplan step, at which the root search stops refining.
DEFAULT_TOLERANCE = 1e-6
#: Default iteration cap of one primitive CCD query; a capped query counts as a contact.
DEFAULT_MAX_ITERATIONS = 1_000_000

#: Contact feature codes (``feature`` columns).
FEATURE_NAMES = {0: "vertex-face", 1: "face-vertex", 2: "edge-edge", 3: "static"}


def _row_order(time, mesh_a, face_a, mesh_b, face_b) -> np.ndarray:
    return np.lexsort((face_b, mesh_b, face_a, mesh_a, time))


@dataclass
class FaceContacts:
    """First contact per authored face pair, sorted by (time, mesh_a, face_a, mesh_b, face_b).

    Self rows have mesh_a == mesh_b and face_a < face_b; inter rows mesh_a < mesh_b.
    """

    time: np.ndarray
    mesh_a: np.ndarray
    face_a: np.ndarray
    mesh_b: np.ndarray
    face_b: np.ndarray
    feature: np.ndarray

    def __len__(self) -> int:
        return int(self.time.shape[0])


@dataclass
class CollisionResult:
    """First contact per triangle pair (time codes), sorted like FaceContacts, plus work counters."""

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

    def face_contacts(self, meshes: Sequence) -> FaceContacts:
        """Collapse triangle contacts to authored faces: earliest time per face pair."""
        offsets = np.zeros(len(meshes) + 1, dtype=np.int64)
        offsets[1:] = np.cumsum([m.triangle_face.shape[0] for m in meshes])
        all_faces = (np.concatenate([m.triangle_face for m in meshes]).astype(np.int64)
                     if meshes else np.zeros(0, np.int64))
        face_a = all_faces[offsets[self.mesh_a] + self.tri_a]
        face_b = all_faces[offsets[self.mesh_b] + self.tri_b]
        mesh_a = self.mesh_a.astype(np.int64)
        mesh_b = self.mesh_b.astype(np.int64)
        self_rows = mesh_a == mesh_b
        swap = self_rows & (face_a > face_b)
        face_a, face_b = np.where(swap, face_b, face_a), np.where(swap, face_a, face_b)
        feature = self.feature.copy()
        feature[swap & (feature == 0)] = 1
        feature[swap & (self.feature == 1)] = 0
        keep = ~(self_rows & (face_a == face_b))
        time, mesh_a, face_a, mesh_b, face_b, feature = (
            a[keep] for a in (self.time, mesh_a, face_a, mesh_b, face_b, feature))
        # Earliest row of each face pair: sort by pair then time, keep group heads.
        order = np.lexsort((time, face_b, mesh_b, face_a, mesh_a))
        keys = np.stack([mesh_a, face_a, mesh_b, face_b])[:, order]
        head = np.ones(order.shape[0], dtype=bool)
        head[1:] = np.any(keys[:, 1:] != keys[:, :-1], axis=0)
        chosen = order[head]
        time, mesh_a, face_a, mesh_b, face_b, feature = (
            a[chosen] for a in (time, mesh_a, face_a, mesh_b, face_b, feature))
        final = _row_order(time, mesh_a, face_a, mesh_b, face_b)
        return FaceContacts(time=time[final], mesh_a=mesh_a[final].astype(np.int32),
                            face_a=face_a[final].astype(np.int32), mesh_b=mesh_b[final].astype(np.int32),
                            face_b=face_b[final].astype(np.int32), feature=feature[final])


def find_contacts(meshes: Sequence, pairs: Iterable[Tuple[int, int]], method: str = "ksl",
                  time_range: Optional[Tuple[float, float]] = None, tolerance: float = DEFAULT_TOLERANCE,
                  thickness: float = 0.0, max_iterations: int = DEFAULT_MAX_ITERATIONS,
                  discrete_substeps: int = 1,
                  progress: Optional[Callable[[float, int], None]] = None) -> CollisionResult:
    """First contact of every triangle pair of the given mesh pairs ((i, i) is a self check).

    ``meshes`` are loader MeshData (or anything with times, points, triangles,
    triangle_face). ``time_range`` defaults to the union of the meshes' sample
    times. A contact whose conservative time falls just before the range start
    (its flightplan step straddles the start) is reported at the range start.
    """
    if method not in METHODS:
        raise ValueError(f"unknown method {method!r}; expected one of {', '.join(METHODS)}")
    pair_array = np.asarray(list(pairs), dtype=np.int32).reshape(-1, 2)
    if time_range is None:
        starts = [float(m.times[0]) for m in meshes]
        ends = [float(m.times[-1]) for m in meshes]
        time_range = (min(starts), max(ends)) if meshes else (0.0, 0.0)
    t_begin, t_end = float(time_range[0]), float(time_range[1])
    native_meshes = [
        (np.ascontiguousarray(m.times, dtype=np.float64), np.ascontiguousarray(m.points, dtype=np.float64),
         np.ascontiguousarray(m.triangles, dtype=np.int32), np.ascontiguousarray(m.triangle_face, dtype=np.int32))
        for m in meshes]
    raw = _native.find_contacts(native_meshes, pair_array, method, t_begin, t_end, float(tolerance),
                                float(thickness), int(max_iterations), int(discrete_substeps), progress)
    time = np.maximum(raw["time"], t_begin)
    order = _row_order(time, raw["mesh_a"], raw["tri_a"], raw["mesh_b"], raw["tri_b"])
    return CollisionResult(time=time[order], mesh_a=raw["mesh_a"][order], tri_a=raw["tri_a"][order],
                           mesh_b=raw["mesh_b"][order], tri_b=raw["tri_b"][order],
                           feature=raw["feature"][order], undecided=raw["undecided"][order],
                           counters=dict(raw["counters"]))
