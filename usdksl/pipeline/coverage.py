"""The coverage account of one check: every prim that can hold geometry and every stretch of the checked range,
each either checked or named as not checked, with why (docs/contracts.md, Coverage).

Three statuses:

* ``checked``: a mesh in at least one checked pair, over the checked range minus its gaps;
* ``scoped out``: left out on purpose, by a rule the user or the scene controls (``--prims``/``--exclude``,
  ``physics:collisionEnabled``, purpose, visibility, pairs that need no check such as two still meshes, samples
  outside ``--time-range``), or holding no surface (an empty mesh): the check is complete without them;
* ``not checked``: geometry or a stretch of time usdksl could not read (an asset that does not resolve, an empty
  or blocked sample, a topology change, a solid that is not a mesh, a nested instancer). Each has
  a warning line; the summary line says how many; ``--strict`` makes any of them exit 2.

Exit 0 therefore means: nothing ``not checked``, and no contact.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import List, Optional, Sequence, Tuple

from ..reading.scope import MESH_ABSENT, MESH_EXCLUDED_BY_PATTERN, Plan
from ..warning_kinds import EMPTY_MESH, EMPTY_SAMPLE, NOT_A_SURFACE, OUTSIDE_TIME_RANGE, SCOPED_OUT, TOPOLOGY_CHANGE

CHECKED = "checked"
SCOPED = "scoped out"
NOT_CHECKED = "not checked"

#: Entries listed one per line by ``-v``; the JSON report lists every one.
COVERAGE_LINES_VERBOSE = 50


@dataclass(frozen=True)
class CoverageEntry:
    """One prim (or the stage, prim ``/``) over ``start..end`` (time codes; None: the whole checked range)."""

    prim: str
    status: str
    reason: str
    kind: Optional[str] = None          # usdksl.warning_kinds name; None for checked entries
    start: Optional[float] = None
    end: Optional[float] = None

    def to_dict(self) -> dict:
        return {"prim": self.prim, "status": self.status, "kind": self.kind, "reason": self.reason,
                "start": self.start, "end": self.end}

    def line(self) -> str:
        when = "" if self.start is None else f" over {self.start:g}..{self.end:g}"
        return f"{self.status}: {self.prim}{when}: {self.reason}"


@dataclass
class Coverage:
    """Every prim and stretch of one check (module docstring); ``span`` is the checked range in time codes."""

    span: Tuple[float, float]
    entries: List[CoverageEntry] = field(default_factory=list)

    def with_status(self, status: str) -> List[CoverageEntry]:
        return [entry for entry in self.entries if entry.status == status]

    @property
    def complete(self) -> bool:
        """True when nothing is ``not checked``: a clean check then means a clean shot."""
        return not self.with_status(NOT_CHECKED)

    def summary_phrase(self) -> str:
        """What the summary line adds when something went unchecked ('' when the check is complete)."""
        missing = self.with_status(NOT_CHECKED)
        if not missing:
            return ""
        prims = len({entry.prim for entry in missing})
        return (f"; NOT CHECKED: {len(missing)} item{'s' if len(missing) != 1 else ''} on {prims} "
                f"prim{'s' if prims != 1 else ''} (see the warnings, -v or the JSON report's coverage)")

    def lines(self, limit: int = COVERAGE_LINES_VERBOSE) -> List[str]:
        """``-v`` lines: not checked first, then scoped out, then checked; at most ``limit`` per status."""
        lines = [f"coverage of {self.span[0]:g}..{self.span[1]:g}: {len(self.with_status(CHECKED))} checked, "
                 f"{len(self.with_status(SCOPED))} scoped out, {len(self.with_status(NOT_CHECKED))} not checked"]
        for status in (NOT_CHECKED, SCOPED, CHECKED):
            entries = self.with_status(status)
            lines.extend(f"  {entry.line()}" for entry in entries[:limit])
            if len(entries) > limit:
                lines.append(f"  ... and {len(entries) - limit} more {status} (the JSON report lists all)")
        return lines

    def to_dict(self) -> dict:
        return {"span": list(self.span), "complete": self.complete,
                "checked": len(self.with_status(CHECKED)), "scoped_out": len(self.with_status(SCOPED)),
                "not_checked": len(self.with_status(NOT_CHECKED)),
                "entries": [entry.to_dict() for entry in self.entries]}


def shot_coverage(segments: Sequence, plan: Plan, gaps: Sequence, span: Tuple[float, float],
                  time_range: Optional[Tuple[float, float]] = None) -> Coverage:
    """The coverage account of a planned shot: ``segments`` [(range, Shot)] as the pipeline loads them, ``plan``
    their merged plan, ``gaps`` (usdksl.reading.segments.Gap) of meshes that cannot be followed
    across some samples, ``span`` the checked range, ``time_range`` the user's --time-range (None: the shot)."""
    coverage = Coverage(span=(float(span[0]), float(span[1])))
    entries = coverage.entries
    seen = set()
    for _, shot in segments:
        for item in shot.unchecked:
            key = (item.prim, item.reason)
            if key not in seen:
                seen.add(key)
                # an empty mesh holds no surface: nothing is missed without it
                status = SCOPED if item.kind in (EMPTY_MESH, NOT_A_SURFACE) else NOT_CHECKED
                entries.append(CoverageEntry(item.prim, status, item.reason, item.kind))
    for gap in gaps:
        start, end = max(gap.start, coverage.span[0]), min(gap.end, coverage.span[1])
        if start < end or (start == end and gap.start < start < gap.end):
            entries.append(CoverageEntry(gap.path, NOT_CHECKED,
                                         "topology changes" if gap.kind == TOPOLOGY_CHANGE else
                                         "points are empty or blocked", gap.kind, float(start), float(end)))
    partners: dict = {}
    for i, j in plan.pairs.tolist():
        partners.setdefault(i, set()).add(j)
        partners.setdefault(j, set()).add(i)
    skipped_reasons: dict = {}
    for i, j, reason in plan.skipped_pairs:
        skipped_reasons.setdefault(i, set()).add(reason)
        skipped_reasons.setdefault(j, set()).add(reason)
    for index, path in enumerate(plan.paths):
        if index in partners:
            entries.append(CoverageEntry(path, CHECKED, _checked_reason(plan, index, partners[index])))
        elif index in plan.skipped_meshes and plan.skipped_meshes[index] != MESH_ABSENT:
            entries.append(CoverageEntry(path, SCOPED, plan.skipped_meshes[index], SCOPED_OUT))
        elif index in plan.skipped_meshes:   # left out of every piece it has points in? never: it has none here
            entries.append(CoverageEntry(path, NOT_CHECKED, plan.skipped_meshes[index], EMPTY_SAMPLE))
        else:
            reasons = "; ".join(sorted(skipped_reasons.get(index, ()))) or "no other mesh"
            entries.append(CoverageEntry(path, SCOPED, f"no pair needs a check: {reasons}", SCOPED_OUT))
    for path in plan.excluded_paths:
        entries.append(CoverageEntry(path, SCOPED, MESH_EXCLUDED_BY_PATTERN + " (not loaded)", SCOPED_OUT))
    if time_range is not None:
        metadata = segments[0][1].metadata
        stage_start, stage_end = metadata.get("startTimeCode"), metadata.get("endTimeCode")
        for start, end in ((stage_start, time_range[0]), (time_range[1], stage_end)):
            if start is not None and end is not None and float(start) < float(end):
                entries.append(CoverageEntry("/", SCOPED, "outside --time-range", OUTSIDE_TIME_RANGE,
                                             float(start), float(end)))
    return coverage


def _checked_reason(plan: Plan, index: int, partners) -> str:
    names = (["itself"] if index in partners else []) + sorted(plan.paths[other] for other in partners if other != index)
    more = f" and {len(names) - 3} more" if len(names) > 3 else ""
    return f"against {', '.join(names[:3])}{more}"
