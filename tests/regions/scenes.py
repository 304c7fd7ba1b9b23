"""Animated meshes the region tests build as plain numpy arrays (no USD): sheets (open), boxes and spheres
(closed), and the contacts the check finds between them."""

from dataclasses import dataclass
from typing import Callable, Optional, Sequence, Tuple

import numpy as np

from usdksl.checking.collision import find_contacts


@dataclass(frozen=True, eq=False)
class Mesh:
    """What the core reads of a mesh (MeshData's arrays)."""

    times: np.ndarray          # float64[K]
    points: np.ndarray         # float64[K, N, 3]
    triangles: np.ndarray      # int32[M, 3]
    triangle_face: np.ndarray  # int32[M]


def quads_to_triangles(quads: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
    """Fan triangulation of quads (int[F, 4]): (triangles int32[2F, 3], triangle_face int32[2F])."""
    quads = np.asarray(quads, dtype=np.int32).reshape(-1, 4)
    triangles = np.stack([quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]], axis=1).reshape(-1, 3)
    return triangles.astype(np.int32), np.repeat(np.arange(quads.shape[0], dtype=np.int32), 2)


def grid(columns: int, rows: int) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A (columns x rows)-quad grid over the unit square: (u[N], v[N], quads[F, 4]); face f covers column
    f % columns, row f // columns; vertex j * (columns + 1) + i sits at u = i / columns, v = j / rows."""
    u, v = np.meshgrid(np.linspace(0.0, 1.0, columns + 1), np.linspace(0.0, 1.0, rows + 1))
    ids = np.arange((rows + 1) * (columns + 1)).reshape(rows + 1, columns + 1)
    quads = np.stack([ids[:-1, :-1], ids[:-1, 1:], ids[1:, 1:], ids[1:, :-1]], axis=-1).reshape(-1, 4)
    return u.ravel(), v.ravel(), quads


def sheet(columns: int, rows: int, origin, edge_u, edge_v, times=(0.0,),
          offset: Optional[Callable[[float], np.ndarray]] = None) -> Mesh:
    """A flat sheet of quads spanning origin + u * edge_u + v * edge_v (u, v in [0, 1]), moved at each of
    ``times`` by offset(t) (a 3-vector; none: static)."""
    u, v, quads = grid(columns, rows)
    base = np.asarray(origin, float) + u[:, None] * np.asarray(edge_u, float) + v[:, None] * np.asarray(edge_v, float)
    times = np.asarray(times, dtype=np.float64)
    shifts = np.array([np.zeros(3) if offset is None else np.asarray(offset(t), float) for t in times])
    triangles, faces = quads_to_triangles(quads)
    return Mesh(times, base[None, :, :] + shifts[:, None, :], triangles, faces)


#: The quads of a box over its corners (corner i at -h/+h per axis by bits x=1, y=2, z=4), wound
#: counter-clockwise seen from outside: bottom, top, -y, +y, -x, +x.
BOX_QUADS = np.array([[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]])
BOX_BOTTOM, BOX_TOP = 0, 1


def box_corners(half) -> np.ndarray:
    half = np.broadcast_to(np.asarray(half, float), (3,))
    bits = np.arange(8)
    return np.stack([np.where(bits & 1, half[0], -half[0]), np.where(bits & 2, half[1], -half[1]),
                     np.where(bits & 4, half[2], -half[2])], axis=1)


def boxes(half, centres: Callable[[float], np.ndarray], times) -> Mesh:
    """One mesh of several boxes of half-sizes ``half``, box k centred at centres(t)[k] (float[B, 3])."""
    times = np.asarray(times, dtype=np.float64)
    centre = np.array([np.asarray(centres(t), float).reshape(-1, 3) for t in times])  # [K, B, 3]
    count = centre.shape[1]
    points = (centre[:, :, None, :] + box_corners(half)[None, None, :, :]).reshape(len(times), 8 * count, 3)
    quads = (BOX_QUADS[None, :, :] + 8 * np.arange(count)[:, None, None]).reshape(-1, 4)
    triangles, faces = quads_to_triangles(quads)
    return Mesh(times, points, triangles, faces)


def box(half, centre: Callable[[float], np.ndarray], times) -> Mesh:
    """One box of half-sizes ``half`` centred at centre(t)."""
    return boxes(half, lambda t: np.asarray(centre(t), float)[None, :], times)


def icosphere(levels: int) -> Tuple[np.ndarray, np.ndarray]:
    """Unit icosphere: (vertices float[N, 3] on the sphere, triangles int32[M, 3] wound outward)."""
    g = (1.0 + 5 ** 0.5) / 2.0
    vertices = np.array([[-1, g, 0], [1, g, 0], [-1, -g, 0], [1, -g, 0], [0, -1, g], [0, 1, g], [0, -1, -g],
                         [0, 1, -g], [g, 0, -1], [g, 0, 1], [-g, 0, -1], [-g, 0, 1]], float)
    vertices /= np.linalg.norm(vertices, axis=1, keepdims=True)
    faces = np.array([[0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11], [1, 5, 9], [5, 11, 4], [11, 10, 2],
                      [10, 7, 6], [7, 1, 8], [3, 9, 4], [3, 4, 2], [3, 2, 6], [3, 6, 8], [3, 8, 9], [4, 9, 5],
                      [2, 4, 11], [6, 2, 10], [8, 6, 7], [9, 8, 1]])
    for _ in range(levels):
        edges = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
        keys = np.sort(edges, axis=1)
        unique, inverse = np.unique(keys, axis=0, return_inverse=True)
        middle = vertices[unique[:, 0]] + vertices[unique[:, 1]]
        middle /= np.linalg.norm(middle, axis=1, keepdims=True)
        mid = len(vertices) + inverse.reshape(3, -1)   # [edge ab, bc, ca][face]
        ab, bc, ca = mid
        a, b, c = faces.T
        faces = np.concatenate([np.stack([a, ab, ca], 1), np.stack([b, bc, ab], 1), np.stack([c, ca, bc], 1),
                                np.stack([ab, bc, ca], 1)])
        vertices = np.concatenate([vertices, middle])
    return vertices, faces.astype(np.int32)


def sphere(radius: float, levels: int, centre: Callable[[float], np.ndarray], times,
           radial: Optional[np.ndarray] = None) -> Mesh:
    """An icosphere of ``radius`` (times radial[v] per vertex when given) centred at centre(t)."""
    unit, triangles = icosphere(levels)
    scale = radius * (np.ones(len(unit)) if radial is None else np.asarray(radial, float))
    times = np.asarray(times, dtype=np.float64)
    points = np.array([unit * scale[:, None] + np.asarray(centre(t), float) for t in times])
    return Mesh(times, points, triangles, np.arange(len(triangles), dtype=np.int32))


def sample_times(meshes: Sequence[Mesh]) -> np.ndarray:
    """The union of the meshes' sample times, sorted."""
    return np.unique(np.concatenate([m.times for m in meshes]))


def contacts(meshes: Sequence[Mesh], pairs, thickness: float = 0.0):
    """The check's contact table (first contact per face pair) of ``pairs`` over the meshes' samples."""
    return find_contacts(meshes, pairs, thickness=thickness, threads=1).face_contacts(meshes)


def longest_edge(mesh: Mesh) -> float:
    """Longest triangle edge of the mesh at any sample (scene units)."""
    corners = mesh.points[:, mesh.triangles]   # [K, M, 3, 3]
    edges = corners - np.roll(corners, -1, axis=2)
    return float(np.linalg.norm(edges, axis=-1).max())
