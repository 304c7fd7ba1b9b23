"""Ctrl-C (SIGINT), a farm's SIGTERM and --timeout stop ``usdksl check`` soon, with one line, exit code
130 / 143 / 2, and nothing left behind: no output file, no temporary file, no worker process.

Each case starts the installed command on a shot that takes far longer than the test (a self-colliding
swirl: KSL needs tens of seconds on it), waits until the check runs, signals, and times the stop.
"""

import os
import shutil
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import psutil
import pytest

REPO_ROOT = Path(__file__).resolve().parents[2]
#: Seconds from the signal to the process's end that docs/contracts.md, Stopping, allows ("a second or two").
STOP_SECONDS = 3.0
#: Seconds the check runs before the signal.
RUNNING_SECONDS = 1.0
#: Seconds the command may take to load the shot and print its plan (or to start its workers).
START_SECONDS = 120
PLAN_LINE = "pairs checked"


@pytest.fixture(scope="module")
def slow_shot(tmp_path_factory):
    """A 1,500-face swirl folding over itself: heavy self contact, many seconds of checking."""
    folder = tmp_path_factory.mktemp("slow")
    path = folder / "swirl.usdc"
    subprocess.run([sys.executable, str(REPO_ROOT / "samples" / "generate.py"), "swirl", "--faces", "1500",
                    "--keyframes", "4", "--samples-per-keyframe", "2", "--out", str(path)],
                   check=True, capture_output=True)
    return path


def _usdksl():
    found = shutil.which("usdksl", path=str(Path(sys.executable).parent))
    assert found, f"usdksl is installed beside {sys.executable}"
    return found


class Run:
    """The command in a session of its own (so a signal can go to its whole process group, as a
    terminal's Ctrl-C does), its stderr collected line by line as it comes."""

    def __init__(self, args, tmp_path):
        self.temp = tmp_path / "tmp"
        self.temp.mkdir()
        env = dict(os.environ, TMPDIR=str(self.temp), USDKSL_DEBUG="")
        env.pop("CI", None)
        self.process = subprocess.Popen([_usdksl(), "check", *map(str, args)], stdout=subprocess.DEVNULL,
                                        stderr=subprocess.PIPE, text=True, env=env, start_new_session=True)
        self.lines = []
        self.children = set()
        self._reader = threading.Thread(target=self._read, daemon=True)
        self._reader.start()

    def _read(self):
        for line in self.process.stderr:
            self.lines.append(line.rstrip("\n"))

    def wait_for(self, ready, what):
        deadline = time.monotonic() + START_SECONDS
        while not ready():
            assert self.process.poll() is None, f"ended before {what}: {self.lines}"
            assert time.monotonic() < deadline, f"no {what} after {START_SECONDS} s: {self.lines}"
            time.sleep(0.05)

    def worker_processes(self):
        try:
            found = psutil.Process(self.process.pid).children(recursive=True)
        except psutil.NoSuchProcess:
            return []
        self.children.update(child.pid for child in found)
        return found

    def stop(self, signum, group=False):
        """Send ``signum`` after RUNNING_SECONDS; (exit code, seconds from the signal to the end)."""
        time.sleep(RUNNING_SECONDS)
        self.worker_processes()
        assert self.process.poll() is None, f"ended before the signal: {self.lines}"
        sent = time.monotonic()
        if group:
            os.killpg(self.process.pid, signum)
        else:
            self.process.send_signal(signum)
        code = self.process.wait(timeout=60)
        elapsed = time.monotonic() - sent
        self._reader.join(timeout=10)
        return code, elapsed

    def after_plan(self):
        """stderr lines after the plan (the plan's lines start with 'usdksl: ' and come first)."""
        plan_end = max((i for i, line in enumerate(self.lines) if line.startswith("usdksl:   ")), default=-1)
        return self.lines[plan_end + 1:]


def assert_nothing_left(run, out, shot_folder):
    assert not out.exists() or sorted(out.iterdir()) == [], "no output may be left"
    leftovers = [p.name for p in shot_folder.iterdir() if p.name.startswith(".usdksl-tmp-")]
    assert leftovers == [], "the atomic writer's temporary files must be gone"
    assert sorted(run.temp.iterdir()) == [], "nothing may be left in the temporary folder"
    assert all("Traceback" not in line and "internal error" not in line for line in run.lines), run.lines


def assert_children_gone(run):
    deadline = time.monotonic() + 5
    alive = [pid for pid in run.children if psutil.pid_exists(pid)
             and psutil.Process(pid).status() != psutil.STATUS_ZOMBIE]
    while alive and time.monotonic() < deadline:
        time.sleep(0.1)
        alive = [pid for pid in alive if psutil.pid_exists(pid)
                 and psutil.Process(pid).status() != psutil.STATUS_ZOMBIE]
    assert alive == [], f"worker processes left running: {alive}"


