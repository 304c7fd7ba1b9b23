"""Polygon meshes of Newton's analytic collision shapes, for writing colliders into a USD cache.

Every function returns ``(points float64[N, 3], face_vertex_counts int32[F], face_vertex_indices int32[I])``
in the shape's local frame, in scene units (metres in the Newton scenes), outward-facing. Spheres and
capsules are tessellated with their vertices on the analytic surface, so the mesh lies inside the shape
the simulator collided against (by at most the chord sag).
"""

from __future__ import annotations

import math
from typing import Tuple

import numpy as np

MeshArrays = Tuple[np.ndarray, np.ndarray, np.ndarray]


def box(half_extents) -> MeshArrays:
    """An axis-aligned box centred on the origin: 8 points, 6 quads."""
    hx, hy, hz = (float(v) for v in half_extents)
    corners = np.array([[sx * hx, sy * hy, sz * hz] for sz in (-1, 1) for sy in (-1, 1) for sx in (-1, 1)])
    quads = np.array([[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]])
    return corners, np.full(6, 4, np.int32), quads.reshape(-1).astype(np.int32)


def _rings_along_z(ring_z: np.ndarray, ring_radius: np.ndarray, segments: int, z_top: float,
                   z_bottom: float) -> MeshArrays:
    """A closed surface of revolution about Z: quads between rings, triangle fans at the two poles."""
    phi = np.linspace(0.0, 2.0 * math.pi, segments, endpoint=False)
    rings = np.stack([np.outer(ring_radius, np.cos(phi)).reshape(-1), np.outer(ring_radius, np.sin(phi)).reshape(-1),
                      np.repeat(ring_z, segments)], axis=1)
    top, bottom = len(rings), len(rings) + 1
    points = np.concatenate([rings, [[0.0, 0.0, z_top], [0.0, 0.0, z_bottom]]])
    s = np.arange(segments)
    s_next = (s + 1) % segments
    r = np.arange(len(ring_z) - 1)[:, None]
    # rings run from the top pole down; these windings face outward
    quads = np.stack([r * segments + s, (r + 1) * segments + s, (r + 1) * segments + s_next, r * segments + s_next],
                     axis=2).reshape(-1, 4)
    top_fan = np.stack([np.full(segments, top), s, s_next], axis=1)
    last = (len(ring_z) - 1) * segments
    bottom_fan = np.stack([np.full(segments, bottom), last + s_next, last + s], axis=1)
    counts = np.concatenate([np.full(segments, 3), np.full(len(quads), 4), np.full(segments, 3)]).astype(np.int32)
    indices = np.concatenate([top_fan.reshape(-1), quads.reshape(-1), bottom_fan.reshape(-1)]).astype(np.int32)
    return points, counts, indices


def sphere(radius: float, segments: int = 24, rings: int = 12) -> MeshArrays:
    """A UV sphere centred on the origin, poles on Z."""
    theta = np.linspace(0.0, math.pi, rings + 1)[1:-1]
    return _rings_along_z(radius * np.cos(theta), radius * np.sin(theta), segments, radius, -radius)


def capsule(radius: float, half_height: float, segments: int = 24, cap_rings: int = 6) -> MeshArrays:
    """A capsule along Z (Newton's convention): a cylinder of half length ``half_height`` and two hemispheres."""
    theta = np.linspace(0.0, math.pi / 2.0, cap_rings + 1)[1:]
    upper_z = half_height + radius * np.cos(theta)
    upper_r = radius * np.sin(theta)
    ring_z = np.concatenate([upper_z, -upper_z[::-1]])
    ring_r = np.concatenate([upper_r, upper_r[::-1]])
    return _rings_along_z(ring_z, ring_r, segments, half_height + radius, -half_height - radius)


def ground(half_size: float, height: float = 0.0) -> MeshArrays:
    """A square on the Z-up ground plane: one quad facing +Z."""
    h = float(half_size)
    points = np.array([[-h, -h, height], [h, -h, height], [h, h, height], [-h, h, height]])
    return points, np.array([4], np.int32), np.array([0, 1, 2, 3], np.int32)


def transform_points(points: np.ndarray, position, quaternion_xyzw) -> np.ndarray:
    """Apply a rigid transform (Newton's (p, q) with q = (x, y, z, w)) to points."""
    return points @ quaternion_matrix(quaternion_xyzw).T + np.asarray(position, np.float64)


def quaternion_matrix(quaternion_xyzw) -> np.ndarray:
    x, y, z, w = (float(v) for v in quaternion_xyzw)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])
