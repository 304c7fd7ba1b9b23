"""``usdksl check SHOT``: first contacts of a whole shot, written to CSV and to a USD override layer.

Streams: stdout stays empty (or carries the JSON document with ``--json -``) so pipelines can parse it;
the plan (what is checked and why the rest is skipped), warnings, the progress bar and the final summary
line go to stderr. Exit codes: 0 clean, 1 contacts found, 2 usage or input error (nothing written).
"""

from __future__ import annotations

import os
import sys
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Optional, Sequence, Tuple

import click
import numpy as np

from .. import __version__
from ..crosscheck import crosscheck_csv_path, crosscheck_shot
from ..errors import UsdkslInputError, UsdkslUsageError
from ..interpolation import reject_spline_motion
from ..loader import load_shot, mesh_prims, open_stage
from ..output import OutputTransaction, check_writable_directory, resolve_output_path
from ..override import build_override_layer, shot_stem
from ..progress import Progress
from ..reports import ContactTable, json_report, junit_report, summary_line
from ..scope import ScopeOptions, include_predicate, merge_plans, plan_shot, split_patterns
from ..segments import full_range, is_topology_change, split_range, topology_gaps
from .options import parse_time_range

METHODS = ("ksl", "swept", "discrete", "brute")
# Like linters (ruff): abnormal termination shares the "could not check" code, never 1 ("contacts found").
INTERNAL_ERROR_EXIT_CODE = 2


#: Exit code when the Embree cross-check disagrees with the continuous result.
CROSSCHECK_DISAGREES = 3

@dataclass
class CheckResult:
    exit_code: int
    table: ContactTable
    plan: object
    written: list
    summary: str


