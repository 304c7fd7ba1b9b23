"""Shot-level cross-check: generated stages with known intersections, contacts consistency, the command."""

import csv
import os

import numpy as np
import pytest
from click.testing import CliRunner

from usdksl.cli.crosscheck import crosscheck
from usdksl.contacts.csv_file import read_contacts_csv
from usdksl.contacts.table import ContactTable
from usdksl.crosscheck.shot import crosscheck_shot, default_mesh_pairs, parse_frames, points_at
from usdksl.errors import UsdkslInputError, UsdkslUsageError
from usdksl.reading.loader import load_shot

from builders import grid_sheet

QUAD = [0, 1, 2, 3]


def vertical_quad(z_offset):
    """A quad in the plane x = 0.5 spanning y in [-0.5, 1.5], z in [-0.5, 0.5] + z_offset."""
    return np.array([[0.5, -0.5, -0.5], [0.5, 1.5, -0.5], [0.5, 1.5, 0.5], [0.5, -0.5, 0.5]]) + [0, 0, z_offset]


@pytest.fixture
def falling_quad_shot(shot_writer):
    """/World/Floor (static unit quad at z=0) and /World/Blade (a vertical quad falling through it).

    The blade's z offset goes from 2 at t=0 to 0 at t=10: it first touches the floor at t=7.5 and crosses
    it properly afterwards."""
    floor = {"path": "/World/Floor", "points": [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]],
             "counts": [4], "indices": QUAD}
    blade = {"path": "/World/Blade", "samples": {0: vertical_quad(2.0), 10: vertical_quad(0.0)},
             "counts": [4], "indices": QUAD}
    return shot_writer("falling.usda", [floor, blade])


def write_contacts(path, rows):
    with open(path, "w", newline="") as handle:
        writer = csv.writer(handle, lineterminator="\n")
        writer.writerow(["time", "prim_a", "face_a", "prim_b", "face_b", "kind"])
        writer.writerows(rows)
    return str(path)


def read_rows(path):
    with open(path, newline="") as handle:
        return list(csv.reader(handle))


def test_two_quads_crossing_give_exactly_their_face_pair_at_the_right_frames(falling_quad_shot):
    shot = load_shot(falling_quad_shot)
    contacts = ContactTable.from_rows(None, np.array([7.5]), np.array([shot.meshes.index(shot.mesh("/World/Blade"))]),
                                      np.array([0]), np.array([shot.meshes.index(shot.mesh("/World/Floor"))]),
                                      np.array([0]))
    result = crosscheck_shot(shot, frames="0:10:1", contacts=contacts)
    assert result.frames.tolist() == [float(t) for t in range(11)]
    assert result.time.tolist() == [8.0, 9.0, 10.0]
    paths = result.prim_paths
    assert {(paths[a], fa, paths[b], fb) for a, fa, b, fb in
            zip(result.mesh_a, result.face_a, result.mesh_b, result.face_b)} == {("/World/Blade", 0, "/World/Floor", 0)}
    assert result.consistent and result.exit_code() == 1
    assert result.csv_text().splitlines() == ["time,prim_a,face_a,prim_b,face_b",
                                              "8.0,/World/Blade,0,/World/Floor,0",
                                              "9.0,/World/Blade,0,/World/Floor,0",
                                              "10.0,/World/Blade,0,/World/Floor,0"]


def test_a_late_or_missing_contact_is_a_disagreement(falling_quad_shot):
    shot = load_shot(falling_quad_shot)
    blade, floor = (shot.meshes.index(shot.mesh(p)) for p in ("/World/Blade", "/World/Floor"))
    late = ContactTable.from_rows(None, np.array([9.5]), np.array([floor]), np.array([0]), np.array([blade]),
                                  np.array([0]))
    result = crosscheck_shot(shot, frames="0:10:1", contacts=late)
    assert result.violation.tolist() == [True, True, False]
    assert result.exit_code() == 3
    assert result.error_lines() == ["crosscheck: /World/Blade face 0 and /World/Floor face 0 intersect at time "
                                    "8.0 (and 1 later frame(s)) but has its first contact later, at time 9.5"]
    empty = ContactTable.empty(None)
    result = crosscheck_shot(shot, contacts=empty)   # default frames: the shot's samples 0 and 10
    assert result.time.tolist() == [10.0] and result.exit_code() == 3
    assert "has no contact" in result.error_lines()[0]


def pierced_sheet_shot(shot_writer, spike_points):
    """A static 4x4-quad sheet (unit square, z=0) and a one-triangle spike moving slightly in y."""
    points, counts, indices = grid_sheet(1.0, 4)
    sheet = {"path": "/World/Sheet", "points": points, "counts": counts, "indices": indices}
    spike_points = np.asarray(spike_points, float)
    spike = {"path": "/World/Spike", "samples": {1: spike_points, 2: spike_points + [0, 0.01, 0]},
             "counts": [3], "indices": [0, 1, 2]}
    return shot_writer("pierced.usda", [spike, sheet])


