"""Baselines: contacts accepted earlier do not fail the check again (docs/contracts.md, Baselines).

A baseline file is a CSV read by its header (``#`` lines are comments):

* a ``<stem>.contacts.csv`` of an earlier run (``time,prim_a,face_a,prim_b,face_b,kind,...``), or
* an accept list written by hand: columns ``prim_a,prim_b`` and optionally ``face_a,face_b`` and
  ``time``, where a face that is ``*`` or empty (or a missing face column) accepts every face::

      # cloth resting on the table edge: accepted in review
      prim_a,face_a,prim_b,face_b
      /World/Cloth,*,/World/Table,*
      /World/Cloth,12,/World/Cloth,40

An entry is matched by its prim paths and face indices, in either order of its two sides. With a time
tolerance (``--baseline-time-tolerance T``, time codes) an entry that has a time also needs a contact
within T of that time; without one, times are not compared. A contact that some entry matches is
*known*; the others are *new*, and only new contacts count for the exit code. Entries that match no
contact any more are *fixed*.

Matching is a join on integer keys (numpy), never a loop over contacts.
"""

from __future__ import annotations

import csv
import io
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable, List, Optional, Sequence, Tuple, Union

import numpy as np

from ..errors import UsdkslInputError, UsdkslUsageError
from .csv_file import KNOWN, NEW, is_number
from .orientation import canonical_swap, swap_sides
from .table import ContactTable

#: A face column that is empty or this accepts every face of its prim.
ANY_FACE = "*"
#: How an entry says "any face" once read.
WILDCARD = -1
#: Where a wildcard face stands in the canonical orientation: after every face index, so a self entry
#: keeps its one numbered face on side a.
WILDCARD_ORDER = np.iinfo(np.int64).max
#: Lines starting with this are comments.
COMMENT = "#"
#: Fraction (0..1) of a baseline's distinct prims that may fail to be meshes of the shot before the check
#: warns that the baseline was made from another shot.
MISMATCH_FRACTION = 0.5


@dataclass
class Baseline:
    """Accepted contacts: one entry per row of the file, sides in canonical order (prim_a <= prim_b by
    string; self entries with face_a <= face_b, a wildcard on side b). ``time`` NaN: any time."""

    source: str
    prim_a: np.ndarray      # object[E]
    face_a: np.ndarray      # int64[E], WILDCARD for any face
    prim_b: np.ndarray      # object[E]
    face_b: np.ndarray      # int64[E]
    time: np.ndarray        # float64[E], time codes; NaN when the entry has none
    #: Time codes an entry's time may differ from the contact's; None: times are not compared.
    time_tolerance: Optional[float] = None

    @property
    def count(self) -> int:
        return int(self.time.shape[0])

    def describe(self, index: int) -> str:
        """One entry as the console names it: ``/A face 3 x /B face *`` (and its time)."""
        def side(prim, face):
            return f"{prim} face {ANY_FACE if face == WILDCARD else int(face)}"
        text = f"{side(self.prim_a[index], self.face_a[index])} x {side(self.prim_b[index], self.face_b[index])}"
        time = float(self.time[index])
        return text if np.isnan(time) else f"{text} at t={time!r}"

    def entry(self, index: int) -> dict:
        """One entry as the JSON report lists it."""
        time = float(self.time[index])
        return {"prim_a": str(self.prim_a[index]),
                "face_a": ANY_FACE if self.face_a[index] == WILDCARD else int(self.face_a[index]),
                "prim_b": str(self.prim_b[index]),
                "face_b": ANY_FACE if self.face_b[index] == WILDCARD else int(self.face_b[index]),
                "time": None if np.isnan(time) else time}


