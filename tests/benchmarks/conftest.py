"""Tiny generated shots and the benchmark modules (benchmarks/ is a script folder, not a package)."""

import subprocess
import sys
from pathlib import Path

import pytest

REPO_ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO_ROOT / "benchmarks"))


def _generate(out: Path, scene: str, size_option: str, size: int) -> Path:
    subprocess.run([sys.executable, str(REPO_ROOT / "samples" / "generate.py"), scene, size_option, str(size),
                    "--keyframes", "3", "--samples-per-keyframe", "2", "--out", str(out)],
                   check=True, capture_output=True)
    return out


@pytest.fixture(scope="session")
def tiny_tablecloth(tmp_path_factory):
    """A 150-face tablecloth over a static table, 3 keyframes x 2 samples (5 samples)."""
    return _generate(tmp_path_factory.mktemp("bench") / "tablecloth_tiny.usdc", "tablecloth", "--faces", 150)


@pytest.fixture(scope="session")
def suite_rows(tiny_tablecloth, tmp_path_factory):
    """Every benchmark method once on the tiny tablecloth (fresh interpreters, as in a real run)."""
    import run
    raw = tmp_path_factory.mktemp("raw")
    shot = run.describe_shot(str(tiny_tablecloth), "tablecloth", 150, 2)
    lines = []
    rows = run.run_suite([shot], list(run.METHODS), budget_s=300.0, raw_dir=str(raw), echo=lines.append)
    return rows, lines
