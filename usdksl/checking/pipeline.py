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
from typing import Callable, Dict, List, Optional, Sequence, Tuple, Union

import numpy as np

from ..baseline import Baseline, BaselineComparison, compare
from ..ccd_defaults import DEFAULT_THICKNESS, DEFAULT_TOLERANCE
from ..clock import StageClock
from ..contacts import ContactTable
from ..errors import UsdkslGapError, UsdkslInputError, UsdkslUsageError
from ..exit_codes import CLEAN, CONTACTS_FOUND, CROSSCHECK_DISAGREES
from ..reading.blowups import describe_blowups, describe_glitches, shot_faults
from ..reading.interpolation import reject_spline_motion
from ..reading.loader import load_shot, mesh_prims, open_stage
from ..reading.scope import (PAIR_RIGID_ONLY, PAIR_SELF_RIGID, PAIR_SELF_STATIC, PAIR_STATIC_STATIC, Plan, ScopeOptions,
                             include_predicate, merge_plans, plan_shot, split_patterns)
from ..reading.segments import (absent_meshes, cut_range, full_range, is_topology_change, mesh_gaps, mesh_stretches,
                                topology_epochs)
from ..reports.formats import contacts_csv, json_report, mesh_pair_lines, summary_csv, summary_line
from ..reports.output import check_writable_directory, resolve_output_path
from ..reports.override import override_layer, override_layer_name, shot_stem
from ..version import package_version
from ..warning_kinds import BLOW_UP, CACHE_GLITCH, EMPTY_MESH, NOT_A_SURFACE, NOTHING_CHECKED, SPARSE_SKIN_KEYS
from .collision import METHODS, default_threads, find_contacts
from .coverage import Coverage, shot_coverage
from .memory_budget import check_memory, memory_limit, parse_memory_size, scan_shot
from .progress import Progress

# Imported where they are used, so that a plain check does not pay for them at start-up: the JUnit
# writer (xml.etree), a farm chunk's manifest (hashlib), the contact timeline and the backwards run of
# --last-contact.

TimeRange = Tuple[float, float]
#: What write_files publishes at a target: text, bytes, or None (remove the file if there is one).
FileData = Optional[Union[str, bytes]]

# Message levels: how a line is shown (``usdksl: warning: ...``) and at which verbosity (cli/check.py):
# plan and info lines with -v; results (the baseline's new and fixed contacts) and warnings by default;
# errors always.
PLAN = "plan"
INFO = "info"
RESULT = "result"
WARNING = "warning"
ERROR = "error"
#: Console verbosity (usdksl check -q, default, -v) and the least verbosity that shows each level.
QUIET = 0
NORMAL = 1
VERBOSE = 2
LEVEL_VERBOSITY = {ERROR: QUIET, WARNING: NORMAL, RESULT: NORMAL, INFO: VERBOSE, PLAN: VERBOSE}
#: Baseline lines shown by default (new face pairs, fixed entries, each); -v shows up to BASELINE_LINES_VERBOSE.
BASELINE_LINES_SHOWN = 5
BASELINE_LINES_VERBOSE = 200

#: How the progress bar of the backwards run (last contacts) is labelled; it shows reversed time codes.
REVERSE_PROGRESS_LABEL = "last contacts, reversed time"

#: CheckResult.counters entry: triangle pairs reported as contacts because the narrow phase hit its cap.
UNDECIDED_COUNTER = "undecided_triangle_pairs"


