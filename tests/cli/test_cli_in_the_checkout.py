"""cli/ imports the library by absolute name, so the checkout's folder imports as it stands (as ``cli``), not
only where the wheel installs it (``usdksl.cli``): its modules read the same in both places."""

import subprocess
import sys
from pathlib import Path

REPO_ROOT = Path(__file__).resolve().parents[2]

#: Imports every module of the checkout's cli/ folder as the top-level package ``cli``; the checkout goes last
#: on the path, so that ``usdksl`` stays the installed package (with its compiled core).
IMPORT_THE_FOLDER = """
import importlib, sys
sys.path.append(sys.argv[1])
for name in sys.argv[2:]:
    module = importlib.import_module("cli." + name)
    print(module.__name__, module.__file__)
"""


def test_the_checkouts_cli_folder_imports_as_it_stands(tmp_path):
    names = sorted(path.stem for path in (REPO_ROOT / "cli").glob("*.py") if path.stem != "__init__")
    completed = subprocess.run([sys.executable, "-P", "-c", IMPORT_THE_FOLDER, str(REPO_ROOT), *names],
                               cwd=tmp_path, capture_output=True, text=True)
    assert completed.returncode == 0, completed.stderr
    imported = dict(line.split(" ", 1) for line in completed.stdout.splitlines())
    assert sorted(imported) == [f"cli.{name}" for name in names]
    assert all(Path(path).parent == REPO_ROOT / "cli" for path in imported.values())
