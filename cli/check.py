"""``usdksl check SHOT [SHOT...]``: first contacts of whole shots, written to CSV and to USD override layers.

Streams: stdout stays empty (or carries the JSON document with ``--json -``, JSON Lines for several shots)
so pipelines can parse it; everything else goes to stderr. By default: warnings, the baseline's new and
fixed contacts, one line per shot (counts and the first contact's frame) and, for several shots, a total
line; ``-v`` adds the plan (what is checked and why the rest is not), one line per mesh pair and the files written; ``-q`` prints
errors only. A progress bar is drawn on a terminal (not in CI, not with ``-q``). ``--junit`` is written
whatever the exit code (an <error> test case for a shot that could not be checked). Exit codes: 0 clean, 1 contacts found, 2 usage or input error (nothing
written for that shot), 3 the cross-check disagrees; the worst (largest) over all shots.
"""

from __future__ import annotations

import functools
import os
import sys

import click

from usdksl.ccd_defaults import DEFAULT_THICKNESS, DEFAULT_TOLERANCE
from usdksl.checking.collision import METHODS
from usdksl.checking.memory_windows import MIN_STEPS_PER_WINDOW
from usdksl.regions.baseline import baseline_for_shot
from usdksl.errors import UsdkslInputError, UsdkslUsageError
from usdksl.exit_codes import INPUT_ERROR
from usdksl.pipeline.check import check_shot
from usdksl.pipeline.files import output_targets
from usdksl.pipeline.messages import NORMAL, QUIET, VERBOSE, WARNING, Message
from usdksl.pipeline.options import CheckOptions
from usdksl.pipeline.progress import Progress, progress_enabled
from usdksl.pipeline.report import report_for_results, report_line
from usdksl.reports.output import write_files
from usdksl.reports.override import shot_stem
from usdksl.scale.shot_arguments import expand_shots
from usdksl.stopping import Stopped, deferred_stops, stop_on_signals

from .options import allow_missing_assets_option, parse_time_range


def _echo(line: str) -> None:
    click.echo(line, err=True)


@click.command()
@click.argument("shots", nargs=-1, required=True, metavar="SHOT [SHOT...]",
                type=click.Path(path_type=str))
@click.option("--out", "out", type=click.Path(path_type=str), default=None,
              help="Directory for <stem>.contacts.csv, <stem>.summary.csv, <stem>.usdksl.usda "
                   "(default: beside SHOT; created when missing).")
@click.option("--method", type=click.Choice(METHODS), default="ksl", show_default=True,
              help="ksl: kinetic separation lists; swept: swept-volume BVH baseline; discrete: per-sample "
                   "checks (misses contacts between samples); brute: all pairs (reference, slow).")
@click.option("--tolerance", type=float, default=DEFAULT_TOLERANCE, show_default=True,
              help="Time tolerance of the continuous narrow phase, as a fraction of a sample interval.")
@click.option("--thickness", type=float, default=DEFAULT_THICKNESS, show_default=True,
              help="Report primitives within this Euclidean distance (scene units) of each other as touching.")
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
@click.option("--last-contact", is_flag=True,
              help="Also find when each face pair last touches (the shot checked a second time, played "
                   "backwards: about twice the time). Adds last_time,last_frame,last_seconds columns.")
@click.option("--baseline", "baseline", metavar="PATH", default=None,
              help="Contacts accepted earlier: a contacts.csv of an earlier run or an accept list "
                   "(prim_a,face_a,prim_b,face_b[,time]; face '*' = any), or a folder of <stem>.contacts.csv "
                   "for several shots. Only new contacts count for the exit code.")
@click.option("--baseline-time-tolerance", type=float, default=None, metavar="T",
              help="Also require a baseline entry's time to be within T time codes of the contact's.")
