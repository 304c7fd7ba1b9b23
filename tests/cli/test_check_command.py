"""``usdksl check`` end to end: exit codes, outputs, determinism, brute-force agreement, bad input."""

import json
import math
import os
import shutil
import subprocess
import sys
from pathlib import Path
from xml.etree import ElementTree

import numpy as np
import pytest
from click.testing import CliRunner
from pxr import Ts, Usd, UsdGeom, Vt

from usdksl.cli.main import main
from usdksl.checking.collision import find_contacts
from usdksl.reading.loader import load_shot
from usdksl.clock import StageClock
from usdksl.contacts.csv_file import contacts_csv
from usdksl.contacts.table import ContactTable
from usdksl.reports.override import CLEAN_COLOR, CONTACT_COLOR
from usdksl.reading.scope import plan_shot

from builders import (QUAD_POINTS, STRIP_COUNTS, STRIP_INDICES, STRIP_POINTS, add_mesh, falling_quad_samples,
                      fifty_mesh_scene, new_stage, sha256, snapshot)

SAMPLES = Path(__file__).resolve().parents[2] / "samples"
SAMPLE_EXIT_CODES = {"drape": 1, "fold": 1, "pass_through": 1, "clean": 0}


def run(args):
    return CliRunner().invoke(main, ["check", *map(str, args)], catch_exceptions=False)


def error_lines(result):
    return [line for line in result.stderr.splitlines() if line.startswith("usdksl: error")]


@pytest.fixture(params=sorted(SAMPLE_EXIT_CODES))
def sample(request, tmp_path):
    path = SAMPLES / f"{request.param}.usda"
    if not path.is_file():
        pytest.skip(f"{path} not shipped")
    return request.param, path


def test_samples_exit_codes_outputs_and_determinism(sample, tmp_path):
    name, path = sample
    before = sha256(path)
    first = run([path, "--out", tmp_path / "one"])
    second = run([path, "--out", tmp_path / "two"])
    assert first.exit_code == SAMPLE_EXIT_CODES[name], first.stderr
    assert second.exit_code == first.exit_code
    assert first.stdout == ""                                # stdout stays parseable: nothing on it
    for suffix in ("contacts.csv", "summary.csv", "regions.csv", "usdksl.usda"):
        one = (tmp_path / "one" / f"{name}.{suffix}").read_bytes()
        two = (tmp_path / "two" / f"{name}.{suffix}").read_bytes()
        assert one == two, suffix
    rows = (tmp_path / "one" / f"{name}.contacts.csv").read_text().splitlines()
    assert rows[0] == "time,prim_a,face_a,prim_b,face_b,kind,feature,frame,seconds,region"
    assert (len(rows) > 1) == (first.exit_code == 1)
    assert sha256(path) == before
    assert first.stderr.splitlines()[-1].startswith("usdksl: ")
    assert "pairs checked:" not in first.stderr              # the plan is printed with -v only
    verbose = run([path, "--out", tmp_path / "three", "-v"])
    assert "pairs checked:" in verbose.stderr
    assert verbose.stderr.splitlines()[-1].startswith("usdksl: wrote ")


def test_samples_contacts_equal_the_brute_force_reference(sample, tmp_path):
    name, path = sample
    result = run([path, "--out", tmp_path])
    shot = load_shot(str(path))
    plan = plan_shot(shot)
    reference = find_contacts(shot.meshes, plan.pairs, method="brute")
    expected = ContactTable.from_face_contacts(reference.face_contacts(shot.meshes), [m.path for m in shot.meshes])
    assert result.exit_code == (1 if expected.count else 0), result.stderr
    ours = _csv_rows((tmp_path / f"{name}.contacts.csv").read_text())
    theirs = _csv_rows(contacts_csv(expected, StageClock.from_metadata(shot.metadata)))
    # Same face pairs, kinds and features; brute force reads the raw samples while KSL
    # merges collinear flightplan segments, so times agree within the CCD tolerance of a step.
    assert sorted(ours) == sorted(theirs)
    step = float(np.diff(shot.times).max()) if shot.times.size > 1 else 1.0
    for key, time in ours.items():
        assert time == pytest.approx(theirs[key], abs=1e-6 * step), key


