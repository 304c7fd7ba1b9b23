"""What a person and a CI job get from ``usdksl check``: a concise console (-v, -q), warnings on stderr, and a
JUnit file on every exit code that is valid as Jenkins reads it (tests/junit_schema.py)."""

import subprocess
import sys
from pathlib import Path

import pytest
from click.testing import CliRunner

from usdksl.cli.main import main

from builders import QUAD_POINTS, add_mesh, falling_quad_samples, new_stage, snapshot
from junit_schema import assert_valid_junit

REPO_ROOT = Path(__file__).resolve().parents[2]


def _run(*args):
    return CliRunner().invoke(main, ["check", *map(str, args)])


def _nothing_to_check(path):
    """Two static quads: no mesh moves, so no pair is checked."""
    stage = new_stage(path)
    add_mesh(stage, "/World/A", QUAD_POINTS)
    add_mesh(stage, "/World/B", QUAD_POINTS + [3.0, 0, 0])
    stage.GetRootLayer().Save()
    return path


def _blown_up(path):
    """A falling quad whose vertex 0 leaves for 1e6 units at one sample: a warning, not an error."""
    stage = new_stage(path)
    samples = {float(t): QUAD_POINTS + [0, 1.0 - t / 12.0, 0] for t in range(1, 25)}
    samples[12.0] = samples[12.0].copy()
    samples[12.0][0] = [0.0, 1e6, 0.0]
    add_mesh(stage, "/World/Floor", QUAD_POINTS + [-0.5, 0.0, -0.5])
    add_mesh(stage, "/World/Falling", None, samples=samples)
    stage.GetRootLayer().Save()
    return path


def test_default_console_is_one_line_per_shot(samples_dir, tmp_path):
    result = _run(samples_dir / "fold.usda", "--out", tmp_path)
    assert result.exit_code == 1
    assert result.stdout == ""
    lines = result.stderr.splitlines()
    assert len(lines) == 1
    assert lines[0].startswith("usdksl: 1 problem in 1 mesh pair (132 contacting face pairs), first at frame 31.916 "
                               "(t=31.916), worst region 1: intersection 0.8 long at frame 35; "
                               "checked 1 pair over 1..36 in ")


def test_verbose_adds_the_plan_the_mesh_pairs_and_the_files(samples_dir, tmp_path):
    result = _run(samples_dir / "fold.usda", "--out", tmp_path, "-v")
    lines = result.stderr.splitlines()
    assert "usdksl: pairs checked: 1 of 1 possible (1 meshes, 1 moving)" in lines
    assert "usdksl: /World/Strip (self): 132 face pairs, first at frame 31.916 (t=31.916)" in lines
    assert ("usdksl: region 1: /World/Strip (self): intersection 0.8 long at frame 35, frames 31.916..36, "
            "132 face pairs, around (-0.4638, -1.735e-18, 0)") in lines
    assert lines[-1] == f"usdksl: wrote {tmp_path / 'fold.contacts.csv'}, {tmp_path / 'fold.summary.csv'}, " \
                        f"{tmp_path / 'fold.regions.csv'}, {tmp_path / 'fold.usdksl.usda'}"


def test_quiet_prints_errors_only(samples_dir, tmp_path):
    found = _run(samples_dir / "fold.usda", "--out", tmp_path / "a", "-q")
    assert found.exit_code == 1 and found.stderr == "" and found.stdout == ""
    warned = _run(_blown_up(tmp_path / "blown.usda"), "--out", tmp_path / "b", "-q")
    assert warned.exit_code == 1 and warned.stderr == ""
    missing = _run(tmp_path / "missing.usda", "-q")
    assert missing.exit_code == 2
    assert missing.stderr.splitlines() == [f"usdksl: error: {tmp_path / 'missing.usda'}: no such file"]


def test_warnings_go_to_stderr_by_default(tmp_path):
    result = _run(_blown_up(tmp_path / "blown.usda"), "--out", tmp_path / "out")
    assert result.exit_code == 1 and result.stdout == ""
    warnings = [line for line in result.stderr.splitlines() if line.startswith("usdksl: warning: ")]
    assert warnings and "/World/Falling" in warnings[0] and "vertex 0" in warnings[0]
    assert "pairs checked" not in result.stderr


@pytest.mark.parametrize("shot_kind", ["clean", "contacts"])
def test_junit_of_a_checked_shot_is_valid(samples_dir, tmp_path, shot_kind):
    shot = samples_dir / ("clean.usda" if shot_kind == "clean" else "drape.usda")
    report = tmp_path / "report.xml"
    result = _run(shot, "--out", tmp_path / "out", "--junit", report)
    assert result.exit_code == (0 if shot_kind == "clean" else 1)
    root = assert_valid_junit(report.read_text())
    failures = root.findall("testsuite/testcase/failure")
    assert (len(failures) > 0) == (shot_kind == "contacts")
    assert all(failure.get("type") == "contact" and "first at frame" in failure.get("message")
               for failure in failures)


