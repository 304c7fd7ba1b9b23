"""Farm chunks merged: the outputs of ``usdksl check SHOT --time-range A B`` runs joined into exactly what
one run over the union of their ranges writes.

Each chunk folder holds the chunk's contacts.csv and its run manifest (usdksl.reports.manifest). Windows
merge exactly: the first contact of a face pair over [a, c] is the earliest of its first contacts over
[a, b] and [b, c] (docs/contracts.md, Windows and merging), which is what
:func:`usdksl.contacts.table.canonical_first_contacts` keeps. Merging refuses (UsdkslUsageError, exit 2, one
line) chunks that leave a gap, that overlap with different answers, that come from another shot (the
root layer's SHA-256), another usdksl version, other settings or another set of checked mesh pairs,
chunks cut between two time samples of a moving mesh (the chunk re-samples its motion there, so its
times could differ in the last bits), and chunks that split at a topology change (checked per segment).
It also refuses chunks that do not cover the shot's whole checked range (the span of the sample times of
the meshes the chunks load): a farm task that died without leaving a folder is never a half-checked shot.
A part of a shot is merged on purpose with an explicit time range, which the chunks must cover exactly.

The same joining serves the time windows of a long shot checked on Dask (usdksl.scale.windows): both are
*parts* of one shot — a start, an end, the mesh pairs they checked and their contacts — and
:func:`merge_parts` turns parts into the result of one check, with one code path for both.
"""

from __future__ import annotations

import time
from pathlib import Path
from typing import List, Optional, Sequence, Tuple

import numpy as np

from ..regions.baseline import AnyBaseline
from ..contacts.csv_file import CONTACT_COLUMNS, read_contacts_csv
from ..contacts.table import ContactTable, face_pair_ids, latest_per_face_pair, match_face_pairs
from ..errors import UsdkslUsageError
from ..pipeline.check import conclude, load_and_plan
from ..pipeline.files import OutputTargets
from ..pipeline.loading import checked_span, report_blowups
from ..pipeline.messages import Message, message_collector
from ..pipeline.options import CheckOptions, TimeRange
from ..pipeline.result import CheckResult
from ..reading.loader import shot_sample_times
from ..reading.meshes import STATIC
from ..reading.scope import include_predicate
from ..reports.manifest import checked_pairs, file_sha256, manifest_name, read_manifest
from ..reports.override import shot_stem


class Chunk:
    """One chunk folder: its manifest and (read on demand) its contacts over the shot's meshes.

    A part for :func:`merge_parts`: ``start``/``end`` (time codes), ``checked_pairs``
    (usdksl.reports.manifest.checked_pairs), ``where`` (what a refusal names), ``contacts(paths, stem)``."""

    def __init__(self, folder: Path, manifest: dict):
        self.folder = folder
        self.manifest = manifest
        self.start, self.end = (float(value) for value in manifest["time_range"])
        self.checked_pairs = manifest.get("checked_pairs")
        self.where = str(folder)

    def contacts(self, paths: Sequence[str], stem: str) -> ContactTable:
        """The chunk's contacts.csv over the meshes ``paths`` of the merged load (every column usdksl writes
        must be there; a prim that is not among ``paths`` is an error)."""
        return read_contacts_csv(self.folder / f"{stem}.contacts.csv", paths, required=CONTACT_COLUMNS).table

    def __repr__(self) -> str:
        return f"{self.folder} ({self.start:g}..{self.end:g})"


