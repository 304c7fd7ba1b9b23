"""Fixtures of the loader tests."""

import pytest

from builders import bare_stage


@pytest.fixture
def build(tmp_path):
    """build(name, fill) -> path: a new stage, fill(stage) authors it, then it is saved."""
    def make(name, fill):
        path = tmp_path / name
        stage = bare_stage(path)
        fill(stage)
        stage.GetRootLayer().Save()
        return str(path)
    return make
