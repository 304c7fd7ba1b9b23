"""The texts of a check's reports: summary.csv and the --json document (contacts.csv:
usdksl.contacts.csv_file; JUnit: reports/junit.py).

Every text is rendered from a :class:`usdksl.contacts.table.ContactTable`, whose rows are already in canonical
order (docs/contracts.md, Contacts).

summary.csv   ``prim_a,prim_b,kind,first_contact_time,face_pairs,first_contact_frame,first_contact_seconds``
              (with last contacts also ``last_contact_time,last_contact_frame,last_contact_seconds``):
              one row per mesh pair that has contacts (clean pairs are not listed; the JUnit report and
              the JSON plan list every checked pair), sorted by first_contact_time, then prim_a, prim_b.
"""

from __future__ import annotations

import json
from typing import Optional

import numpy as np

from ..clock import StageClock, console_number
from ..contacts.csv_file import KNOWN, NEW, STATUS_COLUMN
from ..contacts.table import ContactTable
from ..reading.scope import PAIR_RIGID_ONLY
from ..regions.csv_file import region_records
from ..regions.table import PENETRATION, RegionTable

SUMMARY_COLUMNS = ("prim_a", "prim_b", "kind", "first_contact_time", "face_pairs", "first_contact_frame",
                   "first_contact_seconds")
SUMMARY_LAST_COLUMNS = ("last_contact_time", "last_contact_frame", "last_contact_seconds")
#: summary.csv column with a baseline: face pairs of the mesh pair the baseline does not know.
NEW_FACE_PAIRS = "new_face_pairs"


def summary_rows(table: ContactTable, clock: StageClock, known: Optional[np.ndarray] = None) -> list:
    """ContactTable.summary() with each time also as a frame and in seconds (the summary.csv columns), and
    with ``known`` (bool per row, from a baseline) the number of new face pairs per mesh pair."""
    rows = table.summary()
    new_per_pair = {}
    if known is not None and table.count:
        new = ~np.asarray(known, bool)
        pairs, counts = np.unique(np.stack([table.mesh_a[new], table.mesh_b[new]], axis=1), axis=0,
                                  return_counts=True)
        names = table.mesh_names()
        for (a, b), count in zip(pairs.tolist(), counts.tolist()):     # one per mesh pair
            new_per_pair[(names[a], names[b])] = int(count)
    for row in rows:
        if known is not None:
            row[NEW_FACE_PAIRS] = new_per_pair.get((row["prim_a"], row["prim_b"]), 0)
        for prefix in ("first_contact", "last_contact"):
            if f"{prefix}_time" in row:
                row[f"{prefix}_frame"] = clock.frame(row[f"{prefix}_time"])
                row[f"{prefix}_seconds"] = float(clock.seconds(row[f"{prefix}_time"]))
    return rows


def summary_csv(table: ContactTable, clock: StageClock, known: Optional[np.ndarray] = None) -> str:
    """summary.csv: the header, then one line per mesh pair with contacts (ContactTable.summary); with
    ``known`` (from a baseline) a last column new_face_pairs."""
    columns = (SUMMARY_COLUMNS + (SUMMARY_LAST_COLUMNS if table.last_time is not None else ())
               + ((NEW_FACE_PAIRS,) if known is not None else ()))
    lines = [",".join(columns)]
    for row in summary_rows(table, clock, known):
        lines.append(",".join(value if isinstance(value, str) else repr(value)
                              for value in (row[column] for column in columns)))
    return "\n".join(lines) + "\n"


