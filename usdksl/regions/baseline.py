"""Baselines by region: problems accepted earlier do not fail the check again, and nothing new hides behind
them (docs/contracts.md, Baselines, Regions in a baseline).

A region baseline is a CSV read by its header (``#`` lines are comments): the ``<stem>.regions.csv`` of an
earlier run (usdksl.regions.csv_file), or an accept list written by hand with its columns
``prim_a,prim_b,first_frame,last_frame,max_depth,min_x,min_y,min_z,max_x,max_y,max_z`` (and optionally
``region`` and ``depth_measure``)::

      # the cloth rests on the table top from frame 40: accepted in review
      prim_a,prim_b,first_frame,last_frame,max_depth,min_x,min_y,min_z,max_x,max_y,max_z
      /World/Cloth,/World/Table,40,150,0.002,-1,0.9,-1,1,1.0,1

A header with any of the box columns or ``max_depth`` makes a region baseline (a contacts.csv has none of
them); one that then lacks another of the columns above is an input error, not a contacts baseline.

An entry accepts a region of the current check when all of these hold:

* the same two prims, in either order;
* the region's centre lies in the entry's box grown on every side by :data:`BOX_GROWTH` of the box's
  diagonal plus :data:`BOX_FLOOR` (a centre that is not finite lies in no box);
* the region's frames lie within the entry's ``first_frame..last_frame`` grown by :data:`SPAN_SLACK_FRAMES`
  at either end;
* its ``max_depth`` is at most the entry's grown by :data:`DEPTH_GROWTH` (plus :data:`DEPTH_FLOOR`), and
  its depth measures the same thing when the entry names a ``depth_measure``.

A region some entry accepts is *known*, and so are its contact rows; every other row is *new*. So an
accepted resting contact does not hide a pass-through beside it: a deeper or longer region in the same
place, or a region elsewhere, is new. Entries that accept no region are *fixed*. The result is the
:class:`~usdksl.contacts.baseline.BaselineComparison` of a contacts baseline, so the console, the reports
and the exit code read it alike; :class:`RegionBaseline` describes its entries as :class:`Baseline` does.

Matching is a join of entries and regions on their pair of meshes (numpy), never a loop over regions.
"""

from __future__ import annotations

import csv
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import List, Optional, Tuple, Union

import numpy as np

from ..clock import StageClock, console_number
from ..contacts.baseline import Baseline, BaselineComparison, compare, read_baseline, read_baseline_cells
from ..contacts.baseline import baseline_for_shot as contacts_baseline_for_shot
from ..contacts.csv_file import is_number
from ..contacts.table import ContactTable
from ..errors import UsdkslInputError
from .table import INTERSECTION_LENGTH, NO_REGION, PENETRATION, RegionTable

#: The box columns of regions.csv (world space, scene units).
BOX_MIN_COLUMNS = ("min_x", "min_y", "min_z")
BOX_MAX_COLUMNS = ("max_x", "max_y", "max_z")
#: The columns every region baseline has (a regions.csv has them all).
REQUIRED_COLUMNS = ("prim_a", "prim_b", "first_frame", "last_frame", "max_depth") + BOX_MIN_COLUMNS + BOX_MAX_COLUMNS
#: Columns of which any one in a header makes the file a region baseline: a contacts.csv has none of them.
REGION_ONLY_COLUMNS = ("max_depth",) + BOX_MIN_COLUMNS + BOX_MAX_COLUMNS
#: Optional columns: the entry's region id (to name it), and what its depth measures.
REGION_ID_COLUMN = "region"
DEPTH_MEASURE_COLUMN = "depth_measure"
#: Lines starting with this are comments.
COMMENT = "#"
#: Significant digits of a depth on the console (depths are small numbers in scene units: 0.00042).
DEPTH_DIGITS = 3

#: Fraction (dimensionless) of an entry box's diagonal by which the box grows on every side: a re-simulated
#: cache moves a resting contact a little.
BOX_GROWTH = 0.25
#: Scene units the box grows by at the least, so a flat or point box still holds a centre computed again.
BOX_FLOOR = 1e-4
#: Frames by which an entry's first_frame..last_frame grows at either end.
SPAN_SLACK_FRAMES = 2.0
#: Fraction (dimensionless) by which an entry's max_depth grows before a region is too deep for it.
DEPTH_GROWTH = 0.25
#: Scene units added to the grown max_depth, so an entry of depth 0 accepts the same region measured again.
DEPTH_FLOOR = 1e-6


@dataclass(frozen=True)
class RegionTolerances:
    """How far a region may be from an entry and still be the problem it accepted (module docstring)."""

    box_growth: float = BOX_GROWTH              # fraction of the entry box's diagonal
    box_floor: float = BOX_FLOOR                # scene units
    span_slack_frames: float = SPAN_SLACK_FRAMES  # frames
    depth_growth: float = DEPTH_GROWTH          # fraction of the entry's max_depth
    depth_floor: float = DEPTH_FLOOR            # scene units


