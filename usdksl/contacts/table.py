"""The contact model: one reported contact row per face pair, put in canonical order by one function.

A :class:`ContactTable` holds the first contact of every contacting face pair of a check, column by
column (numpy arrays, no Python object per row): time (USD time codes), the two meshes (indices into
``paths``), the two authored faces and the feature that touched first. Every producer builds it through
:func:`canonical_first_contacts` and every writer (CSV, JSON, JUnit, override layer, merge) reads it,
so there is one order and one choice of row per pair (docs/contracts.md, Contacts):

* self rows have face_a < face_b, inter rows prim_a < prim_b (string order of the prim paths; mesh
  index order when a table has no paths): the orientation of usdksl.contacts.orientation;
* one row per face pair: its earliest time; among equal earliest times the lowest feature code;
* rows sorted by (time, prim_a, face_a, prim_b, face_b).
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import List, Optional, Sequence, Tuple

import numpy as np

from .orientation import canonical_swap, swap_sides

#: Feature codes (the native core's ContactFeature) and the words the reports write for them.
FEATURE_VERTEX_FACE = 0
FEATURE_FACE_VERTEX = 1
FEATURE_EDGE_EDGE = 2
#: Found by a test at one instant: already touching at the start of the checked range (the core's
#: ContactFeature::Initial).
FEATURE_INITIAL = 3
FEATURE_NAMES = ("vertex-face", "face-vertex", "edge-edge", "initial")
#: Written for a feature code outside FEATURE_NAMES (a table built without features).
FEATURE_UNKNOWN = "unknown"

KIND_SELF = "self"
KIND_INTER = "inter"

Columns = Tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]


def path_rank(paths: Sequence[str]) -> np.ndarray:
    """int64[N]: each mesh's position in the string order of ``paths``."""
    rank = np.empty(len(paths), dtype=np.int64)
    rank[sorted(range(len(paths)), key=list(paths).__getitem__)] = np.arange(len(paths))
    return rank


def _pair_key(rank_a: np.ndarray, face_a: np.ndarray, rank_b: np.ndarray, face_b: np.ndarray):
    """int64[C] whose numeric order is the lexicographic order of (rank_a, face_a, rank_b, face_b), or
    None when the four do not fit in 63 bits together (one sort key instead of four)."""
    rank_bits = int(max(rank_a.max(), rank_b.max())).bit_length()
    face_bits = int(max(face_a.max(), face_b.max())).bit_length()
    side_bits = rank_bits + face_bits
    if 2 * side_bits > 63 or min(int(face_a.min()), int(face_b.min())) < 0:
        return None
    side_a = (rank_a << face_bits) | face_a
    side_b = (rank_b << face_bits) | face_b
    return (side_a << side_bits) | side_b


