"""Every bad input raises one UsdkslInputError line naming file, prim and time; input unchanged."""

import math

import numpy as np
import pytest
from pxr import Usd, UsdGeom

from usdksl.errors import UsdkslInputError, UsdkslUsageError
from usdksl.reading.loader import load_shot
from builders import quad_grid, sha256 as file_digest, write_mesh

POINTS, COUNTS, INDICES = quad_grid(2, 2)


def fill_nan(value):
    def fill(stage):
        write_mesh(stage, "/Good", COUNTS, INDICES, samples={1.0: POINTS, 2.0: POINTS + 1})
        bad = POINTS.copy()
        bad[4, 1] = value
        write_mesh(stage, "/World/Bad", COUNTS, INDICES,
                   samples={1.0: POINTS, 2.5: bad, 3.0: POINTS})
    return fill


def fill_index_out_of_range(stage):
    indices = list(INDICES)
    indices[5] = 9                                   # 9 points: 0..8
    write_mesh(stage, "/World/Bad", COUNTS, indices, points=POINTS)


def fill_points_count_changes(stage):
    write_mesh(stage, "/World/Bad", COUNTS, INDICES,
               samples={1.0: POINTS, 2.0: POINTS, 4.0: np.vstack([POINTS, [[5, 5, 5]]])})


def fill_topology_changes(stage):
    flipped = INDICES[4:8] + INDICES[:4] + INDICES[8:]
    write_mesh(stage, "/World/Bad", COUNTS, INDICES,
               samples={float(t): POINTS + [0, t, 0] for t in range(1, 8)},
               topology_samples={1.0: (COUNTS, INDICES), 6.0: (COUNTS, flipped)})


def fill_no_points(stage):
    write_mesh(stage, "/World/Bad", COUNTS, INDICES, points=np.zeros((0, 3)))


def fill_no_faces(stage):
    write_mesh(stage, "/World/Bad", [], [], points=POINTS)


def fill_only_holes(stage):
    write_mesh(stage, "/World/Bad", COUNTS, INDICES, points=POINTS, holes=[0, 1, 2, 3])


def fill_counts_mismatch(stage):
    write_mesh(stage, "/World/Bad", [4, 4, 4, 5], INDICES, points=POINTS)


def fill_no_meshes(stage):
    UsdGeom.Xform.Define(stage, "/World")
    UsdGeom.Sphere.Define(stage, "/World/Ball")
    UsdGeom.BasisCurves.Define(stage, "/World/Hair")


CASES = {
    # name: (fill, prim named, time named, words in the message)
    "nan": (fill_nan(math.nan), "/World/Bad", 2.5, "NaN"),
    "inf": (fill_nan(math.inf), "/World/Bad", 2.5, "infinite"),
    "index out of range": (fill_index_out_of_range, "/World/Bad", 0.0, "out of range"),
    "points count changes": (fill_points_count_changes, "/World/Bad", 4.0, "points count"),
    "topology changes": (fill_topology_changes, "/World/Bad", 6.0, "topology"),
    "no points": (fill_no_points, "/World/Bad", 0.0, "empty mesh"),
    "no faces": (fill_no_faces, "/World/Bad", 0.0, "empty mesh"),
    "only holes": (fill_only_holes, "/World/Bad", 0.0, "empty mesh"),
    "counts do not match indices": (fill_counts_mismatch, "/World/Bad", 0.0, "faceVertexIndices"),
    "no meshes": (fill_no_meshes, None, None, "no UsdGeom.Mesh"),
}


@pytest.mark.parametrize("case", sorted(CASES))
def test_bad_stage_raises_one_line_naming_file_prim_and_time(build, case):
    fill, prim, time, words = CASES[case]
    path = build(case.replace(" ", "_") + ".usda", fill)
    digest = file_digest(path)
    with pytest.raises(UsdkslInputError) as raised:
        load_shot(path)
    error = raised.value
    line = str(error)
    assert "\n" not in line and "Traceback" not in line
    assert words in line
    assert error.file == path and line.startswith(path)
    assert error.prim == prim
    if prim is not None:
        assert prim in line
    if time is None:
        assert error.time is None
    else:
        assert error.time == time and f"time {time:g}" in line
    assert file_digest(path) == digest


