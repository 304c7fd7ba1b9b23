"""benchmarks/check_e2e_ab.py: this build's usdksl check against another build's, in alternating processes."""

import os
import stat
import subprocess
import sys

from conftest import REPO_ROOT

SCRIPT = REPO_ROOT / "benchmarks" / "check_e2e_ab.py"
USDKSL = os.path.join(os.path.dirname(sys.executable), "usdksl")


def _compare(shot, baseline, rounds="2"):
    return subprocess.run([sys.executable, str(SCRIPT), str(shot), "--baseline", str(baseline), "--rounds", rounds],
                          capture_output=True, text=True)


def test_a_build_against_itself_times_both_and_finds_every_file_the_same(samples_dir):
    run = _compare(samples_dir / "fold.usda", USDKSL)
    assert run.returncode == 0, run.stdout + run.stderr
    lines = run.stdout.splitlines()
    assert "(2 alternating rounds" in lines[0]
    assert any(line.strip().startswith("this build ") and "wall least" in line and "exit codes [1]" in line
               for line in lines)
    assert any("this build / baseline: least" in line for line in lines)
    assert "fold.contacts.csv" in lines[-1] and "fold.usdksl.usda" in lines[-1]
    assert lines[-1].endswith("all byte-identical")


def test_a_baseline_that_writes_other_bytes_is_named_and_fails(samples_dir, tmp_path):
    other = tmp_path / "other-usdksl"
    other.write_text(f"#!/bin/sh\n{USDKSL} \"$@\"\ncode=$?\nprintf x >> \"$4/fold.summary.csv\"\nexit $code\n")
    other.chmod(other.stat().st_mode | stat.S_IEXEC)
    run = _compare(samples_dir / "fold.usda", other, rounds="1")
    assert run.returncode == 1, run.stdout + run.stderr
    assert run.stdout.splitlines()[-1].endswith("DIFFERENT: fold.summary.csv")