def canonical_first_contacts(time, mesh_a, face_a, mesh_b, face_b, feature,
                             mesh_rank: Optional[np.ndarray] = None) -> Columns:
    """The one place a contact pair is put in canonical order.

    Takes contact rows in any order and orientation (several rows per face pair allowed) and returns
    ``(time float64, mesh_a int32, face_a int32, mesh_b int32, face_b int32, feature int8)``: sides
    swapped so self rows have face_a < face_b and inter rows ``mesh_rank[mesh_a] < mesh_rank[mesh_b]``
    (vertex-face and face-vertex swap with the sides), rows inside one face dropped, the first contact
    of each face pair kept (earliest time, then lowest feature), sorted by (time, rank_a, face_a,
    rank_b, face_b). ``mesh_rank`` defaults to the mesh index order.
    """
    time = np.asarray(time, dtype=np.float64).reshape(-1)
    mesh_a = np.asarray(mesh_a, dtype=np.int64).reshape(-1)
    face_a = np.asarray(face_a, dtype=np.int64).reshape(-1)
    mesh_b = np.asarray(mesh_b, dtype=np.int64).reshape(-1)
    face_b = np.asarray(face_b, dtype=np.int64).reshape(-1)
    feature = (np.full(time.shape, -1, np.int8) if feature is None
               else np.asarray(feature, dtype=np.int8).reshape(-1))
    if mesh_rank is None:
        count = int(max(mesh_a.max(initial=-1), mesh_b.max(initial=-1))) + 1
        mesh_rank = np.arange(count, dtype=np.int64)
    mesh_rank = np.asarray(mesh_rank, dtype=np.int64)

    same_mesh = mesh_a == mesh_b
    swap = canonical_swap(mesh_rank[mesh_a], face_a, mesh_rank[mesh_b], face_b) if time.size else same_mesh
    mesh_a, mesh_b = swap_sides(swap, mesh_a, mesh_b)
    face_a, face_b = swap_sides(swap, face_a, face_b)
    flipped = np.where(feature == FEATURE_VERTEX_FACE, FEATURE_FACE_VERTEX,
                       np.where(feature == FEATURE_FACE_VERTEX, FEATURE_VERTEX_FACE, feature))
    feature = np.where(swap, flipped, feature).astype(np.int8)

    keep = ~(same_mesh & (face_a == face_b))
    time, mesh_a, face_a, mesh_b, face_b, feature = (
        column[keep] for column in (time, mesh_a, face_a, mesh_b, face_b, feature))

    if time.size:
        rank_a, rank_b = mesh_rank[mesh_a], mesh_rank[mesh_b]
        pair = _pair_key(rank_a, face_a, rank_b, face_b)
        if pair is not None:
            by_pair = np.lexsort((feature, time, pair))
            sorted_pair = pair[by_pair]
            first = np.ones(by_pair.size, bool)
            first[1:] = sorted_pair[1:] != sorted_pair[:-1]
            chosen = by_pair[first]
            order = chosen[np.lexsort((feature[chosen], pair[chosen], time[chosen]))]
        else:
            by_pair = np.lexsort((feature, time, face_b, rank_b, face_a, rank_a))
            key = np.stack([rank_a, face_a, rank_b, face_b], axis=1)[by_pair]
            first = np.ones(by_pair.size, bool)
            first[1:] = np.any(key[1:] != key[:-1], axis=1)
            chosen = by_pair[first]
            order = chosen[np.lexsort((feature[chosen], face_b[chosen], rank_b[chosen], face_a[chosen],
                                       rank_a[chosen], time[chosen]))]
        time, mesh_a, face_a, mesh_b, face_b, feature = (
            column[order] for column in (time, mesh_a, face_a, mesh_b, face_b, feature))
    return (time, mesh_a.astype(np.int32), face_a.astype(np.int32), mesh_b.astype(np.int32),
            face_b.astype(np.int32), feature)