def test_topology_error_lists_the_constant_segments(build):
    path = build("segments.usda", fill_topology_changes)
    with pytest.raises(UsdkslInputError, match=r"\[1, 5\], \[6, 7\]"):
        load_shot(path)
    # each segment alone loads
    assert load_shot(path, time_range=(1, 5)).meshes[0].kind == "deforming"
    assert load_shot(path, time_range=(6, 7)).meshes[0].times.tolist() == [6.0, 7.0]


def test_nan_outside_the_time_range_is_not_read(build):
    path = build("nan_later.usda", fill_nan(math.nan))
    # the NaN sample at 2.5 spoils USD's interpolation on (1, 3), not after 3
    shot = load_shot(path, time_range=(3.0, 4.0))
    assert np.isfinite(shot.mesh("/World/Bad").points).all()
    with pytest.raises(UsdkslInputError) as raised:
        load_shot(path, time_range=(1.0, 2.0))
    assert raised.value.time == 2.0


def test_missing_file(tmp_path):
    path = str(tmp_path / "nowhere.usda")
    with pytest.raises(UsdkslInputError) as raised:
        load_shot(path)
    assert str(raised.value) == f"{path}: no such file"


def test_directory_is_not_a_shot(tmp_path):
    with pytest.raises(UsdkslInputError, match="not a file"):
        load_shot(tmp_path)


@pytest.mark.parametrize("name, content", [
    ("notes.txt", b"just some text\n"),
    ("garbage.usda", b"#usda 1.0\ndef Mesh \"M\" {\n point3f[] points = [(0, 0"),
    ("binary.usdc", bytes(range(256)) * 4),
    ("empty.usdc", b""),
])
def test_files_that_are_not_usd(tmp_path, name, content):
    path = tmp_path / name
    path.write_bytes(content)
    with pytest.raises(UsdkslInputError) as raised:
        load_shot(path)
    line = str(raised.value)
    assert line.startswith(f"{path}: cannot open as USD") and "\n" not in line
    assert path.read_bytes() == content


@pytest.mark.parametrize("content, line", [
    (b'#usda 1.0\n\ndef Mesh "M\xff\xfe"\n{\n}\n', 3),                                      # in a prim name
    (b'#usda 1.0\n\ndef Mesh "M"\n{\n    point3f[] points = [(0, 0, 0), (1, 0, \xc3\x28)]\n}\n', 5),  # in a value
])
def test_usda_with_bytes_that_are_not_utf8(tmp_path, content, line):
    """USD's parser quotes the bytes it stopped at, which Python cannot decode: still one line, with
    the line of the first such bytes (this was an internal error, found by the fuzz suite)."""
    path = tmp_path / "shot.usda"
    path.write_bytes(content)
    with pytest.raises(UsdkslInputError) as raised:
        load_shot(path)
    text = str(raised.value)
    assert text.startswith(f"{path}: cannot open as USD: bytes that are not UTF-8 text (first at line {line})")
    assert "\n" not in text
    assert path.read_bytes() == content


