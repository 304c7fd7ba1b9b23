"""``usdksl check`` with several shots: ``--json`` as JSON Lines, and a folder as a shot argument."""

import json
from xml.etree import ElementTree

from click.testing import CliRunner

from usdksl.cli.main import main

from builders import QUAD_POINTS, add_mesh, falling_quad_samples, new_stage, snapshot


def run(args):
    return CliRunner().invoke(main, ["check", *map(str, args)], catch_exceptions=False)


def _shot(path, touching):
    """A falling quad and a floor quad: through the floor (exit 1) or beside it, far away (exit 0)."""
    stage = new_stage(path)
    add_mesh(stage, "/World/Floor", QUAD_POINTS + ([-0.5, 0.0, -0.5] if touching else [10.0, 0.0, 10.0]))
    add_mesh(stage, "/World/Falling", None, samples=falling_quad_samples())
    stage.GetRootLayer().Save()
    return path


def test_json_with_several_shots_is_one_line_per_shot_in_argument_order(tmp_path):
    clean = _shot(tmp_path / "b_clean.usda", touching=False)
    touching = _shot(tmp_path / "a_touching.usda", touching=True)
    missing = tmp_path / "missing.usda"
    shots = [clean, missing, touching]     # not sorted: the lines follow the arguments

    to_stdout = run([*shots, "--out", tmp_path / "out", "--json", "-"])
    assert to_stdout.exit_code == 2, to_stdout.stderr
    lines = to_stdout.stdout.splitlines()
    assert len(lines) == 3 and to_stdout.stdout.endswith("\n")
    documents = [json.loads(line) for line in lines]
    assert [d["shot"] for d in documents] == [str(shot) for shot in shots]
    assert [d["exit_code"] for d in documents] == [0, 2, 1]
    assert documents[2]["contact_count"] > 0 and documents[0]["contact_count"] == 0
    assert str(missing) in documents[1]["error"]

    report = tmp_path / "reports" / "all.jsonl"
    junit = tmp_path / "reports" / "junit.xml"
    to_file = run([*shots, "--out", tmp_path / "out2", "--json", report, "--junit", junit])
    assert to_file.exit_code == 2 and to_file.stdout == ""
    assert [json.loads(line)["shot"] for line in report.read_text().splitlines()] == [str(s) for s in shots]
    assert junit.exists()
    assert not list((tmp_path / "out2").glob("*.json"))    # no per-shot JSON beside the CSVs


def test_json_with_one_shot_is_the_indented_document(tmp_path):
    shot = _shot(tmp_path / "touching.usda", touching=True)
    to_stdout = run([shot, "--out", tmp_path / "out", "--json", "-"])
    to_file = run([shot, "--out", tmp_path / "out", "--json", tmp_path / "report.json"])
    assert to_stdout.exit_code == to_file.exit_code == 1
    assert to_stdout.stdout == (tmp_path / "report.json").read_text()
    assert to_stdout.stdout.startswith("{\n") and len(to_stdout.stdout.splitlines()) > 10
    assert json.loads(to_stdout.stdout)["shot"] == str(shot)


def test_a_folder_checks_the_usd_files_in_it(tmp_path):
    folder = tmp_path / "shots"
    folder.mkdir()
    _shot(folder / "b.usda", touching=False)
    _shot(folder / "a.usda", touching=True)
    (folder / "notes.txt").write_text("not a shot\n")
    (folder / "deeper").mkdir()
    _shot(folder / "deeper" / "c.usda", touching=True)      # not recursive
    junit = tmp_path / "junit.xml"
    result = run([folder, "--out", tmp_path / "out", "--junit", junit])
    assert result.exit_code == 1, result.stderr
    suites = [suite.get("name") for suite in ElementTree.parse(junit).getroot().iter("testsuite")]
    assert suites == [str(folder / "a.usda"), str(folder / "b.usda")]
    assert sorted(p.name for p in (tmp_path / "out").glob("*.contacts.csv")) == ["a.contacts.csv",
                                                                                 "b.contacts.csv"]


def test_a_folder_without_usd_files_is_one_error_with_its_junit(tmp_path):
    folder = tmp_path / "empty"
    folder.mkdir()
    (folder / "notes.txt").write_text("not a shot\n")
    (folder / "deeper").mkdir()
    _shot(folder / "deeper" / "c.usda", touching=True)
    other = _shot(tmp_path / "other.usda", touching=True)
    junit = tmp_path / "reports" / "junit.xml"
    before = snapshot(tmp_path)
    result = run([other, folder, "--out", tmp_path / "out", "--junit", junit])
    assert result.exit_code == 2
    errors = [line for line in result.stderr.splitlines() if line]
    assert len(errors) == 1 and errors[0].startswith(f"usdksl: error: {folder}: no USD file")
    cases = list(ElementTree.parse(junit).getroot().iter("testsuite"))
    assert [suite.get("name") for suite in cases] == [str(folder)]
    assert cases[0].find("testcase/error") is not None
    assert not (tmp_path / "out").exists()
    assert {k: v for k, v in snapshot(tmp_path).items() if not k.startswith("reports")} == before
