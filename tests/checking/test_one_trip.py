"""One trip per shot: a check opens the stage and lists its meshes once (the memory estimate counts the
loader's own mesh sources), builds the contact table and the clock once, and validates its options once."""

import pytest
from click.testing import CliRunner
from pxr import Sdf, Usd

from builders import define_mesh, falling_instancer, grid, new_stage
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

#: Time codes of every sample of the sheets below (one per frame).
TIMES = [float(t) for t in range(1, 25)]
#: When the sheets come to rest on their floors (time codes): they fall from y = 1 at t = 1.
REST_TIME = 11.0


def falling_sheets(path, blocked=()):
    """Two 3x3 sheets falling onto a floor each and resting there from REST_TIME; ``blocked`` time codes at which
    /World/Cloth's points are blocked (the check then cuts the range around the gap)."""
    stage = new_stage(path, start=1.0, end=24.0)
    for name, x in (("Cloth", 0.0), ("Other", 10.0)):
        points, counts, indices = grid(3, 3, 2.0, 2.0, center=(x, 0.0, 0.0))
        floor, floor_counts, floor_indices = grid(1, 1, 4.0, 4.0, center=(x, 0.0, 0.0))
        define_mesh(stage, f"/World/{name}Floor", floor, floor_counts, floor_indices)
        samples = {t: points + [0.0, max(0.0, (REST_TIME - t) / 10.0), 0.0] for t in TIMES}
        mesh = define_mesh(stage, f"/World/{name}", None, counts, indices, samples=samples)
        if name == "Cloth":
            for time in blocked:
                mesh.GetPointsAttr().Set(Sdf.ValueBlock(), time)
    stage.GetRootLayer().Save()
    return str(path)


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
