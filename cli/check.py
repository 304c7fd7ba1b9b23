"""``usdksl check SHOT [SHOT...]``: first contacts of whole shots, written to CSV and to USD override layers.

Streams: stdout stays empty (or carries the JSON document with ``--json -``) so pipelines can parse it;
the plan (what is checked and why the rest is skipped), warnings, the progress bar and the final summary
line go to stderr. With several shots (or ``--jobs`` / ``--scheduler``) each shot gets one line (and its
warnings), then a total line. Exit codes: 0 clean, 1 contacts found, 2 usage or input error (nothing
written for that shot), 3 the cross-check disagrees; the worst (largest) over all shots.
"""

from __future__ import annotations

import functools
import os
import sys

import click

from ..ccd import DEFAULT_THICKNESS, DEFAULT_TOLERANCE
from ..checking.collision import METHODS
from ..checking.pipeline import ERROR, WARNING, CheckOptions, check_shot, output_targets
from ..checking.progress import Progress, progress_enabled
from ..errors import UsdkslInputError
from ..exit_codes import INPUT_ERROR
from ..reports.output import write_files
from ..scale.batch import expand_shots, make_jobs, run_batch, run_here, total_line, worst_exit_code
from ..stopping import Stopped, deferred_stops, stop_on_signals
from .options import parse_time_range


def _echo(line: str) -> None:
    click.echo(line, err=True)


@click.command()
@click.argument("shots", nargs=-1, required=True, metavar="SHOT [SHOT...]",
                type=click.Path(dir_okay=False, path_type=str))
@click.option("--out", "out", type=click.Path(path_type=str), default=None,
              help="Directory for <stem>.contacts.csv, <stem>.summary.csv, <stem>.usdksl.usda "
                   "(default: beside SHOT; created when missing).")
@click.option("--method", type=click.Choice(METHODS), default="ksl", show_default=True,
              help="ksl: kinetic separation lists; swept: swept-volume BVH baseline; discrete: per-sample "
                   "checks (misses contacts between samples); brute: all pairs (reference, slow).")
@click.option("--tolerance", type=float, default=DEFAULT_TOLERANCE, show_default=True,
              help="Time tolerance of the continuous narrow phase, as a fraction of a sample interval.")
