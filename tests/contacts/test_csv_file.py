"""contacts.csv: the one reader reads back exactly what the one writer wrote, and names what it cannot read."""

import re

import numpy as np
import pytest

from usdksl.clock import StageClock
from usdksl.contacts.csv_file import CONTACT_COLUMNS, contacts_csv, read_contacts_csv
from usdksl.contacts.table import FEATURE_EDGE_EDGE, FEATURE_INITIAL, FEATURE_VERTEX_FACE, ContactTable
from usdksl.errors import UsdkslInputError

# mesh 0 is "/Z/Cloth", mesh 1 is "/A/Box": index order differs from string order on purpose
PATHS = ["/Z/Cloth", "/A/Box"]
# 48 time codes a second at 24 fps: frames and seconds differ from time codes
CLOCK = StageClock(time_codes_per_second=48.0, frames_per_second=24.0)


def written_table() -> ContactTable:
    """Self and inter rows with every kind of feature (one unknown) and times that need all 17 digits."""
    table = ContactTable.from_rows(PATHS, time=[0.1 + 0.2, 17.488909631961178, 1.0 / 3.0, 1e-7],
                                   mesh_a=[0, 0, 1, 0], face_a=[7, 9, 3, 2], mesh_b=[1, 0, 1, 0],
                                   face_b=[3, 4, 8, 5], feature=[FEATURE_VERTEX_FACE, FEATURE_EDGE_EDGE,
                                                                 FEATURE_INITIAL, -1])
    return table.with_last_times(table.time + np.array([2.0 / 3.0, 0.0, 1e-9, 40.0]))


def assert_same_rows(read: ContactTable, written: ContactTable):
    for column in ("time", "mesh_a", "face_a", "mesh_b", "face_b", "feature", "last_time"):
        assert getattr(read, column).tolist() == getattr(written, column).tolist(), column


def test_the_reader_reads_back_what_the_writer_wrote_with_last_contacts_and_baseline(tmp_path):
    table = written_table()
    known = np.array([True, False, True, False])
    text = contacts_csv(table, CLOCK, known)
    assert text.splitlines()[0].endswith("last_time,last_frame,last_seconds,baseline")
    assert "unknown" in text and "initial" in text
    path = tmp_path / "shot.contacts.csv"
    path.write_text(text, encoding="utf-8")

    read = read_contacts_csv(path, PATHS, face_counts=[10, 10], required=CONTACT_COLUMNS)
    assert read.source == str(path) and read.ignored_rows == 0
    assert_same_rows(read.table, table)
    assert contacts_csv(read.table, CLOCK, known) == text


def test_a_file_reads_over_meshes_in_another_order(tmp_path):
    table = written_table()
    path = tmp_path / "shot.contacts.csv"
    path.write_text(contacts_csv(table, CLOCK), encoding="utf-8")
    reordered = list(reversed(PATHS))
    read = read_contacts_csv(path, reordered).table
    assert read.records() == table.records()
    assert read.prim_names()[0].tolist() == table.prim_names()[0].tolist()


def test_a_file_with_only_the_face_pair_columns_reads_with_unknown_features(tmp_path):
    path = tmp_path / "other_tool.csv"
    path.write_text("prim_b,face_b,prim_a,face_a,time\n/A/Box,3,/Z/Cloth,7,2.5\n", encoding="utf-8")
    read = read_contacts_csv(path, PATHS).table
    assert read.records() == [{"time": 2.5, "prim_a": "/A/Box", "face_a": 3, "prim_b": "/Z/Cloth", "face_b": 7,
                               "kind": "inter", "feature": "unknown"}]
    assert read.last_time is None


@pytest.mark.parametrize("text, message", [
    ("time,prim_a,face_a,prim_b,face_b\n", "lacks column(s) kind, feature, frame, seconds"),
    ("time,prim_a,face_a,prim_b,face_b,kind,feature,frame,seconds\n"
     "1.0,/A/Box,0,/Z/Cloth,1,inter,corner,0.5,0.02\n", "row 2: feature 'corner' is not one of"),
    ("time,prim_a,face_a,prim_b,face_b,kind,feature,frame,seconds\n"
     "1.0,/A/Box,0,/Elsewhere,1,inter,initial,0.5,0.02\n", "row 2: prim '/Elsewhere' is not a mesh of the shot"),
    ("time,prim_a,face_a,prim_b,face_b,kind,feature,frame,seconds\n"
     "1.0,/A/Box,-1,/Z/Cloth,1,inter,initial,0.5,0.02\n", "row 2: face_a '-1' is not a face index"),
    ("time,prim_a,face_a,prim_b,face_b,kind,feature,frame,seconds,last_time\n"
     "1.0,/A/Box,0,/Z/Cloth,1,inter,initial,0.5,0.02,later\n", "row 2: last_time 'later' is not a number"),
])
def test_what_the_reader_cannot_read_is_named_with_file_and_row(tmp_path, text, message):
    path = tmp_path / "bad.contacts.csv"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(UsdkslInputError, match=re.escape(message)) as raised:
        read_contacts_csv(path, PATHS, required=CONTACT_COLUMNS)
    assert str(path) in str(raised.value)
