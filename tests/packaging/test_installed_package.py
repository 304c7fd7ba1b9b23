"""The installed package is what users get: native module inside, CLI as usdksl.cli only."""

import importlib.util
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

import usdksl

REPO_ROOT = Path(__file__).resolve().parents[2]
EDITABLE = Path(usdksl.__file__).resolve().parent == REPO_ROOT / "usdksl"


def _run_outside_repo(code, tmp_path):
    # From a neutral folder, so nothing in the source tree can shadow the installed package.
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    return subprocess.run([sys.executable, "-c", code], cwd=tmp_path, env=env, capture_output=True, text=True)


def test_native_module_lives_inside_the_package():
    native = Path(usdksl._native.__file__)
    assert native.name.startswith("_native") and native.suffix in (".so", ".pyd")
    assert hasattr(usdksl._native, "find_contacts")


@pytest.mark.skipif(EDITABLE, reason="editable install maps the source tree, where cli/ is importable; "
                                      "CI installs the wheel and runs this")
def test_cli_is_shipped_as_usdksl_cli_and_not_as_top_level_cli(tmp_path):
    assert importlib.util.find_spec("usdksl.cli.main") is not None
    result = _run_outside_repo("import cli", tmp_path)
    assert result.returncode != 0 and "ModuleNotFoundError" in result.stderr
    result = _run_outside_repo("import usdksl.cli.main as m; print(m.main.name)", tmp_path)
    assert result.returncode == 0 and result.stdout.strip() == "main"


def test_readme_test_command_is_what_ci_runs_against_the_wheel():
    # The README installs from source; CI installs the repaired wheel with the same extras, then runs the
    # same pytest command.
    readme = (REPO_ROOT / "README.md").read_text()
    ci_lines = [line.strip() for line in (REPO_ROOT / ".ci" / "run").read_text().splitlines()]
    command = next(line.strip() for line in readme.splitlines() if ".venv/bin/pytest" in line)
    install, pytest_part = command.rsplit(" && ", 1)
    extras = re.search(r'pip install (?:-q )?"\.(\[[\w,]+\])"', install).group(1)
    assert pytest_part == ci_lines[-1]
    assert any(".venv/bin/pip install" in line and f'"$wheel{extras}"' in line for line in ci_lines)
