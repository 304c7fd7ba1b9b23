"""contacts.csv: the one writer and the one reader (docs/contracts.md, Outputs).

``time,prim_a,face_a,prim_b,face_b,kind,feature,frame,seconds``: the six contract columns, the feature
that touched first (vertex-face, face-vertex, edge-edge or initial), then the time as a frame and in
seconds on the stage's timeline (usdksl.clock); with last contacts (``--last-contact``) also
``last_time,last_frame,last_seconds``; then the ``region`` (usdksl.regions) the row belongs to, when
regions were found; with a baseline a last column ``baseline``: new or known.

The writer renders a :class:`~usdksl.contacts.table.ContactTable`, whose rows are already in canonical
order. Times are written with ``repr(float)``, the shortest text that reads back to the same double, so
two runs give byte-identical files and the reader gets the very table back.

The reader reads its columns by name, so it also takes a file that another tool wrote with only the
columns a face pair needs (:data:`REQUIRED_COLUMNS`).
"""

from __future__ import annotations

import csv
import os
from dataclasses import dataclass
from typing import Dict, Optional, Sequence, Union

import numpy as np

from ..clock import StageClock
from ..errors import UsdkslInputError
from .table import FEATURE_NAMES, FEATURE_UNKNOWN, ContactTable, latest_per_face_pair, match_face_pairs

#: The columns usdksl writes, in this order.
CONTACT_COLUMNS = ("time", "prim_a", "face_a", "prim_b", "face_b", "kind", "feature", "frame", "seconds")
#: Written after CONTACT_COLUMNS when last contacts were computed.
LAST_CONTACT_COLUMNS = ("last_time", "last_frame", "last_seconds")
#: The columns a contacts.csv needs to be read: a face pair and its first contact.
REQUIRED_COLUMNS = ("time", "prim_a", "face_a", "prim_b", "face_b")
FEATURE_COLUMN = "feature"
#: The column with a row's baseline status (usdksl.contacts.baseline), and its words.
STATUS_COLUMN = "baseline"
#: The column with the id of the row's contact region (usdksl.regions), before the baseline status.
REGION_COLUMN = "region"
NEW = "new"
KNOWN = "known"
#: Rows of the file are numbered from this one (the header is row 1).
FIRST_ROW = 2


# --------------------------------------------------------------------------- writing

def format_times(times: np.ndarray) -> np.ndarray:
    """object[C] of repr(float) strings; repr runs once per distinct time, not once per row."""
    times = np.asarray(times, dtype=np.float64)
    if times.size == 0:
        return np.zeros(0, dtype=object)
    distinct, inverse = np.unique(times, return_inverse=True)
    text = np.array(list(map(repr, distinct.tolist())), dtype=object)
    return text[inverse.reshape(-1)]


def _int_text(values: np.ndarray) -> np.ndarray:
    # str() over a list of Python ints runs in C and takes under half the time of numpy's
    # astype(str).astype(object) (2.4M face indices: 0.36 s against 0.83 s).
    return np.array(list(map(str, np.asarray(values).astype(np.int64).tolist())), dtype=object)


def contacts_csv(table: ContactTable, clock: StageClock, known: Optional[np.ndarray] = None,
                 region: Optional[np.ndarray] = None) -> str:
    """contacts.csv: the header, then one line per row of ``table`` (frames and seconds by ``clock``);
    ``known`` (bool per row, from a baseline) adds the ``baseline`` column: new or known; ``region`` (int per
    row: its region id) the ``region`` column."""
    with_last = table.last_time is not None
    header = ",".join(CONTACT_COLUMNS + (LAST_CONTACT_COLUMNS if with_last else ())
                      + ((REGION_COLUMN,) if region is not None else ())
                      + ((STATUS_COLUMN,) if known is not None else ())) + "\n"
    if table.count == 0:
        return header
    prim_a, prim_b = table.prim_names()
    columns = [format_times(table.time), prim_a, _int_text(table.face_a), prim_b, _int_text(table.face_b),
               table.kinds(), table.feature_names(), format_times(clock.frames(table.time)),
               format_times(clock.seconds(table.time))]
    if with_last:
        columns += [format_times(table.last_time), format_times(clock.frames(table.last_time)),
                    format_times(clock.seconds(table.last_time))]
    if region is not None:
        columns.append(_int_text(region))
    if known is not None:
        columns.append(np.where(known, KNOWN, NEW).astype(object))
    # Columns are numpy object arrays; map/zip/join run in C (measured: 0.05 s for 100k rows, 3.5x
    # faster than chained object-array additions), no Python code runs per row.
    columns = [column.tolist() for column in columns]
    return header + "\n".join(map(",".join, zip(*columns))) + "\n"


