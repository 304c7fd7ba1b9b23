"""Many shots in one call: one job per shot, run in this process or on Dask, written by the caller only.

A :class:`ShotJob` says which file to check (an absolute path, so any worker finds it whatever its working
folder), how the reports name it (the path as the user gave it) and where its files go. :func:`run_job`
checks it and returns a :class:`ShotOutcome` — plain data that pickles — and never raises: a shot that
cannot be checked is an outcome with exit code 2 and its one-line error, so it does not stop the others.
Only the caller writes files (:func:`write_outcome`), so a job that runs twice (a Dask worker died and
the task was run again) cannot write anything twice.
"""

from __future__ import annotations

import json
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable, Dict, Iterable, List, Optional, Sequence

from ..regions.baseline import AnyBaseline, baseline_for_shot
from ..errors import UsdkslInputError, UsdkslUsageError
from ..exit_codes import CLEAN, CONTACTS_FOUND, CROSSCHECK_DISAGREES, INPUT_ERROR
from ..pipeline.check import check_shot
from ..pipeline.files import OutputTargets, output_targets, require_report_libraries
from ..pipeline.messages import WARNING, Message
from ..pipeline.options import CheckOptions
from ..pipeline.report import report_html
from ..pipeline.result import CheckResult
from ..reports.junit import error_suite, junit_document, shot_suite
from ..reports.output import check_writable_directory, write_files
from ..reports.override import shot_stem
from ..stopping import deferred_stops
from ..version import package_version
from .batch_progress import BatchProgress



@dataclass(frozen=True)
class ShotJob:
    """One shot to check: ``path`` (absolute) is read, ``name`` (as given) is what reports and messages
    say, ``targets`` (absolute) where its files go."""

    path: str
    name: str
    targets: OutputTargets
    #: --baseline as given (absolute): a file, or a folder of <stem>.contacts.csv (usdksl.contacts.baseline).
    baseline: Optional[str] = None
    #: --baseline-time-tolerance, time codes.
    baseline_time_tolerance: Optional[float] = None


@dataclass
class ShotOutcome:
    """What became of one shot: its exit code, and either its result or the line saying why it failed."""

    name: str
    exit_code: int
    result: Optional[CheckResult] = None
    error: Optional[str] = None
    messages: List[Message] = field(default_factory=list)
    #: Time windows the shot was checked in on Dask (usdksl.scale.windows); 1: checked whole.
    windows: int = 1

    def line(self) -> str:
        """The shot's line in a batch: its summary, or its error."""
        if self.result is None:
            return f"usdksl: error: {self.error}"
        return self.result.line


def make_jobs(shots: Sequence[str], out: Optional[str], json_path: Optional[str] = None,
              junit_path: Optional[str] = None, baseline: Optional[str] = None,
              baseline_time_tolerance: Optional[float] = None, plot_path: Optional[str] = None,
              report_path: Optional[str] = None) -> List[object]:
    """A ShotJob per shot, or a failed ShotOutcome for a shot whose file or output folder is unusable.

    ``junit_path`` and ``json_path`` are only checked to be writable: the jobs do not write them, the caller
    writes one document for all shots (:func:`junit_for_outcomes`, :func:`json_for_outcomes`,
    :func:`report_for_outcomes`: with ``report_path`` each job draws its worst regions); each job's
    JSON document comes back as its result's ``stdout``. Raises UsdkslUsageError when the call cannot work
    at all: --plot or a baseline file (not a folder) with several shots, a baseline that does not exist, or
    two shots that would write the same files."""
    if len(shots) > 1 and plot_path:
        raise UsdkslUsageError(f"--plot takes one shot; got {len(shots)}")
    for report in (junit_path, json_path, report_path):
        if report and report != "-":
            check_writable_directory(Path(report).resolve().parent)
    if report_path is not None:
        require_report_libraries()
    if baseline is not None:
        if not os.path.exists(baseline):
            raise UsdkslUsageError("baseline not found", file=baseline)
        if len(shots) > 1 and not os.path.isdir(baseline):
            raise UsdkslUsageError(f"a baseline file serves one shot; for {len(shots)} shots give a folder of "
                                   f"<stem>.contacts.csv files (an earlier run's --out)", file=baseline)
        baseline = str(Path(baseline).resolve())
    entries: List[object] = []
    owners: Dict[Path, str] = {}
    for shot in shots:
        try:
            targets = output_targets(shot, out, "-" if json_path else None, plot_path=plot_path)
        except UsdkslInputError as error:
            entries.append(ShotOutcome(name=shot, exit_code=error.exit_code, error=error.one_line()))
            continue
        targets = OutputTargets(out_dir=targets.out_dir.resolve(),
                                json_to_stdout=targets.json_to_stdout,
                                plot_path=targets.plot_path and targets.plot_path.resolve(),
                                report_path=None if report_path is None else Path(report_path).resolve())
        written = targets.contacts_csv(shot)
        if written in owners:
            raise UsdkslUsageError(f"{owners[written]} and {shot} would both write {written}; "
                                   f"give shots with different names or check them into different --out folders")
        owners[written] = shot
        entries.append(ShotJob(path=str(Path(shot).resolve()), name=shot, targets=targets, baseline=baseline,
                               baseline_time_tolerance=baseline_time_tolerance))
    return entries


