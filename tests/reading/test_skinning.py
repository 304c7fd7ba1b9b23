"""UsdSkel skinning: usdksl poses skinned meshes exactly as UsdSkel.BakeSkinning bakes them."""

import numpy as np
import pytest
from pxr import Sdf, Usd, UsdGeom, UsdSkel

from usdksl.errors import UsdkslInputError
from usdksl.reading.loader import load_shot
from usdksl.reading.skinning import find_skinned_meshes

from builders import baked_copy, sha256 as file_digest, skinned_arm, skinned_crowd
from .conftest import run_cli

#: Largest time difference between a contact on the skinned stage and on its baked copy (time codes).
TIME_AGREEMENT = 1e-4
#: Float32 resolution of the arm's coordinates (|p| <= 4): UsdSkel skins and stores points as float32.
FLOAT32_POINTS = 4 * 4.0 * np.finfo(np.float32).eps

SHARED_FILES = {"lbs": "/Root", "blendshapes": "/TestPlane"}


@pytest.fixture
def arm(tmp_path):
    path = tmp_path / "arm.usda"
    names = skinned_arm(path, rigid_bound_prop=True)
    digest = file_digest(path)
    baked = baked_copy(path, tmp_path / "arm_baked.usda")
    assert file_digest(path) == digest                   # baking wrote the copy only
    return path, baked, names


def test_check_on_skinned_stage_matches_check_on_baked_copy(arm, check):
    path, baked, names = arm
    digest = file_digest(path)
    result, contacts, summary = check(path)
    baked_result, baked_contacts, baked_summary = check(baked)
    assert result.exit_code == baked_result.exit_code == 1, result.stderr + baked_result.stderr
    assert len(contacts) > 10
    assert set(contacts) == set(baked_contacts)
    assert max(abs(contacts[key] - baked_contacts[key]) for key in contacts) <= TIME_AGREEMENT
    assert {pair for pair in summary} == {(names["arm"], names["sheet"]), (names["prop"], names["sheet"])}
    assert file_digest(path) == digest


def test_loaded_points_equal_baked_points(arm):
    path, baked, names = arm
    skinned, reference = load_shot(path), load_shot(baked)
    assert [m.path for m in skinned.meshes] == [m.path for m in reference.meshes]
    for mesh in skinned.meshes:
        other = reference.mesh(mesh.path)
        assert mesh.times.tolist() == other.times.tolist()
        assert mesh.kind == other.kind
        np.testing.assert_allclose(mesh.points, other.points, rtol=0, atol=FLOAT32_POINTS)
    arm_mesh = skinned.mesh(names["arm"])
    assert arm_mesh.kind == "deforming"
    assert arm_mesh.times.tolist() == [float(t) for t in range(1, 13)]
    # the bend really takes the forearm down through y = 0; the shoulder vertex (on the shoulder joint's
    # pivot) moves only with the SkelRoot, which translates by 0.4 in x
    assert arm_mesh.points[0, :, 1].min() > 1.0 and arm_mesh.points[-1, :, 1].min() < -0.1
    np.testing.assert_allclose(arm_mesh.points[:, 0, 0], np.linspace(0.0, 0.4, 12), rtol=0, atol=1e-6)
    assert skinned.mesh(names["prop"]).kind == "rigid"  # constant influences: one transform, like the bake


def test_unbaked_stage_was_called_static_before(arm):
    """Without UsdSkel the arm's authored points never change: a reader that skips UsdSkel would call it
    static."""
    path, _, names = arm
    stage = Usd.Stage.Open(str(path))
    points = UsdGeom.Mesh(stage.GetPrimAtPath(names["arm"])).GetPointsAttr()
    assert points.GetNumTimeSamples() == 0
    assert names["arm"] in find_skinned_meshes(stage)


def test_a_usd_that_cannot_name_the_skel_root_type_asks_usdskel(arm, monkeypatch):
    """The loader looks for SkelRoots before importing UsdSkel; when USD does not know the schema's type by
    name it does not conclude "no skeleton" but asks UsdSkel, and the arm is still posed."""
    from usdksl.reading import loader

    path, _, names = arm
    expected = load_shot(path).mesh(names["arm"]).points
    monkeypatch.setattr(loader, "SKEL_ROOT_SCHEMA", "NoSuchSchemaInThisUsd")
    posed = load_shot(path).mesh(names["arm"])
    assert posed.kind == "deforming" and posed.points.tobytes() == expected.tobytes()


def test_info_calls_the_skinned_arm_deforming(arm):
    path, _, names = arm
    result = run_cli("info", path)
    assert result.exit_code == 0, result.stderr
    kinds = {line.split()[0]: line.split()[-1] for line in result.stdout.splitlines()[1:] if line.startswith("/")}
    assert kinds[names["arm"]] == "deforming" and kinds[names["prop"]] == "rigid"


def test_sample_times_are_the_union_of_animation_blend_shape_and_transform_samples(tmp_path):
    path = tmp_path / "sparse.usda"
    names = skinned_arm(path, bend_degrees=((1.0, 0.0), (4.0, 90.0)), bulge_weights=((1.0, 0.0), (9.5, 1.0)),
                        root_motion=((1.0, (0, 0, 0)), (6.5, (0.3, 0, 0)), (12.0, (0.5, 0, 0))), with_sheet=False)
    times = load_shot(path, skin_keys_only=True).mesh(names["arm"]).times.tolist()
    assert times == [1.0, 2.0, 3.0, 4.0, 6.5, 9.5, 12.0]
    # by default the frames between the sparse keys of the blend shape and the root are posed too
    times = load_shot(path).mesh(names["arm"]).times.tolist()
    assert times == sorted([float(t) for t in range(1, 13)] + [6.5, 9.5])


