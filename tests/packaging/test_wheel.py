"""The wheel users get: a manylinux wheel that installs without a compiler and checks a shot at once.

Runs when USDKSL_WHEEL names a built wheel (.ci/run builds one, repairs it with auditwheel and sets it). A fresh
virtual environment installs it as a user would, ``pip install --only-binary :all: <wheel>[usd]``: binaries
only, so nothing is compiled. That base install leaves Dask out (it is the ``dask`` extra), and ``--jobs`` then
says in one line which extra to install. (.ci/run times the same install; tests are not timed.)
"""

import json
import os
import re
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

REPO_ROOT = Path(__file__).resolve().parents[2]
WHEEL = os.environ.get("USDKSL_WHEEL")
SAMPLE = REPO_ROOT / "samples" / "fold.usda"
#: What the base install with the usd extra holds besides pip and setuptools: README, "Set up", lists them.
BASE_INSTALL_WITH_USD = {"usdksl", "numpy", "click", "embreex", "tqdm", "usd-core"}
#: What a fresh virtual environment holds before anything is installed.
VENV_SEED = {"pip", "setuptools"}
DASK_HINT = "pip install 'usdksl[dask]'"

pytestmark = pytest.mark.skipif(not WHEEL, reason="USDKSL_WHEEL does not name a built wheel: .ci/run builds the "
                                                  "manylinux wheel and sets it, to check what users install")


def _environment():
    return {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}


@pytest.fixture(scope="module")
def wheel_venv(tmp_path_factory):
    """A fresh virtual environment with the wheel and usd-core installed from binaries only."""
    venv = tmp_path_factory.mktemp("wheel_venv")
    subprocess.run([sys.executable, "-m", "venv", str(venv)], check=True)
    installed = subprocess.run([str(venv / "bin" / "pip"), "install", "-q", "--only-binary", ":all:", f"{WHEEL}[usd]"],
                               capture_output=True, text=True, env=_environment())
    assert installed.returncode == 0, installed.stderr
    return venv


def _usdksl(venv, *arguments, cwd):
    return subprocess.run([str(venv / "bin" / "usdksl"), *map(str, arguments)], cwd=cwd, capture_output=True,
                          text=True, env=_environment())


def test_the_wheel_is_manylinux_with_the_core_the_cli_and_the_version_inside():
    name = Path(WHEEL).name
    assert re.fullmatch(r"usdksl-[\w.]+-cp\d+-cp\d+-manylinux_\d+_\d+_x86_64(\.manylinux\w+)*\.whl", name), name
    version = name.split("-")[1]
    with zipfile.ZipFile(WHEEL) as wheel:
        names = wheel.namelist()
        assert any(re.fullmatch(r"usdksl/_native\.cpython-\d+-x86_64-linux-gnu\.so", n) for n in names)
        assert "usdksl/cli/entry.py" in names and not any(n.startswith("cli/") for n in names)
        assert f'version = "{version}"' in wheel.read("usdksl/_version.py").decode()


def test_the_installed_wheel_checks_the_shipped_sample(wheel_venv, tmp_path):
    result = _usdksl(wheel_venv, "check", SAMPLE, "--out", tmp_path, cwd=tmp_path)
    assert result.returncode == 1, result.stderr           # contacts found
    assert result.stderr.splitlines()[-1].startswith("usdksl: 1 problem in 1 mesh pair")
    rows = (tmp_path / "fold.contacts.csv").read_text().splitlines()
    assert rows[0].startswith("time,prim_a,face_a,prim_b,face_b,kind") and len(rows) > 1
    version = _usdksl(wheel_venv, "--version", cwd=tmp_path)
    assert version.stdout.strip() == f"usdksl, version {Path(WHEEL).name.split('-')[1]}"


def test_the_base_install_pulls_only_what_a_single_shot_check_needs(wheel_venv):
    listed = subprocess.run([str(wheel_venv / "bin" / "pip"), "list", "--format=json"], capture_output=True,
                            text=True, check=True, env=_environment())
    installed = {package["name"].lower() for package in json.loads(listed.stdout)}
    assert installed - VENV_SEED == BASE_INSTALL_WITH_USD


@pytest.mark.parametrize("option", [["--jobs", "2"], ["--scheduler", "tcp://127.0.0.1:8786"]])
def test_dask_options_without_dask_name_the_extra_in_one_line(wheel_venv, tmp_path, option):
    result = _usdksl(wheel_venv, "check", SAMPLE, "--out", tmp_path / "out", *option, cwd=tmp_path)
    assert result.returncode == 2
    assert len(result.stderr.splitlines()) == 1 and DASK_HINT in result.stderr, result.stderr
    assert not (tmp_path / "out").exists()
