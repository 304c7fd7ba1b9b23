"""Real files: OpenUSD's baked-skinning tests, the shipped samples, the benchmark generator."""

import filecmp
import importlib.util
import math

import numpy as np
import pytest
from pxr import Usd, UsdGeom

from usdksl.reading.loader import load_shot

OPENUSD_FILES = ["openusd_testUsdSkelBakeSkinning_lbs.baked.usda",
                 "openusd_testUsdSkelBakeSkinning_blendshapes.baked.usda"]


def pxr_world_points(stage, prim, time):
    """World points via pxr's ComputeLocalToWorldTransform, applied as a numpy matrix product."""
    local = np.asarray(UsdGeom.Mesh(prim).GetPointsAttr().Get(time), dtype=np.float64)
    matrix = np.array(UsdGeom.Xformable(prim).ComputeLocalToWorldTransform(time))
    return (np.hstack([local, np.ones((len(local), 1))]) @ matrix)[:, :3]


@pytest.mark.parametrize("name", OPENUSD_FILES)
def test_openusd_files_load_meshes_only_with_pxr_world_points(shared_data, name):
    path = shared_data / "openusd" / name
    shot = load_shot(path)
    stage = Usd.Stage.Open(str(path))
    all_prims = list(stage.Traverse())
    meshes = [p for p in all_prims if p.GetTypeName() == "Mesh"]
    others = {str(p.GetPath()) for p in all_prims} - {str(p.GetPath()) for p in meshes}
    assert [m.path for m in shot.meshes] == [str(p.GetPath()) for p in meshes]
    assert not others & {m.path for m in shot.meshes}
    for mesh, prim in zip(shot.meshes, meshes):
        expected_times = sorted(set(UsdGeom.Mesh(prim).GetPointsAttr().GetTimeSamples()))
        assert mesh.times.tolist() == expected_times
        assert mesh.kind == "deforming"
        counts = np.array(UsdGeom.Mesh(prim).GetFaceVertexCountsAttr().Get(mesh.times[0]))
        assert mesh.face_count == len(counts)
        assert mesh.triangle_count == int(np.maximum(counts - 2, 0).sum())
        for k, time in enumerate(mesh.times):
            np.testing.assert_allclose(mesh.points[k], pxr_world_points(stage, prim, time),
                                       rtol=0, atol=1e-9)
    assert shot.times.tolist() == sorted(set(np.concatenate([m.times for m in shot.meshes])))


def test_openusd_lbs_passes_over_curves_and_implicit_shapes(shared_data):
    shot = load_shot(shared_data / "openusd" / OPENUSD_FILES[0])
    stage = shot.stage
    skipped = {"BasisCurves", "Sphere", "Cube", "Cylinder", "Skeleton"}
    present = {p.GetTypeName() for p in stage.Traverse()}
    assert skipped <= present                       # the file really has them
    assert all(stage.GetPrimAtPath(m.path).GetTypeName() == "Mesh" for m in shot.meshes)
    assert shot.metadata["upAxis"] == "Y" and shot.metadata["startTimeCode"] == 1.0


def test_openusd_blendshapes_metadata(shared_data):
    shot = load_shot(shared_data / "openusd" / OPENUSD_FILES[1])
    assert shot.metadata["upAxis"] == "Z"
    assert shot.metadata["defaultPrim"] == "TestPlane"
    assert shot.metadata["endTimeCode"] == 131.0


EXPECTED_SAMPLES = {
    "drape.usda": {"/World/Cloth": "deforming", "/World/Box": "static"},
    "fold.usda": {"/World/Strip": "deforming"},
    "pass_through.usda": {"/World/Wall": "deforming", "/World/Mover/Box": "rigid"},
    "clean.usda": {"/World/Sheet": "deforming", "/World/Box": "static", "/World/Mover/Box": "rigid"},
}


@pytest.mark.parametrize("name", sorted(EXPECTED_SAMPLES))
def test_shipped_samples_load_with_expected_kinds(samples_dir, name):
    path = samples_dir / name
    assert path.stat().st_size < 2 * 2 ** 20
    shot = load_shot(path)
    assert {m.path: m.kind for m in shot.meshes} == EXPECTED_SAMPLES[name]
    metadata = shot.metadata
    assert metadata["timeCodesPerSecond"] == 24.0 and metadata["upAxis"] == "Y"
    assert metadata["defaultPrim"] == "World"
    assert shot.times[0] == metadata["startTimeCode"] and shot.times[-1] == metadata["endTimeCode"]


def test_pass_through_box_moves_through_the_wall(samples_dir):
    shot = load_shot(samples_dir / "pass_through.usda")
    box = shot.mesh("/World/Mover/Box")
    assert box.times.tolist() == [1.0, 24.0]          # the parent's keys, not the wall's frames
    assert box.points[0, :, 0].max() < -0.1 and box.points[-1, :, 0].min() > 0.1


def _load_script(samples_dir, name):
    spec = importlib.util.spec_from_file_location(f"usdksl_samples_{name}", samples_dir / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_make_samples_rewrites_the_shipped_files_byte_for_byte(samples_dir, tmp_path):
    make_samples = _load_script(samples_dir, "make_samples")
    assert make_samples.main(["--out", str(tmp_path)]) == 0
    for name in EXPECTED_SAMPLES:
        assert filecmp.cmp(tmp_path / name, samples_dir / name, shallow=False), name


@pytest.mark.parametrize("scene, size", [("tablecloth", 2000), ("swirl", 4000), ("character", 35000)])
def test_generated_scenes_are_piecewise_linear_between_keyframes(samples_dir, tmp_path, scene, size):
    generate = _load_script(samples_dir, "generate")
    keyframes, per_key = 3, 4
    path = generate.generate(scene, size, keyframes, per_key, seed=1, out=str(tmp_path / "g.usdc"))
    shot = load_shot(path)
    assert shot.times.tolist() == [float(t) for t in range(1, (keyframes - 1) * per_key + 2)]
    deforming = [m for m in shot.meshes if m.kind == "deforming"]
    assert len(deforming) == 1
    cloth = deforming[0]
    triangles = sum(m.triangle_count for m in shot.meshes)
    if scene == "character":
        assert abs(triangles - size) < 0.1 * size
        assert {m.kind for m in shot.meshes} == {"rigid", "deforming"}
    else:
        assert abs(cloth.face_count - size) < 0.05 * size
    # between keys (times 1, 5, 9) every sample is the linear blend of its two keys
    p = cloth.points
    for j in range(1, per_key):
        np.testing.assert_allclose(p[j], p[0] + (p[per_key] - p[0]) * j / per_key, atol=1e-5)
    assert not np.allclose(p[per_key] - p[0], p[2 * per_key] - p[per_key])   # keys differ


def test_generated_scene_is_deterministic(samples_dir, tmp_path):
    generate = _load_script(samples_dir, "generate")
    a = generate.generate("swirl", 4000, 3, 2, seed=5, out=str(tmp_path / "a.usdc"))
    b = generate.generate("swirl", 4000, 3, 2, seed=5, out=str(tmp_path / "b.usdc"))
    np.testing.assert_array_equal(load_shot(a).meshes[0].points, load_shot(b).meshes[0].points)
    assert math.isfinite(float(load_shot(a).meshes[0].points.sum()))