@pytest.mark.parametrize("signum, code, word, group, method", [
    (signal.SIGINT, 130, "interrupted (SIGINT)", False, "ksl"),
    (signal.SIGINT, 130, "interrupted (SIGINT)", True, "ksl"),     # Ctrl-C at a terminal: the whole group
    (signal.SIGTERM, 143, "terminated (SIGTERM)", False, "ksl"),
    (signal.SIGINT, 130, "interrupted (SIGINT)", False, "swept"),
    (signal.SIGTERM, 143, "terminated (SIGTERM)", False, "brute"),
])
def test_a_signal_stops_one_shot_with_one_line_and_leaves_nothing(slow_shot, tmp_path, signum, code, word,
                                                                   group, method):
    shot = tmp_path / "in" / slow_shot.name
    shot.parent.mkdir()
    shutil.copyfile(slow_shot, shot)
    out = tmp_path / "out"
    run = Run([shot, "-v", "--out", out, "--method", method], tmp_path)   # -v: the plan is the cue to signal
    run.wait_for(lambda: any(PLAN_LINE in line for line in run.lines), "plan")
    exit_code, elapsed = run.stop(signum, group=group)
    assert exit_code == code, run.lines
    assert run.after_plan() == [f"usdksl: {shot}: {word}; nothing written"], run.lines
    assert elapsed < STOP_SECONDS, f"took {elapsed:.2f} s to stop"
    assert_nothing_left(run, out, shot.parent)


def test_timeout_ends_the_check_with_exit_2_and_one_line(slow_shot, tmp_path):
    out = tmp_path / "out"
    started = time.monotonic()
    run = Run([slow_shot, "--out", out, "--timeout", "2"], tmp_path)
    exit_code = run.process.wait(timeout=120)
    run._reader.join(timeout=10)
    assert exit_code == 2, run.lines
    assert run.after_plan() == [f"usdksl: error: {slow_shot}: timed out after 2 s (--timeout); nothing written"]
    assert time.monotonic() - started >= 2
    assert_nothing_left(run, out, slow_shot.parent)


@pytest.mark.parametrize("signum, code, word, group", [
    (signal.SIGINT, 130, "interrupted (SIGINT)", True),
    (signal.SIGTERM, 143, "terminated (SIGTERM)", False),
])
def test_a_signal_stops_a_dask_run_and_its_workers(slow_shot, tmp_path, signum, code, word, group):
    shots = []
    for name in ("a", "b", "c"):
        shots.append(tmp_path / f"{name}.usdc")
        shutil.copyfile(slow_shot, shots[-1])
    out = tmp_path / "out"
    run = Run([*shots, "--out", out, "--jobs", "2"], tmp_path)
    # two workers and multiprocessing's resource tracker
    run.wait_for(lambda: len(run.worker_processes()) >= 3, "worker processes")
    exit_code, elapsed = run.stop(signum, group=group)
    assert exit_code == code, run.lines
    assert run.lines == [f"usdksl: {word}; nothing written"]
    assert elapsed < STOP_SECONDS, f"took {elapsed:.2f} s to stop"
    assert_nothing_left(run, out, tmp_path)
    assert_children_gone(run)


def test_a_stop_between_shots_keeps_the_finished_ones_complete(slow_shot, samples_dir, tmp_path):
    quick = tmp_path / "fold.usda"
    shutil.copyfile(samples_dir / "fold.usda", quick)
    out = tmp_path / "out"
    run = Run([quick, slow_shot, "--out", out], tmp_path)
    run.wait_for(lambda: any(line.startswith(f"usdksl: {quick}: ") for line in run.lines), "the first shot")
    exit_code, elapsed = run.stop(signal.SIGINT)
    assert exit_code == 130
    assert run.lines[-1] == "usdksl: interrupted (SIGINT); 1 of 2 shots finished (their files are written), " \
                            "the others not"
    assert elapsed < STOP_SECONDS
    assert sorted(p.name for p in out.iterdir()) == ["fold.contacts.csv", "fold.regions.csv", "fold.summary.csv",
                                                     "fold.usdksl.usda"]
    assert (out / "fold.contacts.csv").read_text().startswith("time,prim_a,face_a,prim_b,face_b,kind")
    assert not any(line.startswith(f"usdksl: {slow_shot}") for line in run.lines)


def _catches(pid, signum):
    """Whether process ``pid`` has a handler installed for ``signum`` (Linux /proc)."""
    with open(f"/proc/{pid}/status") as status:
        for line in status:
            if line.startswith("SigCgt:"):
                return bool(int(line.split()[1], 16) >> (signum - 1) & 1)
    return False


@pytest.mark.skipif(not Path("/proc/self/status").exists(), reason="reads handlers from /proc")
def test_a_ctrl_c_while_the_command_starts_is_one_line_too(slow_shot, tmp_path):
    # USD's module loader swallows an exception raised while it imports; the command holds the stop
    # back until the imports are done. SIGTERM gets a handler only from usdksl: that is the moment.
    out = tmp_path / "out"
    run = Run([slow_shot, "--out", out], tmp_path)
    run.wait_for(lambda: _catches(run.process.pid, signal.SIGTERM), "stop handlers")
    run.process.send_signal(signal.SIGINT)
    exit_code = run.process.wait(timeout=60)
    run._reader.join(timeout=10)
    assert exit_code == 130
    # stopped before the check began (no plan, no shot named), not after the imports
    assert run.lines == ["usdksl: interrupted (SIGINT); nothing written"]
    assert_nothing_left(run, out, slow_shot.parent)
