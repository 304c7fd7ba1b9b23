"""The console script imports with the cyclic garbage collector paused and runs the check with it on again;
the objects the imports made are frozen out of its sight. In-process callers keep their collector as is."""

import gc
import json
import subprocess
import sys

from click.testing import CliRunner

from usdksl.cli.import_pause import collector_paused
from usdksl.cli.main import main as command_line

COLLECTOR_DURING_THE_CHECK = """
import gc, json, sys
import usdksl.pipeline.check as pipeline
seen = {}
original = pipeline.load_and_plan
def watched(*args, **kwargs):
    seen.update(enabled=gc.isenabled(), frozen=gc.get_freeze_count())
    return original(*args, **kwargs)
pipeline.load_and_plan = watched
import atexit
atexit.register(lambda: sys.__stdout__.write(json.dumps(seen) + "\\n"))
sys.argv = ["usdksl"] + sys.argv[1:]
from usdksl.cli.entry import main
main()
"""


def test_the_console_script_checks_with_the_collector_on_and_the_imports_frozen(two_quads_shot, tmp_path):
    completed = subprocess.run([sys.executable, "-P", "-c", COLLECTOR_DURING_THE_CHECK, "check", str(two_quads_shot),
                                "--out", str(tmp_path)], capture_output=True, text=True)
    assert completed.returncode == 1, completed.stderr   # the quads touch
    seen = json.loads(completed.stdout.strip().splitlines()[-1])
    assert seen["enabled"] is True
    assert seen["frozen"] > 10_000   # numpy's, USD's and usdksl's modules, classes and functions


def test_an_in_process_run_keeps_the_callers_collector(two_quads_shot, tmp_path):
    frozen = gc.get_freeze_count()
    result = CliRunner().invoke(command_line, ["check", str(two_quads_shot), "--out", str(tmp_path)])
    assert result.exit_code == 1, result.output
    assert gc.get_freeze_count() == frozen and gc.isenabled()


def test_the_pause_restores_the_collector_as_it_was():
    assert gc.isenabled()
    try:
        with collector_paused():
            assert not gc.isenabled()
        assert gc.isenabled()
        gc.disable()
        with collector_paused():
            assert not gc.isenabled()
        assert not gc.isenabled()
    finally:
        gc.enable()
        gc.unfreeze()
