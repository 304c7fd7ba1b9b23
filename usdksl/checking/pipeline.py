"""The check of one shot as a library call: load, scope, find first contacts, render every report.

:func:`check_shot` does the work of ``usdksl check`` for one shot (or one time window of it) and returns
a :class:`CheckResult`: the contacts, the plan, the counters, the exit code, the messages (plan lines and
warnings, as data) and the text of every output file. It writes nothing; :func:`usdksl.reports.output.
write_files` publishes ``result.files`` all together. The CLI, the benchmarks and Dask workers call the
same function; a result is plain data (numpy arrays, strings, paths), so it pickles.
"""

from __future__ import annotations

import os
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable, Dict, List, Optional, Sequence, Tuple

import numpy as np

from ..ccd import DEFAULT_THICKNESS, DEFAULT_TOLERANCE
from ..contacts import ContactTable
from ..errors import UsdkslInputError, UsdkslUsageError
from ..exit_codes import CLEAN, CONTACTS_FOUND, CROSSCHECK_DISAGREES
from ..reading.blowups import describe_blowups, shot_blowups
from ..reading.interpolation import reject_spline_motion
from ..reading.loader import load_shot, mesh_prims, open_stage
from ..reading.scope import Plan, ScopeOptions, include_predicate, merge_plans, plan_shot, split_patterns
from ..reading.segments import full_range, is_topology_change, split_range, topology_gaps
from ..reports.formats import contacts_csv, json_report, junit_report, summary_csv, summary_line
from ..reports.output import check_writable_directory, resolve_output_path
from ..reports.override import build_override_layer, shot_stem
from ..version import __version__
from .collision import METHODS, find_contacts
from .memory_budget import check_memory, memory_limit, parse_memory_size, scan_shot

TimeRange = Tuple[float, float]

# Message levels: how a line is shown (``usdksl: warning: ...``) and whether a batch of shots shows it.
PLAN = "plan"
INFO = "info"
WARNING = "warning"
ERROR = "error"

#: CheckResult.counters entry: triangle pairs reported as contacts because the narrow phase hit its cap.
UNDECIDED_COUNTER = "undecided_triangle_pairs"


@dataclass(frozen=True)
class Message:
    """One line the check has to say: a plan line, a warning, an error found by the cross-check."""

    level: str
    text: str

    def line(self, shot: Optional[str] = None) -> str:
        """As ``usdksl check`` prints it on stderr (after the shot's name when it checks several)."""
        prefix = f"{self.level}: " if self.level in (WARNING, ERROR) else ""
        return f"usdksl: {shot + ': ' if shot else ''}{prefix}{self.text}"


@dataclass(frozen=True)
class CheckOptions:
    """What ``usdksl check`` is asked to do, without the output locations. Times in USD time codes;
    ``tolerance`` a fraction of one sample interval; ``thickness`` in scene units."""

    method: str = "ksl"
    tolerance: float = DEFAULT_TOLERANCE
    thickness: float = DEFAULT_THICKNESS
    self_check: bool = True
    inter_check: bool = True
    time_range: Optional[TimeRange] = None
    prims: Tuple[str, ...] = ()
    exclude: Tuple[str, ...] = ()
    include_guides: bool = False
    include_invisible: bool = False
    crosscheck: bool = False
    #: Turn warnings that mean the answer cannot be trusted (a simulation blow-up, nothing left to
    #: check) into input errors (exit 2), for CI. Does not change any result, so not in settings().
    strict: bool = False
    #: Memory the check may use: a size ("8G", bytes), "off", or None for what the machine has
    #: (usdksl.checking.memory_budget). Does not change any result, so not in settings().
    memory_limit: Optional[str] = None

    def validate(self) -> None:
        """Raise UsdkslUsageError (exit 2) on a value the check cannot use."""
        parse_memory_size(self.memory_limit)
        if self.method not in METHODS:
            raise UsdkslUsageError(f"--method must be one of {', '.join(METHODS)}, got {self.method!r}")
        if not self.tolerance > 0:
            raise UsdkslUsageError(f"--tolerance must be positive, got {self.tolerance!r}")
        if not self.thickness >= 0:
            raise UsdkslUsageError(f"--thickness must be zero or positive, got {self.thickness!r}")

    def patterns(self) -> Tuple[Tuple[str, ...], Tuple[str, ...]]:
        """(include, exclude) prim patterns, a leading '!' in --prims moved to the excludes."""
        return split_patterns(self.prims, self.exclude)

    def settings(self) -> dict:
        """The ``settings`` object of the JSON report (and of a chunk's manifest)."""
        include, excluded = self.patterns()
        return {"method": self.method, "tolerance": self.tolerance, "thickness": self.thickness,
                "self": self.self_check, "inter": self.inter_check,
                "time_range": list(self.time_range) if self.time_range else None,
                "prims": list(include), "exclude": list(excluded), "include_guides": self.include_guides,
                "include_invisible": self.include_invisible}