def run_job(job: ShotJob, options: CheckOptions) -> ShotOutcome:
    """Check one shot; never raises (a failure is an outcome with exit code 2). Runs on Dask workers."""
    return checked_outcome(job, lambda baseline: check_shot(job.path, options, job.targets, name=job.name,
                                                             baseline=baseline))


def checked_outcome(job: ShotJob, check: Callable[[Optional[AnyBaseline]], CheckResult]) -> ShotOutcome:
    """The outcome of ``check(baseline)`` for ``job`` (its baseline read first); never raises: bad input
    or a crash is an outcome with exit code 2 and one line."""
    notes: List[Message] = []
    try:
        baseline, warning = baseline_for_shot(job.baseline, shot_stem(job.name), job.baseline_time_tolerance)
        if warning is not None:
            notes.append(Message(WARNING, warning))
        result = check(baseline)
    except UsdkslInputError as error:
        if error.file == job.path:
            error.file = job.name
        return ShotOutcome(name=job.name, exit_code=error.exit_code, error=error.one_line())
    except Exception as error:  # noqa: BLE001  (a crash fails this shot, never the batch, never exit 1)
        if os.environ.get("USDKSL_DEBUG"):
            raise
        return ShotOutcome(name=job.name, exit_code=INPUT_ERROR,
                           error=f"{job.name}: internal error: {type(error).__name__}: "
                                 f"{' '.join(str(error).split())} (set USDKSL_DEBUG=1 for a traceback)")
    result.messages[:0] = notes
    return ShotOutcome(name=job.name, exit_code=result.exit_code, result=result, messages=result.messages)


def write_outcome(outcome: ShotOutcome) -> ShotOutcome:
    """Publish a checked shot's files (all or none); a write failure turns the outcome into exit 2."""
    if outcome.result is None:
        return outcome
    try:
        write_files(outcome.result.files)
    except UsdkslInputError as error:
        return ShotOutcome(name=outcome.name, exit_code=error.exit_code, error=error.one_line(),
                           messages=outcome.messages)
    return outcome


def run_here(jobs: Iterable[ShotJob], options: CheckOptions,
             progress: Optional[BatchProgress] = None) -> Iterable[ShotOutcome]:
    """The jobs one after the other in this process, in order (one piece of ``progress`` each)."""
    for job in jobs:
        outcome = run_job(job, options)
        if progress is not None:
            progress.advance()
        yield outcome