def read_chunks(shot: str, folders: Sequence[str]) -> List[Chunk]:
    """The chunks in ``folders`` for ``shot``, sorted by start; refuses what cannot be merged."""
    if not folders:
        raise UsdkslUsageError("give at least one chunk folder")
    stem = shot_stem(shot)
    chunks = []
    for folder in folders:
        path = Path(folder) / manifest_name(stem)
        try:
            manifest = read_manifest(path)
        except ValueError as error:
            raise UsdkslUsageError(f"cannot merge: {error}", file=str(path)) from None
        if manifest is None:
            raise UsdkslUsageError("cannot merge: no run manifest (check each chunk with --time-range A B "
                                   "--out FOLDER)", file=str(path))
        chunks.append(Chunk(Path(folder), manifest))
    digest = file_sha256(shot)
    first = chunks[0]
    for chunk in chunks:
        if chunk.manifest.get("shot_sha256") != digest:
            raise UsdkslUsageError(f"cannot merge: chunk {chunk} was checked on another shot or another version "
                                   f"of {shot}", file=str(chunk.folder))
        for key, what in (("version", "usdksl version"),):
            if chunk.manifest.get(key) != first.manifest.get(key):
                raise UsdkslUsageError(f"cannot merge: chunks {first} and {chunk} differ in their {what}",
                                       file=str(chunk.folder))
        if _settings_but_range(chunk.manifest) != _settings_but_range(first.manifest):
            raise UsdkslUsageError(f"cannot merge: chunks {first} and {chunk} were checked with other options",
                                   file=str(chunk.folder))
        if chunk.manifest.get("segments") != 1:
            raise UsdkslUsageError(f"cannot merge: chunk {chunk} spans a topology change; check the shot whole",
                                   file=str(chunk.folder))
    chunks.sort(key=lambda chunk: (chunk.start, chunk.end))
    return chunks


def _require_consistent_parts(parts: Sequence) -> None:
    """Refuse parts (sorted by start) that leave a gap or checked different mesh pairs."""
    reach = parts[0].end
    for part in parts[1:]:
        if part.start > reach:
            raise UsdkslUsageError(f"cannot merge: nothing covers {reach:g}..{part.start:g} "
                                   f"(gap before chunk {part})", file=part.where)
        reach = max(reach, part.end)
    for part in parts[1:]:
        if part.checked_pairs != parts[0].checked_pairs:
            raise UsdkslUsageError(f"cannot merge: chunks {parts[0]} and {part} differ in their set of checked "
                                   f"mesh pairs", file=part.where)


def _require_cuts_on_samples(parts: Sequence, span: Tuple[float, float], shot, ends_given: bool) -> None:
    """Refuse parts cut between two time samples of a moving mesh: the part then moves it along a
    different (re-sampled) line, and its contact times differ in the last bits from one run's. The ends
    of ``span`` are cuts too unless they are a given time range (which re-samples there in one run as well)."""
    cuts = {time for part in parts for time in (part.start, part.end)}
    if ends_given:
        cuts -= {span[0], span[1]}
    for mesh in shot.meshes:
        if mesh.kind == STATIC:
            continue
        off_sample = [cut for cut in sorted(cuts) if not np.any(mesh.times == cut)]
        if off_sample:
            raise UsdkslUsageError(f"cannot merge exactly: chunks are cut at time {off_sample[0]:g}, between two "
                                   f"time samples of {mesh.path}; cut chunks at sampled times", file=shot.path)


def shot_checked_range(shot: str, prims: Sequence[str], exclude: Sequence[str]) -> Optional[TimeRange]:
    """The range (time codes) ``usdksl check SHOT`` checks with these ``--prims`` includes and ``--exclude``
    patterns: the span of the sample times of the meshes it loads, or None when none of them moves (then
    every time shows the same shot). Reads time samples only. Raises UsdkslInputError like the loader."""
    predicate = include_predicate(prims, exclude) if (prims or exclude) else None
    times = [mesh_times for mesh_times in shot_sample_times(shot, predicate) if mesh_times.size]
    if not times:
        return None
    return (float(min(mesh_times[0] for mesh_times in times)), float(max(mesh_times[-1] for mesh_times in times)))


def require_covered(shot: str, chunks: Sequence[Chunk], time_range: Optional[TimeRange] = None) -> TimeRange:
    """The range the chunks (sorted by start, without gaps) cover, in time codes. Refuses (UsdkslUsageError
    naming ``shot``) chunks that leave out part of the shot's checked range (:func:`shot_checked_range`), or,
    given ``time_range``, chunks that do not cover exactly that range."""
    covered = (chunks[0].start, max(chunk.end for chunk in chunks))
    if time_range is not None:
        wanted, what, hint = time_range, f"--time-range {_span_text(time_range)}", ""
        beyond = _stretches_outside(wanted, covered)
        if beyond:
            raise UsdkslUsageError(f"the chunks cover {_span_text(covered)}, beyond --time-range "
                                   f"{_span_text(wanted)} ({' and '.join(map(_span_text, beyond))}): merge only "
                                   f"the chunks of that range, or give the range they cover", file=shot)
    else:
        settings = chunks[0].manifest.get("settings", {})
        wanted = shot_checked_range(shot, settings.get("prims", ()), settings.get("exclude", ()))
        if wanted is None:
            return covered
        what = f"the shot's range {_span_text(wanted)}"
        hint = f" (or give --time-range {_time_text(covered[0])} {_time_text(covered[1])} to merge a part)"
    missing = _stretches_outside(covered, wanted)
    if missing:
        raise UsdkslUsageError(f"the chunks cover {_span_text(covered)}, not {' and '.join(map(_span_text, missing))} "
                               f"of {what}: a chunk is missing{hint}", file=shot)
    return covered