@dataclass
class RegionBaseline:
    """Accepted regions: one entry per row of the file, prim_a <= prim_b by string. Frames on the stage's
    clock, lengths in scene units, world space."""

    source: str
    prim_a: np.ndarray          # object[E]
    prim_b: np.ndarray          # object[E]
    first_frame: np.ndarray     # float64[E]
    last_frame: np.ndarray      # float64[E]
    max_depth: np.ndarray       # float64[E]
    box_min: np.ndarray         # float64[E, 3]
    box_max: np.ndarray         # float64[E, 3]
    region: np.ndarray          # int64[E], the region id in the run it comes from; -1 when not given
    depth_measure: np.ndarray   # object[E]: PENETRATION, INTERSECTION_LENGTH or "" (any)
    tolerances: RegionTolerances = field(default_factory=RegionTolerances)
    #: A region baseline compares no times (BaselineComparison.to_dict reports this as null).
    time_tolerance: Optional[float] = None

    @property
    def count(self) -> int:
        return int(self.first_frame.shape[0])

    def describe(self, index: int) -> str:
        """One entry as the console names it: ``region 3: /A x /B, frames 12..40, max depth 0.031``."""
        name = f"region {int(self.region[index])}: " if self.region[index] >= 0 else "region "
        return (f"{name}{self.prim_a[index]} x {self.prim_b[index]}, frames "
                f"{console_number(self.first_frame[index])}..{console_number(self.last_frame[index])}, "
                f"max depth {float(self.max_depth[index]):.{DEPTH_DIGITS}g}")

    def entry(self, index: int) -> dict:
        """One entry as the JSON report lists it."""
        return {"region": int(self.region[index]) if self.region[index] >= 0 else None,
                "prim_a": str(self.prim_a[index]), "prim_b": str(self.prim_b[index]),
                "first_frame": float(self.first_frame[index]), "last_frame": float(self.last_frame[index]),
                "max_depth": float(self.max_depth[index]),
                "depth_measure": str(self.depth_measure[index]) or None,
                "box_min": [float(value) for value in self.box_min[index]],
                "box_max": [float(value) for value in self.box_max[index]]}


#: What --baseline can be once read: accepted contacts (usdksl.contacts.baseline) or accepted regions.
AnyBaseline = Union[Baseline, RegionBaseline]


def _header_of(path: Union[str, os.PathLike]) -> Optional[List[str]]:
    """The column names of a baseline file's first line that is neither blank nor a comment; None when the
    file cannot be read or has none."""
    try:
        with open(path, encoding="utf-8", newline="") as handle:
            for line in handle:
                if line.strip() and not line.lstrip().startswith(COMMENT):
                    return [column.strip() for column in next(csv.reader([line]))]
    except (OSError, UnicodeDecodeError):
        return None
    return None


def is_region_baseline(path: Union[str, os.PathLike]) -> bool:
    """Whether ``path`` is a region baseline by its header (module docstring); False for a file that cannot
    be read (reading it as a contacts baseline then says why)."""
    header = _header_of(path)
    return header is not None and any(column in header for column in REGION_ONLY_COLUMNS)


def read_region_baseline(path: Union[str, os.PathLike],
                         tolerances: RegionTolerances = RegionTolerances()) -> RegionBaseline:
    """Read a region baseline (module docstring). Raises UsdkslInputError naming the file and line."""
    name = str(path)
    header, cells, numbers = read_baseline_cells(path, REQUIRED_COLUMNS,
                                                 f"a regions.csv, or an accept list {','.join(REQUIRED_COLUMNS)}")
    line_numbers = np.array(numbers, dtype=np.int64)

    def column(column_name: str) -> Optional[np.ndarray]:
        if column_name not in header:
            return None
        return np.array([value.strip() for value in cells[:, header.index(column_name)].tolist()],
                        dtype=object).astype(str).reshape(cells.shape[0])

    prim_a, prim_b = column("prim_a"), column("prim_b")
    empty = np.flatnonzero((prim_a == "") | (prim_b == ""))
    if empty.size:
        raise UsdkslInputError(f"line {line_numbers[empty[0]]}: empty prim path", file=name)
    first_frame = _numbers(column("first_frame"), "first_frame", line_numbers, name)
    last_frame = _numbers(column("last_frame"), "last_frame", line_numbers, name)
    backwards = np.flatnonzero(last_frame < first_frame)
    if backwards.size:
        raise UsdkslInputError(f"line {line_numbers[backwards[0]]}: last_frame is before first_frame", file=name)
    max_depth = _numbers(column("max_depth"), "max_depth", line_numbers, name)
    negative = np.flatnonzero(max_depth < 0)
    if negative.size:
        raise UsdkslInputError(f"line {line_numbers[negative[0]]}: max_depth is negative", file=name)
    box = np.stack([_numbers(column(column_name), column_name, line_numbers, name)
                    for column_name in BOX_MIN_COLUMNS + BOX_MAX_COLUMNS], axis=1).reshape(cells.shape[0], 6)
    inverted = np.flatnonzero((box[:, :3] > box[:, 3:]).any(axis=1))
    if inverted.size:
        raise UsdkslInputError(f"line {line_numbers[inverted[0]]}: the box has a min above its max", file=name)
    region = _region_ids(column(REGION_ID_COLUMN), line_numbers, name)
    measure = _depth_measures(column(DEPTH_MEASURE_COLUMN), cells.shape[0], line_numbers, name)
    swap = prim_a > prim_b
    prim_a, prim_b = np.where(swap, prim_b, prim_a).astype(object), np.where(swap, prim_a, prim_b).astype(object)
    return RegionBaseline(source=name, prim_a=prim_a, prim_b=prim_b, first_frame=first_frame, last_frame=last_frame,
                          max_depth=max_depth, box_min=box[:, :3].copy(), box_max=box[:, 3:].copy(), region=region,
                          depth_measure=measure, tolerances=tolerances)


