"""Stages the check_stage tests open and change in memory: copies of the samples, and a prop with variants."""

import shutil

import pytest

from .stages import write_prop_with_variants


@pytest.fixture
def sample_copy(tmp_path, samples_dir):
    """sample_copy(name) -> path of a copy of samples/<name>.usda in tmp_path (its reports go beside it)."""
    def copy(name):
        target = tmp_path / f"{name}.usda"
        shutil.copyfile(samples_dir / f"{name}.usda", target)
        return target
    return copy


@pytest.fixture
def prop_with_variants(tmp_path):
    """The path of :func:`stages.write_prop_with_variants`' stage in tmp_path."""
    return write_prop_with_variants(tmp_path / "prop.usda")
