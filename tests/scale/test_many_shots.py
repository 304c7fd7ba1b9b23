"""``usdksl check S1 S2 S3``: in one process, on a LocalCluster (--jobs) and on a running Dask scheduler
(--scheduler), with a worker killed mid-run: every shot's files equal a single run's, byte for byte."""

import os
import shutil
import signal
import subprocess
import time
from pathlib import Path

import pytest
from click.testing import CliRunner

from usdksl.cli.main import main

from .conftest import POLL_SECONDS, RUN_SECONDS, STARTUP_SECONDS, executable, processing_worker

SHOTS = ("fold", "drape", "pass_through")
#: The files every shot writes (no --json/--junit/--crosscheck).
SUFFIXES = (".contacts.csv", ".summary.csv", ".usdksl.usda")


def _files(folder, names=SHOTS):
    """{file name: bytes} of the shots' files; the folder must sit at the depth of the reference folder
    (tmp_path and tmp_path_factory.mktemp do), since each layer names its shot by a relative path."""
    return {f"{name}{suffix}": (Path(folder) / f"{name}{suffix}").read_bytes()
            for name in names for suffix in SUFFIXES}


@pytest.fixture(scope="module")
def single_runs(tmp_path_factory, samples_dir):
    """Each shot checked on its own, the way it always was: the reference bytes."""
    out = tmp_path_factory.mktemp("single")
    for name in SHOTS:
        result = CliRunner().invoke(main, ["check", str(samples_dir / f"{name}.usda"), "--out", str(out)])
        assert result.exit_code == 1, result.output
    return _files(out)


def _check_command(samples_dir, out, *extra):
    return [executable("usdksl"), "check", *[str(samples_dir / f"{name}.usda") for name in SHOTS],
            "--out", str(out), *extra]


def test_several_shots_in_one_process_equal_single_runs_and_a_bad_one_does_not_stop_them(
        single_runs, samples_dir, tmp_path):
    (tmp_path / "inputs").mkdir()
    broken = tmp_path / "inputs" / "broken.usda"
    broken.write_text("#usda 1.0\n( this is not usd\n")
    # out at the depth of the single runs' folder, so the layers' relative sublayer paths match
    arguments = ["check", str(samples_dir / "fold.usda"), str(broken), str(samples_dir / "drape.usda"),
                 str(tmp_path / "missing.usda"), str(samples_dir / "pass_through.usda"), "--out", str(tmp_path)]
    result = CliRunner().invoke(main, arguments)
    assert result.exit_code == 2, result.output            # the worst: two shots could not be checked
    assert _files(tmp_path) == single_runs
    assert not list(tmp_path.glob("broken.*")) and not list(tmp_path.glob("missing.*"))
    lines = result.stderr.splitlines()
    assert sum(line.startswith("usdksl: error: ") for line in lines) == 2
    assert any(str(broken) in line and line.startswith("usdksl: error: ") for line in lines)
    assert sum("(132 contacting face pairs)" in line or "(16 contacting" in line or "(38 contacting" in line
               for line in lines) == 3
    assert lines[-1] == "usdksl: 5 shots: 0 clean, 3 with contacts, 2 failed; exit code 2"


def test_quoted_glob_expands_and_worst_code_over_clean_and_contacts(samples_dir, tmp_path):
    result = CliRunner().invoke(main, ["check", str(samples_dir / "[cf]*.usda"), "--out", str(tmp_path)])
    assert result.exit_code == 1, result.output
    assert sorted(p.name for p in tmp_path.glob("*.contacts.csv")) == ["clean.contacts.csv", "fold.contacts.csv"]
    assert result.stderr.splitlines()[-1] == "usdksl: 2 shots: 1 clean, 1 with contacts, 0 failed; exit code 1"


def test_two_shots_writing_the_same_files_is_a_usage_error(samples_dir, tmp_path):
    other = tmp_path / "elsewhere"
    other.mkdir()
    shutil.copy(samples_dir / "fold.usda", other / "fold.usda")
    result = CliRunner().invoke(main, ["check", str(samples_dir / "fold.usda"), str(other / "fold.usda"),
                                       "--out", str(tmp_path / "o")])
    assert result.exit_code == 2 and "would both write" in result.stderr
    assert not (tmp_path / "o").exists()


def test_jobs_on_a_local_cluster_write_what_single_runs_write(single_runs, samples_dir, tmp_path):
    completed = subprocess.run(_check_command(samples_dir, tmp_path, "--jobs", "2"), capture_output=True,
                               text=True, timeout=RUN_SECONDS, env={**os.environ, "CI": "1"})
    assert completed.returncode == 1, completed.stderr
    assert _files(tmp_path) == single_runs
    assert completed.stderr.splitlines()[-1] == "usdksl: 3 shots: 0 clean, 3 with contacts, 0 failed; exit code 1"


def test_scheduler_address_writes_what_single_runs_write(single_runs, samples_dir, tmp_path, dask_cluster):
    address, _, _ = dask_cluster
    completed = subprocess.run(_check_command(samples_dir, tmp_path, "--scheduler", address),
                               capture_output=True, text=True, timeout=RUN_SECONDS, env={**os.environ, "CI": "1"})
    assert completed.returncode == 1, completed.stderr
    assert _files(tmp_path) == single_runs


def test_a_worker_killed_mid_run_loses_and_duplicates_nothing(single_runs, samples_dir, tmp_path, dask_cluster):
    address, workers, client = dask_cluster
    check = subprocess.Popen(_check_command(samples_dir, tmp_path, "--scheduler", address),
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                             env={**os.environ, "CI": "1"})
    killed = None
    deadline = time.monotonic() + RUN_SECONDS
    try:
        while killed is None and check.poll() is None and time.monotonic() < deadline:
            killed = processing_worker(client, workers, "usdksl-check-")
            if killed is not None:
                workers[killed].send_signal(signal.SIGKILL)
            time.sleep(POLL_SECONDS)
        _, stderr = check.communicate(timeout=RUN_SECONDS)
    finally:
        if check.poll() is None:
            check.kill()
    assert killed is not None, "the check finished before a worker had a task: nothing was killed"
    assert workers[killed].wait(timeout=STARTUP_SECONDS) == -signal.SIGKILL
    assert check.returncode == 1, stderr
    assert _files(tmp_path) == single_runs
    assert stderr.splitlines()[-1] == "usdksl: 3 shots: 0 clean, 3 with contacts, 0 failed; exit code 1"
