"""contacts.csv / summary.csv / JSON / JUnit built from hand-made face contacts."""

import csv
import io
import json

import numpy as np
import pytest

from usdksl.clock import StageClock
from usdksl.contacts.csv_file import contacts_csv, format_times
from usdksl.contacts.table import ContactTable, canonical_first_contacts, path_rank
from usdksl.reports.formats import json_report, summary_csv, summary_line
from usdksl.reports.junit import junit_report

from junit_schema import assert_valid_junit
from usdksl.reading.scope import SceneFlags, plan_pairs


def contacts(rows):
    columns = list(zip(*rows)) if rows else [[]] * 6
    return ContactTable(None, np.array(columns[0], float), *(np.array(c, np.int32) for c in columns[1:5]),
                        np.array(columns[5], np.int8))


# mesh 0 is "/Z/Cloth", mesh 1 is "/A/Box": index order differs from string order on purpose
PATHS = ["/Z/Cloth", "/A/Box"]
# frames and seconds differ from time codes: 48 time codes a second, 24 fps (frame = time / 2)
CLOCK = StageClock(time_codes_per_second=48.0, frames_per_second=24.0)


def test_prim_order_face_order_sorting_and_dedup():
    table = ContactTable.from_face_contacts(contacts([
        (2.5, 0, 7, 1, 3, 0),      # inter, must swap: /A/Box first; vertex-face becomes face-vertex
        (1.0, 0, 9, 0, 4, 2),      # self, must swap faces: 4 < 9
        (1.0, 0, 1, 0, 1, 0),      # same face self pair: dropped
        (0.5, 1, 3, 0, 7, 1),      # the same face pair as row 1, earlier: kept, row 1 dropped
        (1.0, 1, 0, 0, 2, 3),
    ]), PATHS)
    rows = list(csv.reader(io.StringIO(contacts_csv(table, CLOCK))))
    assert rows[0] == ["time", "prim_a", "face_a", "prim_b", "face_b", "kind", "feature", "frame", "seconds"]
    assert rows[1:] == [
        ["0.5", "/A/Box", "3", "/Z/Cloth", "7", "inter", "face-vertex", "0.25", "0.010416666666666666"],
        ["1.0", "/A/Box", "0", "/Z/Cloth", "2", "inter", "initial", "0.5", "0.020833333333333332"],
        ["1.0", "/Z/Cloth", "4", "/Z/Cloth", "9", "self", "edge-edge", "0.5", "0.020833333333333332"],
    ]


def test_vertex_face_flips_with_the_sides():
    table = ContactTable.from_face_contacts(contacts([(2.0, 0, 7, 1, 3, 0)]), PATHS)
    assert table.records()[0]["feature"] == "face-vertex"
    assert table.records()[0]["prim_a"] == "/A/Box" and table.records()[0]["face_a"] == 3


def test_times_are_repr_exact_and_round_trip():
    times = np.array([0.1 + 0.2, 1e-7, 17.488909631961178, 48.0, -3.25])
    text = format_times(times).tolist()
    assert text == [repr(t) for t in times.tolist()]
    assert [float(t) for t in text] == times.tolist()


def test_summary_rows():
    table = ContactTable.from_face_contacts(contacts([
        (3.0, 0, 1, 1, 1, 2), (2.0, 0, 2, 1, 2, 2), (5.0, 0, 1, 0, 5, 2), (4.0, 1, 4, 0, 4, 2)]), PATHS)
    rows = list(csv.reader(io.StringIO(summary_csv(table, CLOCK))))
    assert rows == [["prim_a", "prim_b", "kind", "first_contact_time", "face_pairs", "first_contact_frame",
                     "first_contact_seconds"],
                    ["/A/Box", "/Z/Cloth", "inter", "2.0", "3", "1.0", "0.041666666666666664"],
                    ["/Z/Cloth", "/Z/Cloth", "self", "5.0", "1", "2.5", "0.10416666666666667"]]


def test_empty_table_has_headers_only():
    table = ContactTable.from_face_contacts(contacts([]), PATHS)
    assert contacts_csv(table, CLOCK) == "time,prim_a,face_a,prim_b,face_b,kind,feature,frame,seconds\n"
    assert summary_csv(table, CLOCK) == ("prim_a,prim_b,kind,first_contact_time,face_pairs,first_contact_frame,"
                                         "first_contact_seconds\n")


def test_large_table_is_deterministic_and_sorted():
    rng = np.random.default_rng(7)
    count = 100_000
    raw = ContactTable(None, np.round(rng.uniform(0, 48, count), 3), rng.integers(0, 3, count).astype(np.int32),
                           rng.integers(0, 5000, count).astype(np.int32), rng.integers(0, 3, count).astype(np.int32),
                           rng.integers(0, 5000, count).astype(np.int32), rng.integers(0, 4, count).astype(np.int8))
    paths = ["/c", "/a", "/b"]
    first = contacts_csv(ContactTable.from_face_contacts(raw, paths), CLOCK)
    permutation = rng.permutation(count)
    shuffled = ContactTable(None, *(getattr(raw, name)[permutation] for name in
                                  ("time", "mesh_a", "face_a", "mesh_b", "face_b", "feature")))
    second = contacts_csv(ContactTable.from_face_contacts(shuffled, paths), CLOCK)
    # the same face pair at the same time with different features can appear; ties break on feature
    assert first == second
    rows = list(csv.reader(io.StringIO(first)))[1:]
    keys = [(float(r[0]), r[1], int(r[2]), r[3], int(r[4])) for r in rows]
    assert keys == sorted(keys)
    assert all(r[1] < r[3] or (r[1] == r[3] and int(r[2]) < int(r[4])) for r in rows)
    assert len(set((r[1], r[2], r[3], r[4]) for r in rows)) == len(rows)