@dataclass(frozen=True)
class OutputTargets:
    """Where the files of one shot go. ``json_path``/``junit_path`` None: not written; ``json_to_stdout``:
    the JSON document goes to stdout instead of a file (``--json -``)."""

    out_dir: Path
    json_path: Optional[Path] = None
    junit_path: Optional[Path] = None
    json_to_stdout: bool = False

    def contacts_csv(self, shot: str) -> Path:
        return self.out_dir / f"{shot_stem(shot)}.contacts.csv"

    def summary_csv(self, shot: str) -> Path:
        return self.out_dir / f"{shot_stem(shot)}.summary.csv"

    def override_layer(self, shot: str) -> Path:
        return self.out_dir / f"{shot_stem(shot)}.usdksl.usda"

    def crosscheck_csv(self, shot: str) -> Path:
        return self.out_dir / f"{shot_stem(shot)}.crosscheck.csv"


def output_targets(shot: str, out: Optional[str] = None, json_path: Optional[str] = None,
                   junit_path: Optional[str] = None) -> OutputTargets:
    """Resolve and check the output locations before any work is done: ``out`` defaults to the shot's
    folder; ``json_path`` '-' means stdout. Raises UsdkslInputError for a missing shot and
    UsdkslUsageError for a folder that cannot be written."""
    if not os.path.isfile(shot):
        open_stage(shot)   # a missing input is reported as such, before anything about the output folder
    out_dir = Path(out) if out else Path(shot).resolve().parent
    check_writable_directory(out_dir)
    extra = [resolve_output_path(value) for value in (json_path, junit_path)]
    for target in extra:
        if target is not None:
            check_writable_directory(target.resolve().parent)
    return OutputTargets(out_dir=out_dir, json_path=extra[0], junit_path=extra[1],
                         json_to_stdout=json_path == "-")


@dataclass
class CheckResult:
    """Everything one check found and would write; plain data (pickles for Dask)."""

    shot: str
    options: CheckOptions
    exit_code: int
    table: ContactTable
    plan: Plan
    span: TimeRange
    seconds: float
    counters: Dict[str, int]
    messages: List[Message]
    files: Dict[Path, str]
    stdout: Optional[str] = None
    segments: List[Tuple[Optional[TimeRange], ContactTable]] = field(default_factory=list)

    @property
    def undecided(self) -> int:
        """Triangle pairs the narrow phase could not separate within the tolerance (reported as contacts)."""
        return self.counters.get(UNDECIDED_COUNTER, 0)

    @property
    def summary(self) -> str:
        """The final line of ``usdksl check``."""
        return summary_line(self.table, self.plan, self.span, self.seconds)


ProgressFactory = Callable[[float, float], Callable[[float, int], None]]


