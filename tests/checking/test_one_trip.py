"""One trip per shot: a check opens the stage and lists its meshes once (the memory estimate counts the
loader's own mesh sources), builds the contact table and the clock once, and validates its options once."""

import pytest
from click.testing import CliRunner
from pxr import Usd

from builders import RESTING_SHEETS_TIMES, falling_instancer, resting_sheets
from usdksl.cli.main import main
from usdksl.clock import StageClock
from usdksl.errors import UsdkslUsageError
from usdksl.pipeline import check as check_module
from usdksl.pipeline import files as files_module
from usdksl.pipeline.check import check_shot
from usdksl.pipeline.memory_budget import scan_shot, sources_size
from usdksl.pipeline.options import CheckOptions
from usdksl.reading import loader
from usdksl.reading.loader import find_mesh_sources, load_shot, load_sources

TIMES = RESTING_SHEETS_TIMES


def falling_sheets(path, blocked=()):
    """:func:`builders.resting_sheets` with /World/Cloth's points blocked at the ``blocked`` time codes (the check
    then cuts the range around the gap)."""
    return resting_sheets(path, {time: "block" for time in blocked})


@pytest.fixture
def counted(monkeypatch):
    """{what: calls} of Usd.Stage.Open, the loader's search for meshes, the clock and the joined table."""
    calls = {"open": 0, "mesh_prims": 0, "clock": 0, "table": 0}

    def counting(name, function):
        def wrapper(*args, **kwargs):
            calls[name] += 1
            return function(*args, **kwargs)
        return wrapper

    monkeypatch.setattr(Usd.Stage, "Open", counting("open", Usd.Stage.Open))
    monkeypatch.setattr(loader, "mesh_prims", counting("mesh_prims", loader.mesh_prims))
    monkeypatch.setattr(StageClock, "from_metadata", counting("clock", StageClock.from_metadata))
    joined = counting("table", files_module.concatenate_pieces)
    monkeypatch.setattr(files_module, "concatenate_pieces", joined)
    monkeypatch.setattr(check_module, "concatenate_pieces", joined)
    return calls


@pytest.mark.parametrize("blocked", [(), (5.0,)], ids=["whole", "cut-at-a-gap"])
def test_a_check_opens_the_stage_and_lists_its_meshes_once(tmp_path, counted, blocked):
    shot = falling_sheets(tmp_path / "sheets.usda", blocked)
    result = check_shot(shot, CheckOptions(memory_limit="1T"))   # a limit: the memory estimate is made
    assert result.table.count > 0
    assert (len(result.segments) > 1) == bool(blocked)
    assert counted == {"open": 1, "mesh_prims": 1, "clock": 1, "table": 1}


def test_the_estimate_from_the_loaders_sources_is_the_scan_of_the_file(tmp_path):
    shot = falling_sheets(tmp_path / "sheets.usda")
    found = find_mesh_sources(shot)
    for time_range in (None, (3.0, 9.5)):
        assert sources_size(found, time_range) == scan_shot(shot, time_range)
    assert sources_size(found).vertex_samples == 2 * 16 * len(TIMES) + 2 * 4   # the floors: one sample each


def test_sources_load_again_with_the_same_answer_and_warnings(tmp_path):
    # an instancer whose velocities disagree with its positions warns while it loads: once per load, as pieces
    # of a shot cut at gaps are loaded from the same sources
    shot = str(tmp_path / "scatter.usda")
    falling_instancer(shot, velocities="zero")
    found = find_mesh_sources(shot)
    expected = load_shot(shot)
    for loaded in (load_sources(found), load_sources(found)):
        assert [mesh.path for mesh in loaded.meshes] == [mesh.path for mesh in expected.meshes]
        assert all((a.points == b.points).all() for a, b in zip(loaded.meshes, expected.meshes))
        assert loaded.warnings == expected.warnings
        assert any("velocities" in line for line in loaded.warnings)
    assert not any("velocities" in line for line in found.warnings)


def test_options_are_validated_once_at_construction(monkeypatch, tmp_path):
    with pytest.raises(UsdkslUsageError, match="--thickness must be zero or positive"):
        CheckOptions(thickness=-1.0)
    with pytest.raises(UsdkslUsageError, match="memory limit"):
        CheckOptions(memory_limit="lots")
    shot = falling_sheets(tmp_path / "sheets.usda")
    validated = []
    real = CheckOptions.validate
    monkeypatch.setattr(CheckOptions, "validate", lambda self: (validated.append(self), real(self))[1])

    result = CliRunner().invoke(main, ["check", shot, "--out", str(tmp_path / "out")])
    assert result.exit_code == 1, result.output
    assert len(validated) == 1