def test_truncated_usdc(tmp_path):
    whole = tmp_path / "whole.usdc"
    stage = Usd.Stage.CreateNew(str(whole))
    write_mesh(stage, "/Cloth", COUNTS, INDICES,
               samples={float(t): POINTS + [0, t, 0] for t in range(50)})
    stage.GetRootLayer().Save()
    data = whole.read_bytes()
    cut = tmp_path / "cut.usdc"
    cut.write_bytes(data[: len(data) // 2])
    with pytest.raises(UsdkslInputError) as raised:
        load_shot(cut)
    assert str(raised.value).startswith(f"{cut}: cannot open as USD")
    assert "truncated" in str(raised.value) and "\n" not in str(raised.value)
    assert cut.read_bytes() == data[: len(data) // 2]


def test_single_sample_mesh_is_static_not_an_error(build):
    path = build("single.usda", lambda s: write_mesh(s, "/One", COUNTS, INDICES,
                                                     samples={7.0: POINTS}))
    mesh = load_shot(path).mesh("/One")
    assert mesh.kind == "static" and mesh.times.tolist() == [7.0]


@pytest.mark.parametrize("time_range", [(3, 1), (0, math.inf), ("a", 1)])
def test_bad_time_range_is_a_usage_error(build, time_range):
    path = build("ok.usda", lambda s: write_mesh(s, "/M", COUNTS, INDICES, points=POINTS))
    with pytest.raises(UsdkslUsageError):
        load_shot(path, time_range=time_range)


def test_loading_never_writes_the_input(build):
    path = build("untouched.usda", fill_nan(1.0))
    digest = file_digest(path)
    shot = load_shot(path)
    assert not shot.stage.GetRootLayer().dirty
    assert file_digest(path) == digest


@pytest.mark.parametrize("sample, authored, unknown, prim", [
    ("drape", 'point3f[] points = [(-0.5', 'point9f[] points = [(-0.5', "/World/Box"),
    ("drape", "int[] faceVertexCounts = [4, 4, 4, 4, 4, 4]", "int9[] faceVertexCounts = [4, 4, 4, 4, 4, 4]",
     "/World/Box"),
    ("drape", "int[] faceVertexIndices = [0, 21", "int9[] faceVertexIndices = [0, 21", "/World/Cloth"),
    ("clean", "uniform token[] xformOpOrder", "uniform token9[] xformOpOrder", "/World/Mover"),
])
def test_attributes_authored_with_a_type_usd_does_not_know(samples_dir, tmp_path, sample, authored, unknown, prim):
    """USD opens such a file and hands back an opaque value (an unknown transform order is even dropped,
    which would check the mesh where it is not): one line naming file and prim (found by fuzzing)."""
    text = (samples_dir / f"{sample}.usda").read_text()
    assert text.count(authored) == 1
    path = tmp_path / "shot.usda"
    path.write_text(text.replace(authored, unknown))
    with pytest.raises(UsdkslInputError) as raised:
        load_shot(path)
    line = str(raised.value)
    assert line.startswith(f"{path}: {prim}: ") and "with a type USD does not know" in line and "\n" not in line


def fill_nan_then_points_count_changes(stage):
    bad = POINTS.copy()
    bad[2, 0] = math.nan
    write_mesh(stage, "/World/Bad", COUNTS, INDICES,
               samples={1.0: POINTS, 2.0: bad, 3.0: POINTS, 4.0: np.vstack([POINTS, [[5, 5, 5]]])})


@pytest.mark.parametrize("block_values", [None, 27, 2 * 27])
def test_the_earliest_bad_sample_is_named_however_samples_are_batched(build, monkeypatch, block_values):
    """Samples under a still transform are read, then moved to world space, a block at a time: the error is
    still the one at the earliest bad sample (the NaN at 2, not the points count at 4)."""
    from usdksl.reading import meshes

    if block_values is not None:   # blocks of one sample, and of two
        monkeypatch.setattr(meshes, "TRANSFORM_BLOCK_VALUES", block_values)
    path = build("nan_then_count.usda", fill_nan_then_points_count_changes)
    with pytest.raises(UsdkslInputError, match="point 2 is NaN") as raised:
        load_shot(path)
    assert raised.value.time == 2.0


def fill_moving_with_bad_transform_and_nan(bad_transform_time, nan_time):
    """A mesh under a transform that moves (one matrix per sample) with a NaN transform and a NaN point."""
    def fill(stage):
        mover = UsdGeom.Xform.Define(stage, "/World/Mover")
        translate = mover.AddTranslateOp()
        for time in (1.0, 2.0, 3.0, 4.0):
            offset = math.nan if time == bad_transform_time else time
            translate.Set((offset, 0.0, 0.0), time)
        bad = POINTS.copy()
        bad[1, 2] = math.nan
        write_mesh(stage, "/World/Mover/Bad", COUNTS, INDICES,
                   samples={time: bad if time == nan_time else POINTS for time in (1.0, 2.0, 3.0, 4.0)})
    return fill


@pytest.mark.parametrize("block_values", [None, 27, 2 * 27])
@pytest.mark.parametrize("bad_transform_time, nan_time, message", [(3.0, 2.0, "point 1 is NaN"),
                                                                   (2.0, 3.0, "transform is not finite"),
                                                                   (2.0, 2.0, "transform is not finite")])
def test_under_a_moving_transform_the_earliest_bad_sample_is_named(build, monkeypatch, block_values,
                                                                   bad_transform_time, nan_time, message):
    """Under a transform that moves, samples are moved to world space a block at a time with one matrix
    each: the error is the earliest sample's, and at one sample a bad transform is named before its points."""
    from usdksl.reading import meshes

    if block_values is not None:
        monkeypatch.setattr(meshes, "TRANSFORM_BLOCK_VALUES", block_values)
    path = build("moving.usda", fill_moving_with_bad_transform_and_nan(bad_transform_time, nan_time))
    with pytest.raises(UsdkslInputError, match=message) as raised:
        load_shot(path)
    assert raised.value.time == min(bad_transform_time, nan_time)
    assert raised.value.prim == "/World/Mover/Bad"

