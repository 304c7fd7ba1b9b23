"""A finished ``usdksl`` command ends without the interpreter's teardown, yet nothing visible changes:
the exit code, everything printed (also unflushed), atexit handlers; and where skipping the teardown would
show (another thread still running, an exit code that is a message, a profiler), the normal exit does the
work."""

import subprocess
import sys
import tempfile

import pytest

ENDING = """
import atexit, sys, threading, time
from usdksl.cli.quick_exit import exit_quickly
atexit.register(lambda: sys.stdout.write(" atexit"))
sys.stdout.write("printed, not flushed")
sys.stderr.write("and on stderr")
if "thread" in sys.argv:
    threading.Thread(target=lambda: (time.sleep(0.3), sys.stdout.write(" thread done"))).start()
code = int(sys.argv[1]) if sys.argv[1].lstrip("-").isdigit() else (None if sys.argv[1] == "none" else sys.argv[1])
try:
    raise SystemExit(code)
except SystemExit as done:
    exit_quickly(done.code)
    sys.stdout.write(" normal exit")
    raise
"""


#: Where the child runs: not the checkout, whose usdksl/ (without cli/, which only an install maps into
#: the package) would shadow the installed package for ``python -c`` and ``python -m``.
OUTSIDE_THE_CHECKOUT = tempfile.gettempdir()


def _end(*args):
    return subprocess.run([sys.executable, "-c", ENDING, *args], capture_output=True, text=True,
                          cwd=OUTSIDE_THE_CHECKOUT)


@pytest.mark.parametrize("code, status", [("0", 0), ("1", 1), ("3", 3), ("130", 130), ("none", 0), ("-1", 255)])
def test_the_exit_code_output_and_atexit_handlers_are_kept(code, status):
    completed = _end(code)
    assert completed.returncode == status
    assert completed.stdout == "printed, not flushed atexit"
    assert completed.stderr == "and on stderr"


def test_a_running_thread_gets_the_normal_exit_which_waits_for_it():
    completed = _end("1", "thread")
    assert completed.returncode == 1
    assert completed.stdout == "printed, not flushed normal exit thread done atexit"


def test_a_message_as_exit_code_gets_the_normal_exit_which_prints_it():
    completed = _end("bad input")
    assert completed.returncode == 1
    assert completed.stdout == "printed, not flushed normal exit atexit"
    assert completed.stderr == "and on stderrbad input\n"


def test_a_profiled_run_gets_the_normal_exit_so_the_profile_is_written(tmp_path):
    script, report = tmp_path / "ending.py", tmp_path / "run.prof"
    script.write_text(ENDING)
    completed = subprocess.run([sys.executable, "-m", "cProfile", "-o", str(report), str(script), "2"],
                               capture_output=True, text=True, cwd=OUTSIDE_THE_CHECKOUT)
    assert completed.returncode == 0   # cProfile's own way: it swallows the script's SystemExit
    assert completed.stdout == "printed, not flushed normal exit atexit"
    assert report.is_file() and report.stat().st_size > 0