def _unbaked_over_shared_file(shared, name, root, tmp_path):
    """A layer that sublayers OpenUSD's baked file in place and undoes the bake: the root is a SkelRoot again
    and each skinned mesh's points are its rest points (the default BakeSkinning left under its samples)."""
    source = shared / "openusd" / f"openusd_testUsdSkelBakeSkinning_{name}.baked.usda"
    baked = Usd.Stage.Open(str(source))
    layer = Sdf.Layer.CreateNew(str(tmp_path / f"unbaked_{name}.usda"))
    layer.subLayerPaths.append(str(source))
    spec = Sdf.CreatePrimInLayer(layer, root)
    spec.specifier, spec.typeName = Sdf.SpecifierOver, "SkelRoot"
    rebound = []
    for prim in baked.Traverse():
        if prim.IsA(UsdGeom.Mesh) and prim.HasAPI(UsdSkel.BindingAPI):
            mesh_spec = Sdf.CreatePrimInLayer(layer, prim.GetPath())
            mesh_spec.specifier = Sdf.SpecifierOver
            points = Sdf.AttributeSpec(mesh_spec, "points", Sdf.ValueTypeNames.Point3fArray)
            points.default = UsdGeom.Mesh(prim).GetPointsAttr().Get(Usd.TimeCode.Default())
            rebound.append(str(prim.GetPath()))
    layer.Save()
    return source, layer.identifier, rebound


@pytest.mark.parametrize("name", sorted(SHARED_FILES))
def test_skinning_reproduces_openusd_baked_baselines(shared_data, tmp_path, name):
    source, unbaked, rebound = _unbaked_over_shared_file(shared_data, name, SHARED_FILES[name], tmp_path)
    digest = file_digest(source)
    assert rebound
    ours, reference = load_shot(unbaked), load_shot(source)
    assert set(find_skinned_meshes(ours.stage)) == set(rebound)
    assert not find_skinned_meshes(reference.stage)      # the bake made its SkelRoot an Xform: not skinned twice
    for path in rebound:
        mesh, baked = ours.mesh(path), reference.mesh(path)
        assert mesh.kind == "deforming"
        common, mine, theirs = np.intersect1d(mesh.times, baked.times, return_indices=True)
        assert len(common) == len(mesh.times) >= 2
        np.testing.assert_allclose(mesh.points[mine], baked.points[theirs], rtol=0,
                                   atol=4 * np.abs(baked.points).max() * np.finfo(np.float32).eps)
    assert file_digest(source) == digest


def test_skeleton_that_cannot_be_posed_is_an_input_error(tmp_path):
    path = tmp_path / "unposed.usda"
    names = skinned_arm(path, with_sheet=False)
    stage = Usd.Stage.Open(str(path))
    UsdSkel.BindingAPI(stage.GetPrimAtPath(names["skeleton"])).GetAnimationSourceRel().ClearTargets(True)
    UsdSkel.Skeleton(stage.GetPrimAtPath(names["skeleton"])).GetRestTransformsAttr().Clear()
    stage.GetRootLayer().Save()
    with pytest.raises(UsdkslInputError) as raised:
        load_shot(path)
    assert raised.value.prim == names["arm"] and "cannot pose" in str(raised.value)
    result = run_cli("check", path, "--out", tmp_path / "out")
    assert result.exit_code == 2
    assert [line for line in result.stderr.splitlines() if line.startswith("usdksl: error")] == [
        f"usdksl: error: {raised.value}"]
    excluded = run_cli("check", path, "--out", tmp_path / "out", "--exclude", names["arm"])
    assert excluded.exit_code == 2 and "no UsdGeom.Mesh prims match" in excluded.stderr   # not the skel error


def test_skinned_prototype_instances_are_posed_as_bake_skinning_bakes_them(tmp_path, check):
    """A skinned mesh inside a PointInstancer prototype: each instance carries UsdSkel's pose (its baked
    copy is the reference), so the arms reach the sheet; loaded unskinned they would never touch it."""
    path = tmp_path / "crowd.usda"
    names = skinned_crowd(path)
    baked = baked_copy(path, tmp_path / "crowd_baked.usda")
    skinned, reference = load_shot(path), load_shot(baked)
    for name in names:
        mesh, other = skinned.mesh(name), reference.mesh(name)
        assert mesh.kind == other.kind == "deforming"
        assert mesh.times.tolist() == other.times.tolist()
        np.testing.assert_allclose(mesh.points, other.points, rtol=0, atol=2 * FLOAT32_POINTS)
        assert mesh.points[0, :, 1].min() > 1.0 and mesh.points[-1, :, 1].min() < 0.0   # the bend is there

    result, contacts, summary = check(path)
    baked_result, baked_contacts, _ = check(baked)
    assert result.exit_code == baked_result.exit_code == 1, result.stderr + baked_result.stderr
    assert set(summary) == {tuple(sorted((name, "/World/Sheet"))) for name in names}
    assert set(contacts) == set(baked_contacts)
    assert max(abs(contacts[key] - baked_contacts[key]) for key in contacts) <= TIME_AGREEMENT
