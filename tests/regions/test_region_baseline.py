"""Baselines by region: an accepted problem stays known on a re-run, and nothing new hides behind it (a
pass-through elsewhere, a deeper region in the same place, a region outside the accepted frames)."""

import json
from pathlib import Path

import numpy as np
import pytest

from usdksl.checking.collision import find_contacts
from usdksl.clock import StageClock
from usdksl.contacts.baseline import Baseline, BaselineComparison, mismatch_warning
from usdksl.errors import UsdkslInputError
from usdksl.reading.loader import load_shot
from usdksl.regions.baseline import (BOX_FLOOR, BOX_GROWTH, DEPTH_FLOOR, DEPTH_GROWTH, REQUIRED_COLUMNS,
                                     SPAN_SLACK_FRAMES, RegionBaseline, RegionTolerances, baseline_for_shot,
                                     compare_any, compare_regions, is_region_baseline, known_regions,
                                     read_any_baseline, read_region_baseline)
from usdksl.regions.csv_file import REGION_COLUMNS, REGION_DETAIL_COLUMNS
from usdksl.regions.table import INTERSECTION_LENGTH, PENETRATION, RegionTable

from builders import box, define_mesh, new_stage, stretching_sheet

#: The contract that states the default tolerances.
CONTRACTS = Path(__file__).resolve().parents[2] / "docs" / "contracts.md"
#: 48 time codes a second played at 24 frames: a frame is half a time code, so frames and times differ.
CLOCK = StageClock(time_codes_per_second=48.0, frames_per_second=24.0)
#: Box centre heights (edge 1, so its bottom is 0.5 lower) over a sheet at y = 0.
ABOVE, RESTING, SUNK = 1.5, 0.45, 0.2
#: The resting box of the baseline: it settles into the sheet by 0.05 at time 12 and stays.
REST = {1.0: ABOVE, 12.0: RESTING, 24.0: RESTING}
CORNER, OTHER_CORNER = (-1.5, -1.5), (1.5, 1.5)


def box_on_sheet(path, boxes):
    """A deforming sheet at y = 0 and boxes {name: ((x, z), {time: centre height})} moving down onto it."""
    stage = new_stage(path, tcps=48.0, fps=24.0, start=1.0, end=24.0)
    stretching_sheet(stage, "/World/Sheet", size=6.0, columns=6, times=(1.0, 24.0))
    points, counts, indices = box(1.0)
    for name, ((x, z), heights) in boxes.items():
        define_mesh(stage, f"/World/{name}", None, counts, indices,
                    samples={time: points + [x, height, z] for time, height in heights.items()})
    stage.GetRootLayer().Save()
    return str(path)


def check(path):
    """(contact table, regions) of a shot: its real contacts, grouped by hand into one region per box (the
    region finder's numbering: by earliest row). A region lasts to the shot's end; its box holds the
    vertices of its faces on both sides at the end; its depth is how far the box went below the sheet."""
    shot = load_shot(path)
    paths = [mesh.path for mesh in shot.meshes]
    sheet = paths.index("/World/Sheet")
    pairs = [(sheet, index) for index in range(len(paths)) if index != sheet]
    table = find_contacts(shot.meshes, pairs).face_contacts(shot.meshes)
    other = np.where(table.mesh_a == sheet, table.mesh_b, table.mesh_a)
    _, first_rows = np.unique(other, return_index=True)
    earliest = np.sort(first_rows)
    region_of = {int(other[row]): k for k, row in enumerate(earliest.tolist())}
    row_region = np.array([region_of[label] for label in other.tolist()], np.int32)
    count = earliest.size
    box_min, box_max, depth = np.zeros((count, 3)), np.zeros((count, 3)), np.zeros(count)
    for region in range(count):
        rows = np.flatnonzero(row_region == region)
        corners = []
        for meshes, faces in ((table.mesh_a, table.face_a), (table.mesh_b, table.face_b)):
            mesh = shot.meshes[int(meshes[rows[0]])]
            vertices = mesh.triangles[np.isin(mesh.triangle_face, faces[rows])].ravel()
            corners.append(mesh.points[-1][vertices])
        corners = np.concatenate(corners)
        box_min[region], box_max[region] = corners.min(axis=0), corners.max(axis=0)
        depth[region] = max(0.0, -float(shot.meshes[int(other[rows[0]])].points[-1][:, 1].min()))
    first_time = np.array([table.time[row_region == k].min() for k in range(count)])
    regions = RegionTable(
        paths=table.paths, mesh_a=table.mesh_a[earliest].astype(np.int32),
        mesh_b=table.mesh_b[earliest].astype(np.int32),
        first_time=first_time, last_time=np.full(count, 24.0),
        face_pairs=np.bincount(row_region, minlength=count).astype(np.int64),
        depth_measure=np.array([PENETRATION] * count, dtype=object), max_depth=depth,
        max_depth_time=np.full(count, 24.0), max_intersection_length=np.zeros(count),
        center=(box_min + box_max) / 2, box_min=box_min, box_max=box_max, row_region=row_region)
    return table, regions


