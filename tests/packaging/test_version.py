"""The version comes from a file the build writes, not from importlib.metadata (start-up cost of every check).

An installed build (the wheel, or an editable install) reads the version pyproject.toml gives from
``usdksl/_version.py``; a source tree that was never built has no such file and says UNINSTALLED_VERSION.
"""

import os
import subprocess
import sys
from pathlib import Path

import pytest

from usdksl.version import UNINSTALLED_VERSION

REPO_ROOT = Path(__file__).resolve().parents[2]

#: Prints the version and whether reading it loaded importlib.metadata.
PRINT_VERSION = """
import sys
from usdksl.version import package_version
print(package_version())
print("importlib.metadata" in sys.modules)
"""


def _pyproject_version():
    tomllib = pytest.importorskip("tomllib")
    return tomllib.loads((REPO_ROOT / "pyproject.toml").read_text())["project"]["version"]


def _python(arguments, tmp_path, env=None):
    environment = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    environment.update(env or {})
    completed = subprocess.run([sys.executable, *arguments], cwd=tmp_path, env=environment, capture_output=True,
                               text=True)
    assert completed.returncode == 0, completed.stderr
    return completed.stdout.split()


def test_the_installed_build_reads_its_version_without_importlib_metadata(tmp_path):
    # -P and a neutral folder: the installed package, not the checkout.
    version, metadata_loaded = _python(["-P", "-c", PRINT_VERSION], tmp_path)
    assert version == _pyproject_version() != UNINSTALLED_VERSION
    assert metadata_loaded == "False"


def test_a_source_tree_that_was_never_built_says_uninstalled(tmp_path):
    # -S: no site-packages, so neither the installed package nor an editable install's finder; the checkout
    # is first on the path. A stand-in pxr lets `import usdksl` pass its OpenUSD check.
    stand_in = tmp_path / "stand_in" / "pxr"
    stand_in.mkdir(parents=True)
    (stand_in / "__init__.py").write_text("")
    code = f"import sys; sys.path[:0] = [{str(REPO_ROOT)!r}, {str(stand_in.parent)!r}]\n" + PRINT_VERSION \
        + "import usdksl; print(usdksl.__file__)"
    version, metadata_loaded, package_file = _python(["-S", "-P", "-c", code], tmp_path)
    assert Path(package_file) == REPO_ROOT / "usdksl" / "__init__.py"
    assert version == UNINSTALLED_VERSION and metadata_loaded == "False"


def test_the_generated_version_file_is_git_ignored():
    ignored = (REPO_ROOT / ".gitignore").read_text().splitlines()
    assert "usdksl/_version.py" in ignored
    assert not (REPO_ROOT / "usdksl" / "_version.py").exists()   # the build writes it into the install only
