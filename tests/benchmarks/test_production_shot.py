"""benchmarks/production_shot.py: the generated shot looks like a studio's cloth cache (a sample at every frame from
1001, a closed body, an open dress, vertices on curves), is clean in its first half and has both kinds of contact
in its second, and ``measure`` checks it whole and in farm chunks that merge into the whole run's contacts."""

import subprocess
import sys

import numpy as np
import pytest
from pxr import Usd, UsdGeom

import production_shot as production
from conftest import REPO_ROOT

SCRIPT = REPO_ROOT / "benchmarks" / "production_shot.py"
#: Size of the shot the tests check: small enough for seconds, large enough for both contacts.
TRIANGLES = 6000
FRAMES = 40
#: Most the generated triangle count may stray from the asked one (share of it).
TRIANGLE_SLACK = 0.02
#: Smallest second difference of a vertex's samples (cm) that counts as curved motion: float32 points of
#: about 200 cm are exact to about 1e-5 cm.
CURVED = 1e-3
#: Size of the shots the measure test generates and checks (three processes each, and a merge).
MEASURED_TRIANGLES, MEASURED_FRAMES = 2000, (20, 40)


@pytest.fixture(scope="module")
def shot(tmp_path_factory):
    path = tmp_path_factory.mktemp("production") / "shot.usdc"
    return production.write_shot(str(path), TRIANGLES, FRAMES)


@pytest.fixture(scope="module")
def stage(shot):
    return Usd.Stage.Open(shot.path)


def _mesh(stage, path):
    mesh = UsdGeom.Mesh(stage.GetPrimAtPath(path))
    assert mesh, path
    return mesh


def _directed_edges(mesh):
    """int64[E] codes (from * vertices + to) of every face's edges, in the face's winding."""
    counts = np.asarray(mesh.GetFaceVertexCountsAttr().Get(), dtype=np.int64)
    indices = np.asarray(mesh.GetFaceVertexIndicesAttr().Get(), dtype=np.int64)
    ends = np.cumsum(counts)
    position = np.arange(indices.size)
    following = np.where(position + 1 == np.repeat(ends, counts), np.repeat(ends - counts, counts), position + 1)
    vertices = int(indices.max()) + 1
    return indices * vertices + indices[following], indices[following] * vertices + indices


def _samples(mesh, times):
    return np.stack([np.asarray(mesh.GetPointsAttr().Get(time), dtype=np.float64) for time in times])


def test_the_shot_has_a_body_and_a_dress_sampled_at_every_frame_from_1001(shot, stage):
    frames = [float(production.START_FRAME + k) for k in range(FRAMES)]
    assert (stage.GetStartTimeCode(), stage.GetEndTimeCode()) == (frames[0], frames[-1])
    assert stage.GetTimeCodesPerSecond() == stage.GetFramesPerSecond() == 24
    assert UsdGeom.GetStageUpAxis(stage) == UsdGeom.Tokens.y
    assert UsdGeom.GetStageMetersPerUnit(stage) == production.METERS_PER_UNIT
    meshes = [str(prim.GetPath()) for prim in stage.Traverse() if prim.IsA(UsdGeom.Mesh)]
    assert meshes == [production.BODY_PATH, production.GARMENT_PATH]
    for path in meshes:
        mesh = _mesh(stage, path)
        assert mesh.GetPointsAttr().GetTimeSamples() == frames
        assert mesh.GetExtentAttr().GetTimeSamples() == frames
    assert abs(shot.triangles - TRIANGLES) <= TRIANGLE_SLACK * TRIANGLES
    assert abs(shot.body_triangles / shot.triangles - production.BODY_SHARE) < TRIANGLE_SLACK
    assert shot.vertices == sum(len(_mesh(stage, path).GetPointsAttr().Get(frames[0])) for path in meshes)


def test_the_body_is_closed_and_the_dress_is_open(stage):
    body, reversed_body = _directed_edges(_mesh(stage, production.BODY_PATH))
    # closed and consistently wound: every edge is used twice, once each way
    assert np.unique(body).size == body.size
    assert np.array_equal(np.sort(body), np.sort(reversed_body))
    dress, reversed_dress = _directed_edges(_mesh(stage, production.GARMENT_PATH))
    assert np.unique(dress).size == dress.size
    assert np.setdiff1d(dress, reversed_dress).size > 0       # its top edge and hem are borders


def test_every_vertex_moves_on_a_curve(shot, stage):
    times = [production.START_FRAME + k for k in range(FRAMES)]
    for path in (production.BODY_PATH, production.GARMENT_PATH):
        points = _samples(_mesh(stage, path), times)
        second = np.abs(points[2:] - 2 * points[1:-1] + points[:-2]).max(axis=(0, 2))
        assert second.min() > CURVED, path


def test_the_check_finds_the_bulge_and_the_pinch_in_the_second_half_only(shot):
    import usdksl

    result = usdksl.check_shot(shot.path, usdksl.CheckOptions())
    table = result.table
    body, dress = table.paths.index(production.BODY_PATH), table.paths.index(production.GARMENT_PATH)
    inter = (table.mesh_a != table.mesh_b)
    dress_self = (table.mesh_a == dress) & (table.mesh_b == dress)
    body_self = (table.mesh_a == body) & (table.mesh_b == body)
    assert result.exit_code == 1
    assert inter.any() and dress_self.any()
    assert not body_self.any()
    middle = production.ProductionShot(TRIANGLES, FRAMES).middle
    assert middle == production.START_FRAME + (FRAMES - 1) / 2
    assert table.time.min() > middle


def test_chunks_are_cut_at_whole_frames_and_each_reaches_the_next():
    ranges = production.chunk_ranges(1001, 1480, 4)
    assert len(ranges) == 4
    assert ranges[0][0] == 1001 and ranges[-1][1] == 1480
    assert all(end == following[0] for (_, end), following in zip(ranges, ranges[1:]))
    assert all(isinstance(a, int) and isinstance(b, int) and a < b for a, b in ranges)
    with pytest.raises(ValueError):
        production.chunk_ranges(1001, 1003, 3)


def test_measure_checks_each_shot_and_merges_chunks_into_the_whole_run(tmp_path):
    markdown = tmp_path / "production.md"
    command = [sys.executable, str(SCRIPT), "measure", "--triangles", str(MEASURED_TRIANGLES), "--frames",
               *map(str, MEASURED_FRAMES), "--chunks", "2", "--threads", "1", "--markdown", str(markdown),
               "--keep", str(tmp_path / "kept")]
    run = subprocess.run(command, capture_output=True, text=True)
    assert run.returncode == 0, run.stdout + run.stderr
    assert "chunks merged == whole: True" in run.stdout
    text = markdown.read_text()
    # the shots' table: eleven columns (triangles, vertices, frames, ..., face pairs, exit)
    table = [line.split("|")[1:-1] for line in text.splitlines() if line.count("|") == 12 and line[2].isdigit()]
    assert sorted(int(cells[2]) for cells in table) == list(MEASURED_FRAMES), text
    assert all(int(cells[9]) > 0 and cells[10].strip() == "1" for cells in table)   # face pairs found, exit 1
    assert f"Peak memory of the {MEASURED_FRAMES[1]}-frame shot over the {MEASURED_FRAMES[0]}-frame shot's" in text
    stem = f"production_{MEASURED_TRIANGLES}_f{MEASURED_FRAMES[1]}"
    assert (tmp_path / "kept" / f"{stem}.usdc").exists()
    assert (tmp_path / "kept" / "chunks" / "merged" / f"{stem}.contacts.csv").exists()