@dataclass(frozen=True)
class Message:
    """One line the check has to say: a plan line, a warning, an error found by the cross-check."""

    level: str
    text: str
    #: Stable name of what the line is about (usdksl.warning_kinds), as OpenUSD names its validators;
    #: None for lines that are not findings (plan lines, progress notes).
    kind: Optional[str] = None

    def shown(self, verbosity: int) -> bool:
        """Whether ``usdksl check`` at this verbosity prints it (LEVEL_VERBOSITY)."""
        return verbosity >= LEVEL_VERBOSITY.get(self.level, VERBOSE)

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
    #: Also check pairs in which neither mesh deforms (rigid or still against rigid or still).
    rigid: bool = False
    crosscheck: bool = False
    #: Also find each face pair's last contact by checking the shot played backwards
    #: (usdksl.checking.last_contact): a second run of the core, about as long as the first.
    last_contact: bool = False
    #: Turn warnings that mean the answer cannot be trusted (a simulation blow-up, geometry read past
    #: unchecked, nothing left to check) into input errors (exit 2), for CI. Does not change any result, so not in settings().
    strict: bool = False
    #: Threads of the core (None: every core this process may use). Does not change any result, so
    #: not in settings().
    threads: Optional[int] = None
    #: Memory the check may use: a size ("8G", bytes), "off", or None for what the machine has
    #: (usdksl.checking.memory_budget). Does not change any result, so not in settings().
    memory_limit: Optional[str] = None
    #: Check what the stage composes even when a reference, payload, sublayer or clip asset does not
    #: resolve (the coverage account names each as not checked). Off: such a stage is an input error.
    allow_missing_assets: bool = False
    #: Pose skinned meshes at their animation's keys only, instead of at every frame of the stage's range
    #: where the keys are sparser (as UsdSkel.BakeSkinning bakes them).
    skin_keys_only: bool = False

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
                "include_invisible": self.include_invisible, "rigid": self.rigid,
                "last_contact": self.last_contact, "allow_missing_assets": self.allow_missing_assets,
                "skin_keys_only": self.skin_keys_only}


@dataclass(frozen=True)
class OutputTargets:
    """Where the files of one shot go. ``json_path``/``junit_path`` None: not written; ``json_to_stdout``:
    the JSON document goes to stdout instead of a file (``--json -``)."""

    out_dir: Path
    json_path: Optional[Path] = None
    junit_path: Optional[Path] = None
    json_to_stdout: bool = False
    #: --plot: the contact timeline PNG (usdksl.reports.timeline).
    plot_path: Optional[Path] = None

    def contacts_csv(self, shot: str) -> Path:
        return self.out_dir / f"{shot_stem(shot)}.contacts.csv"

    def summary_csv(self, shot: str) -> Path:
        return self.out_dir / f"{shot_stem(shot)}.summary.csv"

    def override_layer(self, shot: str, binary: bool = False) -> Path:
        """``<stem>.usdksl.usda``, or ``.usdksl.usdc`` for a layer written as a crate file."""
        return self.out_dir / override_layer_name(shot, binary)

    def crosscheck_csv(self, shot: str) -> Path:
        return self.out_dir / f"{shot_stem(shot)}.crosscheck.csv"

    def manifest(self, shot: str) -> Path:
        from ..reports.manifest import manifest_name

        return self.out_dir / manifest_name(shot_stem(shot))


def output_targets(shot: str, out: Optional[str] = None, json_path: Optional[str] = None,
                   junit_path: Optional[str] = None, plot_path: Optional[str] = None) -> OutputTargets:
    """Resolve and check the output locations before any work is done: ``out`` defaults to the shot's
    folder; ``json_path`` '-' means stdout. Raises UsdkslInputError for a missing shot and
    UsdkslUsageError for a folder that cannot be written."""
    if not os.path.isfile(shot):
        open_stage(shot)   # a missing input is reported as such, before anything about the output folder
    out_dir = Path(out) if out else Path(shot).resolve().parent
    check_writable_directory(out_dir)
    extra = [resolve_output_path(value) for value in (json_path, junit_path, plot_path)]
    for target in extra:
        if target is not None:
            check_writable_directory(target.resolve().parent)
    if plot_path is not None:
        from ..reports.timeline import require_matplotlib

        require_matplotlib()
    return OutputTargets(out_dir=out_dir, json_path=extra[0], junit_path=extra[1],
                         json_to_stdout=json_path == "-", plot_path=extra[2])


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
    #: {target: text, bytes (a crate file, a PNG) or None (a stale file of ours to remove)}
    files: Dict[Path, "FileData"]
    stdout: Optional[str] = None
    segments: List[Tuple[Optional[TimeRange], ContactTable]] = field(default_factory=list)
    #: Frames and seconds of the shot's time codes (its stage metadata).
    clock: StageClock = StageClock()
    #: The contacts held against a baseline (None without one).
    baseline: Optional[BaselineComparison] = None
    #: Threads the core ran with (options.threads, or every core of the process that checked).
    threads: int = 1
    #: Every prim and stretch of the checked range, checked or not, with why (usdksl.checking.coverage).
    coverage: Optional[Coverage] = None

    @property
    def undecided(self) -> int:
        """Triangle pairs the narrow phase could not separate within the tolerance (reported as contacts)."""
        return self.counters.get(UNDECIDED_COUNTER, 0)

    @property
    def line(self) -> str:
        """The shot's line on the console: ``usdksl: SHOT: <summary>``."""
        return f"usdksl: {self.shot}: {self.summary[len('usdksl: '):]}"

    @property
    def summary(self) -> str:
        """The final line of ``usdksl check``."""
        return summary_line(self.table, self.plan, self.span, self.seconds, self.clock,
                            None if self.baseline is None else self.baseline.known,
                            None if self.baseline is None else self.baseline.fixed_count,
                            "" if self.coverage is None else self.coverage.summary_phrase())