def regions_csv(path, table, regions):
    """A regions.csv of ``regions`` with every column of usdksl.regions.csv_file, numbers as repr."""
    names = table.mesh_names()
    lines = [",".join(REGION_COLUMNS + REGION_DETAIL_COLUMNS)]
    for k in range(regions.count):
        a, b = int(regions.mesh_a[k]), int(regions.mesh_b[k])
        values = [int(regions.ids[k]), names[a], names[b], "self" if a == b else "inter",
                  float(regions.first_time[k]), float(regions.last_time[k]), CLOCK.frame(regions.first_time[k]),
                  CLOCK.frame(regions.last_time[k]), int(regions.face_pairs[k]), float(regions.max_depth[k]),
                  float(regions.max_depth_time[k]), *map(float, regions.center[k]), regions.depth_measure[k],
                  CLOCK.frame(regions.max_depth_time[k]), float(regions.max_intersection_length[k]),
                  *map(float, regions.box_min[k]), *map(float, regions.box_max[k]), 1, 1]
        lines.append(",".join(value if isinstance(value, str) else repr(value) for value in values))
    path.write_text("\n".join(lines) + "\n")
    return path


def baseline_of(tmp_path, boxes, name="accepted.regions.csv"):
    """The regions.csv of an earlier run over ``boxes``, read back as a baseline."""
    table, regions = check(box_on_sheet(tmp_path / "earlier.usda", boxes))
    return read_region_baseline(regions_csv(tmp_path / name, table, regions))


def rerun(tmp_path, boxes):
    return check(box_on_sheet(tmp_path / "now.usda", boxes))


def test_an_accepted_resting_region_stays_known_on_a_rerun(tmp_path):
    baseline = baseline_of(tmp_path, {"Box": (CORNER, REST)})
    assert baseline.count == 1 and baseline.max_depth[0] == pytest.approx(0.05, abs=1e-6)
    table, regions = rerun(tmp_path, {"Box": (CORNER, REST)})
    comparison = compare_regions(table, regions, CLOCK, baseline)
    assert isinstance(comparison, BaselineComparison) and comparison.table is table
    assert table.count > 0 and comparison.known.all() and comparison.fixed_count == 0
    assert (comparison.new_count, comparison.known_count) == (0, table.count)
    # arriving a frame later, within the accepted frames, is the same problem
    table, regions = rerun(tmp_path, {"Box": (CORNER, {1.0: ABOVE, 13.0: RESTING, 24.0: RESTING})})
    assert CLOCK.frame(regions.first_time[0]) > baseline.first_frame[0]
    assert compare_regions(table, regions, CLOCK, baseline).known.all()


def test_a_new_pass_through_elsewhere_is_new(tmp_path):
    baseline = baseline_of(tmp_path, {"Box": (CORNER, REST)})
    through = {1.0: ABOVE, 12.0: RESTING, 24.0: -2.0}
    table, regions = rerun(tmp_path, {"Box": (CORNER, REST), "Ball": (OTHER_CORNER, through)})
    comparison = compare_regions(table, regions, CLOCK, baseline)
    names = table.mesh_names()
    other = np.where(np.array(names, dtype=object)[table.mesh_a] == "/World/Sheet", table.mesh_b, table.mesh_a)
    is_ball = np.array(names, dtype=object)[other] == "/World/Ball"
    assert is_ball.any() and (~is_ball).any()
    assert np.array_equal(comparison.known, ~is_ball)     # the resting box is known, every ball row new
    assert comparison.fixed_count == 0
    # the same two prims in another place: the entry's box does not hold it, so it is new and the entry fixed
    table, regions = rerun(tmp_path, {"Box": (OTHER_CORNER, REST)})
    comparison = compare_regions(table, regions, CLOCK, baseline)
    assert table.count and not comparison.known.any() and comparison.fixed.tolist() == [0]


