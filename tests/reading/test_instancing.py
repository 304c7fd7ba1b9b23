"""PointInstancer instances are meshes: found at the analytic time, named by instancer and index."""

import math

import numpy as np
import pytest
from pxr import Usd, UsdGeom

from usdksl.reading.loader import load_shot

from builders import INSTANCE_DROP, falling_instancer, sha256 as file_digest
from .conftest import contact_rows, run_cli

INSTANCER = "/World/scatter"
PROTOTYPE_PRIMS = ("/World/scatter/Prototypes/box", "/World/scatter/Prototypes/crate/lid",
                   "/World/scatter/Prototypes/crate/body/geo")
INSTANCE_MESHES = {0: ["/box"], 1: ["/crate/lid", "/crate/body/geo"], 3: ["/crate/lid", "/crate/body/geo"],
                   4: ["/box"]}
#: The continuous check's default time tolerance, as a fraction of a sample interval (usdksl check --tolerance).
CCD_TOLERANCE = 1e-6
#: Rounding slack for "never later": the analytic time is computed in double from the same float32 data.
ROUNDING = 1e-9


def _first_contact_per_instance(contacts):
    first = {}
    for (_, _, prim_b, _), time in contacts.items():
        index = _instance_of(prim_b)
        first[index] = min(first.get(index, math.inf), time)
    return first


def _assert_analytic(first, expected):
    interval = INSTANCE_DROP["end"] - INSTANCE_DROP["start"]
    assert set(first) == set(expected)
    for index, time in first.items():
        assert expected[index] - CCD_TOLERANCE * interval <= time <= expected[index] + ROUNDING, (index, time)


def _instance_of(name):
    """'/World/scatter[3]/crate/lid' -> 3."""
    assert name.startswith(INSTANCER + "[")
    return int(name[len(INSTANCER) + 1:name.index("]")])


@pytest.fixture
def scatter(tmp_path):
    path = tmp_path / "scatter.usda"
    expected = falling_instancer(path)
    return path, expected


def test_instances_are_loaded_by_name_and_prototypes_never_alone(scatter):
    path, expected = scatter
    shot = load_shot(path)
    names = {mesh.path for mesh in shot.meshes}
    wanted = {f"{INSTANCER}[{i}]{relative}" for i, relatives in INSTANCE_MESHES.items() for relative in relatives}
    assert names == wanted | {"/World/Sheet"}
    assert not names & set(PROTOTYPE_PRIMS)
    for mesh in shot.meshes:
        if mesh.instancer:
            assert mesh.instancer == INSTANCER and mesh.instance_index == _instance_of(mesh.path)
            assert mesh.source in PROTOTYPE_PRIMS and mesh.kind == "rigid"
            assert mesh.times.tolist() == [INSTANCE_DROP["start"], INSTANCE_DROP["end"]]


def test_instance_points_follow_usd_instance_transforms(scatter):
    path, _ = scatter
    shot = load_shot(path)
    stage = shot.stage
    instancer = UsdGeom.PointInstancer(stage.GetPrimAtPath(INSTANCER))
    for mesh in shot.meshes:
        if not mesh.instancer:
            continue
        prototype_mesh = stage.GetPrimAtPath(mesh.source)
        root = stage.GetPrimAtPath("/World/scatter/Prototypes/" + mesh.path.split("]/")[1].split("/")[0])
        for k, time in enumerate(mesh.times.tolist()):
            code = Usd.TimeCode(time)
            xform = np.array(instancer.ComputeInstanceTransformsAtTime(
                code, code, UsdGeom.PointInstancer.IncludeProtoXform, UsdGeom.PointInstancer.IgnoreMask))
            relative = (np.array(UsdGeom.Xformable(prototype_mesh).ComputeLocalToWorldTransform(code))
                        @ np.linalg.inv(np.array(UsdGeom.Xformable(root).ComputeLocalToWorldTransform(code))))
            full = relative @ xform[mesh.instance_index] @ np.array(instancer.ComputeLocalToWorldTransform(code))
            local = np.asarray(UsdGeom.Mesh(prototype_mesh).GetPointsAttr().Get(code), float)
            expected = (np.hstack([local, np.ones((len(local), 1))]) @ full)[:, :3]
            np.testing.assert_allclose(mesh.points[k], expected, rtol=0, atol=1e-9)


