"""Farm chunks merged: the outputs of ``usdksl check SHOT --time-range A B`` runs joined into exactly what
one run over the union of their ranges writes.

Each chunk folder holds the chunk's contacts.csv and its run manifest (usdksl.reports.manifest). Windows
merge exactly: the first contact of a face pair over [a, c] is the earliest of its first contacts over
[a, b] and [b, c] (docs/contracts.md, Windows and merging), which is what
:func:`usdksl.contacts.canonical_first_contacts` keeps. Merging refuses (UsdkslUsageError, exit 2, one
line) chunks that leave a gap, that overlap with different answers, that come from another shot (the
root layer's SHA-256), another usdksl version, other settings or another set of checked mesh pairs,
chunks cut between two time samples of a moving mesh (the chunk re-samples its motion there, so its
times could differ in the last bits), and chunks that split at a topology change (checked per segment).
"""

from __future__ import annotations

import time
from pathlib import Path
from typing import List, Optional, Sequence, Tuple

import numpy as np

from ..baseline import Baseline, compare
from ..checking.pipeline import CheckOptions, CheckResult, OutputTargets, load_segments, render_files
from ..clock import StageClock
from ..contacts import ContactTable, latest_per_face_pair, match_face_pairs
from ..errors import UsdkslUsageError
from ..exit_codes import CLEAN, CONTACTS_FOUND
from ..reading.meshes import STATIC
from ..reading.scope import ScopeOptions, include_predicate, plan_shot
from ..reports.formats import read_contacts_table
from ..reports.manifest import checked_pairs, file_sha256, manifest_name, read_manifest
from ..reports.override import shot_stem


class Chunk:
    """One chunk folder: its manifest and (read on demand) its contacts over the shot's meshes."""

    def __init__(self, folder: Path, manifest: dict):
        self.folder = folder
        self.manifest = manifest
        self.start, self.end = (float(value) for value in manifest["time_range"])

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
        for key, what in (("version", "usdksl version"), ("checked_pairs", "set of checked mesh pairs")):
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
    reach = chunks[0].end
    for previous, chunk in zip(chunks[:-1], chunks[1:]):
        if chunk.start > reach:
            raise UsdkslUsageError(f"cannot merge: nothing covers {reach:g}..{chunk.start:g} "
                                   f"(gap before chunk {chunk})", file=str(chunk.folder))
        reach = max(reach, chunk.end)
    return chunks


def _require_cuts_on_samples(chunks: Sequence[Chunk], span: Tuple[float, float], shot) -> None:
    """Refuse chunks cut between two time samples of a moving mesh: the chunk then moves it along a
    different (re-sampled) line, and its contact times differ in the last bits from one run's."""
    cuts = sorted({time for chunk in chunks for time in (chunk.start, chunk.end)} - {span[0], span[1]})
    for mesh in shot.meshes:
        if mesh.kind == STATIC:
            continue
        off_sample = [cut for cut in cuts if not np.any(mesh.times == cut)]
        if off_sample:
            raise UsdkslUsageError(f"cannot merge exactly: chunks are cut at time {off_sample[0]:g}, between two "
                                   f"time samples of {mesh.path}; cut chunks at sampled times", file=shot.path)


def _settings_but_range(manifest: dict) -> dict:
    return {key: value for key, value in manifest.get("settings", {}).items() if key != "time_range"}


def check_overlap(earlier: Chunk, later: Chunk, first: ContactTable, second: ContactTable) -> None:
    """Refuse two overlapping chunks whose answers on their common interval differ.

    ``earlier`` starts first. Inside the overlap (later.start, min(ends)) both saw the same motion: a first
    contact that ``earlier`` reports after later.start must be ``later``'s first contact at the same time,
    and every first contact ``later`` reports before the overlap ends must have one in ``earlier`` at that
    time or before. Both ends of the overlap are left out: there a contact found by the continuous check
    of one chunk meets the static test of the other's range start."""
    overlap_end = min(earlier.end, later.end)
    if later.start >= overlap_end:
        return
    keys = np.concatenate([_pair_rows(first), _pair_rows(second)])
    ids = np.unique(keys, axis=0, return_inverse=True)[1].reshape(-1) if len(keys) else np.zeros(0, np.int64)
    ids_first, ids_second = ids[:first.count], ids[first.count:]
    # each table has one row per face pair, so these scatters are one-to-one
    time_in_first = np.full(len(keys), np.inf)
    time_in_first[ids_first] = first.time
    time_in_second = np.full(len(keys), np.inf)
    time_in_second[ids_second] = second.time
    inside = (first.time > later.start) & (first.time < overlap_end)
    differs = inside & (time_in_second[ids_first] != first.time)
    if differs.any():
        raise UsdkslUsageError(f"cannot merge: chunks {earlier} and {later} overlap but disagree on a face pair "
                               f"first touching at time {float(first.time[differs][0])!r}", file=str(later.folder))
    missing = (second.time < overlap_end) & ~(time_in_first[ids_second] <= second.time)
    if missing.any():
        raise UsdkslUsageError(f"cannot merge: chunks {earlier} and {later} overlap but disagree on a face pair "
                               f"touching at time {float(second.time[missing][0])!r}", file=str(later.folder))