def face_rows(result):
    paths = result.prim_paths
    return [(t, paths[a], int(fa), paths[b], int(fb)) for t, a, fa, b, fb in
            zip(result.time.tolist(), result.mesh_a, result.face_a, result.mesh_b, result.face_b)]


def test_sheet_pierced_inside_one_face(shot_writer):
    path = pierced_sheet_shot(shot_writer, [[0.30, 0.30, -0.2], [0.45, 0.30, -0.2], [0.375, 0.45, 0.3]])
    result = crosscheck_shot(load_shot(path), contacts=ContactTable.empty(None))
    assert face_rows(result) == [(1.0, "/World/Sheet", 5, "/World/Spike", 0),
                                 (2.0, "/World/Sheet", 5, "/World/Spike", 0)]


def test_sheet_pierced_across_a_shared_edge_reports_both_faces(shot_writer):
    path = pierced_sheet_shot(shot_writer, [[0.15, 0.30, -0.2], [0.45, 0.30, -0.2], [0.30, 0.45, 0.3]])
    result = crosscheck_shot(load_shot(path), frames=[1.0], contacts=ContactTable.empty(None))
    assert face_rows(result) == [(1.0, "/World/Sheet", 4, "/World/Spike", 0),
                                 (1.0, "/World/Sheet", 5, "/World/Spike", 0)]


def test_touching_and_coplanar_frames_report_nothing(shot_writer):
    # the spike's tip rests exactly on the sheet; then a coplanar triangle lying in the sheet
    touching = pierced_sheet_shot(shot_writer, [[0.30, 0.30, 0.0], [0.45, 0.30, 0.5], [0.375, 0.45, 0.5]])
    assert len(crosscheck_shot(load_shot(touching), contacts=ContactTable.empty(None)).time) == 0
    coplanar = pierced_sheet_shot(shot_writer, [[0.1, 0.1, 0.0], [0.9, 0.2, 0.0], [0.4, 0.8, 0.0]])
    assert len(crosscheck_shot(load_shot(coplanar), contacts=ContactTable.empty(None)).time) == 0


def test_self_intersection_rows_order_faces_and_skip_same_face(shot_writer):
    """One deforming mesh: quad 0 flat, quad 1 vertical through it, and a bow-tie pentagon (face 2) whose
    fan triangles pass through each other: pairs inside one authored face are never reported."""
    flat = [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]]
    upright = vertical_quad(0.0).tolist()
    pentagon = [[3, 0, 0], [4, 0, 0.5], [4, 1, -0.5], [3.2, 1, 0.5], [3.5, -0.2, -0.5]]
    points = np.array(flat + upright + pentagon, float)
    mesh = {"path": "/Cloth", "samples": {0: points, 1: points + [0, 0, 1e-3]}, "counts": [4, 4, 5],
            "indices": list(range(13))}
    result = crosscheck_shot(load_shot(shot_writer("self.usda", [mesh])), contacts=ContactTable.empty(None))
    assert face_rows(result) == [(0.0, "/Cloth", 0, "/Cloth", 1), (1.0, "/Cloth", 0, "/Cloth", 1)]


def test_doctored_contact_list_is_caught_by_the_command(shot_writer, tmp_path):
    """Sheet pierced across a shared edge: two face pairs. Removing one contact must exit 3 naming it."""
    path = pierced_sheet_shot(shot_writer, [[0.15, 0.30, -0.2], [0.45, 0.30, -0.2], [0.30, 0.45, 0.3]])
    full = write_contacts(tmp_path / "full.csv", [["1.0", "/World/Sheet", 4, "/World/Spike", 0, "inter"],
                                                  ["1.0", "/World/Sheet", 5, "/World/Spike", 0, "inter"]])
    runner = CliRunner()
    out = tmp_path / "out"
    clean = runner.invoke(crosscheck, [path, "--contacts", full, "--out", str(out)])
    assert clean.exit_code == 1, clean.output
    assert "2 frame(s)" in clean.output and "4 intersecting face pair-frame(s)" in clean.output
    assert "2 distinct face pair(s)" in clean.output and "consistent" in clean.output
    written = read_rows(out / "pierced.crosscheck.csv")
    assert written == [["time", "prim_a", "face_a", "prim_b", "face_b"],
                       ["1.0", "/World/Sheet", "4", "/World/Spike", "0"],
                       ["1.0", "/World/Sheet", "5", "/World/Spike", "0"],
                       ["2.0", "/World/Sheet", "4", "/World/Spike", "0"],
                       ["2.0", "/World/Sheet", "5", "/World/Spike", "0"]]
    assert sorted(os.listdir(out)) == ["pierced.crosscheck.csv"]  # no temp file left behind

    doctored = write_contacts(tmp_path / "doctored.csv", [["1.0", "/World/Sheet", 4, "/World/Spike", 0, "inter"]])
    caught = runner.invoke(crosscheck, [path, "--contacts", doctored, "--out", str(out)])
    assert caught.exit_code == 3, caught.output
    errors = [line for line in caught.output.splitlines() if line.startswith("usdksl: error:")]
    assert errors == ["usdksl: error: crosscheck: /World/Sheet face 5 and /World/Spike face 0 intersect at "
                      f"time 1.0 (and 1 later frame(s)) but has no contact in {doctored}"]


