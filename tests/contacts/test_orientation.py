"""One orientation of a face pair: the contact table, the cross-check's keys and the baseline's entries agree."""

from types import SimpleNamespace

import numpy as np

from usdksl.contacts.baseline import ANY_FACE, read_baseline
from usdksl.contacts.orientation import canonical_swap, swap_sides
from usdksl.contacts.table import ContactTable, path_rank
from usdksl.crosscheck.shot import _FaceNumbering

# mesh 0 is "/Z/Cloth", mesh 1 is "/A/Box": index order differs from string order on purpose
PATHS = ["/Z/Cloth", "/A/Box"]
# (mesh_a, face_a, mesh_b, face_b) in the order a producer might give them, and canonical
GIVEN = [(0, 7, 1, 3), (1, 3, 0, 7), (0, 9, 0, 4), (0, 4, 0, 9)]
CANONICAL = [(1, 3, 0, 7), (1, 3, 0, 7), (0, 4, 0, 9), (0, 4, 0, 9)]


def test_prim_paths_and_their_ranks_orient_alike():
    mesh_a, face_a, mesh_b, face_b = (np.array(column) for column in zip(*GIVEN))
    names, rank = np.array(PATHS, dtype=object), path_rank(PATHS)
    by_name = canonical_swap(names[mesh_a], face_a, names[mesh_b], face_b)
    by_rank = canonical_swap(rank[mesh_a], face_a, rank[mesh_b], face_b)
    assert by_name.tolist() == by_rank.tolist() == [True, False, True, False]
    side_a, side_b = swap_sides(by_rank, mesh_a, mesh_b)
    first, second = swap_sides(by_rank, face_a, face_b)
    assert list(zip(side_a.tolist(), first.tolist(), side_b.tolist(), second.tolist())) == CANONICAL


def test_table_and_crosscheck_keys_put_a_pair_the_same_way_round():
    for given, canonical in zip(GIVEN, CANONICAL):
        table = ContactTable.from_rows(PATHS, [1.0], *([value] for value in given))
        assert table.pair_rows().tolist() == [list(canonical)]
    numbering = _FaceNumbering([SimpleNamespace(path=path, face_count=10) for path in PATHS])
    mesh_a, face_a, mesh_b, face_b = (np.array(column) for column in zip(*GIVEN))
    keys = numbering.pair_keys(mesh_a, face_a, mesh_b, face_b)
    assert keys[0] == keys[1] and keys[2] == keys[3]
    unpacked = [column.tolist() for column in numbering.unpack(keys)]
    assert list(zip(*unpacked)) == CANONICAL


def test_baseline_entries_take_the_same_orientation_with_wildcards_last(tmp_path):
    path = tmp_path / "accept.csv"
    path.write_text("prim_a,face_a,prim_b,face_b\n"
                    f"/Z/Cloth,7,/A/Box,3\n/Z/Cloth,9,/Z/Cloth,4\n/Z/Cloth,{ANY_FACE},/Z/Cloth,12\n"
                    f"/Z/Cloth,{ANY_FACE},/A/Box,{ANY_FACE}\n", encoding="utf-8")
    baseline = read_baseline(path)
    assert [baseline.entry(index) for index in range(baseline.count)] == [
        {"prim_a": "/A/Box", "face_a": 3, "prim_b": "/Z/Cloth", "face_b": 7, "time": None},
        {"prim_a": "/Z/Cloth", "face_a": 4, "prim_b": "/Z/Cloth", "face_b": 9, "time": None},
        {"prim_a": "/Z/Cloth", "face_a": 12, "prim_b": "/Z/Cloth", "face_b": ANY_FACE, "time": None},
        {"prim_a": "/A/Box", "face_a": ANY_FACE, "prim_b": "/Z/Cloth", "face_b": ANY_FACE, "time": None},
    ]
