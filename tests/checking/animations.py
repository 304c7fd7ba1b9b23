"""Small animated meshes for core tests: built with numpy, no USD involved."""

from dataclasses import dataclass

import numpy as np


@dataclass
class Mesh:
    times: np.ndarray
    points: np.ndarray
    triangles: np.ndarray
    triangle_face: np.ndarray


def grid(nx, ny, size=1.0):
    """A flat (nx x ny quads) sheet in the XY plane, two triangles per quad, one face per triangle."""
    xs, ys = np.meshgrid(np.linspace(0, size, nx + 1), np.linspace(0, size, ny + 1), indexing="ij")
    verts = np.stack([xs.ravel(), ys.ravel(), np.zeros(xs.size)], axis=1)
    idx = np.arange((nx + 1) * (ny + 1)).reshape(nx + 1, ny + 1)
    a, b, c, d = idx[:-1, :-1].ravel(), idx[1:, :-1].ravel(), idx[1:, 1:].ravel(), idx[:-1, 1:].ravel()
    tris = np.concatenate([np.stack([a, b, c], 1), np.stack([a, c, d], 1)]).astype(np.int32)
    return verts, tris


def animated(times, frames, triangles, faces=None):
    times = np.asarray(times, dtype=np.float64)
    points = np.ascontiguousarray(np.asarray(frames, dtype=np.float64))
    triangles = np.asarray(triangles, dtype=np.int32)
    if faces is None:
        faces = np.arange(triangles.shape[0], dtype=np.int32)
    return Mesh(times, points, triangles, np.asarray(faces, dtype=np.int32))


def folding_sheet(n=6, samples=9):
    """A sheet folding about its middle line until the halves pass through each other."""
    verts, tris = grid(n, 2)
    frames = []
    for angle in np.linspace(0.0, 1.15 * np.pi, samples):
        p = verts.copy()
        right = p[:, 0] > 0.5
        dx = p[right, 0] - 0.5
        p[right, 0] = 0.5 + dx * np.cos(angle)
        p[right, 2] = dx * np.sin(angle) + 0.05 * dx * np.sin(angle / 2)  # slight offset so halves cross
        frames.append(p)
    return animated(np.arange(samples, dtype=float), frames, tris)


def sheets_passing(n=4, samples=5):
    """Two parallel sheets: the upper one moves down through the lower one."""
    verts, tris = grid(n, n)
    lower = animated(np.arange(samples, dtype=float), [verts] * samples, tris)
    upper_frames = [verts + [0.1, 0.07, 1.0 - 2.0 * k / (samples - 1)] for k in range(samples)]
    upper = animated(np.arange(samples, dtype=float), upper_frames, tris)
    return lower, upper


def tunnelling_triangle():
    """A small triangle crossing a plane entirely between two samples."""
    verts, tris = grid(2, 2, size=2.0)
    plane = animated([0.0, 1.0], [verts, verts], tris)
    small = np.array([[0.9, 0.9, 1.0], [1.0, 0.9, 1.0], [0.9, 1.0, 1.0]])
    bullet = animated([0.0, 1.0], [small, small - [0, 0, 2.0]], [[0, 1, 2]])
    return plane, bullet
