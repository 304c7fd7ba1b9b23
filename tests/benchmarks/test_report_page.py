"""``python benchmarks/report.py`` assembles REPORT.md from the result files present, each section naming the
command that produced it, and benchmarks/ carries no session or issue numbers."""

import json
import re
from pathlib import Path

import report
from conftest import REPO_ROOT

NEWTON = """# usdksl on Newton simulator caches

Command: `python benchmarks/newton_bench.py a.usdc b.usdc`

Runs made one process per cache are merged with `python benchmarks/newton_bench.py --render PART.json ...`.

| cache | ksl |
|---|---|
| a | 1.0 |

## Counters

numbers
"""
THREADS = """# One thread against two

## Full scale

Command (run under `nice`): `python benchmarks/ksl_vs_swept.py full.usdc ksl --threads 1,2`

## Quarter scale

Command (run under `nice`): `python benchmarks/ksl_vs_swept.py quarter.usdc ksl --threads 1,2`
"""
THICKNESS = """# Thickness above 0: cost and measure

`benchmarks/thickness.py` at abc1234; KSL, one thread.

| shot | thickness |
"""


def test_the_page_holds_the_pages_present_each_with_its_command(tmp_path):
    (tmp_path / "newton.md").write_text(NEWTON)
    (tmp_path / "threads.md").write_text(THREADS)
    (tmp_path / "thickness.md").write_text(THICKNESS)
    (tmp_path / report.NOTES_MD).write_text("- a finding\n")
    assert report.main(["--dir", str(tmp_path)]) == 0
    page = (tmp_path / "REPORT.md").read_text()
    sections = re.findall(r"^## (.+)$", page, flags=re.MULTILINE)
    headings = dict(report.RESULT_PAGES)
    assert sections == [headings["newton.md"], headings["threads.md"], headings["thickness.md"],
                        report.INVESTIGATIONS_HEADING]
    for heading in sections:   # the contents link every section
        assert f"- [{heading}](#{report._anchor(heading)})" in page
    assert "From [newton.md](newton.md). Produced by `python benchmarks/newton_bench.py a.usdc b.usdc`." in page
    assert "Command: `python benchmarks/newton_bench.py a.usdc" not in page   # lifted, not repeated
    assert "### Counters" in page and "# usdksl on Newton simulator caches" not in page
    assert "Produced by `python benchmarks/ksl_vs_swept.py`; the page quotes its command lines." in page
    assert page.count("Command (run under `nice`): `python benchmarks/ksl_vs_swept.py") == 2
    assert "Produced by `python benchmarks/thickness.py` (the page does not record its arguments)." in page
    assert headings["scale.md"] not in page and "What accuracy costs" not in page
    assert not (tmp_path / report.SUMMARY_JSON).exists()


def test_the_accuracy_rows_are_rendered_from_the_folder_without_rewriting_them(suite_rows, tmp_path):
    rows, _ = suite_rows
    saved = {"budget_s": "60 s", "command": "python benchmarks/run.py --quick\tabc1234",
             "rows": json.loads(json.dumps(rows, default=float))}
    summary = tmp_path / report.SUMMARY_JSON
    summary.write_text(json.dumps(saved))
    before = summary.read_bytes()
    assert report.main(["--dir", str(tmp_path)]) == 0
    page = (tmp_path / "REPORT.md").read_text()
    assert page.index(f"## {report.ACCURACY_HEADING}") < page.index(f"## {report.PER_SHOT_HEADING}")
    assert "Produced by these runs of `python benchmarks/run.py`, all of build abc1234" in page
    assert "- `python benchmarks/run.py --quick`" in page
    assert (tmp_path / "time_vs_missed.png").read_bytes()[:4] == b"\x89PNG"
    assert summary.read_bytes() == before


def test_the_quick_runs_write_into_the_folder_they_are_given(tmp_path):
    commands = report.quick_runs(str(tmp_path))
    coverage = next(command for command in commands if command[1] == "benchmarks/coverage_cost.py")
    assert coverage[-2:] == ["--output", str(tmp_path / "coverage_cost.md")]
    assert all(Path(REPO_ROOT, argument).exists() for argument in coverage[2:-2])