#: progress(start, end, label="") -> callback(time_reached, contacts_so_far), e.g. usdksl.checking.progress.Progress
ProgressFactory = Callable[..., Callable[[float, int], None]]


def check_shot(shot: str, options: CheckOptions = CheckOptions(), targets: Optional[OutputTargets] = None,
               on_message: Optional[Callable[[Message], None]] = None,
               progress: Optional[ProgressFactory] = None, name: Optional[str] = None,
               baseline: Optional[Baseline] = None) -> CheckResult:
    """Check ``shot`` (a USD file) and render its reports; write nothing.

    ``baseline`` (usdksl.checking.baseline): contacts it knows do not count for the exit code; the
    reports mark each contact new or known and list the entries that no longer occur.

    ``name`` is how reports and messages name the shot (default: ``shot``; a Dask worker reads an absolute
    path but names the shot as the user gave it).
    ``targets`` says where the files would go (default: beside the shot, no JSON or JUnit); it only
    names them (the override layer sublayers the shot by a path relative to its folder). ``on_message``
    receives each plan line and warning as it is known (they are also in ``result.messages``).
    ``progress(start, end, label="")`` makes the progress callback of the core for the checked span (an
    object with an optional ``close()``); with ``last_contact`` a second one follows the backwards run. Raises UsdkslInputError / UsdkslUsageError on bad input.
    """
    started = time.monotonic()
    name = name or shot
    options.validate()
    targets = targets or OutputTargets(out_dir=Path(shot).resolve().parent)
    messages: List[Message] = []
    say = message_collector(messages, on_message)
    planned = load_and_plan(shot, options, name, say)
    report_blowups(planned.segments, planned.plans, name, say, options.strict)
    span = checked_span(options, planned.segments)
    bar = progress(span[0], span[1]) if progress is not None else None
    # the backwards run of --last-contact goes from -end to -start
    reverse_bar = (progress(-span[1], -span[0], label=REVERSE_PROGRESS_LABEL)
                   if progress is not None and options.last_contact else None)
    tables = []
    counters: Dict[str, int] = {}
    try:
        for (segment_range, segment), segment_plan in zip(planned.segments, planned.plans):
            contacts_before = sum(table.count for table in tables)
            report = None if not _shown(bar) else (
                lambda reached, count, before=contacts_before: bar(reached, before + count))
            reverse_report = None if not _shown(reverse_bar) else (
                lambda reached, count, before=contacts_before: reverse_bar(reached, before + count))
            tables.append(check_segment(segment, segment_plan, segment_range, options, report, say, counters,
                                        reverse_report))
    finally:
        for shown in (bar, reverse_bar):
            if shown is not None and hasattr(shown, "close"):
                shown.close()
    return conclude(shot, name, options, targets, planned, tables, span, counters, messages, say, baseline,
                    started)


def _shown(bar) -> bool:
    """Whether the core should hand its progress to ``bar``: not to a usdksl Progress that is not drawn (in
    CI, in a pipe), whose calls change nothing anyone sees. Each call takes the GIL from the core's
    threads, which costs them time when the machine is busy; without one the core still calls back as
    often to check for Ctrl-C, SIGTERM and --timeout (usdksl.stopping)."""
    return bar is not None and not (isinstance(bar, Progress) and not bar.enabled)