def check_shot(shot: str, options: CheckOptions = CheckOptions(), targets: Optional[OutputTargets] = None,
               on_message: Optional[Callable[[Message], None]] = None,
               progress: Optional[ProgressFactory] = None, name: Optional[str] = None) -> CheckResult:
    """Check ``shot`` (a USD file) and render its reports; write nothing.

    ``name`` is how reports and messages name the shot (default: ``shot``; a Dask worker reads an absolute
    path but names the shot as the user gave it).
    ``targets`` says where the files would go (default: beside the shot, no JSON or JUnit); it only
    names them (the override layer sublayers the shot by a path relative to its folder). ``on_message``
    receives each plan line and warning as it is known (they are also in ``result.messages``).
    ``progress(start, end)`` makes the progress callback of the core for the checked span (an object
    with an optional ``close()``). Raises UsdkslInputError / UsdkslUsageError on bad input.
    """
    started = time.monotonic()
    name = name or shot
    options.validate()
    targets = targets or OutputTargets(out_dir=Path(shot).resolve().parent)
    messages: List[Message] = []

    def say(level: str, text: str) -> None:
        message = Message(level, text)
        messages.append(message)
        if on_message is not None:
            on_message(message)

    include, excluded = options.patterns()
    predicate = include_predicate(include, excluded) if (include or excluded) else None
    size = scan_shot(shot, options.time_range, predicate)   # its open stage makes the loader's open free
    check_memory(size, options.method, memory_limit(options.memory_limit), file=name)
    segments = load_segments(shot, options.time_range, predicate, say, name)
    del size
    loaded = segments[0][1]
    scope = ScopeOptions(self_check=options.self_check, inter_check=options.inter_check, include=(), exclude=(),
                         include_guides=options.include_guides, include_invisible=options.include_invisible)
    plans = []
    for segment_range, segment in segments:
        reject_spline_motion(segment.stage, [mesh.path for mesh in segment.meshes], file=name)
        segment_plan = plan_shot(segment, scope, segment_range)
        if predicate is not None:
            segment_plan.excluded_paths = list(dict.fromkeys(predicate.rejected))
        if len(segments) > 1:
            say(PLAN, f"segment {segment_range[0]:g}..{segment_range[1]:g}:")
        for line in segment_plan.describe():
            say(PLAN, line.strip() if line.startswith("pairs") else line)
        plans.append(segment_plan)
    plan = merge_plans(plans)
    report_blowups(segments, plans, name, say, options.strict)
    if options.strict and not plan.checked_pairs:
        raise UsdkslInputError("no mesh pair left to check (--strict)", file=name)

    if options.time_range is not None:
        span = options.time_range
    else:
        all_times = np.concatenate([segment.times for _, segment in segments])
        span = (float(all_times.min()), float(all_times.max())) if all_times.size else (0.0, 0.0)
    bar = progress(span[0], span[1]) if progress is not None else None
    tables = []
    counters: Dict[str, int] = {}
    try:
        for (segment_range, segment), segment_plan in zip(segments, plans):
            contacts_before = sum(table.count for table in tables)
            report = None if bar is None else (
                lambda reached, count, before=contacts_before: bar(reached, before + count))
            tables.append(check_segment(segment, segment_plan, segment_range, options, report, say, counters))
    finally:
        if bar is not None and hasattr(bar, "close"):
            bar.close()
    if not plan.checked_pairs:
        say(WARNING, "no mesh pair left to check")
    table = ContactTable.concatenate(tables)

    exit_code = CONTACTS_FOUND if table.count else CLEAN
    files: Dict[Path, str] = {}
    files[targets.contacts_csv(shot)] = contacts_csv(table)
    files[targets.summary_csv(shot)] = summary_csv(table)
    if options.crosscheck:
        crosscheck_text, consistent = _crosscheck(segments, plans, tables, say)
        files[targets.crosscheck_csv(shot)] = crosscheck_text
        if not consistent:
            exit_code = CROSSCHECK_DISAGREES
    layer_path = targets.override_layer(shot)
    checked_meshes = sorted(set(plan.pairs.reshape(-1).tolist()))
    files[layer_path] = build_override_layer(
        loaded, checked_meshes, table, layer_path,
        segments=[(r, seg, t) for (r, seg), t in zip(segments, tables)] if len(segments) > 1 else None)
    stdout = None
    if targets.json_path is not None or targets.json_to_stdout:
        json_text = json_report(name, options.settings(), plan, table, exit_code, version=__version__)
        if targets.json_path is not None:
            files[targets.json_path] = json_text
        else:
            stdout = json_text
    if targets.junit_path is not None:
        files[targets.junit_path] = junit_report(name, plan, table)
    return CheckResult(shot=name, options=options, exit_code=exit_code, table=table, plan=plan, span=span,
                       seconds=time.monotonic() - started, counters=counters,
                       messages=messages, files=files, stdout=stdout,
                       segments=[(r, t) for (r, _), t in zip(segments, tables)])