def test_contacts_at_the_analytic_time_named_by_instancer_and_index(scatter, check):
    path, expected = scatter
    digest = file_digest(path)
    result, contacts, summary = check(path)
    assert result.exit_code == 1, result.stderr
    for prim_a, _, prim_b, _ in contacts:        # instances only touch the sheet
        assert prim_a == "/World/Sheet" and prim_b.startswith(INSTANCER + "[")
    assert set(expected) == {0, 1, 3, 4}          # instance 2 is invisible at every sample
    _assert_analytic(_first_contact_per_instance(contacts), expected)
    assert not any(prim in key for key in summary for prim in PROTOTYPE_PRIMS)
    assert file_digest(path) == digest


def test_velocities_that_agree_with_positions_change_nothing(tmp_path, check):
    path = tmp_path / "consistent.usda"
    expected = falling_instancer(path, velocities="consistent")
    result, contacts, _ = check(path)
    assert result.exit_code == 1 and "velocities" not in result.stderr, result.stderr
    plain = tmp_path / "plain.usda"
    falling_instancer(plain)
    _, plain_contacts, _ = check(plain)
    assert set(contacts) == set(plain_contacts)
    _assert_analytic(_first_contact_per_instance(contacts), expected)
    _assert_analytic(_first_contact_per_instance(plain_contacts), expected)


def test_velocities_that_disagree_with_positions_are_warned_about(tmp_path):
    path = tmp_path / "still.usda"
    falling_instancer(path, velocities="zero")     # USD would hold each instance until the next sample
    result = run_cli("check", path, "--out", tmp_path / "out")
    assert result.exit_code == 1, result.stderr
    warnings = [line for line in result.stderr.splitlines() if "velocities" in line]
    assert len(warnings) == 1 and warnings[0].startswith("usdksl: warning: ")
    assert str(path) in warnings[0] and INSTANCER in warnings[0] and "straight line" in warnings[0]


def test_inactive_ids_are_skipped(tmp_path):
    path = tmp_path / "inactive.usda"
    falling_instancer(path, invisible=(), inactive=(1, 4))
    indices = {mesh.instance_index for mesh in load_shot(path).meshes if mesh.instancer}
    assert indices == {0, 2, 3}


def test_changing_proto_indices_are_an_input_error(tmp_path):
    path = tmp_path / "swap.usda"
    expected = falling_instancer(path, proto_index_change=(6.0, 3, 0))
    result = run_cli("check", path, "--out", tmp_path / "out")
    assert result.exit_code == 2
    errors = [line for line in result.stderr.splitlines() if line.startswith("usdksl: error")]
    assert len(errors) == 1
    assert str(path) in errors[0] and INSTANCER in errors[0] and "time 6" in errors[0]
    assert "instance 3 switches from prototype 1 to 0" in errors[0]
    assert not (tmp_path / "out").exists()
    before = run_cli("check", path, "--out", tmp_path / "out", "--time-range", 1, 5)
    assert before.exit_code == 1, before.stderr
    # the instances that reach the sheet by time 5, each at its analytic time: to the rounding of the positions
    # USD interpolates at the cut (float32, half a unit in the last place is at most 2.4e-7 units here; the
    # instances fall at least 0.35 units a time code, so below 1e-6 time codes)
    first = _first_contact_per_instance(contact_rows(tmp_path / "out" / "swap.contacts.csv"))
    assert set(first) == {index for index, time in expected.items() if time <= 5.0} and first
    assert all(abs(first[index] - expected[index]) <= 1e-6 for index in first), (first, expected)


