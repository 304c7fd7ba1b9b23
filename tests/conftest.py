"""Fixtures shared by every test folder."""

import os
from pathlib import Path

import pytest

REPO_ROOT = Path(__file__).resolve().parent.parent


def _shared_data_dir():
    configured = os.environ.get("USDKSL_SHARED_DATA")
    candidates = [Path(configured)] if configured else []
    candidates.append(REPO_ROOT.parent / "shared" / "data")
    for candidate in candidates:
        if (candidate / "README.md").is_file():
            return candidate
    return None


@pytest.fixture(scope="session")
def shared_data():
    """The public ground-truth folder (../shared/data), read in place; skips when absent."""
    found = _shared_data_dir()
    if found is None:
        pytest.skip("shared ground-truth data not found (set USDKSL_SHARED_DATA or place it at ../shared/data)")
    return found


@pytest.fixture(scope="session")
def samples_dir():
    """The small shots shipped in samples/."""
    return REPO_ROOT / "samples"


@pytest.fixture(scope="session")
def newton_twist_path(shared_data):
    """The third-party Newton cloth-twist cache in the shared data, read in place; skips when absent."""
    path = shared_data / "newton" / "newton_viewerusd_cloth_twist.usd"
    if not path.is_file():
        pytest.skip(f"{path} not found")
    return path
