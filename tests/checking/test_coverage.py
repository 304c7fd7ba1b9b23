"""The coverage account: every prim that can hold geometry and every stretch of the range, checked or named as not
checked (docs/contracts.md, Coverage), in CheckResult, the JSON report, -v and the summary line."""

import json

import pytest
from click.testing import CliRunner
from pxr import Sdf, Usd, UsdGeom

from builders import define_mesh, grid, new_stage
from usdksl.cli.main import main
from usdksl.pipeline import CheckOptions, check_shot
from usdksl.pipeline.coverage import CHECKED, NOT_CHECKED, SCOPED
from usdksl.warning_kinds import EMPTY_SAMPLE, NOT_A_SURFACE, OUTSIDE_TIME_RANGE, SCOPED_OUT, UNMESHED_SOLID

TIMES = [float(t) for t in range(1, 25)]


def cloth_scene(path, sphere=False, blocked_at=None):
    """A 3x3 cloth falling onto a floor (contact at t = 11), a still wall no pair needs and a prop left out by
    physics:collisionEnabled; optionally a UsdGeom.Sphere and a blocked cloth sample."""
    stage = new_stage(path, start=1.0, end=24.0)
    points, counts, indices = grid(3, 3, 2.0, 2.0)
    floor, floor_counts, floor_indices = grid(1, 1, 4.0, 4.0)
    define_mesh(stage, "/World/Floor", floor, floor_counts, floor_indices)
    cloth = define_mesh(stage, "/World/Cloth", None, counts, indices,
                        samples={t: points + [0.0, (11.0 - t) / 10.0, 0.0] for t in TIMES})
    if blocked_at is not None:
        cloth.GetPointsAttr().Set(Sdf.ValueBlock(), blocked_at)
    prop = define_mesh(stage, "/World/Prop", floor + [20.0, 0.0, 0.0], floor_counts, floor_indices,
                       samples={t: floor + [20.0, t, 0.0] for t in TIMES})
    prop.GetPrim().CreateAttribute("physics:collisionEnabled", Sdf.ValueTypeNames.Bool).Set(False)
    if sphere:
        UsdGeom.Sphere.Define(stage, "/World/Ball")
    stage.GetRootLayer().Save()
    return str(path)


def entries(coverage, status):
    return {entry.prim: entry for entry in coverage.entries if entry.status == status}


def test_a_complete_check_accounts_for_every_mesh(tmp_path):
    shot = cloth_scene(tmp_path / "cloth.usda")
    result = check_shot(shot, CheckOptions())
    coverage = result.coverage
    assert coverage.complete and coverage.span == (1.0, 24.0)
    assert set(entries(coverage, CHECKED)) == {"/World/Cloth", "/World/Floor"}
    scoped = entries(coverage, SCOPED)
    assert set(scoped) == {"/World/Prop"} and scoped["/World/Prop"].kind == SCOPED_OUT
    assert "collisionEnabled" in scoped["/World/Prop"].reason
    assert "NOT CHECKED" not in result.summary and result.exit_code == 1
    # every face of the 3x3 cloth lands on the floor's one face at t = 11
    prim_a, prim_b = result.table.prim_names()
    assert sorted(zip(prim_a, result.table.face_a.tolist(), prim_b, result.table.face_b.tolist())) == [
        ("/World/Cloth", face, "/World/Floor", 0) for face in range(9)]
    assert result.table.time.tolist() == pytest.approx([11.0] * 9, abs=1e-6)