@click.option("--plot", "plot_path", metavar="FILE.png", default=None,
              help="Also draw a contact timeline: one row per mesh pair, frames across, shaded while in contact, "
                   "a tick at each first contact. Turns on --last-contact. Needs matplotlib "
                   "(pip install 'usdksl[plot]'). One shot only.")
@click.option("--report", "report_path", metavar="FILE.html", default=None,
              help="Also write one illustrated page for the run: every shot's summary, a timeline of its contact "
                   "regions, the regions by depth and a picture of each of the worst. Needs PyVista and VTK "
                   "(pip install 'usdksl[report]').")
@click.option("--json", "json_path", metavar="FILE", default=None,
              help="Also write a JSON report (shot, settings, plan, summary, contacts); '-' for stdout. With "
                   "several shots: JSON Lines, one compact document per shot in the order given.")
@click.option("--junit", "junit_path", metavar="FILE", default=None,
              help="Also write a JUnit XML report, whatever the exit code: one testsuite per shot, one testcase "
                   "per checked pair; an <error> test case for a shot that cannot be checked.")
@click.option("--strict", is_flag=True,
              help="Exit 2 (nothing written) instead of warning when the cache has a simulation blow-up or a "
                   "cache glitch, or when anything is not checked (empty or blocked samples, topology changes, "
                   "nested PointInstancers, solids that are not meshes, allowed missing assets).")
@allow_missing_assets_option
@click.option("--skin-keys-only", is_flag=True,
              help="Pose skinned meshes at their animation's keys only. By default a skinned mesh keyed more "
                   "sparsely than the stage's frames is posed at every frame, as UsdSkel.BakeSkinning bakes it.")
@click.option("-v", "--verbose", "verbosity", flag_value=VERBOSE,
              help="Also print the plan (what is checked and why the rest is not), one line per mesh pair "
                   "with contacts, and the files written.")
@click.option("-q", "--quiet", "verbosity", flag_value=QUIET, help="Print errors only.")
@click.option("--normal", "verbosity", flag_value=NORMAL, default=True, hidden=True)
@click.option("--jobs", type=click.IntRange(min=1), default=None, metavar="N",
              help="Check the shots on a local Dask cluster of N worker processes; with fewer shots than "
                   "workers, long shots are split into time windows (same files, byte for byte).")
@click.option("--scheduler", default=None, metavar="ADDRESS",
              help="Check the shots on the running Dask scheduler at ADDRESS (e.g. tcp://host:8786).")
@click.option("--timeout", type=click.FloatRange(min=0, min_open=True), default=None, metavar="SECONDS",
              help="Stop after SECONDS: exit 2 with one line, and no files written for a shot not finished.")
@click.option("--threads", type=click.IntRange(min=1), default=None, metavar="N",
              help="Threads per check (default: every core this process may use); results are identical for "
                   "any count.")
@click.option("--memory-limit", default=None, metavar="SIZE",
              help="Memory a shot's check may use (8G, 512M, bytes; 'off': no check). Default: the "
                   "environment variable USDKSL_MEMORY_LIMIT, else what the machine has available. A long "
                   "shot is handed to the core in shorter time windows to fit; one that does not fit even so "
                   "is refused (exit 2) before it is loaded.")
@click.option("--window", type=click.IntRange(min=MIN_STEPS_PER_WINDOW), default=None, metavar="STEPS",
              help="Sample steps of the time windows the core holds at once (default: about 1 GiB of "
                   "samples, or what the triangles take when more; shorter when memory asks); results are "
                   "identical for any value.")