def run_check(shot: str, out: Optional[str] = None, method: str = "ksl", tolerance: float = 1e-6,
              thickness: float = 0.0, self_check: bool = True, inter_check: bool = True,
              time_range: Optional[Tuple[float, float]] = None, prims: Sequence[str] = (),
              exclude: Sequence[str] = (), include_guides: bool = False, include_invisible: bool = False,
              rigid: bool = False, json_path: Optional[str] = None, junit_path: Optional[str] = None,
              crosscheck: bool = False, echo=None, stdout=None) -> CheckResult:
    """The whole command without click: raises UsdkslInputError / UsdkslUsageError on bad input."""
    echo = echo or (lambda text: click.echo(text, err=True))
    started = time.monotonic()
    if not tolerance > 0:
        raise UsdkslUsageError(f"--tolerance must be positive, got {tolerance!r}")
    if not thickness >= 0:
        raise UsdkslUsageError(f"--thickness must be zero or positive, got {thickness!r}")

    if not os.path.isfile(shot):
        open_stage(shot)   # a missing input is reported as such, before anything about the output folder
    out_dir = Path(out) if out else Path(shot).resolve().parent
    check_writable_directory(out_dir)
    extra_targets = [resolve_output_path(value) for value in (json_path, junit_path)]
    for target in extra_targets:
        if target is not None:
            check_writable_directory(target.resolve().parent)

    include, excluded = split_patterns(prims, exclude)
    predicate = include_predicate(include, excluded) if (include or excluded) else None
    segments = _load_segments(shot, time_range, predicate, echo)
    loaded = segments[0][1]
    for warning in dict.fromkeys(w for _, segment in segments for w in getattr(segment, "warnings", ())):
        echo(f"usdksl: warning: {warning}")
    options = ScopeOptions(self_check=self_check, inter_check=inter_check, include=(), exclude=(),
                           include_guides=include_guides, include_invisible=include_invisible, rigid=rigid)
    plans = []
    for segment_range, segment in segments:
        reject_spline_motion(segment.stage, list(dict.fromkeys(
            path for mesh in segment.meshes for path in (mesh.prim_path, mesh.scene_path))), file=shot)
        segment_plan = plan_shot(segment, options, segment_range)
        if predicate is not None:
            segment_plan.excluded_paths = list(dict.fromkeys(predicate.rejected))
        if len(segments) > 1:
            echo(f"usdksl: segment {segment_range[0]:g}..{segment_range[1]:g}:")
        for line in segment_plan.describe():
            echo(f"usdksl: {line.strip() if line.startswith('pairs') else line}")
        plans.append(segment_plan)
    plan = merge_plans(plans)

    if time_range is not None:
        span = time_range
    else:
        all_times = np.concatenate([segment.times for _, segment in segments])
        span = (float(all_times.min()), float(all_times.max())) if all_times.size else (0.0, 0.0)
    progress = Progress(span[0], span[1])
    tables = []
    try:
        for (segment_range, segment), segment_plan in zip(segments, plans):
            tables.append(_check_segment(segment, segment_plan, segment_range, method, tolerance, thickness,
                                         progress, sum(t.count for t in tables), echo))
    finally:
        progress.close()
    if not plan.checked_pairs:
        echo("usdksl: warning: no mesh pair left to check")
    table = ContactTable.concatenate(tables)

    exit_code = 1 if table.count else 0
    stem = shot_stem(shot)
    crosscheck_text = None
    if crosscheck:
        # Embree at every sample, against the contacts just found (per constant-topology segment).
        results = [crosscheck_shot(segment, contacts=segment_table, pairs=segment_plan.pairs,
                                   time_range=segment_range)
                   for (segment_range, segment), segment_plan, segment_table in zip(segments, plans, tables)]
        for result in results:
            for line in result.error_lines():
                echo(f"usdksl: error: {line}")
            echo(f"usdksl: {result.summary_line()}")
        crosscheck_text = "".join(
            text if index == 0 else text.split("\n", 1)[1]
            for index, text in enumerate(result.csv_text() for result in results))
        if not all(result.consistent for result in results):
            exit_code = CROSSCHECK_DISAGREES
    layer_path = out_dir / f"{stem}.usdksl.usda"
    settings = {"method": method, "tolerance": tolerance, "thickness": thickness, "self": self_check,
                "inter": inter_check, "time_range": list(time_range) if time_range else None,
                "prims": list(include), "exclude": list(excluded), "include_guides": include_guides,
                "include_invisible": include_invisible, "rigid": rigid}
    checked_meshes = sorted(set(plan.pairs.reshape(-1).tolist()))
    transaction = OutputTransaction()
    transaction.write_text(out_dir / f"{stem}.contacts.csv", table.contacts_csv())
    transaction.write_text(out_dir / f"{stem}.summary.csv", table.summary_csv())
    if crosscheck_text is not None:
        transaction.write_text(crosscheck_csv_path(shot, out_dir), crosscheck_text)
    transaction.write_text(layer_path, build_override_layer(
        loaded, checked_meshes, table, layer_path,
        segments=[(r, seg, t) for (r, seg), t in zip(segments, tables)] if len(segments) > 1 else None))
    json_text = None
    if json_path is not None:
        json_text = json_report(shot, settings, plan, table, exit_code, version=__version__)
        if extra_targets[0] is not None:
            transaction.write_text(extra_targets[0], json_text)
    if extra_targets[1] is not None:
        transaction.write_text(extra_targets[1], junit_report(shot, plan, table))
    written = transaction.commit()
    if json_text is not None and extra_targets[0] is None:
        (stdout or sys.stdout).write(json_text)

    summary = summary_line(table, plan, span, time.monotonic() - started)
    echo(summary)
    return CheckResult(exit_code=exit_code, table=table, plan=plan, written=written, summary=summary)


def _load_segments(shot, time_range, predicate, echo):
    """[(range, Shot)]: the whole shot, or one Shot per constant-topology stretch (usdksl.segments) with a
    warning per topology change; ``range`` is None when the whole shot is checked without --time-range."""
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
        echo(f"usdksl: warning: {shot}: {path}: topology changes between time {gap_start:g} and {gap_end:g}; "
             f"that interval is not checked")
    echo(f"usdksl: warning: checking {len(ranges)} constant-topology segments: "
         + ", ".join(f"{a:g}..{b:g}" for a, b in ranges))
    return [(segment_range, load_shot(shot, time_range=segment_range, include=predicate))
            for segment_range in ranges]


def _check_segment(segment, plan, segment_range, method, tolerance, thickness, progress, contacts_before, echo):
    paths = [mesh.path for mesh in segment.meshes]
    if not plan.checked_pairs:
        return ContactTable.empty(paths)
    from ..collision import find_contacts

    result = find_contacts(segment.meshes, plan.pairs, method=method, time_range=segment_range,
                           tolerance=tolerance, thickness=thickness,
                           progress=lambda reached, count: progress(reached, contacts_before + count))
    undecided = int(np.count_nonzero(result.undecided)) if hasattr(result, "undecided") else 0
    if undecided:
        echo(f"usdksl: warning: {undecided} triangle pairs could not be separated within the tolerance "
             f"and are reported as contacts (conservative)")
    return ContactTable.from_face_contacts(result.face_contacts(segment.meshes), paths)


