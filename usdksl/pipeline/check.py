"""The check of one shot as a library call: load, scope, find first contacts, render every report.

:func:`check_shot` does the work of ``usdksl check`` for one shot (or one time window of it) and returns
a :class:`~usdksl.pipeline.result.CheckResult`: the contacts, the plan, the counters, the exit code, the
messages (plan lines and warnings, as data) and the text of every output file. It writes nothing;
:func:`usdksl.reports.output.write_files` publishes ``result.files`` all together. The CLI, the benchmarks
and Dask workers call the same function; a result is plain data (numpy arrays, strings, paths), so it pickles.
"""

from __future__ import annotations

import time
from concurrent.futures import Future
from pathlib import Path
from typing import Callable, Dict, List, Optional, Sequence, Tuple

import numpy as np

from ..checking.collision import default_threads, find_contacts
from ..clock import StageClock
from ..contacts.baseline import BaselineComparison, mismatch_warning
from ..contacts.table import ContactTable
from ..errors import UsdkslInputError
from ..exit_codes import CLEAN, CONTACTS_FOUND, CROSSCHECK_DISAGREES
from ..reading.interpolation import reject_spline_motion
from ..reading.loader import find_mesh_sources
from ..reading.scope import (MOTION_SKIP_REASONS, Plan, ScopeOptions, include_predicate, keep_pairs_across_segments,
                             merge_plans, plan_shot)
from ..regions.baseline import AnyBaseline, compare_any
from ..regions.find import concatenate_regions, find_regions
from ..reports.formats import mesh_pair_lines, region_lines
from ..reports.shot_hash import file_sha256_in_background
from ..warning_kinds import BASELINE_MISMATCH, EMPTY_MESH, NOT_A_SURFACE, NOTHING_CHECKED, SPARSE_SKIN_KEYS
from .coverage import shot_coverage
from .files import OutputTargets, concatenate_pieces, render_files, root_layer_file
from .loading import PlannedShot, checked_span, load_segments, report_blowups, require_samples_in_range
from .memory_budget import format_bytes, memory_limit, plan_memory, sources_size
from .messages import ERROR, INFO, PLAN, RESULT, WARNING, Message, message_collector
from .options import CheckOptions, TimeRange
from .progress import Progress
from .result import UNDECIDED_COUNTER, CheckResult

# Imported where they are used, so that a plain check does not pay for them at start-up: the backwards
# run of --last-contact and the cross-check (Embree).

#: Baseline lines shown by default (new face pairs, fixed entries, each); -v shows up to BASELINE_LINES_VERBOSE.
BASELINE_LINES_SHOWN = 5
BASELINE_LINES_VERBOSE = 200
#: Regions -v lists, deepest first (the reports list all).
REGION_LINES_VERBOSE = 20

#: How the progress bar of the backwards run (last contacts) is labelled; it shows reversed time codes.
REVERSE_PROGRESS_LABEL = "last contacts, reversed time"

#: progress(start, end, label="") -> callback(time_reached, contacts_so_far), e.g. usdksl.pipeline.progress.Progress
ProgressFactory = Callable[..., Callable[[float, int], None]]


def check_shot(shot: str, options: CheckOptions = CheckOptions(), targets: Optional[OutputTargets] = None,
               on_message: Optional[Callable[[Message], None]] = None,
               progress: Optional[ProgressFactory] = None, name: Optional[str] = None,
               baseline: Optional[AnyBaseline] = None, stage=None,
               root_layer_text: Optional[str] = None) -> CheckResult:
    """Check ``shot`` (a USD file) and render its reports; write nothing.

    ``baseline`` (usdksl.contacts.baseline): contacts it knows do not count for the exit code; the
    reports mark each contact new or known and list the entries that no longer occur.

    ``name`` is how reports and messages name the shot (default: ``shot``; a Dask worker reads an absolute
    path but names the shot as the user gave it).
    ``targets`` says where the files would go (default: beside the shot, no JSON or JUnit); it only
    names them (the override layer sublayers the shot by a path relative to its folder). ``on_message``
    receives each plan line and warning as it is known (they are also in ``result.messages``).
    ``progress(start, end, label="")`` makes the progress callback of the core for the checked span (an
    object with an optional ``close()``); with ``last_contact`` a second one follows the backwards run. Raises UsdkslInputError / UsdkslUsageError on bad input.
    ``stage``: an open Usd.Stage to check instead of opening ``shot`` (the file of its root layer; see
    usdksl.pipeline.stage.check_stage); ``root_layer_text``: for a stage whose root layer has no file, its
    exported text (``shot`` is then only a name; see render_files).
    """
    started = time.monotonic()
    # read beside the loading and the check, not after them (the override layer names the shot by it)
    shot_hash = file_sha256_in_background(root_layer_file(shot)) if root_layer_text is None else None
    name = name or shot
    targets = targets or OutputTargets(out_dir=Path(shot).resolve().parent)
    messages: List[Message] = []
    say = message_collector(messages, on_message)
    planned = load_and_plan(shot, options, name, say, stage=stage)
    report_blowups(planned.segments, planned.plans, name, say, options.strict, options.threads)
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
                                        reverse_report, planned.steps_per_window,
                                        planned.clock.frames_per_time_code))
    finally:
        for shown in (bar, reverse_bar):
            if shown is not None and hasattr(shown, "close"):
                shown.close()
    return conclude(shot, name, options, targets, planned, tables, span, counters, messages, say, baseline,
                    started, root_layer_text, shot_hash)