# --------------------------------------------------------------------------- reading

@dataclass
class ContactsFile:
    """A contacts.csv read over a shot's meshes."""

    source: str             # the file, as given
    #: Its face pairs over the meshes, in canonical order: first contacts, features (FEATURE_UNKNOWN's code
    #: -1 without a feature column) and, with a last_time column, last contacts.
    table: ContactTable
    ignored_rows: int = 0   # rows naming a prim that is not among the meshes (when told to skip them)


def read_contacts_csv(path: Union[str, os.PathLike], paths: Sequence[str],
                      face_counts: Optional[Sequence[int]] = None, required: Sequence[str] = REQUIRED_COLUMNS,
                      skip_unknown_prims: bool = False) -> ContactsFile:
    """Read a contacts.csv over the meshes ``paths`` (prim paths; mesh indices of the table index them).

    Columns are read by name; the file must have those of ``required``. ``feature`` and ``last_time`` are
    read when present, other columns (frames, seconds, the baseline status) are not. Rows naming a prim
    that is not among ``paths`` are counted and left out with ``skip_unknown_prims`` (the shot may have
    been scoped differently), an error otherwise. With ``face_counts`` (one per mesh) a face index must
    lie inside its mesh. Raises UsdkslInputError naming the file and row (and the prim) on anything else
    malformed: an unreadable file, a missing column, a short row, a time or face that does not parse.
    """
    name = str(path)
    try:
        with open(path, newline="", encoding="utf-8") as handle:
            rows = list(csv.reader(handle))
    except (OSError, UnicodeDecodeError) as error:
        reason = getattr(error, "strerror", None) or str(error)
        raise UsdkslInputError(f"cannot read contacts: {reason}", file=name) from None
    if not rows:
        raise UsdkslInputError("contacts file is empty (no header)", file=name)
    header = [column.strip() for column in rows[0]]
    missing = [column for column in dict.fromkeys(tuple(REQUIRED_COLUMNS) + tuple(required)) if column not in header]
    if missing:
        raise UsdkslInputError(f"contacts header lacks column(s) {', '.join(missing)}", file=name)
    body = [row for row in rows[1:] if row]
    width = len(header)
    short = [number for number, row in enumerate(body, start=FIRST_ROW) if len(row) < width]
    if short:
        raise UsdkslInputError(f"row {short[0]}: expected {width} columns", file=name)
    table = np.array([row[:width] for row in body], dtype=object).reshape(len(body), width)
    column = {column_name: table[:, header.index(column_name)] for column_name in header}

    time = _numbers(column, "time", name)
    face_a, face_b = _faces(column, "face_a", name), _faces(column, "face_b", name)
    last_time = _numbers(column, LAST_CONTACT_COLUMNS[0], name) if LAST_CONTACT_COLUMNS[0] in column else None
    feature = (_features(column[FEATURE_COLUMN], name) if FEATURE_COLUMN in column
               else np.full(len(body), -1, np.int8))

    index_of = {path: index for index, path in enumerate(paths)}
    prims, inverse = np.unique(np.concatenate([column["prim_a"], column["prim_b"]]).astype(str),
                               return_inverse=True)
    lookup = np.array([index_of.get(str(prim), -1) for prim in prims], dtype=np.int64)
    mesh_both = lookup[inverse.reshape(-1)] if len(prims) else np.zeros(0, dtype=np.int64)
    mesh_a, mesh_b = mesh_both[:len(body)], mesh_both[len(body):]
    known = (mesh_a >= 0) & (mesh_b >= 0)
    if not skip_unknown_prims and not known.all():
        row = int(np.flatnonzero(~known)[0])
        prim = column["prim_a"][row] if mesh_a[row] < 0 else column["prim_b"][row]
        raise UsdkslInputError(f"row {row + FIRST_ROW}: prim '{prim}' is not a mesh of the shot", file=name)
    if face_counts is not None and known.any():
        face_counts = np.asarray(face_counts, dtype=np.int64)
        for mesh_column, face_column, label in ((mesh_a, face_a, "face_a"), (mesh_b, face_b, "face_b")):
            too_big = np.flatnonzero(known & (face_column >= face_counts[np.maximum(mesh_column, 0)]))
            if len(too_big):
                row = too_big[0]
                raise UsdkslInputError(f"row {row + FIRST_ROW}: {label} {face_column[row]} is out of range "
                                       f"({face_counts[mesh_column[row]]} faces)", file=name,
                                       prim=paths[mesh_column[row]])

    kept = ContactTable.from_rows(paths, time[known], mesh_a[known], face_a[known], mesh_b[known], face_b[known],
                                  feature[known])
    if last_time is not None:
        latest = latest_per_face_pair(paths, last_time[known], mesh_a[known], face_a[known], mesh_b[known],
                                      face_b[known])
        kept = kept.with_last_times(latest.time[match_face_pairs(kept, latest)[0]])
    return ContactsFile(source=name, table=kept, ignored_rows=int(np.count_nonzero(~known)))


