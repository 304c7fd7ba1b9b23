"""A plain ``usdksl check`` imports only what it uses: start-up is part of every check's time.

The command runs in a fresh interpreter that lists, at exit, the modules it imported. Optional
machinery (Dask, tqdm, matplotlib, Embree), the other commands' modules, importlib.metadata (the
version is a file the build writes, usdksl.version), UsdPhysics (on a stage
without physics schemas), UsdSkel and usdksl's skinning (on a stage without a SkelRoot), numpy's masked
arrays (usdksl.unmasked), the JUnit writer, a chunk's manifest, the contact timeline, the backwards run
of --last-contact, the many-shot machinery and the batch CCD query API must not be among them; a JSON
report has the version without importlib.metadata, and asking for a JUnit report loads its writer.
"""

import json
import os
import subprocess
import sys

#: Modules a plain check must not import (a prefix matches the module and its submodules).
NOT_IMPORTED_BY_A_PLAIN_CHECK = ("dask", "distributed", "tqdm", "matplotlib", "embreex", "importlib.metadata",
                                 "usdksl.crosscheck", "usdksl.scale.dask_runner", "usdksl.scale.merge",
                                 "usdksl.cli.crosscheck", "usdksl.cli.bench", "usdksl.cli.merge", "usdksl.cli.info",
                                 "pxr.UsdPhysics", "pxr.UsdShade", "numpy.ma", "pxr.UsdSkel",
                                 "usdksl.reading.skinning", "usdksl.reports.junit", "xml.etree",
                                 "usdksl.reports.manifest", "usdksl.reports.timeline",
                                 "usdksl.checking.last_contact", "usdksl.scale.batch",
                                 "usdksl.scale.batch_progress", "usdksl.ccd")

LIST_MODULES_AT_EXIT = """
import atexit, json, sys
atexit.register(lambda: sys.__stdout__.write(json.dumps(sorted(sys.modules)) + "\\n"))
sys.argv = ["usdksl"] + sys.argv[1:]
from usdksl.cli.entry import main
main()
"""


def _modules_imported_by(*args):
    # -P: the checkout (the working folder) must not shadow the installed package.
    completed = subprocess.run([sys.executable, "-P", "-c", LIST_MODULES_AT_EXIT, *map(str, args)], capture_output=True,
                               text=True)
    assert completed.returncode == 1, completed.stderr   # the quads touch: contacts found
    return set(json.loads(completed.stdout.strip().splitlines()[-1]))


def _matching(modules, prefixes):
    return sorted(m for m in modules if any(m == p or m.startswith(p + ".") for p in prefixes))


def test_a_plain_check_imports_no_optional_machinery(two_quads_shot, tmp_path):
    modules = _modules_imported_by("check", two_quads_shot, "--out", tmp_path)
    assert "usdksl._native" in modules and "usdksl.cli.check" in modules
    assert _matching(modules, NOT_IMPORTED_BY_A_PLAIN_CHECK) == []


def test_a_junit_report_loads_its_writer(two_quads_shot, tmp_path):
    modules = _modules_imported_by("check", two_quads_shot, "--out", tmp_path, "--junit", tmp_path / "junit.xml")
    assert "usdksl.reports.junit" in modules and "xml.etree.ElementTree" in modules
    assert "<testsuite" in (tmp_path / "junit.xml").read_text()


def test_a_json_report_looks_the_version_up(two_quads_shot, tmp_path):
    modules = _modules_imported_by("check", two_quads_shot, "--out", tmp_path, "--json", tmp_path / "report.json")
    assert "importlib.metadata" not in modules
    from usdksl.version import package_version
    assert json.loads((tmp_path / "report.json").read_text())["version"] == package_version() != ""


BLAS_THREADS_AT_EXIT = """
import atexit, os, sys
atexit.register(lambda: sys.__stdout__.write(repr(os.environ.get("OPENBLAS_NUM_THREADS")) + "\\n"))
sys.argv = ["usdksl"] + sys.argv[1:]
from usdksl.cli.entry import main
main()
"""


def _blas_threads_of_a_check(shot, out, environment):
    completed = subprocess.run([sys.executable, "-P", "-c", BLAS_THREADS_AT_EXIT, "check", str(shot), "--out", str(out)],
                               capture_output=True, text=True, env=environment)
    assert completed.returncode == 1, completed.stderr
    return completed.stdout.strip().splitlines()[-1]


def test_a_check_keeps_numpy_blas_to_one_thread_unless_the_user_says_otherwise(two_quads_shot, tmp_path):
    environment = {k: v for k, v in os.environ.items() if k != "OPENBLAS_NUM_THREADS"}
    assert _blas_threads_of_a_check(two_quads_shot, tmp_path / "default", environment) == "'1'"
    environment["OPENBLAS_NUM_THREADS"] = "3"
    assert _blas_threads_of_a_check(two_quads_shot, tmp_path / "user", environment) == "'3'"


HUGE_PAGES_AT_EXIT = """
import atexit, sys
def report():
    import numpy
    core = getattr(numpy, "_core", None) or numpy.core
    sys.__stdout__.write(repr(core.multiarray._get_madvise_hugepage()) + "\\n")
atexit.register(report)
sys.argv = ["usdksl"] + sys.argv[1:]
from usdksl.cli.entry import main
main()
"""


def test_a_check_keeps_numpy_from_asking_for_huge_pages_unless_the_user_says_otherwise(two_quads_shot, tmp_path):
    """numpy's huge-page advice on large arrays stalls the loader's copy of the points where the kernel compacts
    memory for it (cli/entry.py); a user's NUMPY_MADVISE_HUGEPAGE wins."""
    def numpy_asks_for_huge_pages(environment, out):
        completed = subprocess.run([sys.executable, "-P", "-c", HUGE_PAGES_AT_EXIT, "check", str(two_quads_shot),
                                    "--out", str(out)], capture_output=True, text=True, env=environment)
        assert completed.returncode == 1, completed.stderr
        return completed.stdout.strip().splitlines()[-1]

    environment = {k: v for k, v in os.environ.items() if k != "NUMPY_MADVISE_HUGEPAGE"}
    assert numpy_asks_for_huge_pages(environment, tmp_path / "default") == "False"
    environment["NUMPY_MADVISE_HUGEPAGE"] = "1"
    assert numpy_asks_for_huge_pages(environment, tmp_path / "user") == "True"
