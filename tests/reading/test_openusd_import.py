"""Without any pxr, importing usdksl (and running the command) fails with one actionable line."""

import os
import subprocess
import sys
from pathlib import Path

import pytest

REPO_ROOT = Path(__file__).resolve().parents[2]


def _without_pxr(tmp_path):
    """An environment whose first sys.path entry has a 'pxr' that cannot be imported, like a Python
    without usd-core and outside any studio USD build."""
    fake = tmp_path / "no_usd" / "pxr"
    fake.mkdir(parents=True)
    (fake / "__init__.py").write_text("raise ImportError('No module named pxr (test stand-in)')\n")
    env = {key: value for key, value in os.environ.items() if key != "PYTHONPATH"}
    env["PYTHONPATH"] = str(fake.parent)
    return env


def test_using_usdksl_without_pxr_is_one_actionable_line(tmp_path):
    # usdksl imports its modules on first use (so the command can hold back a Ctrl-C while USD loads);
    # the first name that needs pxr fails with the one line.
    result = subprocess.run([sys.executable, "-c", "import usdksl; usdksl.load_shot"], cwd=tmp_path,
                            env=_without_pxr(tmp_path),
                            capture_output=True, text=True)
    assert result.returncode != 0
    lines = [line for line in result.stderr.splitlines() if "usdksl needs" in line]
    assert len(lines) == 1
    assert lines[0].startswith("ImportError: usdksl needs OpenUSD's Python module 'pxr'")
    assert 'pip install "usdksl[usd]"' in lines[0] and "hython" in lines[0]


def test_command_without_pxr_prints_one_error_line_and_exits_2(tmp_path):
    command = Path(sys.executable).with_name("usdksl")
    if not command.is_file():
        pytest.skip(f"no usdksl console script beside {sys.executable}")
    result = subprocess.run([str(command), "info", "shot.usda"], cwd=tmp_path, env=_without_pxr(tmp_path),
                            capture_output=True, text=True)
    assert result.returncode == 2
    assert result.stderr.splitlines() == [line for line in result.stderr.splitlines()
                                          if line.startswith("usdksl: error: usdksl needs")]
    assert len(result.stderr.splitlines()) == 1 and "Traceback" not in result.stderr


def test_readme_installs_usd_core_through_the_usd_extra():
    readme = (REPO_ROOT / "README.md").read_text()
    commands = [line.strip() for line in readme.splitlines() if line.strip().startswith("python3 -m venv")]
    assert len(commands) == 2                                   # exactly the two set-up commands
    assert 'pip install ".[usd]"' in commands[0] and '".[test]"' in commands[1]


def test_usd_core_is_an_extra_that_the_test_extra_pulls_in():
    tomllib = pytest.importorskip("tomllib")
    project = tomllib.loads((REPO_ROOT / "pyproject.toml").read_text())["project"]
    assert not any(requirement.startswith("usd-core") for requirement in project["dependencies"])
    extras = project["optional-dependencies"]
    assert any(requirement.startswith("usd-core") for requirement in extras["usd"])
    assert any(requirement.startswith("usd-core") for requirement in extras["test"])


@pytest.mark.parametrize("program, expected", [("usdksl", "1"), ("python", None)])
def test_the_command_reads_crate_files_with_pread_and_a_library_user_keeps_usds_choice(program, expected, tmp_path):
    """A mapped crate file's pages stay resident while its stage is open; the command asks USD for pread."""
    from usdksl._openusd import CRATE_PREAD_VARIABLE

    env = {key: value for key, value in os.environ.items() if key != CRATE_PREAD_VARIABLE}
    code = ("import os, sys; sys.argv = [sys.argv[1]]; from usdksl._openusd import require_openusd, "
            "CRATE_PREAD_VARIABLE as name; require_openusd(); print(os.environ.get(name))")
    result = subprocess.run([sys.executable, "-c", code, program], capture_output=True, text=True, env=env,
                            cwd=tmp_path, check=True)
    assert result.stdout.strip() == str(expected)