@dataclass
class ContactTable:
    """First contact per face pair in canonical order. ``paths``: prim paths of the loaded meshes (None
    for meshes without paths, e.g. arrays built in a test; then mesh index order is canonical)."""

    paths: Optional[List[str]]
    time: np.ndarray      # float64[C], time codes
    mesh_a: np.ndarray    # int32[C], index into paths
    face_a: np.ndarray    # int32[C], authored face of mesh_a
    mesh_b: np.ndarray    # int32[C]
    face_b: np.ndarray    # int32[C]
    feature: np.ndarray   # int8[C], FEATURE_* code
    #: float64[C]: the face pair's last contact (time codes), when it was computed (usdksl.checking.
    #: last_contact); None otherwise. Not part of the canonical order.
    last_time: Optional[np.ndarray] = None

    @classmethod
    def from_rows(cls, paths: Optional[Sequence[str]], time, mesh_a, face_a, mesh_b, face_b,
                  feature=None) -> "ContactTable":
        """Any contact rows (see :func:`canonical_first_contacts`) as a table in canonical order."""
        paths = None if paths is None else list(paths)
        rank = None if paths is None else path_rank(paths)
        return cls(paths, *canonical_first_contacts(time, mesh_a, face_a, mesh_b, face_b, feature, rank))

    @classmethod
    def from_face_contacts(cls, contacts, paths: Sequence[str]) -> "ContactTable":
        """Rows of anything with arrays time, mesh_a, face_a, mesh_b, face_b (and optionally feature),
        e.g. another table, re-ordered for ``paths``."""
        return cls.from_rows(paths, contacts.time, contacts.mesh_a, contacts.face_a, contacts.mesh_b,
                             contacts.face_b, getattr(contacts, "feature", None))

    @classmethod
    def concatenate(cls, tables: Sequence["ContactTable"], epochs: Optional[np.ndarray] = None) -> "ContactTable":
        """Tables of consecutive time pieces of one shot (same meshes), in time order. ``epochs`` int[pieces,
        meshes]: pieces where a mesh has the same epoch have the same faces; a face pair found again in a later
        piece with the same epochs for both meshes is kept once, at its first contact (and its latest last
        contact). Without ``epochs`` every row is kept (face indices may refer to different topologies)."""
        return cls.concatenate_rows(tables, epochs)[0]

    @classmethod
    def concatenate_rows(cls, tables: Sequence["ContactTable"],
                         epochs: Optional[np.ndarray] = None) -> Tuple["ContactTable", np.ndarray]:
        """(:meth:`concatenate` of ``tables``, int64[C]: the position of each of its rows among the rows of
        all ``tables`` stacked in order)."""
        if len(tables) == 1:
            return tables[0], np.arange(tables[0].count, dtype=np.int64)
        if any(table.paths != tables[0].paths for table in tables):
            raise ValueError("pieces of one shot loaded different meshes")
        if len({table.last_time is None for table in tables}) > 1:
            raise ValueError("pieces disagree on whether last contacts were computed")
        last_time = (None if tables[0].last_time is None
                     else np.concatenate([table.last_time for table in tables]))
        columns = {name: np.concatenate([getattr(table, name) for table in tables])
                   for name in ("time", "mesh_a", "face_a", "mesh_b", "face_b", "feature")}
        kept = np.arange(columns["time"].size, dtype=np.int64)
        if epochs is not None and columns["time"].size:
            piece = np.repeat(np.arange(len(tables)), [table.count for table in tables])
            epochs = np.asarray(epochs, dtype=np.int64)
            key = np.stack([columns["mesh_a"], columns["face_a"], epochs[piece, columns["mesh_a"]],
                            columns["mesh_b"], columns["face_b"], epochs[piece, columns["mesh_b"]]], axis=1)
            _, first, group = np.unique(key, axis=0, return_index=True, return_inverse=True)
            group = group.reshape(-1)
            if last_time is not None:
                latest = np.full(first.size, -np.inf)
                np.maximum.at(latest, group, last_time)
                last_time = latest[group]
            keep = np.zeros(group.size, bool)
            keep[first] = True    # rows come in time order, so the first of a group is its first contact
            columns = {name: column[keep] for name, column in columns.items()}
            last_time = None if last_time is None else last_time[keep]
            kept = kept[keep]
        return cls(paths=tables[0].paths and list(tables[0].paths), last_time=last_time, **columns), kept

    @classmethod
    def empty(cls, paths: Optional[Sequence[str]]) -> "ContactTable":
        zeros = np.zeros(0, np.int32)
        return cls(paths=None if paths is None else list(paths), time=np.zeros(0), mesh_a=zeros,
                   face_a=zeros, mesh_b=zeros, face_b=zeros, feature=np.zeros(0, np.int8))

    @property
    def count(self) -> int:
        return int(self.time.shape[0])

    def __len__(self) -> int:
        return self.count

    @property
    def is_self(self) -> np.ndarray:
        return self.mesh_a == self.mesh_b

    def mesh_names(self) -> List[str]:
        """The name of each mesh index: its prim path, or the index as text for a table without paths."""
        return self._names()

    def _names(self) -> List[str]:
        if self.paths is not None:
            return list(self.paths)
        count = int(max(self.mesh_a.max(initial=-1), self.mesh_b.max(initial=-1))) + 1
        return [str(index) for index in range(count)]

    def kinds(self) -> np.ndarray:
        """object[C]: 'self' or 'inter' per row."""
        return np.where(self.is_self, KIND_SELF, KIND_INTER).astype(object)

    def feature_names(self) -> np.ndarray:
        """object[C]: the feature word per row (FEATURE_NAMES, or FEATURE_UNKNOWN)."""
        names = np.array(FEATURE_NAMES + (FEATURE_UNKNOWN,), dtype=object)
        known = (self.feature >= 0) & (self.feature < len(FEATURE_NAMES))
        return names[np.where(known, self.feature, len(FEATURE_NAMES))]

    def prim_names(self) -> Tuple[np.ndarray, np.ndarray]:
        """(prim_a, prim_b) object arrays of prim paths per row."""
        names = np.array(self._names() + [""], dtype=object)
        return names[self.mesh_a], names[self.mesh_b]

    def summary(self) -> List[dict]:
        """One dict per mesh pair with contacts: prim_a, prim_b, kind, first_contact_time, face_pairs (and
        last_contact_time, the latest last contact of its face pairs, when the table has last times),
        sorted by first_contact_time, then prim_a, prim_b."""
        if self.count == 0:
            return []
        names = self._names()
        pair_key = self.mesh_a.astype(np.int64) * max(len(names), 1) + self.mesh_b
        # rows are in time order, so the first row of each pair is its first contact
        _, first, inverse, counts = np.unique(pair_key, return_index=True, return_inverse=True,
                                              return_counts=True)
        latest = None
        if self.last_time is not None:
            latest = np.full(first.size, -np.inf)
            np.maximum.at(latest, inverse.reshape(-1), self.last_time)
        rows = []
        for group, (index, count) in enumerate(zip(first.tolist(), counts.tolist())):
            a, b = int(self.mesh_a[index]), int(self.mesh_b[index])
            row = {"prim_a": names[a], "prim_b": names[b], "kind": KIND_SELF if a == b else KIND_INTER,
                   "first_contact_time": float(self.time[index]), "face_pairs": int(count)}
            if latest is not None:
                row["last_contact_time"] = float(latest[group])
            rows.append(row)
        rows.sort(key=lambda row: (row["first_contact_time"], row["prim_a"], row["prim_b"]))
        return rows

    def records(self) -> List[dict]:
        """One dict per row: time, prim_a, face_a, prim_b, face_b, kind, feature (and last_time when the
        table has last times)."""
        if self.count == 0:
            return []
        prim_a, prim_b = self.prim_names()
        records = [{"time": t, "prim_a": a, "face_a": fa, "prim_b": b, "face_b": fb, "kind": k, "feature": f}
                   for t, a, fa, b, fb, k, f in zip(self.time.tolist(), prim_a.tolist(), self.face_a.tolist(),
                                                    prim_b.tolist(), self.face_b.tolist(), self.kinds().tolist(),
                                                    self.feature_names().tolist())]
        if self.last_time is not None:
            for record, last in zip(records, self.last_time.tolist()):
                record["last_time"] = last
        return records

    def pair_rows(self) -> np.ndarray:
        """int64[C, 4]: (mesh_a, face_a, mesh_b, face_b) per row, the key of a face pair."""
        return np.stack([self.mesh_a, self.face_a, self.mesh_b, self.face_b], axis=1).astype(np.int64)

    def with_last_times(self, last_time: Optional[np.ndarray]) -> "ContactTable":
        """This table with the last-contact column set (float64[C], time codes; None drops it)."""
        if last_time is not None:
            last_time = np.asarray(last_time, dtype=np.float64).reshape(-1)
            if last_time.shape[0] != self.count:
                raise ValueError(f"{last_time.shape[0]} last times for {self.count} rows")
        return replace(self, last_time=last_time)


