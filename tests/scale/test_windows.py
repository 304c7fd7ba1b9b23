"""Long shots as time windows on Dask: where a shot is cut, that its windows merge into exactly one check's
files (in this process, on a LocalCluster, with a worker killed mid-window), that a shot whose windows
cannot be merged exactly is checked whole, the threads each worker's core gets, and the batch's progress."""

import io
import os
import signal
import subprocess
import time

import numpy as np
import pytest
from pxr import UsdGeom

from builders import QUAD_POINTS, add_mesh, new_stage
from usdksl.checking.collision import default_threads
from usdksl.pipeline import CheckOptions
from usdksl.scale.batch import make_jobs, run_job
from usdksl.scale.batch_progress import BatchProgress
from usdksl.scale.dask_runner import run_on_dask
from usdksl.scale.windows import (MIN_SAMPLES_PER_WINDOW, WindowPart, check_window, merge_windows, plan_windows,
                                  shot_windows)

from .conftest import POLL_SECONDS, RUN_SECONDS, STARTUP_SECONDS, executable, processing_worker

#: fold.usda is sampled at every frame 1..36; its strip first touches itself at about t = 31.9.
FOLD_FILES = ("fold.contacts.csv", "fold.summary.csv", "fold.usdksl.usda")


def _every(start, end, step=1.0):
    return np.arange(start, end + step / 2, step)


def _covers(windows, start, end):
    return (windows[0][0] == start and windows[-1][1] == end
            and all(a[1] == b[0] for a, b in zip(windows[:-1], windows[1:])))


def test_cuts_fall_on_times_every_animated_mesh_is_sampled_at():
    every_frame, odd_frames, still = _every(1, 41), _every(1, 41, 2), np.zeros(0)
    windows = plan_windows([every_frame, odd_frames, still], None, 2)
    assert len(windows) == 2 and _covers(windows, 1.0, 41.0)
    assert windows[0][1] % 2 == 1 and abs(windows[0][1] - 21) <= 2        # shared by both, near the middle
    windows = plan_windows([every_frame], None, 4)
    assert len(windows) == 4 and _covers(windows, 1.0, 41.0)
    assert [b - a for a, b in windows] == [10.0] * 4


def test_windows_hold_enough_samples_and_short_or_unshared_shots_stay_whole():
    frames = _every(1, 41)                                                    # 40 sample intervals
    windows = plan_windows([frames], None, 10)
    assert len(windows) == 40 // MIN_SAMPLES_PER_WINDOW
    assert all(b - a >= MIN_SAMPLES_PER_WINDOW for a, b in windows)
    assert plan_windows([_every(1, 2 * MIN_SAMPLES_PER_WINDOW)], None, 2) == []   # one interval too few
    assert plan_windows([frames], None, 1) == []
    assert plan_windows([np.zeros(0)], None, 4) == []                        # nothing moves
    assert plan_windows([frames, np.array([1.0, 41.0])], None, 2) == []       # no shared time inside
    # a mesh that starts late would get a held sample at a window's start: whole, unless a range is given
    late = _every(5, 41)
    assert plan_windows([frames, late], None, 2) == []
    windows = plan_windows([frames, late], (1.0, 41.0), 2)
    assert len(windows) == 2 and _covers(windows, 1.0, 41.0)
    windows = plan_windows([frames], (3.5, 30.0), 2)
    assert len(windows) == 2 and _covers(windows, 3.5, 30.0) and windows[0][1] in frames


@pytest.fixture
def fold(samples_dir):
    return str(samples_dir / "fold.usda")


def _job(shot, out, **reports):
    (job,) = make_jobs([shot], str(out), **reports)
    return job


@pytest.mark.parametrize("options", [CheckOptions(), CheckOptions(last_contact=True),
                                     CheckOptions(time_range=(2.5, 33.0), thickness=0.01)],
                         ids=["default", "last-contact", "time-range"])