def _reference_first_contacts(rows, rank):
    """canonical_first_contacts written out row by row: orient, drop same-face rows, keep each pair's
    (earliest time, lowest feature), sort by (time, rank_a, face_a, rank_b, face_b)."""
    flip = {0: 1, 1: 0}
    best = {}
    for time, mesh_a, face_a, mesh_b, face_b, feature in rows:
        swap = face_a > face_b if mesh_a == mesh_b else rank[mesh_a] > rank[mesh_b]
        if swap:
            mesh_a, face_a, mesh_b, face_b, feature = mesh_b, face_b, mesh_a, face_a, flip.get(feature, feature)
        if mesh_a == mesh_b and face_a == face_b:
            continue
        key = (rank[mesh_a], face_a, rank[mesh_b], face_b)
        if key not in best or (time, feature) < best[key][0]:
            best[key] = ((time, feature), (time, mesh_a, face_a, mesh_b, face_b, feature))
    chosen = [row for _, row in best.values()]
    return sorted(chosen, key=lambda r: (r[0], rank[r[1]], r[2], rank[r[3]], r[4], r[5]))


@pytest.mark.parametrize("largest_face", [50, 2 ** 31 - 1])
def test_first_contacts_match_a_row_by_row_reference(largest_face):
    # Small faces take the one-key sort (the four ids packed in an int64); faces near 2**31 do not fit
    # and take the four-key sort: both must give the reference's rows.
    rng = np.random.default_rng(largest_face % 1000)
    count = 3000
    face = lambda: rng.choice([0, 1, 2, largest_face - 1, largest_face], count)  # noqa: E731
    rows = list(zip(rng.integers(0, 6, count).astype(float) / 2, rng.integers(0, 3, count).tolist(), face().tolist(),
                    rng.integers(0, 3, count).tolist(), face().tolist(), rng.integers(0, 4, count).tolist()))
    paths = ["/c", "/a", "/b"]
    rank = path_rank(paths)
    got = canonical_first_contacts(*(np.array(column) for column in zip(*rows)), mesh_rank=rank)
    assert list(zip(*(column.tolist() for column in got))) == _reference_first_contacts(rows, rank)


def _plan():
    return plan_pairs(PATHS, ["deforming", "static"], np.array([True, False]), SceneFlags.permissive(2))


def test_junit_one_case_per_checked_pair_with_failures():
    table = ContactTable.from_face_contacts(contacts([(2.0, 0, 7, 1, 3, 0), (3.0, 0, 8, 1, 3, 0)]), PATHS)
    root = assert_valid_junit(junit_report("shot.usda", _plan(), table, CLOCK))
    suites = root.findall("testsuite")
    assert len(suites) == 1 and suites[0].get("name") == "shot.usda"
    cases = suites[0].findall("testcase")
    assert sorted(c.get("name") for c in cases) == ["/A/Box x /Z/Cloth", "/Z/Cloth"]
    failed = {c.get("name"): c.find("failure") for c in cases}
    assert failed["/Z/Cloth"] is None
    assert failed["/A/Box x /Z/Cloth"].get("message") == "2 face pairs in contact, first at frame 1 (t=2)"
    assert suites[0].get("tests") == "2" and suites[0].get("failures") == "1"


def test_json_document():
    table = ContactTable.from_face_contacts(contacts([(2.0, 0, 7, 1, 3, 0)]), PATHS)
    document = json.loads(json_report("shot.usda", {"method": "ksl"}, _plan(), table, 1, CLOCK,
                                      version="0.1"))
    assert document["shot"] == "shot.usda" and document["settings"] == {"method": "ksl"}
    assert document["plan"]["pairs_checked"] == 2 and document["plan"]["pairs_possible"] == 3
    assert document["clock"] == {"timeCodesPerSecond": 48.0, "framesPerSecond": 24.0}
    assert document["summary"] == [{"prim_a": "/A/Box", "prim_b": "/Z/Cloth", "kind": "inter",
                                    "first_contact_time": 2.0, "face_pairs": 1, "first_contact_frame": 1.0,
                                    "first_contact_seconds": 0.041666666666666664}]
    assert document["contacts"] == [{"time": 2.0, "prim_a": "/A/Box", "face_a": 3, "prim_b": "/Z/Cloth",
                                     "face_b": 7, "kind": "inter", "feature": "face-vertex", "frame": 1.0,
                                     "seconds": 0.041666666666666664}]
    assert document["exit_code"] == 1


def test_summary_line():
    plan = _plan()
    clean = summary_line(ContactTable.empty(PATHS), plan, (0.0, 48.0), 1.23, CLOCK)
    assert clean == "usdksl: clean: no contacts; checked 2 pairs over 0..48 in 1.2s"
    table = ContactTable.from_face_contacts(contacts([(14.5, 0, 7, 1, 3, 0), (15.0, 0, 8, 1, 3, 0)]), PATHS)
    line = summary_line(table, plan, (0.0, 48.0), 0.5, CLOCK)
    assert line.startswith("usdksl: 2 contacting face pairs in 1 mesh pair, first at frame 7.25 (t=14.5);")