def _csv_rows(text):
    lines = text.splitlines()
    assert lines[0].startswith("time,prim_a,face_a,prim_b,face_b,kind")
    rows = {}
    for line in lines[1:]:
        # Keyed by face pair and kind: which primitive pair touches first (the feature column)
        # may differ between methods when several touch at the same instant.
        time, prim_a, face_a, prim_b, face_b, kind = line.split(",")[:6]
        rows[(prim_a, face_a, prim_b, face_b, kind)] = float(time)
    return rows


def test_override_layer_of_a_sample_reads_the_cache_unchanged(tmp_path):
    path = SAMPLES / "drape.usda"
    if not path.is_file():
        pytest.skip("drape sample not shipped")
    assert run([path, "--out", tmp_path]).exit_code == 1
    original = Usd.Stage.Open(str(path))
    layered = Usd.Stage.Open(str(tmp_path / "drape.usdksl.usda"))
    checked = 0
    for prim in original.Traverse():
        if not prim.IsA(UsdGeom.Mesh):
            continue
        a = UsdGeom.Mesh(prim).GetPointsAttr()
        b = UsdGeom.Mesh(layered.GetPrimAtPath(prim.GetPath())).GetPointsAttr()
        assert b.GetTimeSamples() == a.GetTimeSamples()
        for t in a.GetTimeSamples() or [Usd.TimeCode.Default()]:
            assert np.array_equal(np.asarray(a.Get(t)), np.asarray(b.Get(t)))
        faces = len(UsdGeom.Mesh(prim).GetFaceVertexCountsAttr().Get())
        primvar = UsdGeom.PrimvarsAPI(layered.GetPrimAtPath(prim.GetPath())).GetPrimvar("usdksl:firstContactTime")
        assert len(primvar.Get()) == faces
        checked += 1
    assert checked >= 2


def test_json_to_stdout_and_junit_file(two_quads_shot, tmp_path):
    junit = tmp_path / "reports" / "junit.xml"
    result = run([two_quads_shot, "--out", tmp_path / "out", "--json", "-", "--junit", junit])
    assert result.exit_code == 1, result.stderr
    document = json.loads(result.stdout)
    assert document["shot"] == str(two_quads_shot)
    assert document["summary"][0]["prim_a"] == "/World/Falling"
    assert document["summary"][0]["prim_b"] == "/World/Floor"
    first = document["summary"][0]["first_contact_time"]
    assert first == pytest.approx(12.5, abs=1e-4)
    assert document["plan"]["pairs_checked"] == 2      # Falling x Floor, and Falling's self check (deforms)
    suite = ElementTree.parse(junit).getroot().find("testsuite")
    assert suite.get("tests") == "2" and suite.get("failures") == "1"
    summary = (tmp_path / "out" / "two_quads.summary.csv").read_text().splitlines()
    assert summary[1].startswith("/World/Falling,/World/Floor,inter,")


def test_options_change_the_plan(two_quads_shot, tmp_path):
    result = run([two_quads_shot, "--out", tmp_path / "a", "--no-inter", "-v"])
    assert result.exit_code == 0
    assert "inter checks off (--no-inter)" in result.stderr
    excluded = run([two_quads_shot, "--out", tmp_path / "b", "--prims", "!/World/Floor", "-v"])
    assert excluded.exit_code == 0
    assert "skip mesh /World/Floor: excluded by --prims/--exclude" in excluded.stderr
    early = run([two_quads_shot, "--out", tmp_path / "c", "--time-range", "1", "10"])
    assert early.exit_code == 0                            # the quads meet at 12.5
    assert _csv_rows((tmp_path / "c" / "two_quads.contacts.csv").read_text()) == {}
    late = run([two_quads_shot, "--out", tmp_path / "d", "--time-range", "10", "20", "--method", "swept"])
    assert late.exit_code == 1
    assert _csv_rows((tmp_path / "d" / "two_quads.contacts.csv").read_text()) == {
        ("/World/Falling", "0", "/World/Floor", "0", "inter"): pytest.approx(12.5, abs=1e-5)}
    thick = run([two_quads_shot, "--out", tmp_path / "e", "--time-range", "1", "12", "--thickness", "0.2"])
    assert thick.exit_code == 1                            # 0.2 apart at t = 1 + 23 * 0.4 = 10.2
    assert _csv_rows((tmp_path / "e" / "two_quads.contacts.csv").read_text()) == {
        ("/World/Falling", "0", "/World/Floor", "0", "inter"): pytest.approx(10.2, abs=1e-5)}


