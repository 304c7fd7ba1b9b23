"""Meshes that cannot be followed across some samples (empty or blocked points, topology changes): checked over
the stretches where they have points, every other mesh checked throughout (docs/contracts.md, Topology)."""

import csv
import json

import numpy as np
import pytest
from pxr import Vt

from builders import RESTING_SHEETS_REST, RESTING_SHEETS_TIMES, resting_sheets
from .conftest import run_cli
from usdksl.errors import UsdkslInputError
from usdksl.reading.segments import Gap, Stretch, absent_meshes, cut_range, is_topology_change, mesh_gaps
from usdksl.warning_kinds import EMPTY_SAMPLE, TOPOLOGY_CHANGE


def test_gaps_between_stretches_name_their_kind():
    stretches = [Stretch(1.0, 5.0, True), Stretch(6.0, 6.0, False), Stretch(7.0, 9.0, True),
                 Stretch(10.0, 12.0, True)]
    gaps = mesh_gaps("/M", stretches)
    assert [(g.start, g.end, g.kind) for g in gaps] == [(5.0, 7.0, EMPTY_SAMPLE), (9.0, 10.0, TOPOLOGY_CHANGE)]
    assert gaps[0].bad_times == (6.0,)


def test_a_mesh_that_starts_or_ends_empty_is_left_out_before_or_after_its_points():
    stretches = [Stretch(0.0, 0.0, False), Stretch(1.0, 5.0, True), Stretch(6.0, 8.0, False)]
    gaps = mesh_gaps("/M", stretches)
    assert [(g.start, g.end) for g in gaps] == [(-np.inf, 1.0), (5.0, np.inf)]
    assert mesh_gaps("/M", [Stretch(0.0, 3.0, False)]) == []   # empty everywhere: an empty mesh


def test_the_range_is_cut_at_gap_ends_and_only_covered_meshes_are_absent():
    gaps = [Gap(5.0, 7.0, "/A", EMPTY_SAMPLE), Gap(-np.inf, 2.0, "/B", EMPTY_SAMPLE)]
    pieces = cut_range((1.0, 10.0), gaps)
    assert pieces == [(1.0, 2.0), (2.0, 5.0), (5.0, 7.0), (7.0, 10.0)]
    stretches = {"/A": [Stretch(1.0, 5.0, True), Stretch(6.0, 6.0, False), Stretch(7.0, 10.0, True)],
                 "/B": [Stretch(1.0, 1.0, False), Stretch(2.0, 10.0, True)]}
    assert [absent_meshes(piece, gaps, stretches) for piece in pieces] == [{"/B": 2.0}, {}, {"/A": 7.0}, {}]
    assert cut_range((8.0, 9.0), gaps) == [(8.0, 9.0)]


def test_topology_errors_are_recognised():
    assert is_topology_change(UsdkslInputError("topology (faceVertexCounts) changes here", file="f"))
    assert is_topology_change(UsdkslInputError("points count changes from 4 (time 1) to 5", file="f"))
    assert not is_topology_change(UsdkslInputError("point 3 is NaN or infinite", file="f"))


# --------------------------------------------------------------------------------------------- whole shots

TIMES = RESTING_SHEETS_TIMES
CONTACT_TIME = RESTING_SHEETS_REST   # the sheets come down at y = (11 - t) / 10 and rest from then on


def contacts(out, stem):
    with open(out / f"{stem}.contacts.csv", newline="") as stream:
        return [(row["prim_a"], int(row["face_a"]), row["prim_b"], int(row["face_b"]), float(row["time"]))
                for row in csv.DictReader(stream)]


@pytest.fixture
def clean(tmp_path):
    shot = resting_sheets(tmp_path / "clean.usda")
    result = run_cli("check", shot, "--out", tmp_path / "clean_out")
    assert result.exit_code == 1, result.stderr
    rows = contacts(tmp_path / "clean_out", "clean")
    assert {(a, b) for a, _, b, _, _ in rows} == {("/World/Cloth", "/World/ClothFloor"),
                                                  ("/World/Other", "/World/OtherFloor")}
    return rows


@pytest.mark.parametrize("bad", [{5.0: "block"}, {5.0: "empty"}, {15.0: "block"}, {15.0: "empty"},
                                 {1.0: "empty"}, {24.0: "empty"}, {23.0: "block", 24.0: "block"}],
                         ids=["block-before", "empty-before", "block-resting", "empty-resting", "empty-first",
                              "empty-last", "blocked-tail"])
def test_a_bad_sample_leaves_out_only_its_stretch(tmp_path, clean, bad):
    shot = resting_sheets(tmp_path / "bad.usda", bad)
    result = run_cli("check", shot, "--out", tmp_path / "out")
    assert result.exit_code == 1, result.stderr
    assert "internal error" not in result.stderr
    # the cloth keeps every contact (it rests on its floor across the gap: reported once, at its first contact)
    assert contacts(tmp_path / "out", "bad") == clean
    warnings = [line for line in result.stderr.splitlines() if "warning" in line and "/World/Cloth:" in line]
    assert len(warnings) == 1, result.stderr
    assert "empty or blocked" in warnings[0] and f"{min(bad):g}" in warnings[0]
    strict = run_cli("check", shot, "--out", tmp_path / "strict", "--strict")
    assert strict.exit_code == 2, strict.stderr
    assert "/World/Cloth" in strict.stderr and not (tmp_path / "strict").exists()