def contact_records(table: ContactTable, clock: StageClock, known: Optional[np.ndarray] = None) -> list:
    """ContactTable.records() with frame and seconds (and last_frame, last_seconds; with ``known`` the
    baseline status) per row."""
    records = table.records()
    if not records:
        return records
    if known is not None:
        for record, status in zip(records, np.where(known, KNOWN, NEW).tolist()):
            record[STATUS_COLUMN] = status
    frames, seconds = clock.frames(table.time).tolist(), clock.seconds(table.time).tolist()
    for record, frame, second in zip(records, frames, seconds):
        record["frame"], record["seconds"] = frame, second
    if table.last_time is not None:
        frames, seconds = clock.frames(table.last_time).tolist(), clock.seconds(table.last_time).tolist()
        for record, frame, second in zip(records, frames, seconds):
            record["last_frame"], record["last_seconds"] = frame, second
    return records


def clock_settings(clock: StageClock) -> dict:
    """The ``clock`` object of the JSON report: the rates that turn time codes into frames and seconds."""
    return {"timeCodesPerSecond": clock.time_codes_per_second, "framesPerSecond": clock.frames_per_second}


def json_report(shot_path: str, settings: dict, plan, table: ContactTable, exit_code: int, clock: StageClock,
                version: str = "", baseline: Optional[dict] = None, known: Optional[np.ndarray] = None,
                coverage: Optional[dict] = None, findings: Optional[list] = None,
                regions: Optional[RegionTable] = None) -> str:
    """The --json document: shot, settings, clock, plan, coverage (usdksl.pipeline.coverage.Coverage.to_dict),
    findings (warnings with their stable kind), summary rows, regions (the regions.csv columns; each contact then
    has its ``region``), contacts, exit code; with a baseline its comparison (BaselineComparison.to_dict) and each
    contact's and region's status."""
    document = {
        "tool": "usdksl",
        "version": version,
        "shot": str(shot_path),
        "settings": settings,
        "clock": clock_settings(clock),
        "plan": plan.to_dict(),
        "coverage": coverage,
        "findings": list(findings or []),
        "summary": summary_rows(table, clock, known),
        "regions": [] if regions is None else _finite(region_records(regions, table, clock, known,
                                                                     with_face_lists=True)),
        "contacts": contact_records(table, clock, known),
        "contact_count": table.count,
        "exit_code": int(exit_code),
    }
    if regions is not None:
        for record, region in zip(document["contacts"], regions.row_ids.tolist()):
            record["region"] = region
    if baseline is not None:
        document["baseline"] = baseline
    return json.dumps(document, indent=1, allow_nan=False) + "\n"


def mesh_pair_lines(table: ContactTable, clock: StageClock, known: Optional[np.ndarray] = None) -> list:
    """One console line per mesh pair with contacts (``usdksl check -v``): its face pairs (new ones with a
    baseline), first contact and, when computed, last contact."""
    lines = []
    for row in summary_rows(table, clock, known):
        pair = row["prim_a"] if row["kind"] == "self" else f"{row['prim_a']} x {row['prim_b']}"
        count = f"{row['face_pairs']} face pair{'s' if row['face_pairs'] != 1 else ''}"
        if NEW_FACE_PAIRS in row:
            count += f" ({row[NEW_FACE_PAIRS]} new)"
        line = f"{pair} ({row['kind']}): {count}, first at {clock.describe(row['first_contact_time'])}"
        if "last_contact_time" in row:
            line += f", last at {clock.describe(row['last_contact_time'])}"
        lines.append(line)
    return lines


def _finite(records: list) -> list:
    """Records with NaN and infinite numbers as None (JSON has no NaN)."""
    return [{key: (None if isinstance(value, float) and not np.isfinite(value) else value)
             for key, value in record.items()} for record in records]


def depth_text(measure: str, depth: float) -> str:
    """A region's depth as the console says it: ``0.031 deep`` or ``intersection 0.2 long``."""
    return f"{depth:.3g} deep" if measure == PENETRATION else f"intersection {depth:.3g} long"