def test_windows_merged_equal_one_check_byte_for_byte(fold, tmp_path, options):
    job = _job(fold, tmp_path, json_path=str(tmp_path / "fold.json"))
    whole = run_job(job, options)
    assert whole.exit_code == 1 and whole.windows == 1
    windows = shot_windows(job, options, 3)
    assert len(windows) == 3
    parts = [check_window(job, options, window) for window in windows]
    assert all(part.error is None for part in parts)
    merged = merge_windows(job, options, *parts)
    assert merged.windows == 3 and merged.exit_code == 1
    assert merged.result.files == whole.result.files                  # every file, the JSON report included
    assert merged.result.table.count == whole.result.table.count == sum(
        1 for _ in whole.result.files[tmp_path / "fold.contacts.csv"].splitlines()[1:])
    assert [m for m in merged.messages if m.level != "info"] == [m for m in whole.messages if m.level != "info"]


def test_windows_merged_against_a_baseline_equal_one_check_against_it(fold, tmp_path):
    reference = run_job(_job(fold, tmp_path / "reference"), CheckOptions())
    lines = reference.result.files[tmp_path / "reference" / "fold.contacts.csv"].splitlines(keepends=True)
    baseline = tmp_path / "baseline.csv"
    baseline.write_text("".join(lines[:1] + lines[2:]))                  # the first face pair becomes new
    (job,) = make_jobs([fold], str(tmp_path), baseline=str(baseline))
    options = CheckOptions()
    whole = run_job(job, options)
    merged = merge_windows(job, options, *[check_window(job, options, w) for w in shot_windows(job, options, 2)])
    assert merged.windows == 2 and merged.result.files == whole.result.files
    assert merged.result.baseline.new_count == whole.result.baseline.new_count == 1


def test_a_window_that_failed_makes_the_merge_check_the_shot_whole(fold, tmp_path):
    job = _job(fold, tmp_path)
    options = CheckOptions()
    whole = run_job(job, options)
    first, second = shot_windows(job, options, 2)
    parts = [check_window(job, options, first), WindowPart(start=second[0], end=second[1], error="worker lost")]
    merged = merge_windows(job, options, *parts)
    assert merged.windows == 1 and merged.result.files == whole.result.files
    assert "checked whole, not as 2 time windows: time window 18..36 failed: worker lost" in merged.messages[0].text


def _hidden_while_falling(path):
    """A quad falling through a static floor quad at every frame 1..24, touching it at t = 12.5, invisible
    from frame 10 on: the whole range checks it (visible for part of it), a window from 12 on would not."""
    stage = new_stage(path)
    add_mesh(stage, "/World/Floor", QUAD_POINTS)
    falling = add_mesh(stage, "/World/Falling", None,
                       samples={t: QUAD_POINTS + [0.0, 1.0 - 2.0 * (t - 1.0) / 23.0, 0.0] for t in _every(1, 24)})
    visibility = UsdGeom.Imageable(falling.GetPrim()).CreateVisibilityAttr()
    visibility.Set(UsdGeom.Tokens.inherited, 1.0)
    visibility.Set(UsdGeom.Tokens.invisible, 10.0)
    stage.GetRootLayer().Save()
    return str(path)


def test_windows_that_would_check_other_mesh_pairs_are_not_merged_and_the_contact_is_kept(tmp_path):
    shot = _hidden_while_falling(tmp_path / "hidden.usda")
    job = _job(shot, tmp_path / "out")
    options = CheckOptions()
    whole = run_job(job, options)
    assert whole.exit_code == 1 and whole.result.table.count == 1
    windows = shot_windows(job, options, 2)
    assert len(windows) == 2 and windows[0][1] <= 12.5
    parts = [check_window(job, options, window) for window in windows]
    assert parts[0].table.count == 0 and parts[1].table.count == 0     # the late window skips the hidden quad
    merged = merge_windows(job, options, *parts)
    assert merged.windows == 1 and merged.result.files == whole.result.files
    assert "checked mesh pairs" in merged.messages[0].text


def _file_bytes(folder, names=FOLD_FILES):
    return {name: (folder / name).read_bytes() for name in names}