def _stretches_outside(inner: TimeRange, outer: TimeRange) -> List[TimeRange]:
    """The stretches of ``outer`` before and after ``inner`` (time codes), the empty ones left out."""
    if outer[0] == outer[1]:   # one time: left out unless inner holds it
        return [] if inner[0] <= outer[0] <= inner[1] else [outer]
    stretches = [(outer[0], min(inner[0], outer[1])), (max(inner[1], outer[0]), outer[1])]
    return [(start, end) for start, end in stretches if start < end]


def _time_text(value: float) -> str:
    """A time code as short as it reads back exactly (a suggested --time-range must mean the chunks' range)."""
    short = f"{value:g}"
    return short if float(short) == value else repr(value)


def _span_text(span: TimeRange) -> str:
    return f"{_time_text(span[0])}..{_time_text(span[1])}"


def _settings_but_range(manifest: dict) -> dict:
    return {key: value for key, value in manifest.get("settings", {}).items() if key != "time_range"}


def check_overlap(earlier, later, first: ContactTable, second: ContactTable) -> None:
    """Refuse two overlapping parts (chunks or windows) whose answers on their common interval differ.

    ``earlier`` starts first. Inside the overlap (later.start, min(ends)) both saw the same motion: a first
    contact that ``earlier`` reports after later.start must be ``later``'s first contact at the same time,
    and every first contact ``later`` reports before the overlap ends must have one in ``earlier`` at that
    time or before. Both ends of the overlap are left out: there a contact found by the continuous check
    of one chunk meets the static test of the other's range start."""
    overlap_end = min(earlier.end, later.end)
    if later.start >= overlap_end:
        return
    ids_first, ids_second = face_pair_ids(first, second)
    rows = first.count + second.count
    # each table has one row per face pair, so these scatters are one-to-one
    time_in_first = np.full(rows, np.inf)
    time_in_first[ids_first] = first.time
    time_in_second = np.full(rows, np.inf)
    time_in_second[ids_second] = second.time
    inside = (first.time > later.start) & (first.time < overlap_end)
    differs = inside & (time_in_second[ids_first] != first.time)
    if differs.any():
        raise UsdkslUsageError(f"cannot merge: chunks {earlier} and {later} overlap but disagree on a face pair "
                               f"first touching at time {float(first.time[differs][0])!r}", file=later.where)
    missing = (second.time < overlap_end) & ~(time_in_first[ids_second] <= second.time)
    if missing.any():
        raise UsdkslUsageError(f"cannot merge: chunks {earlier} and {later} overlap but disagree on a face pair "
                               f"touching at time {float(second.time[missing][0])!r}", file=later.where)


def merged_last_times(table: ContactTable, tables: Sequence[ContactTable], paths: Sequence[str]) -> np.ndarray:
    """float64[C]: each face pair's last contact over the union of the chunks, the latest of its chunks'
    last contacts (the mirror image of the earliest first contact: docs/contracts.md, Last contacts).
    Raises UsdkslUsageError when a chunk has no last-contact columns."""
    if any(chunk_table.last_time is None for chunk_table in tables):
        raise UsdkslUsageError("cannot merge: a chunk was checked without --last-contact")
    latest = latest_per_face_pair(paths, *(np.concatenate([getattr(t, name) for t in tables])
                                           for name in ("last_time", "mesh_a", "face_a", "mesh_b", "face_b")))
    return latest.time[match_face_pairs(table, latest)[0]]