def test_a_deeper_region_in_the_same_place_is_new(tmp_path):
    baseline = baseline_of(tmp_path, {"Box": (CORNER, REST)})
    table, regions = rerun(tmp_path, {"Box": (CORNER, {1.0: ABOVE, 12.0: RESTING, 24.0: SUNK})})
    # same place, same first contact: only the depth differs
    assert CLOCK.frame(regions.first_time[0]) == baseline.first_frame[0]
    assert np.all((baseline.box_min[0] <= regions.center[0]) & (regions.center[0] <= baseline.box_max[0]))
    assert regions.max_depth[0] == pytest.approx(0.3, abs=1e-6)
    comparison = compare_regions(table, regions, CLOCK, baseline)
    assert comparison.new_count == table.count > 0 and comparison.fixed.tolist() == [0]


def test_a_region_outside_the_accepted_frames_is_new(tmp_path):
    baseline = baseline_of(tmp_path, {"Box": (CORNER, REST)})
    table, regions = rerun(tmp_path, {"Box": (CORNER, {1.0: ABOVE, 3.0: RESTING, 24.0: RESTING})})
    assert CLOCK.frame(regions.first_time[0]) < baseline.first_frame[0] - SPAN_SLACK_FRAMES
    assert regions.max_depth[0] == pytest.approx(baseline.max_depth[0], abs=1e-6)
    comparison = compare_regions(table, regions, CLOCK, baseline)
    assert comparison.new_count == table.count > 0 and comparison.fixed.tolist() == [0]
    # a wider slack takes it in: the frames alone made it new
    wide = read_region_baseline(baseline.source, RegionTolerances(span_slack_frames=10.0))
    assert compare_regions(table, regions, CLOCK, wide).known.all()


def test_a_fixed_entry_is_reported_and_described(tmp_path):
    baseline = baseline_of(tmp_path, {"Box": (CORNER, REST), "Ball": (OTHER_CORNER, REST)})
    assert baseline.count == 2
    table, regions = rerun(tmp_path, {"Box": (CORNER, REST)})
    comparison = compare_regions(table, regions, CLOCK, baseline)
    assert comparison.known.all()
    fixed = comparison.fixed.tolist()
    assert len(fixed) == 1 and {baseline.prim_a[fixed[0]], baseline.prim_b[fixed[0]]} == {"/World/Ball",
                                                                                         "/World/Sheet"}
    text = baseline.describe(fixed[0])
    assert text.startswith(f"region {baseline.region[fixed[0]]}: /World/Ball x /World/Sheet, frames ")
    assert text.endswith(", max depth 0.05")
    report = json.loads(json.dumps(comparison.to_dict()))     # the JSON report's baseline object
    assert report["new"] == 0 and report["known"] == table.count and report["time_tolerance"] is None
    entry = report["fixed"][0]
    assert entry["prim_a"] == "/World/Ball" and entry["depth_measure"] == PENETRATION
    assert entry["box_min"] == pytest.approx(baseline.box_min[fixed[0]].tolist())
    # the mismatch warning reads the prims of a region baseline as of any other
    assert mismatch_warning(baseline, lambda prim: False, "shot.usda").startswith(str(baseline.source))


def test_an_accept_list_written_by_hand(tmp_path):
    table, regions = rerun(tmp_path, {"Box": (CORNER, REST)})
    lo, hi = regions.box_min[0], regions.box_max[0]
    first = CLOCK.frame(regions.first_time[0])
    path = tmp_path / "accepted.csv"
    path.write_text("# the box rests on the sheet: accepted in review\n"
                    "prim_a,prim_b,first_frame,last_frame,max_depth,min_x,min_y,min_z,max_x,max_y,max_z\n"
                    f"/World/Sheet,/World/Box,{first},12,0.05,{lo[0]},{lo[1]},{lo[2]},{hi[0]},{hi[1]},{hi[2]}\n")
    assert is_region_baseline(path)
    baseline = read_region_baseline(path)
    assert (baseline.prim_a[0], baseline.prim_b[0]) == ("/World/Box", "/World/Sheet")    # either order
    assert baseline.region.tolist() == [-1] and baseline.describe(0).startswith("region /World/Box x")
    assert compare_regions(table, regions, CLOCK, baseline).known.all()
    # a depth measure the regions do not have is another problem
    path.write_text(path.read_text().replace("max_z\n", "max_z,depth_measure\n").rstrip("\n")
                    + f",{INTERSECTION_LENGTH}\n")
    assert not compare_regions(table, regions, CLOCK, read_region_baseline(path)).known.any()


