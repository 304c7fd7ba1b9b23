"""Fixtures for the cross-check tests."""

import pytest

from builders import write_shot


@pytest.fixture
def shot_writer(tmp_path):
    def write(name, meshes, **kwargs):
        return write_shot(tmp_path / name, meshes, **kwargs)
    return write
