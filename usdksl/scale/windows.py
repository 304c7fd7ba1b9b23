"""Long shots on Dask: one shot checked as several time-window tasks whose contacts merge exactly.

When a Dask batch has fewer shots than worker slots (usdksl.scale.dask_runner), each shot is cut into
time windows, up to ``ceil(slots / shots)`` of them. The rule (:func:`plan_windows`):

* cuts fall on time codes at which *every* animated mesh has a sample, so a window's load (its samples
  plus its ends evaluated exactly, usdksl.reading.loader) moves every mesh along the very lines one
  run does; without ``--time-range`` the checked range's two ends must be such times as well (a mesh
  that starts late or stops early would otherwise get a held sample at a window's end);
* every window spans at least :data:`MIN_SAMPLES_PER_WINDOW` sample intervals of the shot (below that,
  loading and setting up a window costs more than it saves); a shot too short for two windows, or with
  no such shared time, is checked whole;
* ``--crosscheck`` shots are checked whole (the Embree report is per run, not merged).

Each window is a task (:func:`check_window`) that loads only its range and runs the core there; one
more task (:func:`merge_windows`) joins the windows with :func:`usdksl.scale.merge.merge_parts`, the code
that joins farm chunks: earliest first contact per face pair (docs/contracts.md, Windows and merging),
then the reports of one check, so the files equal a single-process run's byte for byte. A window task is
pure: run again after its worker died, it returns the same contacts, and only the merge task's one
outcome per shot reaches the client, so nothing is lost or counted twice.

When windows cannot be merged exactly (a topology change, visibility or motion that makes a window
check other mesh pairs than the whole range, a window that failed) the merge task checks the shot whole
instead and says so in an info line: slower, never another answer.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, field, replace
from functools import reduce
from typing import Dict, List, Optional, Sequence, Tuple

import numpy as np

from ..contacts.table import ContactTable
from ..errors import UsdkslInputError, UsdkslUsageError
from ..pipeline.check import check_segment, check_shot, load_and_plan
from ..pipeline.messages import INFO, Message, message_collector
from ..pipeline.options import CheckOptions
from ..reading.loader import shot_sample_times
from ..reading.scope import include_predicate
from ..reports.manifest import checked_pairs
from ..unmasked import distinct_sorted
from .batch import ShotJob, ShotOutcome, checked_outcome
from .merge import merge_parts

TimeRange = Tuple[float, float]

#: Fewest sample intervals of the shot in one window.
MIN_SAMPLES_PER_WINDOW = 8


def windows_per_shot(shots: int, slots: int) -> int:
    """Windows to cut each shot into when ``shots`` shots share ``slots`` worker slots: enough for every
    slot to have a task; 1 (no split) when there are at least as many shots as slots."""
    if shots <= 0 or shots >= slots:
        return 1
    return math.ceil(slots / shots)


def plan_windows(sample_times: Sequence[np.ndarray], time_range: Optional[TimeRange], count: int) -> List[TimeRange]:
    """Up to ``count`` consecutive windows [(start, end)] covering the checked range (``time_range``, or
    the span of all samples), by the rule of the module docstring; [] when the shot is to be checked whole.
    ``sample_times``: each mesh's sample times (time codes; empty for a still mesh)."""
    animated = [np.asarray(times, dtype=np.float64) for times in sample_times if len(times)]
    if count < 2 or not animated:
        return []
    union = distinct_sorted(np.concatenate(animated))
    shared = reduce(np.intersect1d, animated)
    if time_range is None:
        start, end = float(union[0]), float(union[-1])
        if not (np.any(shared == start) and np.any(shared == end)):
            return []
    else:
        start, end = float(time_range[0]), float(time_range[1])
    # the sample grid of one run over [start, end]: both ends and every sample between them
    grid = distinct_sorted(np.concatenate([[start, end], union[(union > start) & (union < end)]]))
    intervals = grid.size - 1
    count = min(count, intervals // MIN_SAMPLES_PER_WINDOW)
    if count < 2:
        return []
    candidates = np.searchsorted(grid, shared[(shared > start) & (shared < end)])   # grid indices
    cuts: List[int] = []
    for window in range(1, count):
        ideal = window * intervals / count
        allowed = candidates[(candidates - (cuts[-1] if cuts else 0) >= MIN_SAMPLES_PER_WINDOW)
                             & (intervals - candidates >= MIN_SAMPLES_PER_WINDOW)]
        if allowed.size:
            cuts.append(int(allowed[np.argmin(np.abs(allowed - ideal))]))
    bounds = [start] + [float(grid[cut]) for cut in cuts] + [end]
    return list(zip(bounds[:-1], bounds[1:])) if cuts else []


def shot_windows(job: ShotJob, options: CheckOptions, count: int) -> List[TimeRange]:
    """The windows to check ``job`` in (:func:`plan_windows`), read from its time samples only; [] for a
    shot checked whole, and for one whose samples cannot be read (its whole check reports why)."""
    if count < 2 or options.crosscheck:
        return []
    include, excluded = options.patterns()
    try:
        times = shot_sample_times(job.path, include_predicate(include, excluded) if (include or excluded) else None,
                                  skin_keys_only=options.skin_keys_only)
    except UsdkslInputError:
        return []
    return plan_windows(times, options.time_range, count)


@dataclass
class WindowPart:
    """What one window's task found: a part for :func:`usdksl.scale.merge.merge_parts` (``start``, ``end``,
    ``checked_pairs``, ``where``, ``contacts()``), or the one line saying why it could not be checked."""

    start: float
    end: float
    checked_pairs: Optional[List[List[str]]] = None
    table: Optional[ContactTable] = None
    segment_count: int = 1
    #: What the core said (undecided triangle pairs, last contacts not found backwards).
    messages: List[Message] = field(default_factory=list)
    counters: Dict[str, int] = field(default_factory=dict)
    error: Optional[str] = None

    @property
    def where(self) -> str:
        return f"time window {self.start:g}..{self.end:g}"

    def contacts(self, paths: Sequence[str], stem: str) -> ContactTable:
        """The window's contacts; refuses a window that loaded other meshes than the whole range."""
        if self.table is None or self.table.paths != list(paths):
            raise UsdkslUsageError(f"cannot merge: {self.where} loaded other meshes than the whole shot")
        return self.table

    def __repr__(self) -> str:
        return self.where


def check_window(job: ShotJob, options: CheckOptions, window: TimeRange) -> WindowPart:
    """Check ``job`` over ``window`` only (a Dask task); never raises. Renders nothing and says no plan or
    loader line (the merge task says the whole shot's)."""
    start, end = window
    options = replace(options, time_range=(float(start), float(end)))
    messages: List[Message] = []
    counters: Dict[str, int] = {}
    try:
        # a window with nothing to check is not an error: the merge task plans the whole shot
        planned = load_and_plan(job.path, options, job.name, lambda *line: None, require_pairs=False)
        say = message_collector(messages)
        tables = [check_segment(segment, plan, segment_range, options, None, say, counters,
                                steps_per_window=planned.steps_per_window,
                                frames_per_time_code=planned.clock.frames_per_time_code)
                  for (segment_range, segment), plan in zip(planned.segments, planned.plans)]
    except Exception as error:  # noqa: BLE001  (the merge task then checks the shot whole and reports it)
        if os.environ.get("USDKSL_DEBUG"):
            raise
        text = error.one_line() if isinstance(error, UsdkslInputError) else f"{type(error).__name__}: {error}"
        return WindowPart(start=start, end=end, error=" ".join(text.split()))
    return WindowPart(start=start, end=end, checked_pairs=checked_pairs(planned.plan),
                      table=tables[0] if len(tables) == 1 else None, segment_count=len(tables),
                      messages=messages, counters=counters)


def merge_windows(job: ShotJob, options: CheckOptions, *parts: WindowPart) -> ShotOutcome:
    """The outcome of ``job`` from its windows' parts (a Dask task depending on the window tasks): what
    :func:`usdksl.scale.batch.run_job` returns for it. Never raises."""
    def merged(baseline):
        reason = _unmergeable(parts)
        if reason is None:
            core_messages = list(dict.fromkeys(message for part in parts for message in part.messages))
            counters: Dict[str, int] = {}
            for part in parts:
                for name, value in part.counters.items():
                    counters[name] = counters.get(name, 0) + value
            try:
                result = merge_parts(job.path, job.name, options, job.targets, parts, baseline,
                                     core_messages=core_messages, counters=counters)
            except UsdkslInputError as refusal:
                reason = refusal.one_line()
            else:
                ranges = ", ".join(f"{part.start:g}..{part.end:g}" for part in parts)
                result.messages.insert(0, Message(INFO, f"checked as {len(parts)} time windows: {ranges}"))
                return result
        whole.append(True)
        result = check_shot(job.path, options, job.targets, name=job.name, baseline=baseline)
        result.messages.insert(0, Message(INFO, f"checked whole, not as {len(parts)} time windows: {reason}"))
        return result

    whole: List[bool] = []
    outcome = checked_outcome(job, merged)
    outcome.windows = 1 if whole else len(parts)
    return outcome


def _unmergeable(parts: Sequence[WindowPart]) -> Optional[str]:
    """Why the parts cannot be merged (a failed window, a topology change), or None."""
    for part in parts:
        if part.error is not None:
            return f"{part.where} failed: {part.error}"
        if part.segment_count != 1:
            return f"the topology changes inside {part.where}"
    return None


__all__ = ["MIN_SAMPLES_PER_WINDOW", "WindowPart", "check_window", "merge_windows", "plan_windows",
           "shot_windows", "windows_per_shot"]