def test_the_box_grows_by_its_named_fraction(tmp_path):
    table, regions = rerun(tmp_path, {"Box": (CORNER, REST)})
    size = regions.box_max[0] - regions.box_min[0]
    diagonal = float(np.linalg.norm(size))

    def entry_shifted_by(shift):
        lo, hi = regions.box_min[0] + [shift, 0, 0], regions.box_max[0] + [shift, 0, 0]
        path = tmp_path / f"shift{shift}.csv"
        path.write_text("prim_a,prim_b,first_frame,last_frame,max_depth,min_x,min_y,min_z,max_x,max_y,max_z\n"
                        f"/World/Box,/World/Sheet,0,12,0.05,{lo[0]},{lo[1]},{lo[2]},{hi[0]},{hi[1]},{hi[2]}\n")
        return compare_regions(table, regions, CLOCK, read_region_baseline(path)).known.all()

    # the centre is size/2 from the box's edge; the box grows by BOX_GROWTH of its diagonal (and a floor)
    edge = size[0] / 2 + BOX_GROWTH * diagonal
    assert entry_shifted_by(edge * 0.95) and entry_shifted_by(-edge * 0.95)
    assert not entry_shifted_by(edge * 1.05) and not entry_shifted_by(-edge * 1.05)


def test_known_regions_follow_their_rows(tmp_path):
    baseline = baseline_of(tmp_path, {"Box": (CORNER, REST)})
    table, regions = rerun(tmp_path, {"Box": (CORNER, REST), "Ball": (OTHER_CORNER, {1.0: ABOVE, 24.0: -2.0})})
    comparison = compare_regions(table, regions, CLOCK, baseline)
    box_region = [k for k in range(regions.count) if "/World/Box" in
                  (table.mesh_names()[regions.mesh_a[k]], table.mesh_names()[regions.mesh_b[k]])]
    assert known_regions(regions, comparison.known).tolist() == [k in box_region for k in range(regions.count)]
    # with every row new, no region is known
    assert not known_regions(regions, np.zeros(table.count, bool)).any()


def test_a_region_whose_centre_is_not_finite_is_new(tmp_path):
    baseline = baseline_of(tmp_path, {"Box": (CORNER, REST)})
    table, regions = rerun(tmp_path, {"Box": (CORNER, REST)})
    regions.center[:] = np.nan
    comparison = compare_regions(table, regions, CLOCK, baseline)
    assert table.count and not comparison.known.any() and comparison.fixed.tolist() == [0]


def test_baselines_are_told_apart_by_their_header(tmp_path):
    table, regions = rerun(tmp_path, {"Box": (CORNER, REST)})
    region_file = regions_csv(tmp_path / "shot.regions.csv", table, regions)
    contacts_file = tmp_path / "shot.contacts.csv"
    # a contacts.csv of a --last-contact run has last_frame too, but none of the box columns
    contacts_file.write_text("time,prim_a,face_a,prim_b,face_b,kind,feature,frame,seconds,last_time,last_frame,"
                             "last_seconds\n1.0,/World/Box,0,/World/Sheet,3,inter,vertex-face,0.5,0.02,2.0,1.0,0.04\n")
    assert is_region_baseline(region_file) and not is_region_baseline(contacts_file)
    assert not is_region_baseline(tmp_path / "missing.csv")
    assert isinstance(read_any_baseline(region_file), RegionBaseline)
    assert isinstance(read_any_baseline(contacts_file, 0.5), Baseline)
    assert compare_any(table, regions, CLOCK, read_any_baseline(region_file)).known.all()
    assert compare_any(table, None, CLOCK, read_any_baseline(contacts_file)).known_count == 0
    with pytest.raises(ValueError, match="regions"):
        compare_any(table, None, CLOCK, read_any_baseline(region_file))
    # a folder: <stem>.contacts.csv as before; its regions.csv is not taken in its place
    assert isinstance(baseline_for_shot(tmp_path, "shot")[0], Baseline)
    contacts_file.unlink()
    instead, warning = baseline_for_shot(tmp_path, "shot")
    assert isinstance(instead, Baseline) and instead.count == 0 and "every contact counts as new" in warning
    assert isinstance(baseline_for_shot(region_file, "other")[0], RegionBaseline)
    empty, warning = baseline_for_shot(tmp_path, "absent")
    assert isinstance(empty, Baseline) and empty.count == 0 and "every contact counts as new" in warning


def test_every_column_read_is_a_regions_csv_column():
    assert set(REQUIRED_COLUMNS) | {"region", "depth_measure"} <= set(REGION_COLUMNS + REGION_DETAIL_COLUMNS)


HEADER = "region,prim_a,prim_b,first_frame,last_frame,max_depth,min_x,min_y,min_z,max_x,max_y,max_z"
GOOD = "1,/A,/B,1,5,0.1,0,0,0,1,1,1"


