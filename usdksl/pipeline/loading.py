"""A shot loaded for checking: in pieces cut where a mesh cannot be followed, the range the check covers,
and the faults of the loaded motion (blow-ups, cache glitches)."""

from __future__ import annotations

import functools
from dataclasses import dataclass, field
from typing import Callable, List, Optional, Sequence

import numpy as np

from ..checking.collision import default_threads
from ..clock import StageClock
from ..errors import UsdkslGapError, UsdkslInputError
from ..reading.blowups import describe_blowups, describe_glitches, shot_faults
from ..reading.loader import MeshSources, load_sources
from ..reading.scope import Plan
from ..reading.segments import absent_meshes, cut_range, full_range, is_topology_change, mesh_gaps, mesh_stretches
from ..warning_kinds import BLOW_UP, CACHE_GLITCH
from .coverage import Coverage
from .messages import INFO, WARNING
from .options import CheckOptions, TimeRange


@dataclass
class PlannedShot:
    """A shot loaded for checking: its constant-topology segments [(range, loaded Shot)] (usdksl.reading),
    the plan of each and their merged plan."""

    segments: list
    plans: List[Plan]
    plan: Plan
    #: Gaps of meshes that cannot be followed across some samples (usdksl.reading.segments.Gap).
    gaps: list = field(default_factory=list)
    #: Every prim and stretch, checked or not (usdksl.pipeline.coverage).
    coverage: Optional[Coverage] = None
    #: Sample steps of the memory windows the core is handed the shot in (usdksl.pipeline.memory_budget).
    steps_per_window: Optional[int] = None

    @functools.cached_property
    def clock(self) -> StageClock:
        """The stage's clock (frames, time codes, seconds), read once from its first segment."""
        return StageClock.from_metadata(self.segments[0][1].metadata)


def require_samples_in_range(shot, time_range: Optional[TimeRange], name: str) -> None:
    """Input error when ``time_range`` lies wholly before or after every animated mesh's samples of the loaded
    ``shot`` (usdksl.reading.loader.Shot): nothing in it moves, so a check there would pass without having looked
    at the animation."""
    span = shot.sample_span
    if time_range is None or span is None:
        return
    if time_range[1] < span[0] or time_range[0] > span[1]:
        raise UsdkslInputError(f"--time-range {time_range[0]:g}..{time_range[1]:g} holds no sample of any mesh: "
                               f"the animated meshes' samples span {span[0]:g}..{span[1]:g}", file=name)


def checked_span(options: CheckOptions, segments) -> TimeRange:
    """The range a check covers, in time codes: ``options.time_range``, or the loaded samples' span."""
    if options.time_range is not None:
        return options.time_range
    if segments[0][0] is not None:   # pieces cut at gaps
        return (float(segments[0][0][0]), float(segments[-1][0][1]))
    all_times = np.concatenate([segment.times for _, segment in segments])
    return (float(all_times.min()), float(all_times.max())) if all_times.size else (0.0, 0.0)


def report_blowups(segments, plans: Sequence[Plan], name: str, say: Callable[..., None],
                   strict: bool, threads: Optional[int] = None) -> None:
    """Warn about vertices of checked meshes that blow up and about checked meshes, or most of one, that
    jump away and back (cache glitches; usdksl.reading.blowups); under ``strict`` the first glitch, else
    the first blow-up, is an input error (exit 2, nothing written). ``threads``: how many the scan's passes
    over a mesh's samples may use (default: every core this process may run on, as find_contacts)."""
    threads = threads or default_threads()
    for (_, segment), segment_plan in zip(segments, plans):
        checked = sorted(set(segment_plan.pairs.reshape(-1).tolist()))
        blowups, glitches = shot_faults([segment.meshes[index] for index in checked], threads)
        if glitches and strict:
            first = glitches[0]
            raise UsdkslInputError(f"cache glitch: {first.describe()} (--strict)", file=name, prim=first.prim,
                                   time=first.time)
        if blowups and strict:
            first = blowups[0]
            raise UsdkslInputError(
                f"vertex {first.vertex} blows up between time {first.time_before:g} and {first.time_after:g} "
                f"({first.excess:.3g} units beyond the mesh's motion; --strict)", file=name, prim=first.prim)
        for line in describe_glitches(glitches, name):
            say(WARNING, line, CACHE_GLITCH)
        for line in describe_blowups(blowups, name):
            say(WARNING, line, BLOW_UP)


def load_segments(found: MeshSources, time_range: Optional[TimeRange], say: Callable[..., None],
                  name: Optional[str] = None, strict: bool = False):
    """([(range, Shot)], gaps): the shot whose stage and meshes are ``found``
    (usdksl.reading.loader.find_mesh_sources) loaded whole, or, when a mesh cannot be followed across some
    samples (a topology change, an empty or blocked points sample), one Shot per piece of the range cut at every
    such gap (usdksl.reading.segments), the meshes a gap covers loaded still and left out there; every piece
    from the same open stage and sources. Warns once per gap (an input error under ``strict``: the gap is not
    checked); ``range`` is None when the whole shot is checked without a time range. ``gaps``:
    usdksl.reading.segments.Gap of every mesh that has them."""
    name = name or found.file
    try:
        return [(time_range, load_sources(found, time_range))], []
    except (UsdkslGapError, UsdkslInputError) as error:
        if not (isinstance(error, UsdkslGapError) or is_topology_change(error)):
            raise
        first_error = error
    stretches = {str(prim.GetPath()): mesh_stretches(prim) for prim in found.prims}
    full = full_range(found.sample_times, time_range)
    gaps = [gap for path, mesh in stretches.items() for gap in mesh_gaps(path, mesh)
            if gap.covers(full) or (full[0] == full[1] and gap.start < full[0] < gap.end)]
    if not gaps and isinstance(first_error, UsdkslGapError):   # a PointInstancer's prototype mesh
        raise UsdkslInputError(f"{first_error.message}: the instances of a prototype with empty or blocked samples "
                               f"cannot be checked around them", file=first_error.file, prim=first_error.prim,
                               time=first_error.time) from None
    if not gaps:
        raise first_error
    gaps.sort(key=lambda gap: (max(gap.start, full[0]), gap.path))
    if strict:
        gap = gaps[0]
        raise UsdkslInputError(f"{gap.describe(name).split(': ', 2)[2]} (--strict)", file=name, prim=gap.path,
                               time=max(gap.start, full[0]))
    for gap in gaps:
        say(WARNING, gap.describe(name), gap.kind)
    pieces = cut_range(full, gaps)
    if len(pieces) > 1:
        say(INFO, f"checking {len(pieces)} segments cut at those gaps: " + ", ".join(f"{a:g}..{b:g}" for a, b in pieces))
    return [(piece, load_sources(found, piece, absent=absent_meshes(piece, gaps, stretches)))
            for piece in pieces], gaps