def message_collector(messages: List[Message],
                      on_message: Optional[Callable[[Message], None]] = None) -> Callable[..., None]:
    """say(level, text, kind=None): append the Message to ``messages`` and hand it to ``on_message``."""
    def say(level: str, text: str, kind: Optional[str] = None) -> None:
        message = Message(level, text, kind)
        messages.append(message)
        if on_message is not None:
            on_message(message)
    return say


@dataclass
class PlannedShot:
    """A shot loaded for checking: its constant-topology segments [(range, loaded Shot)] (usdksl.reading),
    the plan of each and their merged plan."""

    segments: list
    plans: List[Plan]
    plan: Plan
    #: Gaps of meshes that cannot be followed across some samples (usdksl.reading.segments.Gap).
    gaps: list = field(default_factory=list)
    #: Every prim and stretch, checked or not (usdksl.checking.coverage).
    coverage: Optional[Coverage] = None


def load_and_plan(shot: str, options: CheckOptions, name: str, say: Callable[..., None],
                  require_pairs: bool = True) -> PlannedShot:
    """Load ``shot`` over ``options.time_range`` (the whole shot when None) and plan what is checked; says
    the loader's warnings, the plan lines and the coverage account. Raises UsdkslInputError on bad input (spline
    motion included), when ``options.time_range`` holds no sample, and when no mesh pair is left to check (except
    in a time range where nothing moves, or with ``require_pairs`` False: a Dask window, planned whole later)."""
    include, excluded = options.patterns()
    predicate = include_predicate(include, excluded) if (include or excluded) else None
    # its open stage makes the loader's open free
    size = scan_shot(shot, options.time_range, predicate, skin_keys_only=options.skin_keys_only)
    check_memory(size, options.method, memory_limit(options.memory_limit), file=name,
                 threads=options.threads or default_threads())
    segments, gaps = load_segments(shot, options.time_range, predicate, say, name, options.strict,
                             allow_missing_assets=options.allow_missing_assets, skin_keys_only=options.skin_keys_only)
    del size
    require_samples_in_range(segments[0][1], options.time_range, name)
    for warning in dict.fromkeys(w for _, segment in segments for w in segment.warnings):
        say(WARNING, warning)
    # an empty mesh holds no surface a contact could be with: named, but nothing is missed without it
    unchecked = [item for _, segment in segments for item in segment.unchecked
                 if item.kind not in (EMPTY_MESH, NOT_A_SURFACE)]
    if options.strict and unchecked:
        raise UsdkslInputError(f"{unchecked[0].reason} (--strict)", file=name, prim=unchecked[0].prim)
    scope = ScopeOptions(self_check=options.self_check, inter_check=options.inter_check, include=(), exclude=(),
                         include_guides=options.include_guides, include_invisible=options.include_invisible,
                         rigid=options.rigid)
    plans = []
    for segment_range, segment in segments:
        reject_spline_motion(segment.stage, list(dict.fromkeys(
            path for mesh in segment.meshes for path in (mesh.prim_path, mesh.scene_path))), file=name)
        segment_plan = plan_shot(segment, scope, segment_range)
        if predicate is not None:
            segment_plan.excluded_paths = list(dict.fromkeys(predicate.rejected))
        if len(segments) > 1:
            say(PLAN, f"segment {segment_range[0]:g}..{segment_range[1]:g}:")
        for line in segment_plan.describe():
            say(PLAN, line.strip() if line.startswith("pairs") else line)
        plans.append(segment_plan)
    plan = merge_plans(plans)
    if not plan.checked_pairs and require_pairs:
        still = {PAIR_STATIC_STATIC, PAIR_SELF_STATIC, PAIR_SELF_RIGID, PAIR_RIGID_ONLY}
        if (options.time_range is None or options.strict or plan.skipped_meshes or plan.excluded_paths
                or not all(reason in still for _, _, reason in plan.skipped_pairs)):
            raise UsdkslInputError("no mesh pair left to check: nothing would be checked (-v shows the plan)",
                                   file=name)
        # a farm chunk in which the cloth rests: its motion on either side is in the neighbouring chunks
        say(WARNING, f"nothing moves over {options.time_range[0]:g}..{options.time_range[1]:g}: no pair needs a check",
            NOTHING_CHECKED)
    coverage = shot_coverage(segments, plans, plan, gaps, checked_span(options, segments), options.time_range)
    for note in dict.fromkeys(n for _, segment in segments for n in segment.notes):
        say(INFO, note, SPARSE_SKIN_KEYS)
    for line in coverage.lines():
        say(PLAN, line)
    return PlannedShot(segments=segments, plans=plans, plan=plan, gaps=gaps, coverage=coverage)


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


