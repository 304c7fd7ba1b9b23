"""The C++ unit tests of every native topic (native/tests/<topic>/), built with CMake and run by ctest.

GoogleTest comes from the system (Debian: ``apt-get install libgtest-dev``; ``.ci/run`` installs it);
without it this test is skipped, saying so. The build lives in ``build/ctest`` so reruns are incremental.
"""

import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
BUILD = ROOT / "build" / "ctest"
SHARED_DATA = ROOT.parent / "shared" / "data"
#: A fresh build compiles the whole core; ctest itself takes seconds.
BUILD_TIMEOUT_SECONDS = 1800


def cmake_command():
    found = shutil.which("cmake")
    if found:
        return [found]
    try:
        import cmake  # noqa: F401  (the PyPI cmake package)
    except ImportError:
        pytest.skip("cmake is not installed (pip install cmake)")
    return [sys.executable, "-m", "cmake"]


def run(command, **kwargs):
    return subprocess.run(command, capture_output=True, text=True, timeout=BUILD_TIMEOUT_SECONDS, **kwargs)


@pytest.fixture(scope="module")
def ctest_build():
    BUILD.mkdir(parents=True, exist_ok=True)
    configure = run(cmake_command() + ["-S", str(ROOT), "-B", str(BUILD), "-DUSDKSL_BUILD_PYTHON=OFF",
                                       "-DUSDKSL_BUILD_TESTS=ON", "-DCMAKE_BUILD_TYPE=Release",
                                       f"-DPython_EXECUTABLE={sys.executable}",
                                       f"-DUSDKSL_SHARED_DATA={SHARED_DATA}"])
    if configure.returncode != 0 and "Could NOT find GTest" in configure.stderr:
        pytest.skip("GoogleTest is not installed (Debian: apt-get install libgtest-dev)")
    assert configure.returncode == 0, configure.stderr[-3000:]
    build = run(cmake_command() + ["--build", str(BUILD), "--parallel", str(os.cpu_count() or 2)])
    assert build.returncode == 0, (build.stdout + build.stderr)[-3000:]
    return BUILD


def test_every_native_topic_has_cpp_tests_and_they_pass(ctest_build):
    ctest = shutil.which("ctest") or str(Path(cmake_command()[0]).with_name("ctest"))
    listed = run([ctest, "-N"], cwd=ctest_build)
    topics = {match.group(1) for match in re.finditer(r"Test\s+#\d+: (\w+)\.", listed.stdout)}
    source_topics = {path.name for path in (ROOT / "native" / "src").iterdir() if path.is_dir()}
    assert source_topics <= topics, f"topics without C++ tests: {sorted(source_topics - topics)}"
    result = run([ctest, "--output-on-failure", "--timeout", "300"], cwd=ctest_build)
    assert result.returncode == 0, result.stdout[-5000:]
    passed = re.search(r"100% tests passed(?:, 0 tests failed)? out of (\d+)", result.stdout)
    assert passed, result.stdout[-2000:]
    assert int(passed.group(1)) >= 2 * len(source_topics), "fewer than two C++ tests per topic"
