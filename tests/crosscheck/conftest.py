"""Stage builders for the cross-check tests: small USD shots written to tmp_path with pxr."""

import numpy as np
import pytest
from pxr import Usd, UsdGeom, Vt


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


@pytest.fixture
def shot_writer(tmp_path):
    def write(name, meshes, **kwargs):
        return write_shot(tmp_path / name, meshes, **kwargs)
    return write