@dataclass
class BaselineComparison:
    """A check's contacts held against a baseline."""

    baseline: Baseline
    known: np.ndarray                    # bool[C], per row of the checked table
    fixed: np.ndarray                    # int64[F], indices of baseline entries that matched nothing
    #: The checked table's rows, for describing new contacts.
    table: Optional[ContactTable] = field(default=None, repr=False)

    @property
    def new_count(self) -> int:
        return int(np.count_nonzero(~self.known))

    @property
    def known_count(self) -> int:
        return int(np.count_nonzero(self.known))

    @property
    def fixed_count(self) -> int:
        return int(self.fixed.shape[0])

    def statuses(self) -> np.ndarray:
        """object[C]: 'new' or 'known' per row (the contacts.csv ``baseline`` column)."""
        return np.where(self.known, KNOWN, NEW).astype(object)

    def to_dict(self) -> dict:
        """The ``baseline`` object of the JSON report."""
        return {"file": self.baseline.source, "time_tolerance": self.baseline.time_tolerance,
                "new": self.new_count, "known": self.known_count,
                "fixed": [self.baseline.entry(index) for index in self.fixed.tolist()]}


def read_baseline(path: Union[str, os.PathLike], time_tolerance: Optional[float] = None) -> Baseline:
    """Read a baseline file (module docstring). Raises UsdkslInputError naming the file and row."""
    name = str(path)
    if time_tolerance is not None and not time_tolerance >= 0:
        raise UsdkslUsageError(f"--baseline-time-tolerance must be zero or positive, got {time_tolerance!r}")
    header, table, line_numbers = read_baseline_cells(path, ("prim_a", "prim_b"),
                                                      "a contacts.csv or an accept list prim_a,face_a,prim_b,face_b[,time]")

    def column(column_name: str) -> Optional[np.ndarray]:
        if column_name not in header:
            return None
        return np.array([value.strip() for value in table[:, header.index(column_name)].tolist()], dtype=object)

    prim_a, prim_b = column("prim_a"), column("prim_b")
    face_a = _faces(column("face_a"), table.shape[0], "face_a", line_numbers, name)
    face_b = _faces(column("face_b"), table.shape[0], "face_b", line_numbers, name)
    time = _times(column("time"), table.shape[0], line_numbers, name)
    empty = np.flatnonzero((prim_a == "") | (prim_b == ""))
    if empty.size:
        raise UsdkslInputError(f"line {line_numbers[empty[0]]}: empty prim path", file=name)
    prim_a, face_a, prim_b, face_b = _canonical_sides(prim_a, face_a, prim_b, face_b)
    return Baseline(source=name, prim_a=prim_a, face_a=face_a, prim_b=prim_b, face_b=face_b, time=time,
                    time_tolerance=time_tolerance)


def read_baseline_cells(path: Union[str, os.PathLike], required: Sequence[str],
                        what: str) -> Tuple[List[str], np.ndarray, List[int]]:
    """(header, object[rows, columns] cells, the file's line number of each row) of a baseline CSV: ``#`` lines
    and blank lines skipped. Raises UsdkslInputError naming the file (and line) when it cannot be read, has no
    header, lacks a ``required`` column (``what`` says which files are meant) or has a short row."""
    name = str(path)
    try:
        text = Path(path).read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as error:
        raise UsdkslInputError(f"cannot read baseline: {getattr(error, 'strerror', None) or error}",
                               file=name) from None
    numbered = [(number, line) for number, line in enumerate(text.splitlines(), start=1)
                if line.strip() and not line.lstrip().startswith(COMMENT)]
    if not numbered:
        raise UsdkslInputError("baseline is empty (no header)", file=name)
    rows = list(csv.reader(io.StringIO("\n".join(line for _, line in numbered))))
    header = [column.strip() for column in rows[0]]
    missing = [column for column in required if column not in header]
    if missing:
        raise UsdkslInputError(f"line {numbered[0][0]}: baseline header lacks column(s) {', '.join(missing)} "
                               f"({what})", file=name)
    body = rows[1:]
    line_numbers = [number for number, _ in numbered[1:]]
    short = [number for number, row in zip(line_numbers, body) if len(row) < len(header)]
    if short:
        raise UsdkslInputError(f"line {short[0]}: expected {len(header)} columns", file=name)
    cells = np.array([row[:len(header)] for row in body], dtype=object).reshape(len(body), len(header))
    return header, cells, line_numbers


def empty_baseline(source: str, time_tolerance: Optional[float] = None) -> Baseline:
    """A baseline that accepts nothing."""
    nothing = np.zeros(0, object)
    return Baseline(source=source, prim_a=nothing, face_a=np.zeros(0, np.int64), prim_b=nothing,
                    face_b=np.zeros(0, np.int64), time=np.zeros(0), time_tolerance=time_tolerance)