@pytest.mark.parametrize("bad, gap", [({15.0: "block"}, (14.0, 16.0)), ({15.0: "empty"}, (14.0, 16.0)),
                                      ({1.0: "block"}, (1.0, 2.0)), ({23.0: "block", 24.0: "block"}, (22.0, 24.0))],
                         ids=["block-resting", "empty-resting", "block-first", "blocked-tail"])
def test_a_bad_sample_is_a_not_checked_stretch_of_the_coverage_between_the_samples_around_it(tmp_path, bad, gap):
    # docs/contracts.md, Topology and gaps: the gap runs from the last sample with points before it to the
    # first after it (the checked range's ends where there is none), kind usdksl:EmptySample.
    shot = resting_sheets(tmp_path / "bad.usda", bad)
    report = tmp_path / "report.json"
    result = run_cli("check", shot, "--out", tmp_path / "out", "--json", report)
    assert result.exit_code == 1, result.stderr
    document = json.loads(report.read_text())
    unchecked = [entry for entry in document["coverage"]["entries"] if entry["status"] != "checked"]
    assert [(e["prim"], e["status"], e["kind"], e["start"], e["end"]) for e in unchecked] == [
        ("/World/Cloth", "not checked", EMPTY_SAMPLE, *gap)]
    assert [finding["kind"] for finding in document["findings"]] == [EMPTY_SAMPLE]
    assert result.stderr.splitlines()[-1].endswith(
        "NOT CHECKED: 1 item on 1 prim (see the warnings, -v or the JSON report's coverage)")


def test_a_contact_made_inside_a_gap_is_reported_where_the_gap_ends(tmp_path, clean):
    # The cloth reaches its floor at t = 11, the blocked sample: the mesh is left out of the piece from 10
    # to 12, and from 12 on it rests on the floor, already touching where its piece begins.
    shot = resting_sheets(tmp_path / "bad.usda", {CONTACT_TIME: "block"})
    result = run_cli("check", shot, "--out", tmp_path / "out")
    assert result.exit_code == 1, result.stderr
    with open(tmp_path / "out" / "bad.contacts.csv", newline="") as stream:
        rows = list(csv.DictReader(stream))
    cloth = [row for row in rows if row["prim_a"] == "/World/Cloth"]
    assert {(row["time"], row["feature"]) for row in cloth} == {("12.0", "initial")}
    assert sorted((r["prim_a"], int(r["face_a"]), r["prim_b"], int(r["face_b"])) for r in cloth) == sorted(
        (a, fa, b, fb) for a, fa, b, fb, _ in clean if a == "/World/Cloth")
    other = [(r["prim_a"], int(r["face_a"]), r["prim_b"], int(r["face_b"]), float(r["time"])) for r in rows
             if r["prim_a"] == "/World/Other"]
    assert other == [row for row in clean if row[0] == "/World/Other"]


def test_a_mesh_empty_at_every_sample_is_an_empty_mesh(tmp_path):
    shot = resting_sheets(tmp_path / "bad.usda", {t: "empty" for t in TIMES})
    result = run_cli("check", shot, "--out", tmp_path / "out")
    assert result.exit_code == 1, result.stderr
    assert {(a, b) for a, _, b, _, _ in contacts(tmp_path / "out", "bad")} == {("/World/Other", "/World/OtherFloor")}
    assert "/World/Cloth: time 1: empty mesh" in result.stderr


def test_a_prototype_with_an_empty_sample_is_refused_not_dropped(tmp_path):
    from pxr import Usd, UsdGeom

    from builders import falling_instancer

    path = tmp_path / "scatter.usda"
    falling_instancer(path)
    stage = Usd.Stage.Open(str(path))
    points = UsdGeom.Mesh(stage.GetPrimAtPath("/World/scatter/Prototypes/box")).GetPointsAttr()
    value = points.Get()
    for time, sample in ((1.0, Vt.Vec3fArray()), (2.0, value), (11.0, value)):
        points.Set(sample, time)
    stage.GetRootLayer().Save()
    result = run_cli("check", path, "--out", tmp_path / "out")
    assert result.exit_code == 2, result.stderr
    assert "/World/scatter/Prototypes/box: time 1: points are empty or blocked here" in result.stderr
    assert "cannot be checked around them" in result.stderr and not (tmp_path / "out").exists()


def test_last_contacts_of_a_shot_cut_at_gaps(tmp_path, clean):
    # the piece inside the gap checks nothing (the other sheet rests): its table still carries last contacts
    shot = resting_sheets(tmp_path / "bad.usda", {15.0: "block"})
    result = run_cli("check", shot, "--out", tmp_path / "out", "--last-contact")
    assert result.exit_code == 1, result.stderr
    with open(tmp_path / "out" / "bad.contacts.csv", newline="") as stream:
        rows = list(csv.DictReader(stream))
    assert [(r["prim_a"], int(r["face_a"]), r["prim_b"], int(r["face_b"]), float(r["time"])) for r in rows] == clean
    # resting from t = 11 to the end: the last contact is the end of the checked range
    assert {float(r["last_time"]) for r in rows} == {24.0}