def _parsed(column: Dict[str, np.ndarray], column_name: str, name: str) -> np.ndarray:
    """float64[R]: a column read as numbers (UsdkslInputError naming the row of the first that is not one)."""
    text = column[column_name]
    try:
        return np.array(text, dtype=np.float64)
    except ValueError:
        bad = next(row for row, value in enumerate(text) if not is_number(value))
        raise UsdkslInputError(f"row {bad + FIRST_ROW}: {column_name} '{text[bad]}' is not a number",
                               file=name) from None


def _numbers(column: Dict[str, np.ndarray], column_name: str, name: str) -> np.ndarray:
    """float64[R]: a column of finite numbers (UsdkslInputError naming the row of the first that is not)."""
    values = _parsed(column, column_name, name)
    bad = np.flatnonzero(~np.isfinite(values))
    if len(bad):
        raise UsdkslInputError(f"row {bad[0] + FIRST_ROW}: {column_name} is not finite", file=name)
    return values


def _faces(column: Dict[str, np.ndarray], column_name: str, name: str) -> np.ndarray:
    """int64[R]: a column of face indices (UsdkslInputError naming the row of the first that is not one)."""
    values = _parsed(column, column_name, name)
    bad = np.flatnonzero((values != np.round(values)) | (values < 0) | ~np.isfinite(values))
    if len(bad):
        raise UsdkslInputError(f"row {bad[0] + FIRST_ROW}: {column_name} '{column[column_name][bad[0]]}' is not a "
                               f"face index", file=name)
    return values.astype(np.int64)


def _features(text: np.ndarray, name: str) -> np.ndarray:
    """int8[R]: the feature code of each word (FEATURE_NAMES; FEATURE_UNKNOWN reads as -1)."""
    codes = {word: code for code, word in enumerate(FEATURE_NAMES)}
    codes[FEATURE_UNKNOWN] = -1
    # one dictionary look-up per distinct word, not per row
    distinct, inverse = np.unique(text.astype(str), return_inverse=True)
    unknown = [word for word in distinct.tolist() if word not in codes]
    if unknown:
        row = int(np.flatnonzero(text.astype(str) == unknown[0])[0])
        raise UsdkslInputError(f"row {row + FIRST_ROW}: feature '{unknown[0]}' is not one of "
                               f"{', '.join(FEATURE_NAMES + (FEATURE_UNKNOWN,))}", file=name)
    return np.array([codes[word] for word in distinct.tolist()], dtype=np.int8)[inverse.reshape(-1)]


def is_number(text: str) -> bool:
    """Whether ``float(text)`` reads ``text`` (for naming the first value of a column that does not)."""
    try:
        float(text)
    except ValueError:
        return False
    return True


__all__ = ["CONTACT_COLUMNS", "KNOWN", "LAST_CONTACT_COLUMNS", "NEW", "REQUIRED_COLUMNS", "STATUS_COLUMN",
           "ContactsFile", "contacts_csv", "format_times", "is_number", "read_contacts_csv"]
