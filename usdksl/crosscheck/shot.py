"""Cross-check of a continuous result against static frames intersected with Embree.

Users must be able to trust a result without trusting our CCD. At each checked time sample the frame's
meshes are frozen and intersected with Embree (:mod:`usdksl.crosscheck.embree_frames`); every face pair
found properly intersecting at frame ``f`` must have its first contact at or before ``f`` in the continuous
result. A face pair that intersects with no contact, or only a later one, is a disagreement.

The frame test is one-sided by design: it reports only crossings that double precision confirms with a
clear margin (see :mod:`usdksl.crosscheck.segment_crossing`), so it never raises a false alarm; touching
and grazing contacts are left to the continuous check.

Face pairs follow the contacts.csv conventions: the canonical orientation of usdksl.contacts.orientation
(inter rows have ``prim_a < prim_b``, self rows ``face_a < face_b``); rows sort by time, prim_a, face_a,
prim_b, face_b; times print with ``repr(float)``. The contacts held against the frames are a
:class:`usdksl.contacts.table.ContactTable`, from the continuous check or read from a contacts.csv
(usdksl.contacts.csv_file).
"""

from __future__ import annotations

import csv
import io
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Dict, List, Optional, Sequence, Tuple, Union

import numpy as np

from ..contacts.csv_file import read_contacts_csv
from ..reading.positions import points_at
from ..contacts.orientation import canonical_swap, swap_sides
from ..contacts.table import ContactTable, path_rank
from ..errors import UsdkslUsageError
from ..exit_codes import CLEAN, CONTACTS_FOUND, CROSSCHECK_DISAGREES
from ..reading.meshes import DEFORMING, STATIC
from ..reports.output import write_text_atomic
from ..reports.override import shot_stem
from .embree_frames import FrameTopology, intersecting_triangle_pairs

CROSSCHECK_HEADER = ("time", "prim_a", "face_a", "prim_b", "face_b")
#: What the result names as the source of contacts that the continuous check found in this run.
CONTINUOUS_SOURCE = "continuous check"


# --------------------------------------------------------------------------- frames

def parse_frames(spec: Union[None, str, Sequence[float]], shot_times: np.ndarray) -> np.ndarray:
    """The time codes to check, sorted and unique.

    ``None`` means every sample of the shot. A string is a comma-separated list whose items are a time code
    (``12``), a range of the shot's own samples ``A:B`` (every sample with A <= t <= B), or a stepped range
    ``A:B:S`` (A, A+S, ... up to B). Every time must lie inside the shot's sampled range. Raises
    UsdkslUsageError on a malformed or out-of-range item.
    """
    shot_times = np.asarray(shot_times, dtype=np.float64)
    if spec is None:
        return np.unique(shot_times)
    if isinstance(spec, str):
        chosen: List[np.ndarray] = []
        for item in (part.strip() for part in spec.split(",")):
            if not item:
                continue
            fields = item.split(":")
            try:
                numbers = [float(x) for x in fields]
            except ValueError:
                raise UsdkslUsageError(f"--frames: '{item}' is not a time code or A:B[:STEP] range") from None
            if not all(np.isfinite(numbers)):
                raise UsdkslUsageError(f"--frames: '{item}' is not finite")
            if len(numbers) == 1:
                chosen.append(np.array(numbers))
            elif len(numbers) == 2:
                start, end = numbers
                if start > end:
                    raise UsdkslUsageError(f"--frames: range '{item}' starts after it ends")
                inside = shot_times[(shot_times >= start) & (shot_times <= end)]
                if len(inside) == 0:
                    raise UsdkslUsageError(f"--frames: range '{item}' holds no time sample of the shot")
                chosen.append(inside)
            elif len(numbers) == 3:
                start, end, step = numbers
                if step <= 0 or start > end:
                    raise UsdkslUsageError(f"--frames: range '{item}' needs START <= END and STEP > 0")
                count = int(np.floor((end - start) / step + 1e-9)) + 1
                chosen.append(start + step * np.arange(count, dtype=np.float64))
            else:
                raise UsdkslUsageError(f"--frames: '{item}' has too many ':'")
        times = np.concatenate(chosen) if chosen else np.zeros(0)
    else:
        times = np.asarray(spec, dtype=np.float64).reshape(-1)
    if len(times) == 0:
        raise UsdkslUsageError("--frames: no time code given")
    if len(shot_times):
        low, high = float(shot_times[0]), float(shot_times[-1])
        outside = times[(times < low) | (times > high)]
        if len(outside):
            raise UsdkslUsageError(f"--frames: time {float(outside[0])!r} is outside the shot's samples "
                                   f"{low!r}..{high!r}")
    return np.unique(times)


# --------------------------------------------------------------------------- mesh pairs