def test_what_is_not_checked_is_named_in_the_result_the_json_and_the_summary(tmp_path):
    shot = cloth_scene(tmp_path / "cloth.usda", sphere=True, blocked_at=15.0)
    result = check_shot(shot, CheckOptions())
    missing = [entry for entry in result.coverage.entries if entry.status == NOT_CHECKED]
    assert {(entry.prim, entry.kind) for entry in missing} == {("/World/Ball", UNMESHED_SOLID),
                                                             ("/World/Cloth", EMPTY_SAMPLE)}
    gap = next(entry for entry in missing if entry.kind == EMPTY_SAMPLE)
    assert (gap.start, gap.end) == (14.0, 16.0)
    assert not result.coverage.complete
    assert "NOT CHECKED: 2 items on 2 prims" in result.summary

    out = tmp_path / "out"
    run = CliRunner().invoke(main, ["check", shot, "--out", str(out), "--json", str(out / "report.json"), "-v"])
    assert run.exit_code == 1, run.stderr
    document = json.loads((out / "report.json").read_text())
    assert document["coverage"]["complete"] is False and document["coverage"]["not_checked"] == 2
    assert {(e["prim"], e["status"], e["start"], e["end"]) for e in document["coverage"]["entries"]
            if e["kind"] == EMPTY_SAMPLE} == {("/World/Cloth", NOT_CHECKED, 14.0, 16.0)}
    assert {finding["kind"] for finding in document["findings"]} >= {EMPTY_SAMPLE}
    assert "not checked: /World/Cloth over 14..16: points are empty or blocked" in run.stderr
    strict = CliRunner().invoke(main, ["check", shot, "--out", str(tmp_path / "strict"), "--strict"])
    assert strict.exit_code == 2


def test_a_shot_without_contacts_but_with_unchecked_geometry_is_not_called_clean(tmp_path):
    shot = cloth_scene(tmp_path / "cloth.usda", sphere=True)
    result = check_shot(shot, CheckOptions(time_range=(1.0, 5.0)))
    assert result.exit_code == 0 and result.table.count == 0
    assert "clean" not in result.summary and "no contacts in what was checked" in result.summary
    outside = [entry for entry in result.coverage.entries if entry.kind == OUTSIDE_TIME_RANGE]
    assert [(entry.prim, entry.status, entry.start, entry.end) for entry in outside] == [("/", SCOPED, 5.0, 24.0)]


def test_a_time_range_without_samples_is_an_input_error(samples_dir, tmp_path):
    result = CliRunner().invoke(main, ["check", str(samples_dir / "fold.usda"), "--out", str(tmp_path / "a"),
                                       "--time-range", "50", "60"])
    assert result.exit_code == 2
    assert "--time-range 50..60 holds no sample of any mesh: the animated meshes' samples span 1..36" in result.stderr
    assert not (tmp_path / "a").exists()


def test_a_time_range_in_which_nothing_moves_warns_and_checks_nothing(samples_dir, tmp_path):
    # a farm chunk after the fold has come to rest: its motion is in the chunks before it
    result = CliRunner().invoke(main, ["check", str(samples_dir / "fold.usda"), "--out", str(tmp_path / "a"),
                                       "--time-range", "36", "60"])
    assert result.exit_code == 0, result.stderr
    assert "usdksl: warning: nothing moves over 36..60: no pair needs a check" in result.stderr



def test_curves_and_points_are_scoped_out_as_not_surfaces(tmp_path):
    shot = cloth_scene(tmp_path / "cloth.usda")
    stage = Usd.Stage.Open(shot)
    curves = UsdGeom.BasisCurves.Define(stage, "/World/Hair")
    curves.CreatePointsAttr([(0, 0, 0), (0, 1, 0), (0, 2, 0), (0, 3, 0)])
    curves.CreateCurveVertexCountsAttr([4])
    UsdGeom.Points.Define(stage, "/World/Spray").CreatePointsAttr([(0, 0, 0)])
    stage.GetRootLayer().Save()
    result = check_shot(shot, CheckOptions(strict=True))
    scoped = {entry.prim: entry for entry in result.coverage.entries if entry.kind == NOT_A_SURFACE}
    assert set(scoped) == {"/World/Hair", "/World/Spray"}
    assert all(entry.status == SCOPED for entry in scoped.values()) and result.coverage.complete
    assert not [message for message in result.messages if message.level == "warning"]