def _shown(bar) -> bool:
    """Whether the core should hand its progress to ``bar``: not to a usdksl Progress that is not drawn (in
    CI, in a pipe), whose calls change nothing anyone sees. Each call takes the GIL from the core's
    threads, which costs them time when the machine is busy; without one the core still calls back as
    often to check for Ctrl-C, SIGTERM and --timeout (usdksl.stopping)."""
    return bar is not None and not (isinstance(bar, Progress) and not bar.enabled)


def load_and_plan(shot: str, options: CheckOptions, name: str, say: Callable[..., None],
                  require_pairs: bool = True, stage=None) -> PlannedShot:
    """Load ``shot`` over ``options.time_range`` (the whole shot when None) and plan what is checked; says
    the loader's warnings, the plan lines and the coverage account. Raises UsdkslInputError on bad input (spline
    motion included), when ``options.time_range`` holds no sample, and when no mesh pair is left to check (except
    in a time range where nothing moves, or with ``require_pairs`` False: a Dask window, planned whole later).
    ``stage``: the open Usd.Stage of ``shot`` to read instead of opening it."""
    include, excluded = options.patterns()
    predicate = include_predicate(include, excluded) if (include or excluded) else None
    # the one open of the stage and search for its meshes: counted for memory before any motion is read, then loaded
    found = find_mesh_sources(shot, predicate, allow_missing_assets=options.allow_missing_assets,
                              skin_keys_only=options.skin_keys_only, stage=stage)
    threads = options.threads or default_threads()
    limit = memory_limit(options.memory_limit)
    memory = plan_memory(sources_size(found, options.time_range), options.method, limit, file=name,
                         threads=threads, steps_per_window=options.window)
    if memory.shortened:
        say(INFO, f"memory: the core is handed the shot in windows of {memory.steps_per_window} sample steps "
                  f"(about {format_bytes(memory.estimate)} of the {format_bytes(limit)} available)")
    segments, gaps = load_segments(found, options.time_range, say, name, options.strict)
    del found   # its instancers' cached transforms (instances x samples matrices) are not needed past loading
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
        plans.append(segment_plan)
    keep_pairs_across_segments(plans)
    for (segment_range, _), segment_plan in zip(segments, plans):
        if len(segments) > 1:
            say(PLAN, f"segment {segment_range[0]:g}..{segment_range[1]:g}:")
        for line in segment_plan.describe():
            say(PLAN, line.strip() if line.startswith("pairs") else line)
    plan = merge_plans(plans)
    if not plan.checked_pairs and require_pairs:
        if (options.time_range is None or options.strict or plan.skipped_meshes or plan.excluded_paths
                or not all(reason in MOTION_SKIP_REASONS for _, _, reason in plan.skipped_pairs)):
            raise UsdkslInputError("no mesh pair left to check: nothing would be checked (-v shows the plan)",
                                   file=name)
        # a farm chunk in which the cloth rests: its motion on either side is in the neighbouring chunks
        say(WARNING, f"nothing moves over {options.time_range[0]:g}..{options.time_range[1]:g}: no pair needs a check",
            NOTHING_CHECKED)
    coverage = shot_coverage(segments, plan, gaps, checked_span(options, segments), options.time_range)
    for note in dict.fromkeys(n for _, segment in segments for n in segment.notes):
        say(INFO, note, SPARSE_SKIN_KEYS)
    for line in coverage.lines():
        say(PLAN, line)
    return PlannedShot(segments=segments, plans=plans, plan=plan, gaps=gaps, coverage=coverage,
                       steps_per_window=memory.steps_per_window)