@pytest.fixture(scope="module")
def fold_single_run(tmp_path_factory, samples_dir):
    """fold.usda checked in this process without Dask: the reference bytes."""
    out = tmp_path_factory.mktemp("single")
    outcome = run_job(_job(str(samples_dir / "fold.usda"), out), CheckOptions())
    assert outcome.exit_code == 1
    from usdksl.scale.batch import write_outcome
    write_outcome(outcome)
    return _file_bytes(out)


def test_one_shot_with_jobs_is_checked_in_windows_and_writes_one_runs_files(fold, fold_single_run, tmp_path):
    completed = subprocess.run([executable("usdksl"), "check", fold, "--jobs", "2", "--out", str(tmp_path), "-v"],
                               capture_output=True, text=True, timeout=RUN_SECONDS, env={**os.environ, "CI": "1"})
    assert completed.returncode == 1, completed.stderr
    assert _file_bytes(tmp_path) == fold_single_run
    assert f"usdksl: {fold}: checked as 2 time windows: 1..18, 18..36" in completed.stderr.splitlines()
    assert "\r" not in completed.stderr                                   # no progress bar outside a terminal


def test_workers_run_the_core_on_their_share_of_the_cores_unless_threads_are_given(fold, fold_single_run, tmp_path):
    progress = BatchProgress(1, enabled=False)
    (outcome,) = run_on_dask([_job(fold, tmp_path / "a")], CheckOptions(), workers=2, progress=progress)
    assert outcome.windows == 2 and outcome.exit_code == 1
    assert outcome.result.threads == max(1, default_threads() // 2)
    assert (progress.total, progress.done) == (2, 2)                      # a piece per window
    (outcome,) = run_on_dask([_job(fold, tmp_path)], CheckOptions(threads=3), workers=1)
    assert outcome.windows == 1 and outcome.result.threads == 3
    # tmp_path sits at the depth of the reference folder, so the layer's relative sublayer path matches
    assert {name: outcome.result.files[tmp_path / name].encode() for name in FOLD_FILES} == fold_single_run


def test_a_worker_killed_in_a_window_loses_and_duplicates_nothing(fold, fold_single_run, tmp_path, dask_cluster):
    address, workers, client = dask_cluster
    check = subprocess.Popen([executable("usdksl"), "check", fold, "--scheduler", address, "--out", str(tmp_path),
                              "-v"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                             env={**os.environ, "CI": "1"})
    killed = None
    deadline = time.monotonic() + RUN_SECONDS
    try:
        while killed is None and check.poll() is None and time.monotonic() < deadline:
            killed = processing_worker(client, workers, "usdksl-window-")
            if killed is not None:
                workers[killed].send_signal(signal.SIGKILL)
            time.sleep(POLL_SECONDS)
        _, stderr = check.communicate(timeout=RUN_SECONDS)
    finally:
        if check.poll() is None:
            check.kill()
    assert killed is not None, "the check finished before a window was running: nothing was killed"
    assert workers[killed].wait(timeout=STARTUP_SECONDS) == -signal.SIGKILL
    assert check.returncode == 1, stderr
    assert _file_bytes(tmp_path) == fold_single_run
    assert f"usdksl: {fold}: checked as 2 time windows: 1..18, 18..36" in stderr.splitlines()
    assert stderr.splitlines()[-1] == "usdksl: 1 shot: 0 clean, 1 with contacts, 0 failed; exit code 1"


def test_one_bar_counts_shots_and_windows_on_a_terminal():
    stream = io.StringIO()
    bar = BatchProgress(2, enabled=True, stream=stream)
    bar.split(3)                        # one of the two shots became three windows
    for _ in range(4):
        bar.advance()
    bar.close()
    assert (bar.total, bar.done) == (4, 4)
    drawn = stream.getvalue()
    assert "0/2" in drawn and "0/4" in drawn and "3/4" in drawn and "4/4" in drawn
    quiet = io.StringIO()
    silent = BatchProgress(2, enabled=False, stream=quiet)
    silent.advance(2)
    silent.close()
    assert quiet.getvalue() == "" and silent.done == 2