def junit_for_outcomes(outcomes: Sequence[ShotOutcome]) -> str:
    """The --junit document of a batch: one testsuite per shot, an <error> for a shot that failed."""
    suites = []
    for outcome in outcomes:
        result = outcome.result
        if result is None:
            suites.append(error_suite(outcome.name, outcome.error or "failed"))
        else:
            suites.append(shot_suite(outcome.name, result.plan, result.table, result.clock,
                                     None if result.baseline is None else result.baseline.known))
    return junit_document(suites)


def json_for_outcomes(outcomes: Sequence[ShotOutcome]) -> Optional[str]:
    """The --json text of a batch. One shot: its document exactly as a check of it alone writes it (None
    when it could not be checked: nothing is written, as alone). Several: JSON Lines, one compact document
    per shot in the order of ``outcomes``; a shot that could not be checked has a short document (tool,
    version, shot, exit_code, error)."""
    if len(outcomes) == 1:
        result = outcomes[0].result
        return None if result is None else result.stdout
    lines = []
    for outcome in outcomes:
        if outcome.result is None:
            document = {"tool": "usdksl", "version": package_version(), "shot": outcome.name,
                        "exit_code": int(outcome.exit_code), "error": outcome.error or "failed"}
        else:
            document = json.loads(outcome.result.stdout)
        lines.append(json.dumps(document, separators=(",", ":"), allow_nan=False) + "\n")
    return "".join(lines)


def report_for_outcomes(outcomes: Sequence[ShotOutcome]) -> str:
    """The --report page of a batch: one section per shot in the order of ``outcomes``, a shot that failed
    with its error line."""
    return report_html([(outcome.name, outcome.result, outcome.exit_code, outcome.error) for outcome in outcomes])


def worst_exit_code(outcomes: Iterable[ShotOutcome]) -> int:
    """The largest exit code (docs/contracts.md, Exit codes); 0 for no shot."""
    return max((outcome.exit_code for outcome in outcomes), default=CLEAN)


def total_line(outcomes: Sequence[ShotOutcome]) -> str:
    """The last line of a batch: how many shots ended how, and the exit code."""
    counts = {code: sum(1 for o in outcomes if o.exit_code == code)
              for code in (CLEAN, CONTACTS_FOUND, CROSSCHECK_DISAGREES, INPUT_ERROR)}
    parts = [f"{counts[CLEAN]} clean", f"{counts[CONTACTS_FOUND]} with contacts"]
    if counts[CROSSCHECK_DISAGREES]:
        parts.append(f"{counts[CROSSCHECK_DISAGREES]} where the cross-check disagrees")
    parts.append(f"{counts[INPUT_ERROR]} failed")
    shots = len(outcomes)
    return (f"usdksl: {shots} shot{'s' if shots != 1 else ''}: {', '.join(parts)}; "
            f"exit code {worst_exit_code(outcomes)}")


def run_batch(entries: Sequence[object], options: CheckOptions, runner: Callable = run_here,
              on_outcome: Optional[Callable[[ShotOutcome], None]] = None,
              progress: Optional[BatchProgress] = None) -> List[ShotOutcome]:
    """Run every ShotJob of ``entries`` with ``runner(jobs, options, progress=progress)`` (an iterator of
    outcomes in any order, advancing ``progress`` a piece per shot or per time window), write each shot's
    files as its outcome arrives, and return the outcomes in the order of ``entries`` (failed entries of
    :func:`make_jobs` included; each is a piece done). A stop (usdksl.stopping) ends the loop between two
    shots: shots already handed to ``on_outcome`` are written, the others not."""
    jobs = [entry for entry in entries if isinstance(entry, ShotJob)]
    done: Dict[str, ShotOutcome] = {}
    for entry in entries:
        if isinstance(entry, ShotOutcome):
            done[entry.name] = entry
            if progress is not None:
                progress.advance()
            if on_outcome is not None:
                on_outcome(entry)
    for outcome in runner(jobs, options, progress=progress):
        with deferred_stops():   # a shot's files and its line come together, or neither does
            outcome = write_outcome(outcome)
            done[outcome.name] = outcome
            if on_outcome is not None:
                on_outcome(outcome)
    return [done[entry.name] for entry in entries]