def conclude(shot: str, name: str, options: CheckOptions, targets: OutputTargets, planned: PlannedShot,
             tables: Sequence[ContactTable], span: TimeRange, counters: Dict[str, int], messages: List[Message],
             say: Callable[[str, str], None], baseline: Optional[AnyBaseline], started: float,
             root_layer_text: Optional[str] = None, shot_hash: Optional[Future] = None) -> CheckResult:
    """The result of a check from the contacts of each segment (``tables``): held against ``baseline``,
    cross-checked when asked, every report rendered. Says what a finished check says. ``shot_hash``: the shot's
    hash being computed (:func:`usdksl.reports.shot_hash.file_sha256_in_background`; None: computed here)."""
    plan = planned.plan
    table, kept = concatenate_pieces(planned.segments, tables)
    clock = planned.clock
    regions = concatenate_regions([find_regions(segment.meshes, segment_table, segment.times, options.thickness,
                                                segment_range, clock.frames_per_time_code)
                                   for (segment_range, segment), segment_table in zip(planned.segments, tables)],
                                  table, kept)
    comparison = None
    if baseline is not None:
        mismatch = mismatch_warning(baseline, _mesh_of(planned.segments[0][1].stage, table.paths), name)
        if mismatch is not None:
            say(WARNING, mismatch, BASELINE_MISMATCH)
        comparison = compare_any(table, regions, clock, baseline)
        for level, text in baseline_messages(comparison, clock):
            say(level, text)
    for text in mesh_pair_lines(table, clock, None if comparison is None else comparison.known):
        say(INFO, text)
    for text in region_lines(regions, table, clock, REGION_LINES_VERBOSE):
        say(INFO, text)

    exit_code = CONTACTS_FOUND if (comparison.new_count if comparison else table.count) else CLEAN
    crosscheck_text = None
    if options.crosscheck:
        crosscheck_text, consistent = _crosscheck(planned.segments, planned.plans, tables, say)
        if not consistent:
            exit_code = CROSSCHECK_DISAGREES
    findings = [{"level": message.level, "kind": message.kind, "text": message.text} for message in messages
                if message.level in (WARNING, ERROR) or message.kind is not None]
    files, stdout = render_files(shot, name, options, targets, planned.segments, plan, tables, table, clock,
                                 exit_code, span, crosscheck_text, comparison, planned.coverage, findings, regions,
                                 root_layer_text, None if shot_hash is None else shot_hash.result())
    pictures = {}
    if targets.report_path is not None:
        from .report import region_pictures_of   # PyVista and VTK: only for a report

        pictures = region_pictures_of(planned.segments, regions, table)
    return CheckResult(shot=name, options=options, exit_code=exit_code, table=table, plan=plan, span=span,
                       seconds=time.monotonic() - started, counters=counters,
                       messages=messages, files=files, stdout=stdout,
                       segments=[(r, t) for (r, _), t in zip(planned.segments, tables)], clock=clock,
                       baseline=comparison, threads=options.threads or default_threads(), coverage=planned.coverage,
                       regions=regions, pictures=pictures)


def _mesh_of(stage, loaded: Optional[Sequence[str]]) -> Callable[[str], bool]:
    """is_mesh(prim_path): a mesh the check loaded, or one on the stage it left out (scoped out by --prims,
    purpose, visibility...), or an instance of a PointInstancer on the stage (``/World/scatter[3]/box``)."""
    from pxr import Sdf, UsdGeom

    known = set(loaded or ())

    def is_mesh(path: str) -> bool:
        if path in known:
            return True
        if stage is None:
            return False
        # an instance path (/World/scatter[3]/box) is not an Sdf path; its instancer's part is
        prim_path, instance = path.split("[", 1)[0], "[" in path
        if not Sdf.Path.IsValidPathString(prim_path) or not Sdf.Path(prim_path).IsAbsolutePath():
            return False
        prim = stage.GetPrimAtPath(prim_path)
        return bool(prim) and prim.IsA(UsdGeom.PointInstancer if instance else UsdGeom.Mesh)
    return is_mesh


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


def check_segment(segment, plan: Plan, segment_range: Optional[TimeRange], options: CheckOptions,
                  progress: Optional[Callable[[float, int], None]] = None,
                  say: Optional[Callable[[str, str], None]] = None,
                  counters: Optional[Dict[str, int]] = None,
                  reverse_progress: Optional[Callable[[float, int], None]] = None,
                  steps_per_window: Optional[int] = None, frames_per_time_code: float = 0.0) -> ContactTable:
    """Face contacts of one constant-topology stretch (with last contacts when ``options.last_contact``;
    ``reverse_progress`` then follows the backwards run in reversed time), handed to the core in memory
    windows of ``steps_per_window`` sample steps (None: whole; usdksl.checking.memory_windows); with the
    stage's ``frames_per_time_code`` (:attr:`usdksl.clock.StageClock.frames_per_time_code`) the core steps
    over sub-frame samples (usdksl.checking.collision.find_contacts). Adds the core's work counters
    (and UNDECIDED_COUNTER) to ``counters`` and warns through ``say`` about undecided triangle pairs."""
    paths = [mesh.path for mesh in segment.meshes]
    if not plan.checked_pairs:   # a piece where nothing needs a check still carries the columns of the others
        empty = ContactTable.empty(paths)
        return empty.with_last_times(np.zeros(0)) if options.last_contact else empty
    result = find_contacts(segment.meshes, plan.pairs, method=options.method, time_range=segment_range,
                           tolerance=options.tolerance, thickness=options.thickness, progress=progress,
                           threads=options.threads, steps_per_window=steps_per_window,
                           frames_per_time_code=frames_per_time_code)
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
    from ..checking.last_contact import last_contacts

    last = last_contacts(segment.meshes, plan.pairs, table, segment_range, options.method, options.tolerance,
                         options.thickness, progress=reverse_progress, threads=options.threads,
                         steps_per_window=steps_per_window, frames_per_time_code=frames_per_time_code)
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
