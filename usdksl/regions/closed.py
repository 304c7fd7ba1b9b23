"""Which meshes are closed (watertight): the penetration depth into a mesh is defined only when it has an
inside.

A mesh is closed when every undirected edge of its triangulation is used by exactly two triangles, once in
each direction: a manifold, consistently oriented surface without boundary. A cloth has a boundary, a box or
a body usually has none. Topology alone decides (the points never change it), so one answer holds for the
whole shot. Which way the triangles wind (outward or inward) does not matter: the depth reads it from the
mesh's enclosed volume.
"""

from __future__ import annotations

from typing import Sequence

import numpy as np


def triangles_are_closed(triangles: np.ndarray) -> bool:
    """True when the triangles (int[M, 3], vertex indices) use every undirected edge exactly twice, once in
    each direction. No triangles, or a triangle that repeats a vertex, is not closed."""
    corners = np.asarray(triangles, dtype=np.int64).reshape(-1, 3)
    if corners.shape[0] == 0:
        return False
    start = corners.reshape(-1)
    end = corners[:, [1, 2, 0]].reshape(-1)
    if np.any(start == end) or int(corners.min()) < 0:
        return False
    stride = int(corners.max()) + 1
    directed = np.sort(start * stride + end)
    if np.any(directed[1:] == directed[:-1]):
        return False  # an edge used twice the same way: non-manifold or inconsistently wound
    # every directed edge once and its reverse once: exactly two triangles per edge, opposite ways
    return bool(np.array_equal(directed, np.sort(end * stride + start)))


def closed_meshes(meshes: Sequence) -> np.ndarray:
    """bool[len(meshes)]: whether each mesh (anything with ``triangles``) is closed (see the module)."""
    return np.array([triangles_are_closed(mesh.triangles) for mesh in meshes], dtype=bool)