def conclude(shot: str, name: str, options: CheckOptions, targets: OutputTargets, planned: PlannedShot,
             tables: Sequence[ContactTable], span: TimeRange, counters: Dict[str, int], messages: List[Message],
             say: Callable[[str, str], None], baseline: Optional[Baseline], started: float) -> CheckResult:
    """The result of a check from the contacts of each segment (``tables``): held against ``baseline``,
    cross-checked when asked, every report rendered. Says what a finished check says."""
    plan = planned.plan
    table = concatenate_pieces(planned.segments, tables)
    clock = StageClock.from_metadata(planned.segments[0][1].metadata)
    comparison = None
    if baseline is not None:
        comparison = compare(table, baseline)
        for level, text in baseline_messages(comparison, clock):
            say(level, text)
    for text in mesh_pair_lines(table, clock, None if comparison is None else comparison.known):
        say(INFO, text)

    exit_code = CONTACTS_FOUND if (comparison.new_count if comparison else table.count) else CLEAN
    crosscheck_text = None
    if options.crosscheck:
        crosscheck_text, consistent = _crosscheck(planned.segments, planned.plans, tables, say)
        if not consistent:
            exit_code = CROSSCHECK_DISAGREES
    findings = [{"level": message.level, "kind": message.kind, "text": message.text} for message in messages
                if message.level in (WARNING, ERROR) or message.kind is not None]
    files, stdout = render_files(shot, name, options, targets, planned.segments, plan, tables, exit_code, span,
                                 crosscheck_text, comparison, planned.coverage, findings)
    return CheckResult(shot=name, options=options, exit_code=exit_code, table=table, plan=plan, span=span,
                       seconds=time.monotonic() - started, counters=counters,
                       messages=messages, files=files, stdout=stdout,
                       segments=[(r, t) for (r, _), t in zip(planned.segments, tables)], clock=clock,
                       baseline=comparison, threads=options.threads or default_threads(), coverage=planned.coverage)


def render_files(shot: str, name: str, options: CheckOptions, targets: OutputTargets, segments, plan: Plan,
                 tables: Sequence[ContactTable], exit_code: int, span: TimeRange,
                 crosscheck_text: Optional[str] = None,
                 comparison: Optional[BaselineComparison] = None, coverage: Optional[Coverage] = None,
                 findings: Optional[list] = None) -> Tuple[Dict[Path, FileData], Optional[str]]:
    """({target: text or bytes} of every file of a check, None for a file to remove; the JSON text for
    stdout or None), in write order.

    ``segments``: [(range, loaded Shot)] as :func:`load_segments` gives them, ``tables`` the contacts of
    each. A run over a time range (a farm chunk) also writes its manifest (usdksl.reports.manifest)."""
    table = concatenate_pieces(segments, tables)
    clock = StageClock.from_metadata(segments[0][1].metadata)
    files: Dict[Path, FileData] = {}
    known = None if comparison is None else comparison.known
    files[targets.contacts_csv(shot)] = contacts_csv(table, clock, known)
    files[targets.summary_csv(shot)] = summary_csv(table, clock, known)
    if crosscheck_text is not None:
        files[targets.crosscheck_csv(shot)] = crosscheck_text
    checked_meshes = sorted(set(plan.pairs.reshape(-1).tolist()))
    layer = override_layer(segments[0][1], checked_meshes, table, targets.override_layer(shot),
                           segments=[(r, seg, t) for (r, seg), t in zip(segments, tables)] if len(segments) > 1
                           else None, span=span)
    files[targets.override_layer(shot, layer.binary)] = layer.data()
    files[targets.override_layer(shot, not layer.binary)] = None   # a layer of the other format is stale
    if options.time_range is not None:
        from ..reports.manifest import file_sha256, manifest_text

        files[targets.manifest(shot)] = manifest_text(name, file_sha256(shot), options.settings(), span, plan,
                                                      len(segments), package_version())
    stdout = None
    if targets.json_path is not None or targets.json_to_stdout:
        json_text = json_report(name, options.settings(), plan, table, exit_code, clock,
                                version=package_version(),
                                baseline=None if comparison is None else comparison.to_dict(), known=known,
                                coverage=None if coverage is None else coverage.to_dict(), findings=findings)
        if targets.json_path is not None:
            files[targets.json_path] = json_text
        else:
            stdout = json_text
    if targets.junit_path is not None:
        from ..reports.junit import junit_report

        files[targets.junit_path] = junit_report(name, plan, table, clock, known)
    if targets.plot_path is not None:
        if table.last_time is None:
            raise UsdkslUsageError("the contact timeline needs last contacts (CheckOptions(last_contact=True))")
        from ..reports.timeline import timeline_png

        files[targets.plot_path] = timeline_png(table, clock, span, name, known)
    return files, stdout