def region_lines(regions: Optional[RegionTable], table: ContactTable, clock: StageClock, limit: int) -> list:
    """Console lines (``usdksl check -v``) for up to ``limit`` regions, deepest first, then how many more."""
    if regions is None or regions.count == 0:
        return []
    names = table.mesh_names()
    lines = []
    for row in regions.worst_first()[:limit].tolist():
        a, b = int(regions.mesh_a[row]), int(regions.mesh_b[row])
        pair = names[a] if a == b else f"{names[a]} x {names[b]}"
        count = int(regions.face_pairs[row])
        where = ", ".join(f"{value:.4g}" for value in regions.center[row].tolist())
        lines.append(f"region {row + 1}: {pair} ({'self' if a == b else 'inter'}): "
                     f"{depth_text(regions.depth_measure[row], float(regions.max_depth[row]))} at "
                     f"frame {console_number(clock.frame(float(regions.max_depth_time[row])))}, frames "
                     f"{console_number(clock.frame(float(regions.first_time[row])))}..{console_number(clock.frame(float(regions.last_time[row])))}, "
                     f"{count} face pair{'s' if count != 1 else ''}, around ({where})")
    if regions.count > limit:
        lines.append(f"{regions.count - limit} more regions in the regions.csv report")
    return lines


def summary_line(table: ContactTable, plan, time_range: Optional[tuple], seconds: float,
                 clock: StageClock, known: Optional[np.ndarray] = None, fixed: int = 0, unchecked: str = "",
                 regions: Optional[RegionTable] = None) -> str:
    """The final line printed after every run; with ``known`` (from a baseline) it says how many contacts
    are new and known, and ``fixed`` how many baseline entries no longer occur. ``unchecked``: what the
    coverage account says went unchecked (usdksl.pipeline.coverage.Coverage.summary_phrase); a shot with
    no contacts is then not called clean. With ``regions`` it counts problems (contact regions) first and
    names the deepest."""
    pairs = len(table.summary())
    span = "" if time_range is None else f" over {time_range[0]:g}..{time_range[1]:g}"
    checked = f"checked {plan.checked_pairs} pair{'s' if plan.checked_pairs != 1 else ''}{span} in {seconds:.1f}s"
    checked += unchecked
    rigid_only = plan.skipped_pair_counts().get(PAIR_RIGID_ONLY, 0) if hasattr(plan, "skipped_pair_counts") else 0
    if rigid_only:
        checked += (f"; {rigid_only} rigid-only pair{'s' if rigid_only != 1 else ''} left out "
                    f"(neither mesh deforms; --rigid checks them)")
    fixed_text = f", {fixed} fixed" if known is not None else ""
    if table.count == 0:
        verdict = "no contacts in what was checked" if unchecked else "clean: no contacts"
        return f"usdksl: {verdict}{fixed_text if fixed else ''}; {checked}"
    first = float(table.time[0])
    faces = f"{table.count} contacting face pair{'s' if table.count != 1 else ''}"
    in_pairs = f"in {pairs} mesh pair{'s' if pairs != 1 else ''}"
    last = "" if table.last_time is None else f", last at {clock.describe(float(table.last_time.max()))}"
    if regions is None or regions.count == 0:
        found = f"{faces} {in_pairs}, first at {clock.describe(first)}{last}"
    else:
        deepest = int(regions.worst_first()[0])
        found = (f"{regions.count} problem{'s' if regions.count != 1 else ''} {in_pairs} ({faces}), first at "
                 f"{clock.describe(first)}{last}, worst region {deepest + 1}: "
                 f"{depth_text(regions.depth_measure[deepest], float(regions.max_depth[deepest]))} at frame "
                 f"{console_number(clock.frame(float(regions.max_depth_time[deepest])))}")
    if known is None:
        return f"usdksl: {found}; {checked}"
    new = np.flatnonzero(~np.asarray(known, bool))
    first_new = f", first new at {clock.describe(float(table.time[new[0]]))}" if new.size else ""
    return (f"usdksl: {new.size} new, {table.count - new.size} known{fixed_text}: {found}{first_new}; "
            f"{checked}")
