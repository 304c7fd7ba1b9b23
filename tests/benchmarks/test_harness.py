"""benchmarks/harness.py measures what it says: wall time, CPU time (user + system, children included) and the
RSS high-water mark, of a command, of a function in a fresh interpreter, and of two builds compared in one run."""

import re
import subprocess
import sys

import numpy as np
import pytest

import harness
from conftest import REPO_ROOT

#: Seconds a sleeping command sleeps.
NAP_S = 0.2
#: Most CPU seconds a sleeping command may be charged (process start and exit).
IDLE_CPU_S = 0.05
#: Megabytes a function allocates (and touches) in a fresh interpreter.
ALLOCATED_MB = 200
#: Share of an allocation a measurement in this (pytest's) process is sure to see: memory the process
#: freed before can take part of it.
REUSED_MEMORY_SHARE = 0.9
#: Widest a ratio of a build over itself may stray from 1 on a shared machine (least of the rounds).
SAME_BUILD_RATIO = (0.75, 1.33)

WORKLOAD = '''
import time

def allocate(megabytes):
    import numpy as np
    block = np.ones(int(megabytes * 10**6 / 8))
    return float(block.sum())

def nap(seconds):
    time.sleep(seconds)
    return seconds

def spin():
    while True:
        pass

def fail():
    raise ValueError("the workload gave up")
'''


@pytest.fixture
def workload(tmp_path):
    path = tmp_path / "workload.py"
    path.write_text(WORKLOAD)
    return lambda name: f"{path}:{name}"


def test_a_sleeping_command_takes_its_wall_time_and_almost_no_cpu():
    measured = harness.run(["sleep", str(NAP_S)])
    assert measured.exit_code == 0 and measured.completed
    assert measured.wall_s >= NAP_S
    assert measured.cpu_s < IDLE_CPU_S


def test_a_function_in_a_fresh_interpreter_reports_its_own_peak(workload):
    measured = harness.call_fresh(workload("allocate"), ALLOCATED_MB)
    assert measured.error is None, measured.stderr
    assert measured.value == ALLOCATED_MB * 10**6 / 8
    assert measured.peak_rise_bytes > ALLOCATED_MB * 10**6
    assert measured.peak_rss_bytes > ALLOCATED_MB * 10**6
    assert measured.cpu_s > 0 and measured.wall_s > 0


def test_an_inner_measurement_does_not_hide_the_outer_peak():
    """The inner measurement resets the high-water mark; the block freed before it still counts for the
    outer one."""
    with harness.measuring() as outer:
        block = np.ones(ALLOCATED_MB * 10**6 // 8)
        del block
        with harness.measuring() as inner:
            small = np.ones(1000)
        del small
    assert outer.peak_rise_bytes > REUSED_MEMORY_SHARE * ALLOCATED_MB * 10**6
    assert inner.peak_rise_bytes < ALLOCATED_MB * 10**6 / 2


def test_a_build_compared_with_itself_prints_ratios_near_one():
    completed = subprocess.run([sys.executable, str(REPO_ROOT / "benchmarks" / "harness.py"), "--rounds", "3",
                                "--baseline", sys.executable, "python", "-c", f"import time; time.sleep({NAP_S})"],
                               capture_output=True, text=True)
    assert completed.returncode == 0, completed.stderr
    assert "(3 alternating rounds" in completed.stdout
    ratio = re.search(r"this build / baseline: least ([0-9.]+), median ([0-9.]+) \(wall\)", completed.stdout)
    assert ratio, completed.stdout
    low, high = SAME_BUILD_RATIO
    assert low < float(ratio.group(1)) < high, completed.stdout


def test_builds_alternate_and_summaries_take_least_and_median():
    order = []
    runs = harness.alternate({"a": lambda: order.append("a") or harness.Measurement(wall_s=len(order)),
                              "b": lambda: order.append("b") or harness.Measurement(wall_s=len(order))}, 3)
    assert order == ["a", "b"] * 3
    summary = harness.summarise(runs["a"])
    assert (summary.runs, summary.wall_least_s, summary.wall_median_s) == (3, 1, 3)
    assert harness.ratio_line("a", "b", summary, harness.summarise(runs["b"])).startswith(
        "a / b: least 0.500, median 0.750 (wall)")


def test_limits_end_a_run_and_say_which(workload):
    slow = harness.run(["sleep", "30"], timeout_s=NAP_S)
    assert slow.timed_out and not slow.over_cpu_budget and slow.wall_s < 10
    spinning = harness.call_fresh(workload("spin"), cpu_budget_s=1)
    assert spinning.over_cpu_budget and not spinning.timed_out and not spinning.completed


def test_a_function_that_raises_names_the_error(workload):
    failed = harness.call_fresh(workload("fail"))
    assert not failed.completed and failed.exit_code != 0
    assert failed.error == "ValueError: the workload gave up"


def test_another_build_is_found_from_its_python_or_its_command(tmp_path, workload):
    python = harness.Build.of(sys.executable)
    assert python.usdksl.endswith("usdksl") and python.python == sys.executable
    script = tmp_path / "bin" / "usdksl"
    script.parent.mkdir()
    script.write_text(f"#!{sys.executable}\nprint('a console script')\n")
    command = harness.Build.of(str(script))
    assert (command.usdksl, command.python) == (str(script), sys.executable)
    measured = command.call(workload("nap"), NAP_S)
    assert measured.value == NAP_S and measured.wall_s >= NAP_S
