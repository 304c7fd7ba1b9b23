"""Helpers for the cross-check tests: USD shot writers and a brute-force intersection oracle."""

import numpy as np
from pxr import Usd, UsdGeom, Vt

from usdksl.crosscheck.segment_crossing import segments_cross_triangles


def grid_sheet(size, count, z=0.0, origin=(0.0, 0.0)):
    """A flat square sheet of count x count quads in the plane z: (points[N, 3], counts, indices).

    Face f covers x cell f % count and y cell f // count."""
    ticks = np.linspace(0.0, size, count + 1)
    x, y = np.meshgrid(ticks + origin[0], ticks + origin[1])
    points = np.stack([x.ravel(), y.ravel(), np.full(x.size, float(z))], axis=1)
    ids = np.arange((count + 1) ** 2).reshape(count + 1, count + 1)
    quads = np.stack([ids[:-1, :-1], ids[:-1, 1:], ids[1:, 1:], ids[1:, :-1]], axis=-1).reshape(-1, 4)
    return points, np.full(len(quads), 4), quads.ravel()


def write_shot(path, meshes, start=None, end=None):
    """meshes: list of dicts with prim path, counts, indices and either `points` (static) or
    `samples` {time: points}. Writes a .usda and returns its path as str."""
    stage = Usd.Stage.CreateNew(str(path))
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.z)
    all_times = []
    for mesh in meshes:
        prim_path = mesh["path"]
        parent = prim_path.rsplit("/", 1)[0]
        if parent:
            UsdGeom.Xform.Define(stage, parent)
        geom = UsdGeom.Mesh.Define(stage, prim_path)
        geom.CreateFaceVertexCountsAttr(Vt.IntArray([int(c) for c in mesh["counts"]]))
        geom.CreateFaceVertexIndicesAttr(Vt.IntArray([int(i) for i in mesh["indices"]]))
        attribute = geom.CreatePointsAttr()
        if "samples" in mesh:
            for time, points in mesh["samples"].items():
                attribute.Set(Vt.Vec3fArray.FromNumpy(np.asarray(points, dtype=np.float32)), float(time))
                all_times.append(float(time))
        else:
            attribute.Set(Vt.Vec3fArray.FromNumpy(np.asarray(mesh["points"], dtype=np.float32)))
    if all_times:
        stage.SetStartTimeCode(start if start is not None else min(all_times))
        stage.SetEndTimeCode(end if end is not None else max(all_times))
    stage.GetRootLayer().Save()
    return str(path)


def brute_force_pairs(topology, vertices, allowed=None):
    """Every (triangle, triangle) pair where an edge of one properly crosses the other, the edge sharing
    no vertex with the triangle: all edge x triangle combinations, no acceleration (chunked)."""
    triangles = topology.triangles
    owners_edges = triangles[:, [[0, 1], [1, 2], [2, 0]]].reshape(-1, 2)
    owner = np.repeat(np.arange(len(triangles)), 3)
    found = set()
    chunk = max(1, 400000 // max(len(triangles), 1))
    for begin in range(0, len(owners_edges), chunk):
        edge_index, other = np.meshgrid(np.arange(begin, min(begin + chunk, len(owners_edges))),
                                        np.arange(len(triangles)), indexing="ij")
        edge_index, other = edge_index.ravel(), other.ravel()
        edge = owners_edges[edge_index]
        shares = (triangles[other] == edge[:, :1]).any(axis=1) | (triangles[other] == edge[:, 1:]).any(axis=1)
        keep = ~shares
        if allowed is not None:
            keep &= allowed[topology.triangle_mesh[owner[edge_index]], topology.triangle_mesh[other]]
        edge, edge_index, other = edge[keep], edge_index[keep], other[keep]
        corners = vertices[triangles[other]]
        hit = segments_cross_triangles(vertices[edge[:, 0]], vertices[edge[:, 1]], corners[:, 0],
                                       corners[:, 1], corners[:, 2])
        first, second = owner[edge_index[hit]], other[hit]
        found |= set(zip(np.minimum(first, second).tolist(), np.maximum(first, second).tolist()))
    return found