def _faces(values: Optional[np.ndarray], count: int, column_name: str, line_numbers: List[int],
           name: str) -> np.ndarray:
    if values is None:
        return np.full(count, WILDCARD, np.int64)
    text = values.astype(str)
    wild = (text == "") | (text == ANY_FACE)
    bad = np.flatnonzero(~wild & ~np.char.isdigit(text))
    if bad.size:
        raise UsdkslInputError(f"line {line_numbers[bad[0]]}: {column_name} '{text[bad[0]]}' is not a face index "
                               f"or '{ANY_FACE}'", file=name)
    return np.where(wild, "-1", text).astype(np.int64)


def _times(values: Optional[np.ndarray], count: int, line_numbers: List[int], name: str) -> np.ndarray:
    if values is None:
        return np.full(count, np.nan)
    text = values.astype(str)
    given = text != ""
    times = np.full(count, np.nan)
    try:
        times[given] = text[given].astype(np.float64)
    except ValueError:
        bad = next(row for row in np.flatnonzero(given).tolist() if not is_number(text[row]))
        raise UsdkslInputError(f"line {line_numbers[bad]}: time '{text[bad]}' is not a number", file=name) from None
    bad = np.flatnonzero(given & ~np.isfinite(times))
    if bad.size:
        raise UsdkslInputError(f"line {line_numbers[bad[0]]}: time '{text[bad[0]]}' is not finite", file=name)
    return times


def _canonical_sides(prim_a, face_a, prim_b, face_b):
    """Entries in canonical orientation (usdksl.contacts.orientation): prim_a <= prim_b; in a self entry the
    lower face (or the only numbered one) on side a."""
    swap = canonical_swap(prim_a, np.where(face_a == WILDCARD, WILDCARD_ORDER, face_a), prim_b,
                          np.where(face_b == WILDCARD, WILDCARD_ORDER, face_b))
    prim_a, prim_b = swap_sides(swap, prim_a, prim_b)
    face_a, face_b = swap_sides(swap, face_a, face_b)
    return prim_a, face_a, prim_b, face_b


def compare(table: ContactTable, baseline: Baseline) -> BaselineComparison:
    """Which rows of ``table`` (canonical, with prim paths) the baseline knows, and which entries are fixed."""
    paths = list(table.paths or [])
    index = {path: position for position, path in enumerate(paths)}
    mesh_a = np.array([index.get(prim, -1) for prim in baseline.prim_a.tolist()], dtype=np.int64)
    mesh_b = np.array([index.get(prim, -1) for prim in baseline.prim_b.tolist()], dtype=np.int64)
    present = (mesh_a >= 0) & (mesh_b >= 0)
    rows = table.pair_rows()
    # rows also in swapped orientation: a self entry "/C, 12, /C, *" accepts face 12 on either side
    both_ways = np.concatenate([rows, rows[:, [2, 3, 0, 1]]])
    row_times = np.concatenate([table.time, table.time])
    known = np.zeros(table.count, bool)
    matched = np.zeros(baseline.count, bool)
    for wild_a in (False, True):
        for wild_b in (False, True):
            chosen = np.flatnonzero(present & ((baseline.face_a == WILDCARD) == wild_a)
                                    & ((baseline.face_b == WILDCARD) == wild_b))
            if chosen.size == 0 or table.count == 0:
                continue
            entry_keys = np.stack([mesh_a[chosen], baseline.face_a[chosen], mesh_b[chosen],
                                   baseline.face_b[chosen]], axis=1)
            row_keys = both_ways.copy()
            if wild_a:
                row_keys[:, 1] = WILDCARD
            if wild_b:
                row_keys[:, 3] = WILDCARD
            timed = (~np.isnan(baseline.time[chosen]) if baseline.time_tolerance is not None
                     else np.zeros(chosen.size, bool))
            row_hit = np.zeros(row_keys.shape[0], bool)
            for subset, tolerance in ((~timed, None), (timed, baseline.time_tolerance)):
                if not subset.any():
                    continue
                hit_rows, hit_entries = _join(row_keys, row_times, entry_keys[subset], baseline.time[chosen][subset],
                                              tolerance)
                row_hit |= hit_rows
                matched[chosen[subset]] |= hit_entries
            known |= row_hit[:table.count] | row_hit[table.count:]
    return BaselineComparison(baseline=baseline, known=known, fixed=np.flatnonzero(~matched).astype(np.int64),
                              table=table)


