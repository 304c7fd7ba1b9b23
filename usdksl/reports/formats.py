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

from ..clock import StageClock
from ..contacts.csv_file import KNOWN, NEW, STATUS_COLUMN
from ..contacts.table import ContactTable
from ..reading.scope import PAIR_RIGID_ONLY

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
                coverage: Optional[dict] = None, findings: Optional[list] = None) -> str:
    """The --json document: shot, settings, clock, plan, coverage (usdksl.pipeline.coverage.Coverage.to_dict),
    findings (warnings with their stable kind), summary rows, contacts, exit code; with a baseline its comparison
    (BaselineComparison.to_dict) and each contact's status."""
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
        "contacts": contact_records(table, clock, known),
        "contact_count": table.count,
        "exit_code": int(exit_code),
    }
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


def summary_line(table: ContactTable, plan, time_range: Optional[tuple], seconds: float,
                 clock: StageClock, known: Optional[np.ndarray] = None, fixed: int = 0, unchecked: str = "") -> str:
    """The final line printed after every run; with ``known`` (from a baseline) it says how many contacts
    are new and known, and ``fixed`` how many baseline entries no longer occur. ``unchecked``: what the
    coverage account says went unchecked (usdksl.pipeline.coverage.Coverage.summary_phrase); a shot with
    no contacts is then not called clean."""
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
    found = (f"{table.count} contacting face pair{'s' if table.count != 1 else ''} in {pairs} mesh "
             f"pair{'s' if pairs != 1 else ''}, first at {clock.describe(first)}")
    if table.last_time is not None:
        found += f", last at {clock.describe(float(table.last_time.max()))}"
    if known is None:
        return f"usdksl: {found}; {checked}"
    new = np.flatnonzero(~np.asarray(known, bool))
    first_new = f", first new at {clock.describe(float(table.time[new[0]]))}" if new.size else ""
    return (f"usdksl: {new.size} new, {table.count - new.size} known{fixed_text}: {found}{first_new}; "
            f"{checked}")