def concatenate_pieces(segments, tables: Sequence[ContactTable]) -> ContactTable:
    """The contacts of a shot checked in pieces ([(range, Shot)], usdksl.reading.segments) as one table: a face
    pair whose meshes keep their faces across pieces is reported once, at its first contact."""
    if len(tables) == 1:
        return tables[0]
    return ContactTable.concatenate(list(tables), topology_epochs([shot for _, shot in segments]))


def baseline_messages(comparison: BaselineComparison, clock: StageClock) -> List[Tuple[str, str]]:
    """(level, text) lines naming new face pairs and fixed baseline entries: BASELINE_LINES_SHOWN of each
    as RESULT lines, then up to BASELINE_LINES_VERBOSE as INFO lines (shown with -v), then a count."""
    lines: List[Tuple[str, str]] = []
    table = comparison.table
    new_rows = np.flatnonzero(~comparison.known)[:BASELINE_LINES_VERBOSE]
    if new_rows.size:
        prim_a, prim_b = table.prim_names()
        for shown, row in enumerate(new_rows.tolist()):
            lines.append((RESULT if shown < BASELINE_LINES_SHOWN else INFO,
                          f"new: {prim_a[row]} face {int(table.face_a[row])} x {prim_b[row]} face "
                          f"{int(table.face_b[row])}, first at {clock.describe(float(table.time[row]))}"))
    for shown, entry in enumerate(comparison.fixed[:BASELINE_LINES_VERBOSE].tolist()):
        lines.append((RESULT if shown < BASELINE_LINES_SHOWN else INFO,
                      f"fixed (in the baseline, no longer found): {comparison.baseline.describe(entry)}"))
    for count, listed, what in ((comparison.new_count, new_rows.size, "new face pairs"),
                                (comparison.fixed_count, min(comparison.fixed_count, BASELINE_LINES_VERBOSE),
                                 "fixed baseline entries")):
        if count > BASELINE_LINES_SHOWN:
            lines.append((RESULT, f"{count} {what} in all; -v lists {listed}, the reports list all"))
    return lines


def report_blowups(segments, plans: Sequence[Plan], name: str, say: Callable[..., None],
                   strict: bool) -> None:
    """Warn about vertices of checked meshes that blow up and about checked meshes, or most of one, that
    jump away and back (cache glitches; usdksl.reading.blowups); under ``strict`` the first glitch, else
    the first blow-up, is an input error (exit 2, nothing written)."""
    for (_, segment), segment_plan in zip(segments, plans):
        checked = sorted(set(segment_plan.pairs.reshape(-1).tolist()))
        blowups, glitches = shot_faults([segment.meshes[index] for index in checked])
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