def check(shots, out, method, tolerance, thickness, self_check, inter_check, time_range, prims, exclude,
          include_guides, include_invisible, rigid, crosscheck, last_contact, baseline,
          baseline_time_tolerance, plot_path, report_path, json_path, junit_path, strict, allow_missing_assets, skin_keys_only,
          verbosity, jobs, scheduler, timeout, threads, memory_limit, window):
    """Find the first contacts in each SHOT and write them to CSV and to a USD override layer.

    Quoted globs ('shots/*.usd') are expanded; a folder stands for the USD files in it (not in its
    subfolders). Exit code 0: clean; 1: contacts found; 2: usage or input error (no output written for
    that shot); 3: the cross-check disagrees; the worst over all shots.
    The plan, warnings and the summary lines go to stderr; stdout only carries --json - .
    Ctrl-C (SIGINT) and SIGTERM stop the check within a second or two with one line and exit 130 / 143;
    files of a shot not finished are never written.
    """
    try:
        shots = expand_shots(shots)
    except UsdkslInputError as error:   # a folder without USD files: its <error> test case names the folder
        _fail([error.file], error.one_line(), junit_path, error.exit_code)
    try:   # a value the check cannot use is refused here, before any work
        options = CheckOptions(method=method, tolerance=tolerance, thickness=thickness, self_check=self_check,
                               inter_check=inter_check, time_range=time_range, prims=tuple(prims),
                               exclude=tuple(exclude), include_guides=include_guides,
                               include_invisible=include_invisible, rigid=rigid, crosscheck=crosscheck,
                               last_contact=last_contact or plot_path is not None, strict=strict,
                               threads=threads, memory_limit=memory_limit, window=window,
                               allow_missing_assets=allow_missing_assets, skin_keys_only=skin_keys_only)
    except UsdkslUsageError as error:
        _fail(shots, error.one_line(), junit_path, error.exit_code)
    finished = []
    single = len(shots) == 1 and jobs is None and scheduler is None
    try:
        with stop_on_signals(timeout):
            if single:
                _check_one(shots[0], options, out, json_path, junit_path, baseline, baseline_time_tolerance,
                           verbosity, plot_path, report_path)
            _check_many(shots, options, out, json_path, junit_path, jobs, scheduler, baseline,
                        baseline_time_tolerance, verbosity, plot_path, finished, report_path)
    except Stopped as stop:
        done = ("nothing written" if single or not finished
                else f"{len(finished)} of {len(shots)} shots finished (their files are written), the others not")
        line = stop.line(done, shot=shots[0] if single else None)
        _echo(line)
        if junit_path and junit_path != "-":
            _write_stopped_junit(junit_path, shots, finished, line[len("usdksl: "):], stop.exit_code)
        sys.exit(stop.exit_code)


def _write_stopped_junit(junit_path, shots, finished, message, exit_code):
    """The --junit report of a stopped run: the finished shots as checked, an <error> for every other."""
    from usdksl.scale.batch import ShotOutcome, junit_for_outcomes

    done = {outcome.name: outcome for outcome in finished}
    outcomes = [done.get(shot) or ShotOutcome(name=shot, exit_code=exit_code, error=message) for shot in shots]
    try:
        write_files({junit_path: junit_for_outcomes(outcomes)})
    except UsdkslInputError as error:
        _echo(f"usdksl: error: {error}")


def _fail(shots, message, junit_path, exit_code=INPUT_ERROR, kind="error"):
    """Say why the check could not be done, write the --junit report of it (an <error> per shot) and exit."""
    _echo(f"usdksl: {kind}: {message}")
    if junit_path and junit_path != "-":
        from usdksl.reports.junit import junit_error_report   # xml.etree: only for a report

        try:
            write_files({junit_path: junit_error_report(shots, message)})
        except UsdkslInputError as error:
            _echo(f"usdksl: error: {error}")
    sys.exit(exit_code)


def _crash_message(error):
    return f"{type(error).__name__}: {' '.join(str(error).split())} (set USDKSL_DEBUG=1 for a traceback)"


