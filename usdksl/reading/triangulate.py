"""Fan triangulation of USD polygon topology, vectorised with numpy."""

from __future__ import annotations

from typing import Optional, Tuple

import numpy as np


def fan_triangulate(face_vertex_counts: np.ndarray, face_vertex_indices: np.ndarray,
                    hole_indices: Optional[np.ndarray] = None) -> Tuple[np.ndarray, np.ndarray]:
    """Split every authored polygon into a fan of triangles around its first vertex.

    Faces listed in ``hole_indices`` and faces with fewer than three vertices yield no
    triangles, but authored face numbering is kept: ``triangle_face[j]`` is the index into
    ``face_vertex_counts`` of the polygon that triangle ``j`` came from.

    The counts must be non-negative and sum to ``len(face_vertex_indices)``; the caller
    checks that (it knows the file and prim to name in the error).

    Returns ``(triangles int32[M, 3], triangle_face int32[M])``.
    """
    counts = np.asarray(face_vertex_counts, dtype=np.int64).reshape(-1)
    indices = np.asarray(face_vertex_indices, dtype=np.int64).reshape(-1)
    face_count = counts.shape[0]

    triangles_per_face = np.maximum(counts - 2, 0)
    if hole_indices is not None and len(hole_indices):
        holes = np.asarray(hole_indices, dtype=np.int64).reshape(-1)
        holes = holes[(holes >= 0) & (holes < face_count)]
        triangles_per_face[holes] = 0

    triangle_count = int(triangles_per_face.sum())
    face_starts = np.cumsum(counts) - counts
    triangle_face = np.repeat(np.arange(face_count, dtype=np.int64), triangles_per_face)
    # k-th triangle of its face: (v0, v_{k+1}, v_{k+2}) of that face's vertex list.
    first_triangle_of_face = np.cumsum(triangles_per_face) - triangles_per_face
    fan_step = np.arange(triangle_count, dtype=np.int64) - np.repeat(first_triangle_of_face,
                                                                     triangles_per_face)
    corner0 = face_starts[triangle_face]
    triangles = np.empty((triangle_count, 3), dtype=np.int32)
    triangles[:, 0] = indices[corner0]
    triangles[:, 1] = indices[corner0 + fan_step + 1]
    triangles[:, 2] = indices[corner0 + fan_step + 2]
    return triangles, triangle_face.astype(np.int32)