@pytest.mark.parametrize("arguments, words", [
    (["{missing}"], "no such file"),
    (["{shot}", "--thickness", "-1"], "--thickness must be zero or positive"),
    (["{shot}", "--baseline", "{missing}"], "baseline not found"),
])
def test_junit_is_written_on_bad_input_with_an_error_case(samples_dir, tmp_path, arguments, words):
    names = {"missing": tmp_path / "missing.usda", "shot": samples_dir / "fold.usda"}
    out = tmp_path / "out"
    out.mkdir()
    report = tmp_path / "report.xml"
    result = _run(*[argument.format(**names) for argument in arguments], "--out", out, "--junit", report)
    assert result.exit_code == 2
    assert snapshot(out) == {}                                   # nothing else is written
    root = assert_valid_junit(report.read_text())
    errors = root.findall("testsuite/testcase/error")
    assert len(errors) == 1 and words in errors[0].get("message") and errors[0].get("type") == "input-error"
    assert root.get("errors") == "1" and root.find("testsuite").get("name") == arguments[0].format(**names)


def test_nothing_to_check_is_an_input_error_with_a_junit_error(tmp_path):
    # green must mean checked: a shot in which nothing would be checked is exit 2, with or without --strict
    shot = _nothing_to_check(tmp_path / "still.usda")
    report = tmp_path / "report.xml"
    for name, extra in (("a", ()), ("b", ("--strict",))):
        result = _run(shot, "--out", tmp_path / name, "--junit", report, *extra)
        assert result.exit_code == 2, result.stderr
        assert "no mesh pair left to check" in result.stderr
        assert not (tmp_path / name).exists()
        errors = assert_valid_junit(report.read_text()).findall("testsuite/testcase/error")
        assert len(errors) == 1 and "no mesh pair left to check" in errors[0].get("message")


def test_one_junit_for_several_shots_with_a_failed_one(samples_dir, tmp_path):
    shots = [samples_dir / "fold.usda", samples_dir / "clean.usda", tmp_path / "missing.usda"]
    report = tmp_path / "report.xml"
    result = _run(*shots, "--out", tmp_path / "out", "--junit", report)
    assert result.exit_code == 2
    root = assert_valid_junit(report.read_text())
    suites = {suite.get("name"): suite for suite in root.findall("testsuite")}
    assert list(suites) == [str(shot) for shot in shots]
    assert suites[str(shots[0])].get("failures") == "1" and suites[str(shots[1])].get("failures") == "0"
    assert suites[str(shots[2])].get("errors") == "1"


def test_the_schema_checks_can_fail():
    """The hand-written junit-10 rules reject what Jenkins' schema rejects."""
    bad = [
        '<testsuites><testsuite name="s" tests="1" failures="0"><testcase name="c"/></testsuite></testsuites>',
        '<testsuites><testsuite name="s" tests="1" failures="0" errors="0"><testcase/></testsuite></testsuites>',
        '<testsuites><testsuite name="s" tests="1" failures="0" errors="0">'
        '<testcase name="c" assertions="1"/></testsuite></testsuites>',
        '<testsuites><testsuite name="s" tests="1" failures="0" errors="0" time="1e-3">'
        '<testcase name="c"/></testsuite></testsuites>',
        '<testsuites><testsuite name="s" tests="1" failures="0" errors="0">'
        '<testcase name="c"><failure kind="x"/></testcase></testsuite></testsuites>',
        '<testsuites><testcase name="c"/></testsuites>',
        '<testsuites><testsuite name="s" tests="1" failures="1" errors="0"><testcase name="c"/></testsuite>'
        '</testsuites>',
    ]
    for text in bad:
        with pytest.raises(AssertionError):
            assert_valid_junit(text)
    assert_valid_junit('<testsuites><testsuite name="s" tests="1" failures="1" errors="0" time="1,234.5">'
                       '<testcase name="c"><failure message="m">text</failure></testcase></testsuite></testsuites>')


def test_a_run_stopped_by_its_timeout_still_writes_the_junit_report(tmp_path):
    shot = tmp_path / "swirl.usdc"
    subprocess.run([sys.executable, str(REPO_ROOT / "samples" / "generate.py"), "swirl", "--faces", "1500",
                    "--keyframes", "4", "--samples-per-keyframe", "2", "--out", str(shot)],
                   check=True, capture_output=True)
    report = tmp_path / "report.xml"
    out = tmp_path / "out"
    result = _run(shot, "--out", out, "--junit", report, "--timeout", "1")
    assert result.exit_code == 2, result.output
    assert not out.exists()
    errors = assert_valid_junit(report.read_text()).findall("testsuite/testcase/error")
    assert len(errors) == 1 and "timed out after 1 s (--timeout)" in errors[0].get("message")