@pytest.mark.parametrize("text, line, words", [
    ("", None, "empty"),
    ("# only a comment\n", None, "empty"),
    ("prim_a,prim_b,max_depth\n/A,/B,0.1\n", 1, "lacks column(s) first_frame, last_frame, min_x"),
    (f"# accepted\n{HEADER}\n{GOOD}\n1,/A,/B,1,5,deep,0,0,0,1,1,1\n", 4, "max_depth 'deep' is not a number"),
    (f"{HEADER}\n1,/A,/B,1,5,0.1,0,0,0,1,1\n", 2, "expected 12 columns"),
    (f"{HEADER}\n1,,/B,1,5,0.1,0,0,0,1,1,1\n", 2, "empty prim path"),
    (f"{HEADER}\n1,/A,/B,,5,0.1,0,0,0,1,1,1\n", 2, "first_frame '' is not a number"),
    (f"{HEADER}\n1,/A,/B,1,inf,0.1,0,0,0,1,1,1\n", 2, "last_frame 'inf' is not finite"),
    (f"{HEADER}\n1,/A,/B,6,5,0.1,0,0,0,1,1,1\n", 2, "last_frame is before first_frame"),
    (f"{HEADER}\n1,/A,/B,1,5,-0.1,0,0,0,1,1,1\n", 2, "max_depth is negative"),
    (f"{HEADER}\n1,/A,/B,1,5,nan,0,0,0,1,1,1\n", 2, "max_depth 'nan' is not finite"),
    (f"{HEADER}\n1,/A,/B,1,5,0.1,nan,0,0,1,1,1\n", 2, "min_x 'nan' is not finite"),
    (f"{HEADER}\n1,/A,/B,1,5,0.1,2,0,0,1,1,1\n", 2, "min above its max"),
    (f"{HEADER}\nthree,/A,/B,1,5,0.1,0,0,0,1,1,1\n", 2, "region 'three' is not a region id"),
    (f"{HEADER},depth_measure\n1,/A,/B,1,5,0.1,0,0,0,1,1,1,volume\n", 2, "depth_measure 'volume'"),
])
def test_a_bad_file_is_one_line_naming_file_and_line(tmp_path, text, line, words):
    path = tmp_path / "bad.regions.csv"
    path.write_text(text)
    with pytest.raises(UsdkslInputError) as error:
        read_region_baseline(path)
    message = str(error.value)
    assert "\n" not in message and message.startswith(f"{path}: ")
    assert words in message
    if line is not None:
        assert f": line {line}: " in message


def test_an_unreadable_file_is_an_input_error(tmp_path):
    with pytest.raises(UsdkslInputError, match="cannot read baseline"):
        read_region_baseline(tmp_path / "missing.regions.csv")
    (tmp_path / "latin.csv").write_bytes(b"prim_a,prim_b\n/\xe9,/B\n")
    with pytest.raises(UsdkslInputError, match="cannot read baseline"):
        read_region_baseline(tmp_path / "latin.csv")


def test_the_contract_states_the_default_tolerances():
    def small(value):      # 1e-4, as the contract writes small lengths
        return np.format_float_scientific(value, trim="-", exp_digits=1)

    text = " ".join(CONTRACTS.read_text().split())
    part = text[text.index("### Regions in a baseline"):]
    assert f"by {BOX_GROWTH:g} of the box's diagonal plus {small(BOX_FLOOR)} scene units" in part
    assert f"grown by {SPAN_SLACK_FRAMES:g} frames at either end" in part
    assert f"at most the entry's times {1 + DEPTH_GROWTH:g} plus {small(DEPTH_FLOOR)} scene units" in part


@pytest.mark.parametrize("sample", ["drape.usda", "pass_through.usda"])
def test_the_regions_csv_of_a_check_is_a_baseline_that_knows_its_rerun(samples_dir, sample, tmp_path):
    from usdksl import check_shot
    from usdksl.pipeline.files import OutputTargets

    targets = OutputTargets(out_dir=tmp_path)
    result = check_shot(str(samples_dir / sample), targets=targets)
    written = targets.out_dir / sample.replace(".usda", ".regions.csv")
    written.write_text(result.files[written])
    assert is_region_baseline(written)
    baseline = read_region_baseline(written)
    assert baseline.count == result.regions.count >= 1
    again = check_shot(str(samples_dir / sample), targets=targets)
    comparison = compare_regions(again.table, again.regions, again.clock, baseline)
    assert comparison.known.all() and comparison.fixed_count == 0 and again.table.count > 0
    # the same file with every region a little shallower than measured: nothing is known, everything fixed
    shallow = read_region_baseline(written, RegionTolerances(depth_growth=-0.5, depth_floor=0.0))
    comparison = compare_regions(again.table, again.regions, again.clock, shallow)
    assert not comparison.known.any() and comparison.fixed_count == baseline.count