def _numbers(text: np.ndarray, column_name: str, line_numbers: np.ndarray, name: str) -> np.ndarray:
    """float64[E]: a column of finite numbers; UsdkslInputError naming the line of the first that is not."""
    try:
        values = text.astype(np.float64)
    except ValueError:
        bad = next(row for row, value in enumerate(text.tolist()) if not is_number(value))
        raise UsdkslInputError(f"line {line_numbers[bad]}: {column_name} '{text[bad]}' is not a number",
                               file=name) from None
    bad = np.flatnonzero(~np.isfinite(values))
    if bad.size:
        raise UsdkslInputError(f"line {line_numbers[bad[0]]}: {column_name} '{text[bad[0]]}' is not finite",
                               file=name)
    return values


def _region_ids(text: Optional[np.ndarray], line_numbers: np.ndarray, name: str) -> np.ndarray:
    """int64[E]: the region column, -1 where empty or absent."""
    if text is None:
        return np.full(line_numbers.shape[0], -1, np.int64)
    given = text != ""
    bad = np.flatnonzero(given & ~np.char.isdigit(text))
    if bad.size:
        raise UsdkslInputError(f"line {line_numbers[bad[0]]}: region '{text[bad[0]]}' is not a region id", file=name)
    return np.where(given, text, "-1").astype(np.int64)


def _depth_measures(text: Optional[np.ndarray], count: int, line_numbers: np.ndarray, name: str) -> np.ndarray:
    """object[E]: the depth_measure column ("" where empty or absent: any)."""
    if text is None:
        return np.full(count, "", dtype=object)
    bad = np.flatnonzero(~np.isin(text, ["", PENETRATION, INTERSECTION_LENGTH]))
    if bad.size:
        raise UsdkslInputError(f"line {line_numbers[bad[0]]}: depth_measure '{text[bad[0]]}' is not "
                               f"{PENETRATION} or {INTERSECTION_LENGTH}", file=name)
    return text.astype(object)


def compare_regions(table: ContactTable, regions: RegionTable, clock: StageClock,
                    baseline: RegionBaseline) -> BaselineComparison:
    """Which rows of ``table`` (``regions`` holds its rows' regions) the region baseline knows, and which
    entries are fixed (module docstring). ``clock`` turns the regions' times into the frames the entries
    hold."""
    if regions.row_region.shape[0] != table.count:
        raise ValueError(f"regions of {regions.row_region.shape[0]} contact rows for a table of {table.count}")
    entry, region = _candidate_pairs(list(regions.paths or table.paths or []), regions, baseline)
    tolerances = baseline.tolerances
    first_frame = np.asarray(clock.frames(regions.first_time), dtype=np.float64)[region]
    last_frame = np.asarray(clock.frames(regions.last_time), dtype=np.float64)[region]
    in_span = ((first_frame >= baseline.first_frame[entry] - tolerances.span_slack_frames)
               & (last_frame <= baseline.last_frame[entry] + tolerances.span_slack_frames))
    shallow = (regions.max_depth[region]
               <= baseline.max_depth[entry] * (1.0 + tolerances.depth_growth) + tolerances.depth_floor)
    measure = baseline.depth_measure[entry]
    same_measure = (measure == "") | (measure == regions.depth_measure[region])
    accepted = in_span & shallow & same_measure & _inside(regions.center[region], baseline.box_min[entry],
                                                          baseline.box_max[entry], tolerances)
    known_region = np.zeros(regions.count, bool)
    known_region[region[accepted]] = True
    matched = np.zeros(baseline.count, bool)
    matched[entry[accepted]] = True
    row_region = regions.row_region
    known = np.zeros(table.count, bool)
    grouped = row_region != NO_REGION
    known[grouped] = known_region[row_region[grouped]]
    return BaselineComparison(baseline=baseline, known=known, fixed=np.flatnonzero(~matched).astype(np.int64),
                              table=table)


