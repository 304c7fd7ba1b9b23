"""benchmarks/ksl_vs_swept.py across two builds: the face-contact comparison and a METHOD@baseline run."""

import re
import subprocess
import sys

import numpy as np

import ksl_vs_swept
from conftest import REPO_ROOT


def contacts(rows):
    rows = np.asarray(rows, dtype=np.float64).reshape(-1, 5)
    return {"time": rows[:, 0], "mesh_a": rows[:, 1].astype(np.int32), "face_a": rows[:, 2].astype(np.int32),
            "mesh_b": rows[:, 3].astype(np.int32), "face_b": rows[:, 4].astype(np.int32)}


REFERENCE_ROWS = [(1.5, 0, 3, 1, 7), (2.25, 1, 0, 1, 4), (2.25, 0, 9, 1, 1), (4.0, 1, 2, 1, 8)]
ALLOWANCE = 1e-6


def test_times_inside_the_allowance_are_the_same_answer():
    moved = [(t + 0.9 * ALLOWANCE * (-1) ** k, *rest) for k, (t, *rest) in enumerate(REFERENCE_ROWS)]
    c = ksl_vs_swept.compare_face_contacts(contacts(REFERENCE_ROWS), contacts(moved[::-1]), ALLOWANCE)
    assert ksl_vs_swept.is_same_answer(c) and c["common"] == 4
    assert np.isclose(c["max_abs_dt"], 0.9 * ALLOWANCE)


def test_a_missed_a_later_an_earlier_and_an_extra_pair_are_each_counted():
    other = [(1.5 + 3 * ALLOWANCE, 0, 3, 1, 7), (2.25 - 3 * ALLOWANCE, 1, 0, 1, 4), (4.0, 1, 2, 1, 8),
             (5.0, 0, 1, 1, 1)]
    c = ksl_vs_swept.compare_face_contacts(contacts(REFERENCE_ROWS), contacts(other), ALLOWANCE)
    assert (c["missed"], c["extra"], c["later"], c["earlier"], c["common"]) == (1, 1, 1, 1, 3)
    assert not ksl_vs_swept.is_same_answer(c)


def test_a_baseline_run_is_compared_with_this_build_and_written_as_a_page(tiny_tablecloth, tmp_path):
    page = tmp_path / "before_after.md"
    run = subprocess.run([sys.executable, str(REPO_ROOT / "benchmarks" / "ksl_vs_swept.py"), str(tiny_tablecloth),
                          "ksl,ksl@baseline,swept", "--threads", "1", "--baseline-python", sys.executable,
                          "--markdown", str(page), "--title", "tiny"],
                         capture_output=True, text=True)
    assert run.returncode == 0, run.stdout + run.stderr
    assert "ksl against ksl@baseline: SAME answer within the CCD tolerance" in run.stdout
    assert "ksl/ksl@baseline process time at threads=1:" in run.stdout
    text = page.read_text()
    assert text.startswith("# tiny\n")
    row = next(line for line in text.splitlines() if line.startswith("| tablecloth_tiny.usdc |"))
    cells = [cell.strip() for cell in re.split(r"(?<!\\)\|", row)[1:-1]]
    assert len(cells) == 9  # shot, size, 3 CPU columns, ksl/ksl@baseline, swept/ksl, answer, load
    assert cells[7].startswith("yes (")