def _check_one(shot, options, out, json_path, junit_path, baseline, baseline_time_tolerance, verbosity, plot_path,
               report_path):
    """One shot in this process: the plan and warnings as they come, a progress bar over the shot's time."""
    def show(message):
        if message.shown(verbosity):
            _echo(message.line())

    try:
        targets = output_targets(shot, out, json_path, junit_path, plot_path, report_path)
        if baseline is not None and not os.path.exists(baseline):
            raise UsdkslUsageError("baseline not found", file=baseline)
        accepted, warning = baseline_for_shot(baseline, shot_stem(shot), baseline_time_tolerance)
        if warning is not None:
            show(Message(WARNING, warning))
        result = check_shot(shot, options, targets, on_message=show,
                            progress=Progress if verbosity > QUIET else None, baseline=accepted)
        files = dict(result.files)
        if targets.report_path is not None:
            files[targets.report_path] = report_for_results([result])
    except UsdkslInputError as error:
        _fail([shot], error.one_line(), junit_path, error.exit_code)
    except Exception as error:  # never let a crash look like "contacts found" (exit 1)
        if os.environ.get("USDKSL_DEBUG"):
            raise
        _fail([shot], _crash_message(error), junit_path, kind="internal error")
    with deferred_stops(drop=True):   # the answer is known: publish it, say so and end, uncut
        try:
            written = write_files(files)
        except UsdkslInputError as error:
            _fail([shot], error.one_line(), junit_path, error.exit_code)
        if result.stdout is not None:
            sys.stdout.write(result.stdout)
        if verbosity >= NORMAL:
            _echo(result.summary)
            if targets.report_path is not None:
                _echo(report_line(targets.report_path))
        if verbosity >= VERBOSE:
            _echo(f"usdksl: wrote {', '.join(str(path) for path in written)}")
        sys.exit(result.exit_code)


def _check_many(shots, options, out, json_path, junit_path, jobs, scheduler, baseline, baseline_time_tolerance,
                verbosity, plot_path, finished, report_path=None):
    """Several shots (or Dask): one line per shot as it finishes, with its warnings, then the total.
    ``finished`` collects the outcomes shown (their files are written)."""
    from usdksl.scale.batch import (json_for_outcomes, junit_for_outcomes, make_jobs, report_for_outcomes,
                                    run_batch, run_here, total_line, worst_exit_code)
    from usdksl.scale.batch_progress import BatchProgress

    if jobs is not None and scheduler is not None:
        raise click.UsageError("give --jobs or --scheduler, not both")
    try:
        entries = make_jobs(shots, out, json_path, junit_path, baseline, baseline_time_tolerance, plot_path,
                            report_path)
        if jobs is None and scheduler is None:
            runner = run_here
        else:
            from usdksl.scale.dask_runner import run_on_dask
            runner = functools.partial(run_on_dask, workers=jobs, scheduler=scheduler)
        bar = BatchProgress(len(entries), enabled=verbosity > QUIET and progress_enabled(sys.stderr))

        def show(outcome):
            for message in outcome.messages:
                if message.shown(verbosity):
                    bar.write(message.line(outcome.name))
            if outcome.result is None or verbosity >= NORMAL:
                bar.write(outcome.line())
            finished.append(outcome)

        try:
            outcomes = run_batch(entries, options, runner, on_outcome=show, progress=bar)
        finally:
            bar.close()
        json_text = json_for_outcomes(outcomes) if json_path else None
        reports = {}
        if junit_path:
            reports[junit_path] = junit_for_outcomes(outcomes)
        if json_text is not None and json_path != "-":
            reports[json_path] = json_text
        if report_path:
            reports[report_path] = report_for_outcomes(outcomes)
        if reports:
            write_files(reports)
    except UsdkslInputError as error:
        _fail(shots, error.one_line(), junit_path, error.exit_code)
    with deferred_stops(drop=True):
        if json_text is not None and json_path == "-":
            sys.stdout.write(json_text)
        if verbosity >= NORMAL:
            _echo(total_line(outcomes))
            if report_path:
                _echo(report_line(report_path))
        sys.exit(worst_exit_code(outcomes))