@click.option("--thickness", type=float, default=DEFAULT_THICKNESS, show_default=True,
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
@click.option("--crosscheck", is_flag=True,
              help="Also intersect every sample with Embree and check it against the contacts "
                   "(writes <stem>.crosscheck.csv; exit 3 when they disagree).")
@click.option("--json", "json_path", metavar="FILE", default=None,
              help="Also write a JSON report (shot, settings, plan, summary, contacts); '-' for stdout.")
@click.option("--junit", "junit_path", metavar="FILE", default=None,
              help="Also write a JUnit XML report: one testsuite per shot, one testcase per checked pair.")
@click.option("--strict", is_flag=True,
              help="Exit 2 (nothing written) when the cache has a simulation blow-up or nothing is left "
                   "to check, instead of warning.")
@click.option("--jobs", type=click.IntRange(min=1), default=None, metavar="N",
              help="Check the shots on a local Dask cluster of N worker processes.")
@click.option("--scheduler", default=None, metavar="ADDRESS",
              help="Check the shots on the running Dask scheduler at ADDRESS (e.g. tcp://host:8786).")
@click.option("--timeout", type=click.FloatRange(min=0, min_open=True), default=None, metavar="SECONDS",
              help="Stop after SECONDS: exit 2 with one line, and no files written for a shot not finished.")
@click.option("--memory-limit", default=None, metavar="SIZE",
              help="Memory a shot's check may use (8G, 512M, bytes; 'off': no check). Default: the "
                   "environment variable USDKSL_MEMORY_LIMIT, else what the machine has available. A "
                   "shot estimated to need more is refused (exit 2) before it is loaded.")
def check(shots, out, method, tolerance, thickness, self_check, inter_check, time_range, prims, exclude,
          include_guides, include_invisible, crosscheck, json_path, junit_path, strict, jobs, scheduler,
          timeout, memory_limit):
    """Find the first contacts in each SHOT and write them to CSV and to a USD override layer.

    Quoted globs ('shots/*.usd') are expanded. Exit code 0: clean; 1: contacts found; 2: usage or input
    error (no output written for that shot); 3: the cross-check disagrees; the worst over all shots.
    The plan, warnings and the summary lines go to stderr; stdout only carries --json - .
    Ctrl-C (SIGINT) and SIGTERM stop the check within a second or two with one line and exit 130 / 143;
    files of a shot not finished are never written.
    """
    options = CheckOptions(method=method, tolerance=tolerance, thickness=thickness, self_check=self_check,
                           inter_check=inter_check, time_range=time_range, prims=tuple(prims),
                           exclude=tuple(exclude), include_guides=include_guides,
                           include_invisible=include_invisible, crosscheck=crosscheck, strict=strict,
                           memory_limit=memory_limit)
    shots = expand_shots(shots)
    finished = []
    try:
        with stop_on_signals(timeout):
            if len(shots) == 1 and jobs is None and scheduler is None:
                _check_one(shots[0], options, out, json_path, junit_path)
            _check_many(shots, options, out, json_path, junit_path, jobs, scheduler, finished)
    except Stopped as stop:
        single = len(shots) == 1 and jobs is None and scheduler is None
        done = ("nothing written" if single or not finished
                else f"{len(finished)} of {len(shots)} shots finished (their files are written), the others not")
        _echo(stop.line(done, shot=shots[0] if single else None))
        sys.exit(stop.exit_code)


def _check_one(shot, options, out, json_path, junit_path):
    """One shot in this process: the plan and warnings as they come, a progress bar over the shot's time."""
    try:
        options.validate()
        targets = output_targets(shot, out, json_path, junit_path)
        result = check_shot(shot, options, targets, on_message=lambda message: _echo(message.line()),
                            progress=Progress)
    except UsdkslInputError as error:
        _echo(f"usdksl: error: {error}")
        sys.exit(error.exit_code)
    except Exception as error:  # never let a crash look like "contacts found" (exit 1)
        if os.environ.get("USDKSL_DEBUG"):
            raise
        _echo(f"usdksl: internal error: {type(error).__name__}: {' '.join(str(error).split())} "
              f"(set USDKSL_DEBUG=1 for a traceback)")
        sys.exit(INPUT_ERROR)
    with deferred_stops(drop=True):   # the answer is known: publish it, say so and end, uncut
        try:
            write_files(result.files)
        except UsdkslInputError as error:
            _echo(f"usdksl: error: {error}")
            sys.exit(error.exit_code)
        if result.stdout is not None:
            sys.stdout.write(result.stdout)
        _echo(result.summary)
        sys.exit(result.exit_code)


def _check_many(shots, options, out, json_path, junit_path, jobs, scheduler, finished):
    """Several shots (or Dask): one line per shot as it finishes, with its warnings, then the total.
    ``finished`` collects the outcomes shown (their files are written)."""
    from tqdm import tqdm

    if jobs is not None and scheduler is not None:
        raise click.UsageError("give --jobs or --scheduler, not both")
    try:
        options.validate()
        entries = make_jobs(shots, out, json_path, junit_path)
        if jobs is None and scheduler is None:
            runner = run_here
        else:
            from ..scale.dask_runner import run_on_dask
            runner = functools.partial(run_on_dask, workers=jobs, scheduler=scheduler)
        bar = tqdm(total=len(entries), unit="shot", file=sys.stderr, disable=not progress_enabled(sys.stderr),
                   leave=False)

        def show(outcome):
            for message in outcome.messages:
                if message.level in (WARNING, ERROR):
                    bar.write(message.line(outcome.name), file=sys.stderr)
            bar.write(outcome.line(), file=sys.stderr)
            bar.update(1)
            finished.append(outcome)

        try:
            outcomes = run_batch(entries, options, runner, on_outcome=show)
        finally:
            bar.close()
    except UsdkslInputError as error:
        _echo(f"usdksl: error: {error}")
        sys.exit(error.exit_code)
    with deferred_stops(drop=True):
        _echo(total_line(outcomes))
        sys.exit(worst_exit_code(outcomes))