def merged_last_times(table: ContactTable, tables: Sequence[ContactTable], paths: Sequence[str]) -> np.ndarray:
    """float64[C]: each face pair's last contact over the union of the chunks, the latest of its chunks'
    last contacts (the mirror image of the earliest first contact: docs/contracts.md, Last contacts).
    Raises UsdkslUsageError when a chunk has no last-contact columns."""
    if any(chunk_table.last_time is None for chunk_table in tables):
        raise UsdkslUsageError("cannot merge: a chunk was checked without --last-contact")
    latest = latest_per_face_pair(paths, *(np.concatenate([getattr(t, name) for t in tables])
                                           for name in ("last_time", "mesh_a", "face_a", "mesh_b", "face_b")))
    return latest.time[match_face_pairs(table, latest)[0]]


def _pair_rows(table: ContactTable) -> np.ndarray:
    """int64[C, 4]: (mesh_a, face_a, mesh_b, face_b) per row."""
    return np.stack([table.mesh_a, table.face_a, table.mesh_b, table.face_b], axis=1).astype(np.int64)


def merge_chunks(shot: str, folders: Sequence[str], targets: OutputTargets,
                 baseline: Optional[Baseline] = None) -> CheckResult:
    """What ``usdksl check SHOT --time-range START END`` writes, START..END the union of the chunks'
    ranges, from the chunks' outputs (with ``baseline``: what that check with ``--baseline`` writes).
    Raises UsdkslUsageError (one line) when they cannot be merged."""
    started = time.monotonic()
    chunks = read_chunks(shot, folders)
    settings = chunks[0].manifest["settings"]
    span: Tuple[float, float] = (chunks[0].start, max(chunk.end for chunk in chunks))
    options = CheckOptions(method=settings["method"], tolerance=settings["tolerance"],
                           thickness=settings["thickness"], self_check=settings["self"], inter_check=settings["inter"],
                           time_range=span, prims=tuple(settings["prims"]), exclude=tuple(settings["exclude"]),
                           include_guides=settings["include_guides"], include_invisible=settings["include_invisible"],
                           last_contact=settings.get("last_contact", False))
    include, excluded = options.patterns()
    predicate = include_predicate(include, excluded) if (include or excluded) else None
    messages: List[str] = []
    segments = load_segments(shot, span, predicate, lambda level, text: messages.append(text))
    if len(segments) != 1:
        raise UsdkslUsageError(f"cannot merge: the shot changes topology inside {span[0]:g}..{span[1]:g}; "
                               f"check it whole", file=shot)
    loaded = segments[0][1]
    _require_cuts_on_samples(chunks, span, loaded)
    plan = plan_shot(loaded, ScopeOptions(self_check=options.self_check, inter_check=options.inter_check,
                                          include_guides=options.include_guides,
                                          include_invisible=options.include_invisible), span)
    if predicate is not None:
        plan.excluded_paths = list(dict.fromkeys(predicate.rejected))
    if checked_pairs(plan) != chunks[0].manifest["checked_pairs"]:
        raise UsdkslUsageError("cannot merge: the union of the chunks' ranges checks other mesh pairs than the "
                               "chunks did (visibility changes between them); check the shot whole", file=shot)
    paths = [mesh.path for mesh in loaded.meshes]
    stem = shot_stem(shot)
    tables = [read_contacts_table(chunk.folder / f"{stem}.contacts.csv", paths) for chunk in chunks]
    for i, earlier in enumerate(chunks):
        for j in range(i + 1, len(chunks)):
            check_overlap(earlier, chunks[j], tables[i], tables[j])
    table = ContactTable.from_rows(paths, *(np.concatenate([getattr(t, name) for t in tables])
                                            for name in ("time", "mesh_a", "face_a", "mesh_b", "face_b", "feature")))
    if options.last_contact:
        table = table.with_last_times(merged_last_times(table, tables, paths))
    comparison = None if baseline is None else compare(table, baseline)
    exit_code = CONTACTS_FOUND if (comparison.new_count if comparison else table.count) else CLEAN
    files, stdout = render_files(shot, shot, options, targets, segments, plan, [table], exit_code, span,
                                 comparison=comparison)
    return CheckResult(shot=shot, options=options, exit_code=exit_code, table=table, plan=plan, span=span,
                       seconds=time.monotonic() - started, counters={}, messages=[], files=files, stdout=stdout,
                       segments=[(span, table)], clock=StageClock.from_metadata(loaded.metadata),
                       baseline=comparison)


__all__ = ["Chunk", "check_overlap", "merge_chunks", "read_chunks"]