def test_usage_errors_exit_2(two_quads_shot, tmp_path):
    assert run([two_quads_shot, "--method", "magic"]).exit_code == 2
    assert run([two_quads_shot, "--time-range", "5", "1"]).exit_code == 2
    out = tmp_path / "out"
    out.mkdir()
    negative = run([two_quads_shot, "--out", out, "--thickness", "-1"])
    assert negative.exit_code == 2 and "--thickness" in negative.stderr
    assert snapshot(out) == {}


def test_single_sample_mesh_is_static_and_said_so(tmp_path):
    path = tmp_path / "single.usda"
    stage = new_stage(path)
    add_mesh(stage, "/World/Once", None, samples={5.0: QUAD_POINTS})
    add_mesh(stage, "/World/Falling", None, samples=falling_quad_samples(offset=(3, 0, 0)))
    stage.GetRootLayer().Save()
    result = run([path, "--out", tmp_path / "out", "-v"])
    assert result.exit_code == 0, result.stderr
    assert "/World/Once: a single time sample: treated as static" in result.stderr


# ----------------------------------------------------------------------------------------------- bad input


def _mesh_stage(path):
    stage = new_stage(path)
    add_mesh(stage, "/World/Good", None, STRIP_COUNTS, STRIP_INDICES,
             samples={1.0: STRIP_POINTS, 24.0: STRIP_POINTS + [0, 1, 0]})
    return stage


def bad_missing(path):
    return path.with_name("does_not_exist.usda")


def bad_not_usd(path):
    path.write_text("this is not a USD file\n{[(\n")
    return path


