"""Builders for small USD stages written with pxr in tmp_path, and a pxr-only reference."""

import hashlib

import numpy as np
from pxr import Gf, Usd, UsdGeom, Vt


def write_mesh(stage, path, counts, indices, points=None, samples=None, holes=None,
               topology_samples=None):
    """A mesh with static ``points`` and/or ``samples`` {time: points}."""
    mesh = UsdGeom.Mesh.Define(stage, path)
    mesh.CreateFaceVertexCountsAttr(Vt.IntArray([int(c) for c in counts]))
    mesh.CreateFaceVertexIndicesAttr(Vt.IntArray([int(i) for i in indices]))
    if holes is not None:
        mesh.CreateHoleIndicesAttr(Vt.IntArray([int(h) for h in holes]))
    attribute = mesh.CreatePointsAttr()
    if points is not None:
        attribute.Set(Vt.Vec3fArray.FromNumpy(np.asarray(points, dtype=np.float32)))
    for time, value in (samples or {}).items():
        attribute.Set(Vt.Vec3fArray.FromNumpy(np.asarray(value, dtype=np.float32)), time)
    for time, (t_counts, t_indices) in (topology_samples or {}).items():
        mesh.GetFaceVertexCountsAttr().Set(Vt.IntArray([int(c) for c in t_counts]), time)
        mesh.GetFaceVertexIndicesAttr().Set(Vt.IntArray([int(i) for i in t_indices]), time)
    return mesh


def quad_grid(columns=2, rows=2, size=1.0):
    xs = np.linspace(0, size, columns + 1)
    x, z = np.meshgrid(xs, np.linspace(0, size, rows + 1))
    points = np.stack([x.ravel(), np.zeros(x.size), z.ravel()], axis=1)
    counts, indices = [], []
    for j in range(rows):
        for i in range(columns):
            a = j * (columns + 1) + i
            counts.append(4)
            indices += [a, a + 1, a + columns + 2, a + columns + 1]
    return points, counts, indices


def new_stage(path):
    stage = Usd.Stage.CreateNew(str(path))
    stage.SetTimeCodesPerSecond(24)
    return stage


def reference_world_points(stage, prim_path, time):
    """World points straight from pxr: points.Get(t), each transformed by Gf (tiny meshes only)."""
    prim = stage.GetPrimAtPath(prim_path)
    local = UsdGeom.Mesh(prim).GetPointsAttr().Get(time)
    matrix = UsdGeom.Xformable(prim).ComputeLocalToWorldTransform(Usd.TimeCode(time))
    return np.array([list(matrix.Transform(Gf.Vec3d(p))) for p in local], dtype=np.float64)


def file_digest(path):
    return hashlib.sha256(open(path, "rb").read()).hexdigest()