def test_override_layer_carries_per_instance_times_on_the_instancer(scatter, tmp_path):
    path, expected = scatter
    out = tmp_path / "out"
    result = run_cli("check", path, "--out", out)
    assert result.exit_code == 1, result.stderr
    stage = Usd.Stage.Open(str(out / "scatter.usdksl.usda"))
    instancer = stage.GetPrimAtPath(INSTANCER)
    times = np.array(instancer.GetAttribute("usdksl:instanceFirstContactTime").Get())
    assert times.shape == (5,) and math.isnan(times[2])
    for index, time in expected.items():
        assert abs(times[index] - time) <= CCD_TOLERANCE * 10
    assert instancer.GetAttribute("usdksl:contactInstanceCount").Get() == 4
    assert instancer.GetRelationship("usdksl:contactsWith").GetTargets() == ["/World/Sheet"]
    sheet = stage.GetPrimAtPath("/World/Sheet")
    assert sheet.GetRelationship("usdksl:contactsWith").GetTargets() == [INSTANCER]
    for prototype in PROTOTYPE_PRIMS:          # nothing is authored on the prototypes themselves
        assert not stage.GetPrimAtPath(prototype).GetAttribute("usdksl:contactFaceCount")


def test_info_lists_instances_and_prims_selects_them(scatter, tmp_path):
    path, expected = scatter
    result = run_cli("info", path)
    assert result.exit_code == 0, result.stderr
    listed = [line.split()[0] for line in result.stdout.splitlines() if line.startswith(INSTANCER + "[")]
    assert sorted(listed) == sorted(f"{INSTANCER}[{i}]{r}" for i, rs in INSTANCE_MESHES.items() for r in rs)
    assert f"instances: 6 meshes from 1 PointInstancer ({INSTANCER})" in result.stdout
    selected = run_cli("check", path, "--out", tmp_path / "out", "--prims", INSTANCER, "--prims", "/World/Sheet",
                       "--exclude", f"{INSTANCER}[[]4]*", "-v")
    assert selected.exit_code == 1, selected.stderr
    assert f"check /World/Sheet x {INSTANCER}[0]/box" in selected.stderr
    _assert_analytic(_first_contact_per_instance(contact_rows(tmp_path / "out" / "scatter.contacts.csv")),
                     {index: time for index, time in expected.items() if index != 4})
    # named only where it is said to be left out: in the plan and in the coverage account
    assert f"{INSTANCER}[4]/box" not in selected.stderr.replace(f"skip mesh {INSTANCER}[4]/box", "").replace(
        f"scoped out: {INSTANCER}[4]/box: excluded by --prims/--exclude", "")


def test_excluding_an_instancer_skips_its_checks_too(tmp_path):
    path = tmp_path / "swap.usda"
    falling_instancer(path, proto_index_change=(6.0, 3, 0))   # an input error when the instancer is read
    result = run_cli("check", path, "--out", tmp_path / "out", "--exclude", INSTANCER, "-v")
    assert result.exit_code == 0, result.stderr
    assert f"skip mesh {INSTANCER}[0]/box: excluded by --prims/--exclude (not loaded)" in result.stderr


def test_nested_instancer_and_missing_prototype_are_warned_about(tmp_path):
    path = tmp_path / "nested.usda"
    falling_instancer(path)
    stage = Usd.Stage.Open(str(path))
    UsdGeom.PointInstancer.Define(stage, "/World/scatter/Prototypes/crate/pebbles")
    relationship = UsdGeom.PointInstancer(stage.GetPrimAtPath(INSTANCER)).GetPrototypesRel()
    relationship.AddTarget("/World/scatter/Prototypes/gone")
    stage.GetRootLayer().Save()
    shot = load_shot(path)
    nested = [w for w in shot.warnings if "/World/scatter/Prototypes/crate/pebbles" in w]
    missing = [w for w in shot.warnings if "/World/scatter/Prototypes/gone" in w]
    assert len(nested) == 1 and "not checked" in nested[0]
    assert len(missing) == 1 and "prototype 2" in missing[0]
    assert {mesh.instance_index for mesh in shot.meshes if mesh.instancer} == set(INSTANCE_MESHES)
    assert [item.prim for item in shot.unchecked] == ["/World/scatter/Prototypes/crate/pebbles"]

    out = tmp_path / "out"
    strict = run_cli("check", path, "--strict", "--out", out)
    assert strict.exit_code == 2, strict.output
    errors = [line for line in strict.stderr.splitlines() if line.startswith("usdksl: error")]
    assert len(errors) == 1 and "/World/scatter/Prototypes/crate/pebbles" in errors[0] and "--strict" in errors[0]
    assert not out.exists() or not any(out.iterdir())