def _candidate_pairs(paths: List[str], regions: RegionTable,
                     baseline: RegionBaseline) -> Tuple[np.ndarray, np.ndarray]:
    """(entry rows, region rows): every entry and region of the same two meshes (either order), joined on the
    pair's key through a sort of the regions, so the work is the number of such pairs."""
    index = {path: position for position, path in enumerate(paths)}
    entry_a = np.array([index.get(prim, -1) for prim in baseline.prim_a.tolist()], dtype=np.int64)
    entry_b = np.array([index.get(prim, -1) for prim in baseline.prim_b.tolist()], dtype=np.int64)
    width = np.int64(len(paths) + 1)
    present = np.flatnonzero((entry_a >= 0) & (entry_b >= 0))
    entry_key = (np.minimum(entry_a, entry_b) * width + np.maximum(entry_a, entry_b))[present]
    mesh_a, mesh_b = regions.mesh_a.astype(np.int64), regions.mesh_b.astype(np.int64)
    region_key = np.minimum(mesh_a, mesh_b) * width + np.maximum(mesh_a, mesh_b)
    order = np.argsort(region_key, kind="stable")
    low = np.searchsorted(region_key[order], entry_key, side="left")
    high = np.searchsorted(region_key[order], entry_key, side="right")
    counts = high - low
    entries = np.repeat(present, counts)
    offsets = np.arange(int(counts.sum())) - np.repeat(np.cumsum(counts) - counts, counts)
    return entries, order[np.repeat(low, counts) + offsets]


def _inside(center: np.ndarray, box_min: np.ndarray, box_max: np.ndarray, tolerances: RegionTolerances) -> np.ndarray:
    """bool[P]: each centre lies in its box grown by box_growth of the box's diagonal plus box_floor (a
    centre that is not finite in none)."""
    growth = (tolerances.box_growth * np.linalg.norm(box_max - box_min, axis=1) + tolerances.box_floor)[:, None]
    with np.errstate(invalid="ignore"):
        return ((center >= box_min - growth) & (center <= box_max + growth)).all(axis=1)


def known_regions(regions: RegionTable, known: np.ndarray) -> np.ndarray:
    """bool[R]: a region is known when every one of its contact rows is (``known`` per row, from a contacts
    or a region baseline): the regions.csv ``baseline`` column."""
    return regions.known_regions(known)


def read_any_baseline(path: Union[str, os.PathLike],
                      time_tolerance: Optional[float] = None) -> AnyBaseline:
    """The baseline in ``path``, read by its header: a region baseline, or else a contacts baseline
    (usdksl.contacts.baseline, which ``time_tolerance`` is for; a region baseline compares no times)."""
    if is_region_baseline(path):
        return read_region_baseline(path)
    return read_baseline(path, time_tolerance)


def compare_any(table: ContactTable, regions: Optional[RegionTable], clock: StageClock,
                baseline: AnyBaseline) -> BaselineComparison:
    """``table`` held against either kind of baseline: by region (``regions`` needed) or by face pair."""
    if isinstance(baseline, RegionBaseline):
        if regions is None:
            raise ValueError("a region baseline needs the check's regions")
        return compare_regions(table, regions, clock, baseline)
    return compare(table, baseline)


def baseline_for_shot(baseline: Optional[Union[str, os.PathLike]], shot_stem: str,
                      time_tolerance: Optional[float] = None) -> Tuple[Optional[AnyBaseline],
                                                                       Optional[str]]:
    """(the baseline of one shot or None, a warning or None), as usdksl.contacts.baseline.baseline_for_shot,
    with a file read by its header (:func:`read_any_baseline`). In a folder ``<stem>.contacts.csv`` is the
    shot's baseline, as before; without it, an empty baseline and a warning (its regions.csv is not taken
    instead: a folder of an earlier run accepts contacts, a region baseline is given as a file)."""
    if baseline is None:
        return None, None
    path = Path(baseline)
    if not path.is_dir():
        return read_any_baseline(path, time_tolerance), None
    return contacts_baseline_for_shot(path, shot_stem, time_tolerance)


__all__ = ["RegionBaseline", "RegionTolerances", "baseline_for_shot", "compare_any", "compare_regions",
           "is_region_baseline", "known_regions", "read_any_baseline", "read_region_baseline"]
