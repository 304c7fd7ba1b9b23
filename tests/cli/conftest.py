"""Fixtures of the check tests."""

import pytest

from builders import add_mesh, falling_quad_samples, new_stage, QUAD_POINTS


@pytest.fixture
def two_quads_shot(tmp_path):
    """/World/Floor static quad at y=0.5 offset (x 0..1), /World/Falling quad passing through it."""
    path = tmp_path / "two_quads.usda"
    stage = new_stage(path)
    add_mesh(stage, "/World/Floor", QUAD_POINTS + [-0.5, 0.0, -0.5])
    add_mesh(stage, "/World/Falling", None, samples=falling_quad_samples())
    stage.GetRootLayer().Save()
    return path