def _join(row_keys: np.ndarray, row_times: np.ndarray, entry_keys: np.ndarray, entry_times: np.ndarray,
          tolerance: Optional[float]) -> Tuple[np.ndarray, np.ndarray]:
    """(bool per row: some entry has its key [and a time within ``tolerance``], bool per entry: likewise
    some row). Keys are int64[., 4]."""
    ids = np.unique(np.concatenate([row_keys, entry_keys]), axis=0, return_inverse=True)[1].reshape(-1)
    row_ids, entry_ids = ids[:row_keys.shape[0]], ids[row_keys.shape[0]:]
    if tolerance is None:
        return np.isin(row_ids, entry_ids), np.isin(entry_ids, row_ids)
    return (_any_within(row_ids, row_times, entry_ids, entry_times, tolerance),
            _any_within(entry_ids, entry_times, row_ids, row_times, tolerance))


def _any_within(query_ids, query_times, reference_ids, reference_times, tolerance: float) -> np.ndarray:
    """bool per query: a reference with the same id lies within ``tolerance`` of the query's time. The
    nearest reference in time of each id is one of the two around the query in (id, time) order."""
    if reference_ids.size == 0:
        return np.zeros(query_ids.shape[0], bool)
    distinct_times, inverse = np.unique(np.concatenate([reference_times, query_times]), return_inverse=True)
    inverse = inverse.reshape(-1)
    width = np.int64(distinct_times.size + 1)
    reference_key = reference_ids.astype(np.int64) * width + inverse[:reference_ids.size]
    query_key = query_ids.astype(np.int64) * width + inverse[reference_ids.size:]
    order = np.argsort(reference_key, kind="stable")
    sorted_key = reference_key[order]
    position = np.searchsorted(sorted_key, query_key)
    found = np.zeros(query_ids.shape[0], bool)
    for neighbour in (position - 1, position):
        valid = (neighbour >= 0) & (neighbour < sorted_key.size)
        candidate = order[np.clip(neighbour, 0, sorted_key.size - 1)]
        found |= (valid & (reference_ids[candidate] == query_ids)
                  & (np.abs(reference_times[candidate] - query_times) <= tolerance))
    return found


def mismatch_warning(baseline: Baseline, is_mesh: Callable[[str], bool], shot: str) -> Optional[str]:
    """The warning for a baseline of which more than MISMATCH_FRACTION of the distinct prims it names are
    not meshes of ``shot`` (``is_mesh(prim_path)``), or None. Such a baseline accepts nothing (or accepts
    by accident), so every contact would silently count as new."""
    named = sorted(set(baseline.prim_a.tolist()) | set(baseline.prim_b.tolist()))
    foreign = sum(1 for prim in named if not is_mesh(prim))
    if not named or foreign <= MISMATCH_FRACTION * len(named):
        return None
    return (f"{baseline.source}: {foreign} of {len(named)} prims in the baseline are not meshes of {shot}: "
            f"made from another shot?")


def baseline_for_shot(baseline: Optional[Union[str, os.PathLike]], shot_stem: str,
                      time_tolerance: Optional[float] = None) -> Tuple[Optional[Baseline], Optional[str]]:
    """(the baseline of one shot or None, a warning or None). ``baseline`` is a file, or a folder holding
    ``<stem>.contacts.csv`` files (the ``--out`` folder of an earlier run over many shots); a shot without
    a file in that folder gets an empty baseline (every contact new), with a warning. Raises
    UsdkslInputError for an unreadable file."""
    if baseline is None:
        return None, None
    path = Path(baseline)
    if path.is_dir():
        path = path / f"{shot_stem}.contacts.csv"
        if not path.is_file():
            return empty_baseline(str(path), time_tolerance), f"no baseline {path}: every contact counts as new"
    return read_baseline(path, time_tolerance), None


__all__ = ["ANY_FACE", "Baseline", "BaselineComparison", "baseline_for_shot", "compare", "mismatch_warning",
           "read_baseline"]