def merge_chunks(shot: str, folders: Sequence[str], targets: OutputTargets,
                 baseline: Optional[AnyBaseline] = None, time_range: Optional[TimeRange] = None) -> CheckResult:
    """What ``usdksl check SHOT --time-range START END`` writes, START..END the union of the chunks'
    ranges, from the chunks' outputs (with ``baseline``: what that check with ``--baseline`` writes).
    The chunks must cover the shot's whole checked range, or with ``time_range`` (time codes, a part of
    the shot merged on purpose) exactly that range (:func:`require_covered`).
    Raises UsdkslUsageError (one line) when they cannot be merged."""
    started = time.monotonic()
    chunks = read_chunks(shot, folders)
    settings = chunks[0].manifest["settings"]
    _require_consistent_parts(chunks)   # a gap between chunks is named as one before the ends are checked
    span = require_covered(shot, chunks, time_range)
    options = CheckOptions(method=settings["method"], tolerance=settings["tolerance"],
                           thickness=settings["thickness"], self_check=settings["self"], inter_check=settings["inter"],
                           time_range=span, prims=tuple(settings["prims"]), exclude=tuple(settings["exclude"]),
                           include_guides=settings["include_guides"], include_invisible=settings["include_invisible"],
                           rigid=settings.get("rigid", False), last_contact=settings.get("last_contact", False))
    return merge_parts(shot, shot, options, targets, chunks, baseline, started=started)


def merge_parts(shot: str, name: str, options: CheckOptions, targets: OutputTargets, parts: Sequence,
                baseline: Optional[AnyBaseline] = None, core_messages: Sequence[Message] = (),
                counters: Optional[dict] = None, started: Optional[float] = None) -> CheckResult:
    """What :func:`usdksl.pipeline.check.check_shot` (``shot`` read, ``name`` reported) returns for
    ``options``, from ``parts`` that cover its checked range: chunk folders (:class:`Chunk`) or Dask
    windows (usdksl.scale.windows). Each part has ``start``, ``end``, ``checked_pairs``, ``where`` and
    ``contacts(paths, stem)``. The shot is loaded once more over the whole range to plan and render it,
    and says what check_shot says (plan lines, the loader's warnings, blow-ups), with ``core_messages``
    (what the parts' core runs said) where check_shot says them and ``counters`` their work.
    Raises UsdkslUsageError (one line) when the parts cannot be merged exactly."""
    started = time.monotonic() if started is None else started
    parts = sorted(parts, key=lambda part: (part.start, part.end))
    _require_consistent_parts(parts)
    messages: List[Message] = []
    say = message_collector(messages)
    planned = load_and_plan(shot, options, name, say)
    if len(planned.segments) != 1:
        raise UsdkslUsageError(f"cannot merge: the shot changes topology inside the checked range; "
                               f"check it whole", file=name)
    loaded = planned.segments[0][1]
    report_blowups(planned.segments, planned.plans, name, say, options.strict, options.threads)
    span = checked_span(options, planned.segments)
    if (parts[0].start, max(part.end for part in parts)) != tuple(span):
        raise UsdkslUsageError(f"cannot merge: the parts cover {parts[0].start:g}..{max(p.end for p in parts):g}, "
                               f"not the checked range {span[0]:g}..{span[1]:g}", file=name)
    _require_cuts_on_samples(parts, span, loaded, ends_given=options.time_range is not None)
    if checked_pairs(planned.plan) != parts[0].checked_pairs:
        raise UsdkslUsageError("cannot merge: the union of the chunks' ranges checks other mesh pairs than the "
                               "chunks did (visibility changes between them); check the shot whole", file=name)
    paths = [mesh.path for mesh in loaded.meshes]
    stem = shot_stem(shot)
    tables = [part.contacts(paths, stem) for part in parts]
    for i, earlier in enumerate(parts):
        for j in range(i + 1, len(parts)):
            check_overlap(earlier, parts[j], tables[i], tables[j])
    table = ContactTable.from_rows(paths, *(np.concatenate([getattr(t, column) for t in tables])
                                            for column in ("time", "mesh_a", "face_a", "mesh_b", "face_b", "feature")))
    if options.last_contact:
        table = table.with_last_times(merged_last_times(table, tables, paths))
    for message in core_messages:
        say(message.level, message.text)
    return conclude(shot, name, options, targets, planned, [table], span, dict(counters or {}), messages, say,
                    baseline, started)


__all__ = ["Chunk", "check_overlap", "merge_chunks", "merge_parts", "read_chunks", "require_covered",
           "shot_checked_range"]