@click.command()
@click.argument("shot", type=click.Path(dir_okay=False, path_type=str))
@click.option("--out", "out", type=click.Path(path_type=str), default=None,
              help="Directory for <stem>.contacts.csv, <stem>.summary.csv, <stem>.usdksl.usda "
                   "(default: beside SHOT; created when missing).")
@click.option("--method", type=click.Choice(METHODS), default="ksl", show_default=True,
              help="ksl: kinetic separation lists; swept: swept-volume BVH baseline; discrete: per-sample "
                   "checks (misses contacts between samples); brute: all pairs (reference, slow).")
@click.option("--tolerance", type=float, default=1e-6, show_default=True,
              help="Time tolerance of the continuous narrow phase, as a fraction of a sample interval.")
@click.option("--thickness", type=float, default=0.0, show_default=True,
              help="Report primitives closer than this distance (scene units) as touching.")
@click.option("--self/--no-self", "self_check", default=True, show_default=True,
              help="Self contacts of deforming meshes.")
@click.option("--inter/--no-inter", "inter_check", default=True, show_default=True,
              help="Contacts between different meshes.")
@click.option("--time-range", nargs=2, type=float, default=None, callback=parse_time_range, metavar="A B",
              help="Check only [A, B] (USD time codes), ends included.")
@click.option("--prims", multiple=True, metavar="PATTERN",
              help="Check only meshes whose prim path matches (fnmatch; '*' crosses '/'; a prim path also "
                   "selects every mesh below it). Repeatable. A leading '!' makes it an exclude pattern.")
@click.option("--exclude", multiple=True, metavar="PATTERN",
              help="Leave out meshes whose prim path matches (same rules as --prims). Repeatable.")
@click.option("--include-guides", is_flag=True, help="Also check meshes with purpose guide.")
@click.option("--include-invisible", is_flag=True,
              help="Also check meshes that are invisible over the whole checked range.")
@click.option("--rigid", is_flag=True,
              help="Also check pairs in which neither mesh deforms (rigid against rigid or still). By default "
                   "a pair needs a deforming mesh; the summary says how many pairs this leaves out.")
@click.option("--crosscheck", is_flag=True,
              help="Also intersect every sample with Embree and check it against the contacts "
                   "(writes <stem>.crosscheck.csv; exit 3 when they disagree).")
@click.option("--json", "json_path", metavar="FILE", default=None,
              help="Also write a JSON report (shot, settings, plan, summary, contacts); '-' for stdout.")
@click.option("--junit", "junit_path", metavar="FILE", default=None,
              help="Also write a JUnit XML report: one testsuite per shot, one testcase per checked pair.")
def check(shot, out, method, tolerance, thickness, self_check, inter_check, time_range, prims, exclude,
          include_guides, include_invisible, rigid, crosscheck, json_path, junit_path):
    """Find the first contacts in SHOT and write them to CSV and to a USD override layer.

    Exit code 0: clean; 1: contacts found; 2: usage or input error (no output written). The plan, warnings
    and the summary line go to stderr; stdout only carries --json - .
    """
    try:
        result = run_check(shot, out=out, method=method, tolerance=tolerance, thickness=thickness,
                           self_check=self_check, inter_check=inter_check, time_range=time_range,
                           prims=prims, exclude=exclude, include_guides=include_guides,
                           include_invisible=include_invisible, rigid=rigid, json_path=json_path,
                           junit_path=junit_path,
                           crosscheck=crosscheck)
    except UsdkslInputError as error:
        click.echo(f"usdksl: error: {error}", err=True)
        sys.exit(error.exit_code)
    except Exception as error:  # never let a crash look like "contacts found" (exit 1)
        if os.environ.get("USDKSL_DEBUG"):
            raise
        click.echo(f"usdksl: internal error: {type(error).__name__}: {' '.join(str(error).split())} "
                   f"(set USDKSL_DEBUG=1 for a traceback)", err=True)
        sys.exit(INTERNAL_ERROR_EXIT_CODE)
    sys.exit(result.exit_code)