def default_mesh_pairs(meshes) -> List[Tuple[int, int]]:
    """Mesh pairs the continuous check tests when the scene says nothing more: every pair except two meshes
    that never move (static), and self pairs of deforming meshes only."""
    pairs = []
    for i, first in enumerate(meshes):
        if first.kind == DEFORMING:
            pairs.append((i, i))
        for j in range(i + 1, len(meshes)):
            if first.kind == STATIC and meshes[j].kind == STATIC:
                continue
            pairs.append((i, j))
    return pairs


def scoped_mesh_pairs(shot, time_range=None):
    """The pairs ``usdksl check`` tests by default: the scene's scoping (:func:`usdksl.reading.scope.plan_shot`:
    physics flags, filtered pairs, groups, purpose, visibility) when the shot has a stage, otherwise
    :func:`default_mesh_pairs`."""
    if getattr(shot, "stage", None) is None:
        return default_mesh_pairs(shot.meshes)
    from ..reading.scope import plan_shot
    return [tuple(pair) for pair in np.asarray(plan_shot(shot, time_range=time_range).pairs).tolist()]


def _pair_matrix(pairs, mesh_count: int) -> np.ndarray:
    matrix = np.zeros((mesh_count, mesh_count), dtype=bool)
    pairs = np.asarray(pairs, dtype=np.int64).reshape(-1, 2)
    if len(pairs):
        if pairs.min() < 0 or pairs.max() >= mesh_count:
            raise ValueError("mesh pair index out of range")
        matrix[pairs[:, 0], pairs[:, 1]] = True
        matrix[pairs[:, 1], pairs[:, 0]] = True
    return matrix


# --------------------------------------------------------------------------- face numbering