def load_segments(shot: str, time_range: Optional[TimeRange], predicate, say: Callable[..., None],
                  name: Optional[str] = None, strict: bool = False, allow_missing_assets: bool = False,
                  skin_keys_only: bool = False):
    """([(range, Shot)], gaps): the whole shot, or, when a mesh cannot be followed across some samples (a topology
    change, an empty or blocked points sample), one Shot per piece of the range cut at every such gap
    (usdksl.reading.segments), the meshes a gap covers loaded still and left out there. Warns once per gap (an
    input error under ``strict``: the gap is not checked); ``range`` is None when the whole shot is checked
    without a time range. ``gaps``: usdksl.reading.segments.Gap of every mesh that has them."""
    name = name or shot
    options = dict(include=predicate, allow_missing_assets=allow_missing_assets, skin_keys_only=skin_keys_only)
    try:
        return [(time_range, load_shot(shot, time_range=time_range, **options))], []
    except (UsdkslGapError, UsdkslInputError) as error:
        if not (isinstance(error, UsdkslGapError) or is_topology_change(error)):
            raise
        first_error = error
    stage = open_stage(shot)
    prims = mesh_prims(stage, predicate)
    stretches = {str(prim.GetPath()): mesh_stretches(prim) for prim in prims}
    full = full_range((np.array([s.first for s in found] + [s.last for s in found]) for found in stretches.values()),
                      time_range)
    gaps = [gap for path, found in stretches.items() for gap in mesh_gaps(path, found)
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
    return [(piece, load_shot(shot, time_range=piece, absent=absent_meshes(piece, gaps, stretches), **options))
            for piece in pieces], gaps


def check_segment(segment, plan: Plan, segment_range: Optional[TimeRange], options: CheckOptions,
                  progress: Optional[Callable[[float, int], None]] = None,
                  say: Optional[Callable[[str, str], None]] = None,
                  counters: Optional[Dict[str, int]] = None,
                  reverse_progress: Optional[Callable[[float, int], None]] = None) -> ContactTable:
    """Face contacts of one constant-topology stretch (with last contacts when ``options.last_contact``;
    ``reverse_progress`` then follows the backwards run in reversed time). Adds the core's work counters
    (and UNDECIDED_COUNTER) to ``counters`` and warns through ``say`` about undecided triangle pairs."""
    paths = [mesh.path for mesh in segment.meshes]
    if not plan.checked_pairs:
        return ContactTable.empty(paths)
    result = find_contacts(segment.meshes, plan.pairs, method=options.method, time_range=segment_range,
                           tolerance=options.tolerance, thickness=options.thickness, progress=progress,
                           threads=options.threads)
    undecided = int(np.count_nonzero(result.undecided))
    if counters is not None:
        for name, value in list(result.counters.items()) + [(UNDECIDED_COUNTER, undecided)]:
            counters[name] = counters.get(name, 0) + int(value)
    if undecided and say is not None:
        say(WARNING, f"{undecided} triangle pairs could not be separated within the tolerance "
                     f"and are reported as contacts (conservative)")
    table = result.face_contacts(segment.meshes)
    if not options.last_contact:
        return table
    from .last_contact import last_contacts

    last = last_contacts(segment.meshes, plan.pairs, table, segment_range, options.method, options.tolerance,
                         options.thickness, progress=reverse_progress, threads=options.threads)
    if say is not None and last.missing_in_reverse:
        say(WARNING, f"{last.missing_in_reverse} face pairs were not found played backwards; their last "
                     f"contact is reported at their first")
    if say is not None and last.only_in_reverse:
        say(WARNING, f"{last.only_in_reverse} face pairs touch played backwards but not forwards; the "
                     f"forward (first-contact) result is reported")
    return table.with_last_times(last.last_time)


def _crosscheck(segments, plans: Sequence[Plan], tables: Sequence[ContactTable], say) -> Tuple[str, bool]:
    """Embree at every sample against the contacts just found, per constant-topology segment:
    (crosscheck.csv text, whether every segment agrees)."""
    from ..crosscheck.shot import crosscheck_shot   # Embree is loaded only when asked for

    results = [crosscheck_shot(segment, contacts=segment_table, pairs=segment_plan.pairs, time_range=segment_range)
               for (segment_range, segment), segment_plan, segment_table in zip(segments, plans, tables)]
    for result in results:
        for line in result.error_lines():
            say(ERROR, line)
        say(RESULT, result.summary_line())
    text = "".join(part if index == 0 else part.split("\n", 1)[1]
                   for index, part in enumerate(result.csv_text() for result in results))
    return text, all(result.consistent for result in results)