def test_command_exit_codes_for_clean_and_bad_input(shot_writer, tmp_path):
    path = pierced_sheet_shot(shot_writer, [[0.3, 0.3, 0.2], [0.45, 0.3, 0.2], [0.375, 0.45, 0.5]])
    empty = write_contacts(tmp_path / "none.csv", [])
    runner = CliRunner()
    result = runner.invoke(crosscheck, [path, "--contacts", empty, "--out", str(tmp_path)])
    assert result.exit_code == 0, result.output
    assert read_rows(tmp_path / "pierced.crosscheck.csv") == [["time", "prim_a", "face_a", "prim_b", "face_b"]]

    bad = tmp_path / "bad.csv"
    bad.write_text("time,prim_a,face_a,prim_b,face_b\nsoon,/World/Sheet,0,/World/Spike,0\n")
    for arguments, fragment in (([str(bad)], "row 2: time 'soon' is not a number"),
                                ([empty, "--frames", "7"], "outside the shot's samples"),
                                ([empty, "--frames", "x"], "is not a time code"),
                                ([str(tmp_path / "missing.csv")], "cannot read contacts")):
        outcome = runner.invoke(crosscheck, [path, "--contacts", *arguments, "--out", str(tmp_path / "o2")])
        assert outcome.exit_code == 2, outcome.output
        lines = outcome.output.strip().splitlines()
        assert len(lines) == 1 and lines[0].startswith("usdksl: error:") and fragment in lines[0]
    assert not (tmp_path / "o2").exists()
    missing_shot = runner.invoke(crosscheck, [str(tmp_path / "nope.usda"), "--contacts", empty])
    assert missing_shot.exit_code == 2 and "no such file" in missing_shot.output


def test_contacts_csv_reader_maps_prims_and_rejects_bad_faces(falling_quad_shot, tmp_path):
    shot = load_shot(falling_quad_shot)
    good = write_contacts(tmp_path / "c.csv", [["7.5", "/World/Blade", 0, "/World/Floor", 0, "inter"],
                                               ["3.0", "/Elsewhere", 1, "/World/Floor", 0, "inter"]])
    paths, face_counts = [mesh.path for mesh in shot.meshes], [mesh.face_count for mesh in shot.meshes]
    contacts = read_contacts_csv(good, paths, face_counts, skip_unknown_prims=True)
    assert contacts.table.time.tolist() == [7.5] and contacts.ignored_rows == 1
    assert shot.meshes[contacts.table.mesh_a[0]].path == "/World/Blade"
    with pytest.raises(UsdkslInputError, match="row 3: prim '/Elsewhere' is not a mesh of the shot"):
        read_contacts_csv(good, paths, face_counts)
    bad = write_contacts(tmp_path / "b.csv", [["7.5", "/World/Blade", 1, "/World/Floor", 0, "inter"]])
    with pytest.raises(UsdkslInputError, match="face_a 1 is out of range"):
        read_contacts_csv(bad, paths, face_counts, skip_unknown_prims=True)


def test_frames_parsing():
    times = np.array([0.0, 1.0, 2.0, 5.0, 10.0])
    assert parse_frames(None, times).tolist() == times.tolist()
    assert parse_frames("1:5", times).tolist() == [1.0, 2.0, 5.0]
    assert parse_frames("0:10:2.5, 1", times).tolist() == [0.0, 1.0, 2.5, 5.0, 7.5, 10.0]
    assert parse_frames([3.0, 3.0], times).tolist() == [3.0]
    for bad in ("11", "5:1", "0:1:0", "1:2:3:4", "", "nan", "3:4"):
        with pytest.raises(UsdkslUsageError):
            parse_frames(bad, times)


def test_points_at_interpolates_linearly_and_holds_outside(falling_quad_shot):
    blade = load_shot(falling_quad_shot).mesh("/World/Blade")
    assert np.allclose(points_at(blade, 7.5), vertical_quad(0.5))
    assert np.array_equal(points_at(blade, -3.0), blade.points[0])
    assert np.array_equal(points_at(blade, 12.0), blade.points[-1])


def test_default_mesh_pairs_follow_the_scene_rules(falling_quad_shot):
    class Mesh:
        def __init__(self, kind):
            self.kind = kind
    meshes = [Mesh("static"), Mesh("static"), Mesh("rigid"), Mesh("deforming")]
    assert default_mesh_pairs(meshes) == [(0, 2), (0, 3), (1, 2), (1, 3), (2, 3), (3, 3)]