def report_blowups(segments, plans: Sequence[Plan], name: str, say: Callable[[str, str], None],
                   strict: bool) -> None:
    """Warn about vertices of checked meshes that blow up (usdksl.reading.blowups); under ``strict``
    the first one is an input error (exit 2, nothing written)."""
    for (_, segment), segment_plan in zip(segments, plans):
        checked = sorted(set(segment_plan.pairs.reshape(-1).tolist()))
        blowups = shot_blowups([segment.meshes[index] for index in checked])
        if blowups and strict:
            first = blowups[0]
            raise UsdkslInputError(
                f"vertex {first.vertex} blows up between time {first.time_before:g} and {first.time_after:g} "
                f"({first.excess:.3g} units beyond the mesh's motion; --strict)", file=name, prim=first.prim)
        for line in describe_blowups(blowups, name):
            say(WARNING, line)


def load_segments(shot: str, time_range: Optional[TimeRange], predicate, say: Callable[[str, str], None],
                  name: Optional[str] = None):
    """[(range, Shot)]: the whole shot, or one Shot per constant-topology stretch (usdksl.reading.segments)
    with a warning per topology change; ``range`` is None when the whole shot is checked without a
    time range."""
    try:
        return [(time_range, load_shot(shot, time_range=time_range, include=predicate))]
    except UsdkslInputError as error:
        if not is_topology_change(error):
            raise
        stage = open_stage(shot)
        paths = [str(prim.GetPath()) for prim in mesh_prims(stage, predicate)]
        gaps = topology_gaps(stage, paths)
        ranges = split_range(full_range(stage, paths, time_range), gaps)
        if not gaps or not ranges:
            raise
    for gap_start, gap_end, path in gaps:
        say(WARNING, f"{name or shot}: {path}: topology changes between time {gap_start:g} and {gap_end:g}; "
                     f"that interval is not checked")
    say(WARNING, f"checking {len(ranges)} constant-topology segments: "
                 + ", ".join(f"{a:g}..{b:g}" for a, b in ranges))
    return [(segment_range, load_shot(shot, time_range=segment_range, include=predicate))
            for segment_range in ranges]


def check_segment(segment, plan: Plan, segment_range: Optional[TimeRange], options: CheckOptions,
                  progress: Optional[Callable[[float, int], None]] = None,
                  say: Optional[Callable[[str, str], None]] = None,
                  counters: Optional[Dict[str, int]] = None) -> ContactTable:
    """Face contacts of one constant-topology stretch. Adds the core's work counters (and
    UNDECIDED_COUNTER) to ``counters`` and warns through ``say`` about undecided triangle pairs."""
    paths = [mesh.path for mesh in segment.meshes]
    if not plan.checked_pairs:
        return ContactTable.empty(paths)
    result = find_contacts(segment.meshes, plan.pairs, method=options.method, time_range=segment_range,
                           tolerance=options.tolerance, thickness=options.thickness, progress=progress)
    undecided = int(np.count_nonzero(result.undecided))
    if counters is not None:
        for name, value in list(result.counters.items()) + [(UNDECIDED_COUNTER, undecided)]:
            counters[name] = counters.get(name, 0) + int(value)
    if undecided and say is not None:
        say(WARNING, f"{undecided} triangle pairs could not be separated within the tolerance "
                     f"and are reported as contacts (conservative)")
    return result.face_contacts(segment.meshes)


def _crosscheck(segments, plans: Sequence[Plan], tables: Sequence[ContactTable], say) -> Tuple[str, bool]:
    """Embree at every sample against the contacts just found, per constant-topology segment:
    (crosscheck.csv text, whether every segment agrees)."""
    from ..crosscheck.shot import crosscheck_shot   # Embree is loaded only when asked for

    results = [crosscheck_shot(segment, contacts=segment_table, pairs=segment_plan.pairs, time_range=segment_range)
               for (segment_range, segment), segment_plan, segment_table in zip(segments, plans, tables)]
    for result in results:
        for line in result.error_lines():
            say(ERROR, line)
        say(INFO, result.summary_line())
    text = "".join(part if index == 0 else part.split("\n", 1)[1]
                   for index, part in enumerate(result.csv_text() for result in results))
    return text, all(result.consistent for result in results)
