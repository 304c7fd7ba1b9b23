"""Tiny stage builders for the check tests: every shot is written with pxr into tmp_path."""

import hashlib
from pathlib import Path

import numpy as np
from pxr import Usd, UsdGeom, Vt

# A unit quad split into nothing: one authored quad face in the XZ plane at height 0.
QUAD_POINTS = np.array([[0, 0, 0], [1, 0, 0], [1, 0, 1], [0, 0, 1]], dtype=np.float64)
QUAD_COUNTS = [4]
QUAD_INDICES = [0, 1, 2, 3]

# Two quads sharing an edge (faces 0 and 1).
STRIP_POINTS = np.array([[0, 0, 0], [1, 0, 0], [2, 0, 0], [2, 0, 1], [1, 0, 1], [0, 0, 1]], dtype=np.float64)
STRIP_COUNTS = [4, 4]
STRIP_INDICES = [0, 1, 4, 5, 1, 2, 3, 4]


def new_stage(path, tcps=24.0, fps=None, start=1.0, end=24.0, up="Y", meters=1.0, default_prim="World"):
    stage = Usd.Stage.CreateNew(str(path))
    stage.SetTimeCodesPerSecond(tcps)
    if fps is not None:
        stage.SetFramesPerSecond(fps)
    stage.SetStartTimeCode(start)
    stage.SetEndTimeCode(end)
    UsdGeom.SetStageUpAxis(stage, up)
    UsdGeom.SetStageMetersPerUnit(stage, meters)
    world = UsdGeom.Xform.Define(stage, "/World")
    if default_prim:
        stage.SetDefaultPrim(world.GetPrim())
    return stage


def add_mesh(stage, path, points, counts=QUAD_COUNTS, indices=QUAD_INDICES, samples=None):
    """``samples``: {time: points} for an animated mesh; otherwise ``points`` is the default value."""
    mesh = UsdGeom.Mesh.Define(stage, path)
    mesh.CreateFaceVertexCountsAttr(Vt.IntArray(list(counts)))
    mesh.CreateFaceVertexIndicesAttr(Vt.IntArray(list(indices)))
    attribute = mesh.CreatePointsAttr()
    if samples:
        for time, value in samples.items():
            attribute.Set(Vt.Vec3fArray.FromNumpy(np.asarray(value, np.float32)), time)
    else:
        attribute.Set(Vt.Vec3fArray.FromNumpy(np.asarray(points, np.float32)))
    return mesh


def falling_quad_samples(offset=(0.0, 0.0, 0.0), start_height=1.0, end_height=-1.0, times=(1.0, 24.0)):
    """A quad moving straight down through y = 0 between the two times."""
    base = QUAD_POINTS + np.asarray(offset)
    return {times[0]: base + [0, start_height, 0], times[1]: base + [0, end_height, 0]}


def sha256(path) -> str:
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


def snapshot(directory) -> dict:
    """{relative path: sha256} of every file below directory (to prove nothing was written)."""
    directory = Path(directory)
    return {str(p.relative_to(directory)): sha256(p) for p in sorted(directory.rglob("*")) if p.is_file()}


def fifty_mesh_scene(path):
    """48 static quads, a falling cloth quad and a rigidly moving box under /World/Anim."""
    stage = new_stage(path)
    for k in range(48):
        add_mesh(stage, f"/World/Static/M{k:02d}", QUAD_POINTS + [3.0 * k, 0, 0])
    add_mesh(stage, "/World/Anim/Cloth", None, samples=falling_quad_samples())
    rigid = UsdGeom.Xform.Define(stage, "/World/Anim/Mover")
    op = rigid.AddTranslateOp()
    op.Set((0.0, 0.0, 0.0), 1.0)
    op.Set((5.0, 0.0, 0.0), 24.0)
    add_mesh(stage, "/World/Anim/Mover/Box", QUAD_POINTS + [0, 2.0, 0])
    stage.GetRootLayer().Save()
