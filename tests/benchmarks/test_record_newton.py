"""benchmarks/record_newton.py writes what a simulation recorded (Newton itself is not needed here): a sample a
frame, or with every substep recorded one run twice, every substep (time codes frame + k/N) and its whole
frames alone, the pair benchmarks/densify.py ``--dense`` compares."""

import json

import numpy as np
import pytest
from pxr import Usd, UsdGeom

import record_newton

FRAMES, SUBSTEPS = 3, 4
SAMPLES = FRAMES * SUBSTEPS + 1


@pytest.fixture()
def recorded():
    """A two-triangle cloth and a moving box collider, their positions distinct at every sample."""
    rng = np.random.default_rng(7)
    cloth = record_newton.ClothPiece("/World/Cloth", 0, 4, np.array([[0, 1, 2], [0, 2, 3]], np.int32))
    box = record_newton.Collider("/World/Ball/Shape", 0, np.zeros((3, 3)), np.array([3], np.int32),
                                 np.array([0, 1, 2], np.int32))
    scene = record_newton.Scene(builder=None, cloths=[cloth], colliders=[box], default_frames=FRAMES,
                                substeps=SUBSTEPS, iterations=1, solver_options={})
    positions = rng.normal(size=(SAMPLES, 4, 3)).astype(np.float32)
    bodies = np.zeros((SAMPLES, 1, 7))
    bodies[:, 0, :3] = rng.normal(size=(SAMPLES, 3))
    bodies[:, 0, 6] = 1.0
    return scene, positions, bodies


def _samples(path, prim):
    stage = Usd.Stage.Open(path)
    points = UsdGeom.Mesh(stage.GetPrimAtPath(prim)).GetPointsAttr()
    times = points.GetTimeSamples()
    return times, [np.array(points.Get(t)) for t in times], stage


def test_every_substep_writes_the_run_twice_at_its_sub_frame_times_and_its_frames(recorded, tmp_path):
    scene, positions, bodies = recorded
    path = str(tmp_path / "newton_test_f3.usdc")
    dense, frames = record_newton.write_recording(path, scene, positions, bodies, {"scene": "test"}, SUBSTEPS)
    assert dense.endswith("_f3_sub4.usdc") and frames.endswith("_f3_sub4_frames.usdc")

    times, points, stage = _samples(dense, "/World/Cloth")
    assert times == pytest.approx([i / SUBSTEPS for i in range(SAMPLES)], abs=0)
    for sample, value in enumerate(points):
        np.testing.assert_array_equal(value, positions[sample])
    translate = UsdGeom.Xformable(stage.GetPrimAtPath("/World/Ball")).GetOrderedXformOps()[0]
    assert translate.GetAttr().GetTimeSamples() == times
    np.testing.assert_allclose(np.array(translate.Get(times[5])), bodies[5, 0, :3])
    assert stage.GetEndTimeCode() == FRAMES

    frame_times, frame_points, frame_stage = _samples(frames, "/World/Cloth")
    assert frame_times == [float(f) for f in range(FRAMES + 1)]
    for frame, value in enumerate(frame_points):
        np.testing.assert_array_equal(value, positions[frame * SUBSTEPS])
    translate = UsdGeom.Xformable(frame_stage.GetPrimAtPath("/World/Ball")).GetOrderedXformOps()[0]
    np.testing.assert_allclose(np.array(translate.Get(2.0)), bodies[2 * SUBSTEPS, 0, :3])

    with open(dense[:-len(".usdc")] + ".json") as sidecar:
        assert json.load(sidecar)["samplesPerFrame"] == SUBSTEPS
    with open(frames[:-len(".usdc")] + ".json") as sidecar:
        assert json.load(sidecar)["samplesPerFrame"] == 1


def test_a_sample_a_frame_writes_one_cache_at_whole_frames(recorded, tmp_path):
    scene, positions, bodies = recorded
    path = str(tmp_path / "newton_test_f12.usdc")
    assert record_newton.write_recording(path, scene, positions, bodies, {}) == [path]
    times, points, _ = _samples(path, "/World/Cloth")
    assert times == [float(f) for f in range(SAMPLES)]
    np.testing.assert_array_equal(points[-1], positions[-1])
