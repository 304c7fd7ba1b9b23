"""Solid gprims that are not meshes (implicit colliders, NURBS patches) are never read past in silence:
one warning per kind naming the first prim, exit 2 under --strict; guides, invisible prims and
prototypes without instances are left out, as they are for meshes."""

import numpy as np
from pxr import UsdGeom, Vt

from usdksl.reading.loader import load_shot

from builders import falling_quad_samples, add_mesh, new_stage
from .conftest import run_cli


def solids_stage(path):
    stage = new_stage(path)
    add_mesh(stage, "/World/Cloth", None, samples=falling_quad_samples())
    UsdGeom.Sphere.Define(stage, "/World/Colliders/head")
    UsdGeom.Sphere.Define(stage, "/World/Colliders/hand")
    UsdGeom.Capsule.Define(stage, "/World/Colliders/guide_arm").CreatePurposeAttr(UsdGeom.Tokens.guide)
    UsdGeom.Cube.Define(stage, "/World/Colliders/hidden").CreateVisibilityAttr(UsdGeom.Tokens.invisible)
    rocks = UsdGeom.PointInstancer.Define(stage, "/World/rocks")
    UsdGeom.Cube.Define(stage, "/World/rocks/Prototypes/rock")
    UsdGeom.Cylinder.Define(stage, "/World/rocks/Prototypes/unused")
    rocks.CreatePrototypesRel().SetTargets(["/World/rocks/Prototypes/rock", "/World/rocks/Prototypes/unused"])
    rocks.CreateProtoIndicesAttr(Vt.IntArray([0, 0, 0]))
    rocks.CreatePositionsAttr(Vt.Vec3fArray([(float(x), -3.0, 0.0) for x in range(3)]))
    stage.GetRootLayer().Save()
    return path


def test_each_kind_of_unmeshed_solid_is_one_warning_and_guides_hidden_and_unused_are_not(tmp_path):
    shot = load_shot(solids_stage(tmp_path / "solids.usda"))
    reasons = {item.prim: item.reason for item in shot.unchecked}
    assert set(reasons) == {"/World/Colliders/head", "/World/rocks/Prototypes/rock"}
    assert reasons["/World/Colliders/head"].startswith("2 UsdGeom.Sphere prims (first /World/Colliders/head)")
    assert reasons["/World/rocks/Prototypes/rock"].startswith("1 UsdGeom.Cube prim ")
    assert sum("not checked: usdksl checks UsdGeom.Mesh" in warning for warning in shot.warnings) == 2
    assert [mesh.path for mesh in shot.meshes] == ["/World/Cloth"]


def test_strict_refuses_a_stage_with_unmeshed_solids(tmp_path):
    path = solids_stage(tmp_path / "solids.usda")
    plain = run_cli("check", path, "--out", tmp_path / "plain")
    assert plain.exit_code == 0, plain.output
    assert "UsdGeom.Sphere" in plain.stderr
    strict = run_cli("check", path, "--strict", "--out", tmp_path / "strict")
    assert strict.exit_code == 2, strict.output
    errors = [line for line in strict.stderr.splitlines() if line.startswith("usdksl: error")]
    assert len(errors) == 1 and "/World/Colliders/head" in errors[0] and "--strict" in errors[0], strict.stderr
    assert not (tmp_path / "strict").exists() or not any((tmp_path / "strict").iterdir())


def test_prims_selection_leaves_unselected_solids_out(tmp_path):
    shot = load_shot(solids_stage(tmp_path / "solids.usda"), include=["/World/Cloth"])
    assert shot.unchecked == []
    assert np.asarray([mesh.path for mesh in shot.meshes]).tolist() == ["/World/Cloth"]