def bad_truncated_usdc(path):
    usdc = path.with_suffix(".usdc")
    stage = _mesh_stage(usdc)
    stage.GetRootLayer().Save()
    data = usdc.read_bytes()
    del stage
    usdc.write_bytes(data[: len(data) // 2])
    return usdc


def bad_no_meshes(path):
    stage = new_stage(path)
    UsdGeom.Sphere.Define(stage, "/World/Ball")
    stage.GetRootLayer().Save()
    return path


def _with_bad_points(value):
    def build(path):
        stage = _mesh_stage(path)
        bad = STRIP_POINTS.copy()
        bad[2, 1] = value
        add_mesh(stage, "/World/Bad", None, STRIP_COUNTS, STRIP_INDICES,
                 samples={1.0: STRIP_POINTS, 7.5: bad, 24.0: STRIP_POINTS})
        stage.GetRootLayer().Save()
        return path
    return build


def bad_index_out_of_range(path):
    stage = _mesh_stage(path)
    add_mesh(stage, "/World/Bad", STRIP_POINTS[:5], STRIP_COUNTS, STRIP_INDICES)   # index 5 of 5 points
    stage.GetRootLayer().Save()
    return path


def bad_only_empty_mesh(path):
    # An empty mesh beside good ones is skipped with a warning (tests/reading); with nothing else it is bad input.
    stage = new_stage(path)
    UsdGeom.Mesh.Define(stage, "/World/Bad")
    stage.GetRootLayer().Save()
    return path


def bad_held_spline(path):
    stage = _mesh_stage(path)
    mover = UsdGeom.Xform.Define(stage, "/World/Mover")
    op = mover.AddRotateYOp()
    spline = Ts.Spline("float")
    for time, value in ((1.0, 0.0), (10.0, 90.0)):
        knot = Ts.Knot("float")
        knot.SetTime(time)
        knot.SetValue(value)
        knot.SetNextInterpolation(Ts.InterpHeld)
        spline.SetKnot(knot)
    op.GetAttr().SetSpline(spline)
    add_mesh(stage, "/World/Mover/Box", QUAD_POINTS)
    stage.GetRootLayer().Save()
    return path


# name: (builder, prim named in the message or None, time named or None, words in the message)
BAD_INPUTS = {
    "missing file": (bad_missing, None, None, "no such file"),
    "not USD": (bad_not_usd, None, None, "cannot open"),
    "truncated usdc": (bad_truncated_usdc, None, None, "cannot"),
    "no meshes": (bad_no_meshes, None, None, "no UsdGeom.Mesh"),
    "NaN points": (_with_bad_points(math.nan), "/World/Bad", 7.5, "NaN"),
    "inf points": (_with_bad_points(math.inf), "/World/Bad", 7.5, "infinite"),
    "points do not match topology": (bad_index_out_of_range, "/World/Bad", 1.0, "out of range"),
    "only an empty mesh": (bad_only_empty_mesh, "/World/Bad", None, "empty mesh"),
    "held spline": (bad_held_spline, "/World/Mover", 1.0, "held interpolation"),
}


def _prepare(builder, tmp_path):
    shot_dir = tmp_path / "shot"
    shot_dir.mkdir()
    shot = builder(shot_dir / "bad.usda")
    out_dir = tmp_path / "out"
    out_dir.mkdir()
    (out_dir / "unrelated.txt").write_text("already here\n")
    return shot, shot_dir, out_dir


def _assert_clean_failure(exit_code, stderr, shot, prim, time, words, before_shot, before_out, shot_dir, out_dir):
    assert exit_code == 2, stderr
    lines = [line for line in stderr.splitlines() if line.startswith("usdksl: error")]
    assert len(lines) == 1, stderr
    line = lines[0]
    assert str(shot) in line and words in line, line
    if prim is not None:
        assert prim in line, line
    if time is not None:
        assert f"time {time:g}" in line, line
    assert snapshot(out_dir) == before_out
    assert snapshot(shot_dir) == before_shot                 # input byte-identical, nothing written beside it


@pytest.mark.parametrize("case", sorted(BAD_INPUTS))
def test_bad_input_matrix(case, tmp_path):
    builder, prim, time, words = BAD_INPUTS[case]
    shot, shot_dir, out_dir = _prepare(builder, tmp_path)
    before_shot, before_out = snapshot(shot_dir), snapshot(out_dir)
    for out_args in ([], ["--out", out_dir]):     # default output folder (beside the shot) and --out
        report = out_dir / "r.xml"
        result = CliRunner().invoke(main, ["check", str(shot), *map(str, out_args), "--json", str(out_dir / "r.json"),
                                           "--junit", str(report)])
        # the JUnit report is written on every exit code: one <error> test case with the error line
        errors = ElementTree.parse(report).getroot().findall("testsuite/testcase/error")
        assert len(errors) == 1 and errors[0].get("type") == "input-error"
        assert f"usdksl: error: {errors[0].get('message')}" in result.stderr.splitlines()
        report.unlink()
        _assert_clean_failure(result.exit_code, result.stderr, shot, prim, time, words, before_shot, before_out,
                              shot_dir, out_dir)


def test_unwritable_output_directory(two_quads_shot, tmp_path):
    blocker = tmp_path / "not_a_dir"
    blocker.write_text("a file\n")
    before = snapshot(tmp_path)
    for out in (blocker, blocker / "sub"):
        result = run([two_quads_shot, "--out", out])
        assert result.exit_code == 2
        assert len(error_lines(result)) == 1 and str(blocker) in error_lines(result)[0]
        assert "cannot be written" in error_lines(result)[0]
    json_in_file = run([two_quads_shot, "--out", tmp_path / "ok", "--json", blocker / "r.json"])
    assert json_in_file.exit_code == 2
    assert snapshot(tmp_path) == before


@pytest.mark.skipif(os.geteuid() == 0 if hasattr(os, "geteuid") else True,
                    reason="root ignores directory permissions")
def test_read_only_output_directory(two_quads_shot, tmp_path):
    locked = tmp_path / "locked"
    locked.mkdir()
    locked.chmod(0o555)
    try:
        result = run([two_quads_shot, "--out", locked])
        assert result.exit_code == 2 and list(locked.iterdir()) == []
    finally:
        locked.chmod(0o755)


def _entry_point():
    found = shutil.which("usdksl", path=os.pathsep.join([str(Path(sys.executable).parent),
                                                         os.environ.get("PATH", "")]))
    if found is None:
        pytest.skip("the usdksl entry point is not installed")
    return found


@pytest.mark.parametrize("case", ["missing file", "not USD", "NaN points", "held spline"])
def test_bad_input_through_the_installed_entry_point(case, tmp_path):
    builder, prim, time, words = BAD_INPUTS[case]
    shot, shot_dir, out_dir = _prepare(builder, tmp_path)
    before_shot, before_out = snapshot(shot_dir), snapshot(out_dir)
    completed = subprocess.run([_entry_point(), "check", str(shot), "--out", str(out_dir)], capture_output=True,
                               text=True, env={**os.environ, "CI": "1"}, timeout=300)
    _assert_clean_failure(completed.returncode, completed.stderr, shot, prim, time, words, before_shot,
                          before_out, shot_dir, out_dir)
    assert completed.stdout == ""


def test_entry_point_on_a_shot_with_contacts(two_quads_shot, tmp_path):
    completed = subprocess.run([_entry_point(), "check", str(two_quads_shot), "--out", str(tmp_path / "o")],
                               capture_output=True, text=True, env={**os.environ, "CI": "1"}, timeout=300)
    assert completed.returncode == 1, completed.stderr
    assert completed.stdout == ""
    assert "\r" not in completed.stderr                     # no progress bar in CI / pipes
    last = completed.stderr.splitlines()[-1]
    assert last.startswith("usdksl: ") and "first at frame 12.5 (t=12.5)" in last
    assert sorted(p.name for p in (tmp_path / "o").iterdir()) == [
        "two_quads.contacts.csv", "two_quads.regions.csv", "two_quads.summary.csv", "two_quads.usdksl.usda"]


# ------------------------------------------------------------------------ topology that changes over time

TRIANGLE_COUNTS = [3, 3, 3, 3]
TRIANGLE_INDICES = [0, 1, 4, 0, 4, 5, 1, 2, 3, 1, 3, 4]   # the strip's two quads split in four triangles


def topology_changing_shot(path):
    """/World/Changing descends y = 2 - t/10 onto a static floor (contact at t = 20); its two quads become
    four triangles at t = 12, and it has a sample at 6, so (6, 12) cannot be checked."""
    stage = new_stage(path)
    floor = np.array([[-1, 0, -1], [3, 0, -1], [3, 0, 2], [-1, 0, 2]], dtype=np.float64)
    add_mesh(stage, "/World/Floor", floor)
    mesh = add_mesh(stage, "/World/Changing", None, STRIP_COUNTS, STRIP_INDICES,
                    samples={float(t): STRIP_POINTS + [0, 2 - t / 10, 0] for t in (1, 6, 12, 24)})
    mesh.GetFaceVertexCountsAttr().Set(Vt.IntArray(STRIP_COUNTS), 1.0)
    mesh.GetFaceVertexIndicesAttr().Set(Vt.IntArray(STRIP_INDICES), 1.0)
    mesh.GetFaceVertexCountsAttr().Set(Vt.IntArray(TRIANGLE_COUNTS), 12.0)
    mesh.GetFaceVertexIndicesAttr().Set(Vt.IntArray(TRIANGLE_INDICES), 12.0)
    stage.GetRootLayer().Save()
    return path


def test_topology_change_is_checked_per_segment_with_a_warning(tmp_path):
    shot = topology_changing_shot(tmp_path / "changing.usda")
    before = sha256(shot)
    result = run([shot, "--out", tmp_path / "out", "-v"])
    assert result.exit_code == 1, result.stderr
    assert ("/World/Changing: topology changes between time 6 and 12; that interval is not checked for this mesh"
            in result.stderr)
    # the floor is checked across the gap too: only /World/Changing is left out of 6..12
    assert "checking 3 segments cut at those gaps: 1..6, 6..12, 12..24" in result.stderr
    rows = [line.split(",") for line in (tmp_path / "out" / "changing.contacts.csv").read_text().splitlines()[1:]]
    assert rows and all(abs(float(r[0]) - 20.0) < 1e-4 for r in rows)
    # faces of the triangle topology in force at t = 20 (four faces, all touching the floor)
    assert all(r[1] == "/World/Changing" and r[3] == "/World/Floor" and r[4] == "0" for r in rows)
    assert sorted(int(r[2]) for r in rows) == [0, 1, 2, 3]
    assert sha256(shot) == before
    layered = Usd.Stage.Open(str(tmp_path / "out" / "changing.usdksl.usda"))
    primvar = UsdGeom.PrimvarsAPI(layered.GetPrimAtPath("/World/Changing")).GetPrimvar("usdksl:firstContactTime")
    assert len(primvar.Get(3.0)) == 2 and all(math.isnan(v) for v in primvar.Get(3.0))
    assert len(primvar.Get(20.0)) == 4 and list(primvar.Get(20.0)) == pytest.approx([20.0] * 4, abs=1e-4)
    colors = UsdGeom.PrimvarsAPI(layered.GetPrimAtPath("/World/Changing")).GetPrimvar("displayColor")
    # per face of the topology in force: both faces grey at 3, all four red by the end
    assert np.allclose(np.asarray(colors.ComputeFlattened(3.0)), [CLEAN_COLOR] * 2)
    assert np.allclose(np.asarray(colors.ComputeFlattened(24.0)), [CONTACT_COLOR] * 4)
    prim = layered.GetPrimAtPath("/World/Changing")
    assert prim.GetAttribute("usdksl:firstContactTime").Get() == pytest.approx(20.0, abs=1e-4)

    strict = run([shot, "--strict", "--out", tmp_path / "strict"])     # the interval 6..12 is not checked
    assert strict.exit_code == 2, strict.stderr
    errors = [line for line in strict.stderr.splitlines() if line.startswith("usdksl: error")]
    assert len(errors) == 1 and "/World/Changing" in errors[0] and "6 and 12" in errors[0], strict.stderr
    assert not (tmp_path / "strict").exists() or not any((tmp_path / "strict").iterdir())


def test_points_count_change_is_checked_per_segment(tmp_path):
    # arrays of different sizes cannot be blended, so USD holds the earlier one until the next sample
    path = tmp_path / "grows.usda"
    stage = _mesh_stage(path)
    add_mesh(stage, "/World/Grows", None, STRIP_COUNTS, STRIP_INDICES,
             samples={1.0: STRIP_POINTS + [0, 5, 0], 9.0: np.vstack([STRIP_POINTS + [0, 5, 0], [[5, 5, 5]]]),
                      24.0: np.vstack([STRIP_POINTS + [0, 6, 0], [[5, 5, 5]]])})
    stage.GetRootLayer().Save()
    result = run([path, "--out", tmp_path / "out"])
    assert result.exit_code == 0, result.stderr
    assert "/World/Grows: topology changes between time 1 and 9" in result.stderr
    assert _csv_rows((tmp_path / "out" / "grows.contacts.csv").read_text()) == {}   # 4 or more above /World/Good


def test_fifty_mesh_plan_is_printed_with_its_counter(tmp_path):

    path = tmp_path / "fifty.usda"
    fifty_mesh_scene(path)
    junit = tmp_path / "junit.xml"
    # --rigid: the rigid mover's 48 pairs with the static meshes are left out by default
    result = run([path, "--out", tmp_path / "out", "--junit", junit, "--rigid", "-v"])
    assert result.exit_code == 1, result.stderr          # the falling cloth passes through M00
    assert _csv_rows((tmp_path / "out" / "fifty.contacts.csv").read_text()) == {
        ("/World/Anim/Cloth", "0", "/World/Static/M00", "0", "inter"): pytest.approx(12.5, abs=1e-5)}
    assert "usdksl: pairs checked: 98 of 1275 possible (50 meshes, 2 moving)" in result.stderr
    assert f"skip {48 * 47 // 2} pairs: both never move" in result.stderr
    assert len(ElementTree.parse(junit).getroot().find("testsuite").findall("testcase")) == 98