class _FaceNumbering:
    """Global face ids ordered by (prim path, face): a face pair in canonical orientation is then (lower id,
    higher id), and its key orders as canonical rows do."""

    def __init__(self, meshes):
        self.paths = [mesh.path for mesh in meshes]
        self.mesh_rank = path_rank(self.paths)
        self.rank_to_mesh = np.argsort(self.mesh_rank).astype(np.int64)
        order = self.rank_to_mesh.tolist()
        face_counts = np.array([meshes[index].face_count for index in order], dtype=np.int64)
        self.rank_offset = np.zeros(len(meshes) + 1, dtype=np.int64)
        self.rank_offset[1:] = np.cumsum(face_counts)
        self.mesh_offset = np.zeros(len(meshes), dtype=np.int64)
        self.mesh_offset[self.rank_to_mesh] = self.rank_offset[:-1]
        self.face_total = int(self.rank_offset[-1])

    def global_ids(self, mesh: np.ndarray, face: np.ndarray) -> np.ndarray:
        return self.mesh_offset[np.asarray(mesh, dtype=np.int64)] + np.asarray(face, dtype=np.int64)

    def pair_keys(self, mesh_a, face_a, mesh_b, face_b) -> np.ndarray:
        """int64[C]: one key per face pair, whichever side comes first in the rows (the pair is put in
        canonical orientation first)."""
        mesh_a, mesh_b = np.asarray(mesh_a, dtype=np.int64), np.asarray(mesh_b, dtype=np.int64)
        swap = canonical_swap(self.mesh_rank[mesh_a], face_a, self.mesh_rank[mesh_b], face_b)
        first, second = swap_sides(swap, self.global_ids(mesh_a, face_a), self.global_ids(mesh_b, face_b))
        return first * max(self.face_total, 1) + second

    def split(self, global_id: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
        rank = np.searchsorted(self.rank_offset, global_id, side="right") - 1
        return self.rank_to_mesh[rank].astype(np.int32), (global_id - self.rank_offset[rank]).astype(np.int32)

    def unpack(self, keys: np.ndarray):
        total = max(self.face_total, 1)
        mesh_a, face_a = self.split(keys // total)
        mesh_b, face_b = self.split(keys % total)
        return mesh_a, face_a, mesh_b, face_b


# --------------------------------------------------------------------------- result

@dataclass
class CrosscheckResult:
    """Every face pair found intersecting at every checked frame, and how it agrees with the contacts.

    Rows (``time, mesh_a, face_a, mesh_b, face_b``; mesh indices into ``prim_paths``) are in contacts.csv
    order. ``violation`` marks rows whose pair has no contact at or before the row's time; ``contact_time``
    is the pair's first contact (NaN when it has none).
    """

    prim_paths: List[str]
    frames: np.ndarray
    time: np.ndarray
    mesh_a: np.ndarray
    face_a: np.ndarray
    mesh_b: np.ndarray
    face_b: np.ndarray
    contact_time: np.ndarray
    violation: np.ndarray
    contacts_checked: int
    contacts_source: str
    counters: Dict[str, int] = field(default_factory=dict)

    @property
    def consistent(self) -> bool:
        return not bool(self.violation.any())

    @property
    def face_pairs(self) -> int:
        """Distinct face pairs found intersecting in at least one checked frame."""
        if len(self.time) == 0:
            return 0
        return len(np.unique(np.stack([self.mesh_a, self.face_a, self.mesh_b, self.face_b], axis=1), axis=0))

    def exit_code(self) -> int:
        """3 on disagreement, else 1 when the contacts hold any contact, else 0."""
        if not self.consistent:
            return CROSSCHECK_DISAGREES
        return CONTACTS_FOUND if self.contacts_checked else CLEAN

    def csv_text(self) -> str:
        buffer = io.StringIO()
        writer = csv.writer(buffer, lineterminator="\n")
        writer.writerow(CROSSCHECK_HEADER)
        paths = self.prim_paths
        writer.writerows((repr(float(t)), paths[a], int(fa), paths[b], int(fb)) for t, a, fa, b, fb in
                         zip(self.time, self.mesh_a, self.face_a, self.mesh_b, self.face_b))
        return buffer.getvalue()

    def error_lines(self) -> List[str]:
        """One line per disagreeing face pair, at the first frame where it intersects without a contact."""
        rows = np.flatnonzero(self.violation)
        if len(rows) == 0:
            return []
        keys = np.stack([self.mesh_a[rows], self.face_a[rows], self.mesh_b[rows], self.face_b[rows]], axis=1)
        _, first, counts = np.unique(keys, axis=0, return_index=True, return_counts=True)
        lines = []
        for row_position, count in sorted(zip(first, counts), key=lambda item: rows[item[0]]):
            row = rows[row_position]
            pair = (f"{self.prim_paths[self.mesh_a[row]]} face {self.face_a[row]} and "
                    f"{self.prim_paths[self.mesh_b[row]]} face {self.face_b[row]}")
            if np.isnan(self.contact_time[row]):
                why = f"has no contact in {self.contacts_source}"
            else:
                why = f"has its first contact later, at time {float(self.contact_time[row])!r}"
            later = f" (and {count - 1} later frame(s))" if count > 1 else ""
            lines.append(f"crosscheck: {pair} intersect at time {float(self.time[row])!r}{later} but {why}")
        return lines

    def summary_line(self) -> str:
        verdict = "consistent" if self.consistent else \
            f"DISAGREES on {len(self.error_lines())} face pair(s)"
        unconfirmed = self.counters.get("unconfirmed_candidates", 0)
        return (f"crosscheck: {len(self.frames)} frame(s), {len(self.time)} intersecting face pair-frame(s) "
                f"({self.face_pairs} distinct face pair(s)) checked against {self.contacts_checked} contact(s): "
                f"{verdict}; {unconfirmed} Embree candidate(s) not confirmed in double precision")


# --------------------------------------------------------------------------- running

def intersecting_face_pairs(meshes, frames: np.ndarray, pairs=None, counters: Optional[Dict[str, int]] = None):
    """Face pairs properly intersecting at each of ``frames``: arrays (time, pair_key) in row order, and
    the face numbering that decodes the keys."""
    numbering = _FaceNumbering(meshes)
    allowed = _pair_matrix(default_mesh_pairs(meshes) if pairs is None else pairs, len(meshes))
    topology = FrameTopology.from_meshes([mesh.triangles for mesh in meshes],
                                         [mesh.triangle_face for mesh in meshes],
                                         [mesh.vertex_count for mesh in meshes])
    counters = {} if counters is None else counters
    frame_times: List[np.ndarray] = []
    frame_keys: List[np.ndarray] = []
    for time in frames:
        vertices = np.concatenate([points_at(mesh, float(time)) for mesh in meshes]) if meshes else \
            np.zeros((0, 3))
        found = intersecting_triangle_pairs(topology, vertices, allowed)
        for name, value in found.counters.items():
            counters[name] = counters.get(name, 0) + value
        mesh_a, mesh_b = topology.triangle_mesh[found.triangle_a], topology.triangle_mesh[found.triangle_b]
        face_a, face_b = topology.triangle_face[found.triangle_a], topology.triangle_face[found.triangle_b]
        different_faces = (mesh_a != mesh_b) | (face_a != face_b)
        keys = np.unique(numbering.pair_keys(mesh_a[different_faces], face_a[different_faces],
                                             mesh_b[different_faces], face_b[different_faces]))
        frame_times.append(np.full(len(keys), float(time)))
        frame_keys.append(keys)
    counters["frames"] = len(frames)
    counters["face_frames"] = int(sum(mesh.face_count for mesh in meshes)) * len(frames)
    if frame_keys:
        return np.concatenate(frame_times), np.concatenate(frame_keys).astype(np.int64), numbering
    return np.zeros(0), np.zeros(0, dtype=np.int64), numbering


def compare_with_contacts(meshes, frames: np.ndarray, row_time: np.ndarray, row_keys: np.ndarray,
                          numbering: "_FaceNumbering", contacts: ContactTable, counters: Dict[str, int],
                          contacts_source: str = CONTINUOUS_SOURCE) -> CrosscheckResult:
    """Attach to every intersecting row its pair's first contact and flag rows with none at or before.
    ``contacts_source``: what the result names as the contacts' origin (a file, or the continuous check)."""
    contact_keys = numbering.pair_keys(contacts.mesh_a, contacts.face_a, contacts.mesh_b, contacts.face_b)
    order = np.lexsort((contacts.time, contact_keys))
    contact_keys, contact_times = contact_keys[order], contacts.time[order]
    unique_keys, first = np.unique(contact_keys, return_index=True)
    first_times = contact_times[first]
    position = np.searchsorted(unique_keys, row_keys)
    found = position < len(unique_keys)
    found[found] = unique_keys[position[found]] == row_keys[found]
    contact_time = np.full(len(row_keys), np.nan)
    contact_time[found] = first_times[position[found]]
    violation = ~found | (contact_time > row_time)
    mesh_a, face_a, mesh_b, face_b = numbering.unpack(row_keys)
    return CrosscheckResult([mesh.path for mesh in meshes], np.asarray(frames, dtype=np.float64), row_time,
                            mesh_a, face_a, mesh_b, face_b, contact_time, violation, len(contacts),
                            contacts_source, counters)


def crosscheck_shot(shot, frames=None, contacts=None, pairs=None, time_range=None,
                    **find_contacts_options) -> CrosscheckResult:
    """Cross-check ``shot`` (a loaded :class:`usdksl.Shot`) at static frames with Embree.

    ``frames``: None (every sample of ``shot.times`` inside ``time_range``), a ``--frames`` string, or a
    sequence of time codes. ``contacts``: None runs the continuous check
    (``usdksl.find_contacts(shot.meshes, pairs, time_range=..., **find_contacts_options)``);
    otherwise a :class:`~usdksl.contacts.table.ContactTable` or another object with arrays ``time, mesh_a,
    face_a, mesh_b, face_b`` (mesh indices into ``shot.meshes``), or a path to a contacts.csv, whose rows
    naming prims that are not meshes of the shot are left out (counted as ``contacts_ignored_rows``) and
    whose faces must lie inside their meshes (UsdkslInputError naming file and row). ``pairs``: mesh index
    pairs ((i, i) = self) the continuous check tests; None uses :func:`scoped_mesh_pairs` (what
    ``usdksl check`` tests with its default options).
    """
    meshes = shot.meshes
    shot_times = np.asarray(shot.times, dtype=np.float64)
    if time_range is not None:
        shot_times = shot_times[(shot_times >= time_range[0]) & (shot_times <= time_range[1])]
    frame_times = parse_frames(frames, shot_times)
    if pairs is None:
        pairs = scoped_mesh_pairs(shot, time_range)
    source, ignored_rows = CONTINUOUS_SOURCE, 0
    if contacts is None:
        try:
            from ..checking.collision import find_contacts
        except ImportError:
            raise UsdkslUsageError("the continuous check is not available in this build; "
                                   "give a contacts.csv with --contacts") from None
        result = find_contacts(meshes, pairs, time_range=time_range, **find_contacts_options)
        contacts = result.face_contacts(meshes)
    elif isinstance(contacts, (str, os.PathLike)):
        read = read_contacts_csv(contacts, [mesh.path for mesh in meshes], [mesh.face_count for mesh in meshes],
                                 skip_unknown_prims=True)
        contacts, source, ignored_rows = read.table, read.source, read.ignored_rows
    elif not isinstance(contacts, ContactTable):
        contacts = ContactTable.from_face_contacts(contacts, [mesh.path for mesh in meshes])
    counters: Dict[str, int] = {}
    row_time, row_keys, numbering = intersecting_face_pairs(meshes, frame_times, pairs, counters)
    counters["contacts_ignored_rows"] = ignored_rows
    return compare_with_contacts(meshes, frame_times, row_time, row_keys, numbering, contacts, counters, source)


# --------------------------------------------------------------------------- output

def crosscheck_csv_path(shot_path: Union[str, os.PathLike], out_dir: Union[None, str, os.PathLike] = None) -> Path:
    """``<out_dir>/<stem>.crosscheck.csv``; ``out_dir`` defaults to the shot's folder."""
    folder = Path(out_dir) if out_dir is not None else Path(shot_path).parent
    return folder / f"{shot_stem(shot_path)}.crosscheck.csv"


def write_crosscheck_csv(result: CrosscheckResult, target: Union[str, os.PathLike]) -> Path:
    return write_text_atomic(target, result.csv_text())