def face_pair_ids(*tables: "ContactTable") -> List[np.ndarray]:
    """Per table, int64[C]: one id per row, the same for rows of one face pair in any of the tables (their
    mesh indices must refer to the same meshes)."""
    keys = [table.pair_rows() for table in tables]
    joined = np.concatenate(keys) if keys else np.zeros((0, 4), np.int64)
    if joined.shape[0] == 0:
        return [np.zeros(0, np.int64) for _ in tables]
    ids = np.unique(joined, axis=0, return_inverse=True)[1].reshape(-1)
    bounds = np.cumsum([0] + [key.shape[0] for key in keys])
    return [ids[start:end] for start, end in zip(bounds[:-1], bounds[1:])]


def match_face_pairs(table: "ContactTable", other: "ContactTable") -> Tuple[np.ndarray, np.ndarray]:
    """(int64[C]: for each row of ``table`` the row of ``other`` with the same face pair, -1 when none;
    bool[D]: the rows of ``other`` whose face pair ``table`` lacks). Both tables one row per face pair,
    over the same meshes."""
    ids, other_ids = face_pair_ids(table, other)
    slot = np.full(int(max(ids.max(initial=-1), other_ids.max(initial=-1))) + 1, -1, np.int64)
    slot[other_ids] = np.arange(other_ids.size)
    found = slot[ids]
    present = np.zeros(slot.size, bool)
    present[ids] = True
    return found, ~present[other_ids]


def latest_per_face_pair(paths: Optional[Sequence[str]], last_time, mesh_a, face_a, mesh_b,
                         face_b) -> "ContactTable":
    """Rows in any order and orientation with their last-contact times, as one row per face pair in
    canonical orientation whose ``time`` is the pair's latest last contact (the canonical function keeps
    the earliest time, so it runs on negated times; negation is exact)."""
    negated = ContactTable.from_rows(paths, -np.asarray(last_time, dtype=np.float64), mesh_a, face_a, mesh_b,
                                     face_b, None)
    return replace(negated, time=-negated.time)

