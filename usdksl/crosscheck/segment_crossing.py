"""Double-precision confirmation that a segment properly crosses a triangle.

Embree answers in single precision. Its candidates are confirmed here, in double precision and vectorised
over candidates, with a rule that is deliberately one-sided: a candidate counts only when the segment
passes *through the interior* of the triangle by a clear margin. Touching, grazing and coplanar
configurations are never confirmed, so single-precision noise (or double rounding at an exact touch) can
never produce a false alarm; such contacts are the continuous check's business alone.

The rule, for segment ``p -> q`` and triangle ``a, b, c``, with ``scale`` the largest absolute coordinate
or edge length involved and ``margin = CROSSING_MARGIN_RELATIVE * scale`` (scene units):

1. ``p`` and ``q`` lie on strictly opposite sides of the triangle's plane, each farther than ``margin``;
2. the point where the segment meets the plane lies inside the triangle, farther than ``margin`` from each
   of its three edge lines.
"""

from __future__ import annotations

import numpy as np

#: Relative margin (fraction of the configuration's coordinate scale) by which a crossing must clear the
#: triangle's plane and edges to count. Far above double rounding (~1e-16), far below anything a user
#: would call touching.
CROSSING_MARGIN_RELATIVE = 1e-10


def segments_cross_triangles(p: np.ndarray, q: np.ndarray, a: np.ndarray, b: np.ndarray,
                             c: np.ndarray) -> np.ndarray:
    """True where segment ``p[i] -> q[i]`` properly crosses the interior of triangle ``(a[i], b[i], c[i])``.

    All arguments are float64 arrays of shape (n, 3) in scene units; returns bool[n]. Degenerate triangles
    (zero area) and zero-length segments never cross.
    """
    p, q, a, b, c = (np.asarray(x, dtype=np.float64).reshape(-1, 3) for x in (p, q, a, b, c))
    if len(p) == 0:
        return np.zeros(0, dtype=bool)
    scale = np.max(np.abs(np.stack([p, q, a, b, c], axis=1)), axis=(1, 2))
    edges = np.stack([b - a, c - b, a - c, q - p], axis=1)
    scale = np.maximum(scale, np.max(np.linalg.norm(edges, axis=2), axis=1))
    margin = CROSSING_MARGIN_RELATIVE * scale

    normal = np.cross(b - a, c - a)
    normal_length = np.linalg.norm(normal, axis=1)
    usable = normal_length > 0.0
    safe_length = np.where(usable, normal_length, 1.0)
    unit_normal = normal / safe_length[:, None]

    height_p = np.einsum("ij,ij->i", unit_normal, p - a)
    height_q = np.einsum("ij,ij->i", unit_normal, q - a)
    opposite_sides = ((height_p > margin) & (height_q < -margin)) | ((height_p < -margin) & (height_q > margin))
    usable &= opposite_sides

    denominator = np.where(usable, height_p - height_q, 1.0)
    fraction = height_p / denominator
    crossing = p + fraction[:, None] * (q - p)

    inside = usable
    for start, end in ((a, b), (b, c), (c, a)):
        edge = end - start
        edge_length = np.linalg.norm(edge, axis=1)
        safe_edge = np.where(edge_length > 0.0, edge_length, 1.0)
        # Signed distance of the crossing point from the edge line, positive on the triangle's side.
        inward = np.cross(unit_normal, edge) / safe_edge[:, None]
        distance = np.einsum("ij,ij->i", inward, crossing - start)
        inside &= (edge_length > 0.0) & (distance > margin)
    return inside
