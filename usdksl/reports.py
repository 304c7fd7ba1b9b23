"""Reports of a check: contacts.csv, summary.csv, the --json document and the --junit XML.

Everything is built from a :class:`ContactTable`: the core's face contacts with prim order applied
(inter rows prim_a < prim_b by string order, self rows face_a < face_b) and sorted by
(time, prim_a, face_a, prim_b, face_b). Times are written with ``repr(float)``, the shortest text that
reads back to the same double, so two runs give byte-identical files.

contacts.csv  ``time,prim_a,face_a,prim_b,face_b,kind,feature`` (the six contract columns, then the
              feature that touched first: vertex-face, face-vertex, edge-edge or initial)
summary.csv   ``prim_a,prim_b,kind,first_contact_time,face_pairs``: one row per mesh pair that has
              contacts (clean pairs are not listed; the JUnit report and the JSON plan list every checked
              pair), sorted by first_contact_time, then prim_a, prim_b.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from typing import List, Optional, Sequence
from xml.etree import ElementTree

import numpy as np

from .scope import PAIR_RIGID_ONLY

CONTACT_COLUMNS = ("time", "prim_a", "face_a", "prim_b", "face_b", "kind", "feature")
SUMMARY_COLUMNS = ("prim_a", "prim_b", "kind", "first_contact_time", "face_pairs")

# Feature codes of the core (CONTRACTS.md): what touched first.
FEATURE_NAMES = ("vertex-face", "face-vertex", "edge-edge", "initial")
FEATURE_VERTEX_FACE = 0
FEATURE_FACE_VERTEX = 1


def format_times(times: np.ndarray) -> np.ndarray:
    """object[C] of repr(float) strings; repr runs once per distinct time, not once per row."""
    times = np.asarray(times, dtype=np.float64)
    if times.size == 0:
        return np.zeros(0, dtype=object)
    distinct, inverse = np.unique(times, return_inverse=True)
    text = np.array([repr(value) for value in distinct.tolist()], dtype=object)
    return text[inverse.reshape(-1)]


def _int_text(values: np.ndarray) -> np.ndarray:
    return np.asarray(values).astype(np.int64).astype(str).astype(object)


@dataclass
class ContactTable:
    """Face contacts in report order. ``paths`` are the prim paths of the loaded meshes."""

    paths: List[str]
    time: np.ndarray      # float64[C]
    mesh_a: np.ndarray    # int32[C]
    face_a: np.ndarray    # int32[C]
    mesh_b: np.ndarray    # int32[C]
    face_b: np.ndarray    # int32[C]
    feature: np.ndarray   # int8[C]

    @property
    def count(self) -> int:
        return int(self.time.shape[0])

    @property
    def is_self(self) -> np.ndarray:
        return self.mesh_a == self.mesh_b

    @classmethod
    def from_face_contacts(cls, contacts, paths: Sequence[str]) -> "ContactTable":
        """Normalise anything with FaceContacts' arrays (time, mesh_a, face_a, mesh_b, face_b, feature).

        Swaps sides so inter rows have prim_a < prim_b and self rows face_a < face_b (vertex-face and
        face-vertex swap with the sides), drops same-face self rows, keeps the first contact of each face
        pair if the input repeats one, and sorts in report order.
        """
        paths = list(paths)
        time = np.asarray(contacts.time, dtype=np.float64).reshape(-1)
        mesh_a = np.asarray(contacts.mesh_a, dtype=np.int32).reshape(-1)
        face_a = np.asarray(contacts.face_a, dtype=np.int32).reshape(-1)
        mesh_b = np.asarray(contacts.mesh_b, dtype=np.int32).reshape(-1)
        face_b = np.asarray(contacts.face_b, dtype=np.int32).reshape(-1)
        feature = getattr(contacts, "feature", None)
        feature = (np.full(time.shape, -1, np.int8) if feature is None
                   else np.asarray(feature, dtype=np.int8).reshape(-1))

        rank = np.empty(len(paths), dtype=np.int64)
        rank[sorted(range(len(paths)), key=paths.__getitem__)] = np.arange(len(paths))
        same_mesh = mesh_a == mesh_b
        swap = np.where(same_mesh, face_a > face_b, rank[mesh_a] > rank[mesh_b]) if len(paths) else same_mesh
        mesh_a, mesh_b = np.where(swap, mesh_b, mesh_a), np.where(swap, mesh_a, mesh_b)
        face_a, face_b = np.where(swap, face_b, face_a), np.where(swap, face_a, face_b)
        flipped = np.where(feature == FEATURE_VERTEX_FACE, FEATURE_FACE_VERTEX,
                           np.where(feature == FEATURE_FACE_VERTEX, FEATURE_VERTEX_FACE, feature))
        feature = np.where(swap, flipped, feature).astype(np.int8)

        keep = ~(same_mesh & (face_a == face_b))
        time, mesh_a, face_a, mesh_b, face_b, feature = (
            array[keep] for array in (time, mesh_a, face_a, mesh_b, face_b, feature))

        if time.size:
            rank_a, rank_b = rank[mesh_a], rank[mesh_b]
            # first contact per face pair: sort by pair then time (then feature, for determinism)
            by_pair = np.lexsort((feature, time, face_b, rank_b, face_a, rank_a))
            key = np.stack([rank_a, face_a, rank_b, face_b], axis=1)[by_pair]
            first = np.ones(by_pair.size, bool)
            first[1:] = np.any(key[1:] != key[:-1], axis=1)
            chosen = by_pair[first]
            order = chosen[np.lexsort((feature[chosen], face_b[chosen], rank_b[chosen], face_a[chosen],
                                       rank_a[chosen], time[chosen]))]
            time, mesh_a, face_a, mesh_b, face_b, feature = (
                array[order] for array in (time, mesh_a, face_a, mesh_b, face_b, feature))
        return cls(paths=paths, time=time, mesh_a=mesh_a.astype(np.int32), face_a=face_a.astype(np.int32),
                   mesh_b=mesh_b.astype(np.int32), face_b=face_b.astype(np.int32), feature=feature)

    @classmethod
    def concatenate(cls, tables: Sequence["ContactTable"]) -> "ContactTable":
        """Tables of consecutive, disjoint time segments of one shot, in time order. Rows are kept as they
        are (no first-contact merge across segments: face indices may refer to different topologies)."""
        if len(tables) == 1:
            return tables[0]
        if any(table.paths != tables[0].paths for table in tables):
            raise ValueError("segments of one shot loaded different meshes")
        return cls(paths=list(tables[0].paths),
                   **{name: np.concatenate([getattr(table, name) for table in tables])
                      for name in ("time", "mesh_a", "face_a", "mesh_b", "face_b", "feature")})

    @classmethod
    def empty(cls, paths: Sequence[str]) -> "ContactTable":
        zeros = np.zeros(0, np.int32)
        return cls(paths=list(paths), time=np.zeros(0), mesh_a=zeros, face_a=zeros, mesh_b=zeros,
                   face_b=zeros, feature=np.zeros(0, np.int8))

    # ----------------------------------------------------------------------------------------------------

    def _columns(self):
        names = np.array(self.paths + [""], dtype=object)
        kinds = np.where(self.is_self, "self", "inter").astype(object)
        feature_names = np.array(FEATURE_NAMES + ("unknown",), dtype=object)
        feature = np.where((self.feature >= 0) & (self.feature < len(FEATURE_NAMES)), self.feature,
                           len(FEATURE_NAMES))
        return (format_times(self.time), names[self.mesh_a], _int_text(self.face_a), names[self.mesh_b],
                _int_text(self.face_b), kinds, feature_names[feature])

    def contacts_csv(self) -> str:
        header = ",".join(CONTACT_COLUMNS) + "\n"
        if self.count == 0:
            return header
        # Columns are numpy string arrays; map/zip/join run in C (measured: 0.05 s for 100k rows, 3.5x
        # faster than chained object-array additions), no Python code runs per row.
        columns = [column.tolist() for column in self._columns()]
        return header + "\n".join(map(",".join, zip(*columns))) + "\n"

    def summary(self) -> List[dict]:
        """One dict per mesh pair with contacts: prim_a, prim_b, kind, first_contact_time, face_pairs."""
        if self.count == 0:
            return []
        pair_key = self.mesh_a.astype(np.int64) * max(len(self.paths), 1) + self.mesh_b
        # rows are in time order, so the first row of each pair is its first contact
        keys, first, counts = np.unique(pair_key, return_index=True, return_counts=True)
        rows = []
        for index, count in zip(first.tolist(), counts.tolist()):
            a, b = int(self.mesh_a[index]), int(self.mesh_b[index])
            rows.append({"prim_a": self.paths[a], "prim_b": self.paths[b], "kind": "self" if a == b else "inter",
                         "first_contact_time": float(self.time[index]), "face_pairs": int(count)})
        rows.sort(key=lambda row: (row["first_contact_time"], row["prim_a"], row["prim_b"]))
        return rows

    def summary_csv(self) -> str:
        lines = [",".join(SUMMARY_COLUMNS)]
        for row in self.summary():
            lines.append(f"{row['prim_a']},{row['prim_b']},{row['kind']},{row['first_contact_time']!r},"
                         f"{row['face_pairs']}")
        return "\n".join(lines) + "\n"

    def records(self) -> List[dict]:
        if self.count == 0:
            return []
        _, prim_a, _, prim_b, _, kinds, features = self._columns()
        return [{"time": t, "prim_a": a, "face_a": fa, "prim_b": b, "face_b": fb, "kind": k, "feature": f}
                for t, a, fa, b, fb, k, f in zip(self.time.tolist(), prim_a.tolist(), self.face_a.tolist(),
                                                 prim_b.tolist(), self.face_b.tolist(), kinds.tolist(),
                                                 features.tolist())]


def json_report(shot_path: str, settings: dict, plan, table: ContactTable, exit_code: int,
                version: str = "") -> str:
    """The --json document: shot, settings, plan, summary rows, contacts, exit code."""
    document = {
        "tool": "usdksl",
        "version": version,
        "shot": str(shot_path),
        "settings": settings,
        "plan": plan.to_dict(),
        "summary": table.summary(),
        "contacts": table.records(),
        "contact_count": table.count,
        "exit_code": int(exit_code),
    }
    return json.dumps(document, indent=1, allow_nan=False) + "\n"


def junit_report(shot_path: str, plan, table: ContactTable) -> str:
    """One testsuite per shot, one testcase per checked mesh pair; a failure when the pair has contacts."""
    by_pair = {(row["prim_a"], row["prim_b"]): row for row in table.summary()}
    failures = 0
    cases = []
    for i, j in plan.pairs.tolist():
        a, b = sorted((plan.paths[i], plan.paths[j]))
        kind = "self" if i == j else "inter"
        case = ElementTree.Element("testcase", {"classname": f"usdksl.{kind}",
                                                "name": a if kind == "self" else f"{a} x {b}"})
        row = by_pair.get((a, b))
        if row is not None:
            failures += 1
            message = (f"{row['face_pairs']} face pair{'s' if row['face_pairs'] != 1 else ''} in contact, "
                       f"first at time {row['first_contact_time']!r}")
            failure = ElementTree.SubElement(case, "failure", {"message": message, "type": "contact"})
            failure.text = message
        cases.append(case)
    suite = ElementTree.Element("testsuite", {"name": str(shot_path), "tests": str(len(cases)),
                                              "failures": str(failures), "errors": "0",
                                              "skipped": "0"})
    suite.extend(cases)
    suites = ElementTree.Element("testsuites", {"name": "usdksl check", "tests": str(len(cases)),
                                                "failures": str(failures), "errors": "0"})
    suites.append(suite)
    if hasattr(ElementTree, "indent"):  # Python >= 3.9
        ElementTree.indent(suites)
    return '<?xml version="1.0" encoding="UTF-8"?>\n' + ElementTree.tostring(suites, encoding="unicode") + "\n"


def summary_line(table: ContactTable, plan, time_range: Optional[tuple], seconds: float) -> str:
    """The final line printed after every run."""
    pairs = len(table.summary())
    span = "" if time_range is None else f" over {time_range[0]:g}..{time_range[1]:g}"
    checked = f"checked {plan.checked_pairs} pair{'s' if plan.checked_pairs != 1 else ''}{span} in {seconds:.1f}s"
    rigid_only = plan.skipped_pair_counts().get(PAIR_RIGID_ONLY, 0) if hasattr(plan, "skipped_pair_counts") else 0
    if rigid_only:
        checked += (f"; {rigid_only} rigid-only pair{'s' if rigid_only != 1 else ''} left out "
                    f"(neither mesh deforms; --rigid checks them)")
    if table.count == 0:
        return f"usdksl: clean: no contacts; {checked}"
    first = float(table.time[0])
    return (f"usdksl: {table.count} contacting face pair{'s' if table.count != 1 else ''} in {pairs} mesh "
            f"pair{'s' if pairs != 1 else ''}, first at t={first!r}; {checked}")
