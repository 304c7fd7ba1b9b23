"""Run ``usdksl check`` on many files, each in a process of its own with a time budget, and say what is
wrong with each run.

The command runs exactly as installed (``usdksl.cli.entry.main``), in a child forked from a server that
has imported usdksl, pxr and numpy once (multiprocessing's forkserver), so a case costs its check and
not Python's start-up. The child's file descriptors 1 and 2 go to files, so what USD prints from C++ is
seen too; its temporary folder is a fresh one. A child still running after the budget is killed: a
hang. What a run must do (:func:`problems`): end within the budget with exit code 0, 1 or 2; print no
traceback and no "internal error"; on exit 2 say why in one ``usdksl: error:`` line naming the file;
write all of its files, complete and parseable, or none; leave no temporary file; never touch its input.
"""

from __future__ import annotations

import csv
import hashlib
import math
import multiprocessing
import os
import shutil
import sys
import tempfile
import threading
import time
import types
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path
from typing import Iterable, List, Optional, Sequence

#: Seconds a case may take. The samples check in under a second of CPU (a few seconds of wall time on a
#: loaded two-core machine); a hang runs far past this.
CASE_SECONDS = 30.0
#: Modules the fork server imports once for every case (everything a check of the samples imports).
PRELOAD = ["numpy", "numpy.ma", "pxr.Usd", "pxr.UsdGeom", "pxr.UsdSkel", "pxr.UsdPhysics", "pxr.UsdShade",
           "usdksl._native", "usdksl.cli.entry", "usdksl.cli.main", "usdksl.pipeline.check",
           "usdksl.reports.override"]
OUTPUT_SUFFIXES = (".contacts.csv", ".summary.csv", ".usdksl.usda", ".regions.csv")
CONTACTS_HEADER = ["time", "prim_a", "face_a", "prim_b", "face_b", "kind"]
SUMMARY_HEADER = ["prim_a", "prim_b", "kind", "first_contact_time", "face_pairs"]
REGIONS_HEADER = ["region", "prim_a", "prim_b", "kind"]

_context = None
_start_lock = threading.Lock()


def _fork_server():
    global _context
    if _context is None:
        # The fork server starts as `python -c ...`, which puts the working folder first on sys.path:
        # from a checkout that is the source tree, whose usdksl has no built _native. Children must
        # import the package as installed, as the command does.
        os.environ["PYTHONSAFEPATH"] = "1"
        _context = multiprocessing.get_context("forkserver")
        _context.set_forkserver_preload(PRELOAD)
    return _context


def _start(process) -> None:
    """Start ``process`` without making the child import this interpreter's main module (pytest's, or
    the long-run script): multiprocessing re-imports it in every child, which needs nothing from it, and
    importing pytest there costs a third of a second per case."""
    with _start_lock:
        main = sys.modules["__main__"]
        sys.modules["__main__"] = types.ModuleType("__main__")
        try:
            process.start()
        finally:
            sys.modules["__main__"] = main


def _child(arguments: List[str], stdout_path: str, stderr_path: str, temp_dir: str) -> None:
    """In the forked child: the command with fds 1 and 2 in files; exits with the command's code."""
    for fd, path in ((1, stdout_path), (2, stderr_path)):
        handle = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o644)
        os.dup2(handle, fd)
        os.close(handle)
    os.environ["TMPDIR"] = temp_dir
    tempfile.tempdir = temp_dir
    os.environ.pop("USDKSL_DEBUG", None)
    sys.argv = ["usdksl", *arguments]
    from usdksl.cli.entry import main

    main()


@dataclass
class Case:
    """One run: the shot (a file in a folder of its own), extra arguments, and where its files go."""

    shot: Path
    out: Path
    arguments: Sequence[str] = ()
    label: str = ""

    def command(self) -> List[str]:
        return ["check", str(self.shot), "--out", str(self.out), *self.arguments]


@dataclass
class Outcome:
    case: Case
    exit_code: Optional[int]
    stderr: str
    seconds: float
    hung: bool
    input_changed: bool
    temp_left: List[str] = field(default_factory=list)

    def problems(self) -> List[str]:
        return problems(self)


#: What multiprocessing reports when the fork server lost a child's exit status (it does so, rarely, on a
#: loaded machine: python/cpython#140867); the command itself never exits with it.
STATUS_LOST = 255
#: Runs of one case after a lost status, before the lost status is reported as the outcome.
ATTEMPTS = 3


def run_case(case: Case, seconds: float = CASE_SECONDS) -> Outcome:
    """Run ``case`` in a child of the fork server; again (from a clean output folder) when the server
    lost the exit status, so a flaw of Python's fork server never passes for one of the command."""
    for _ in range(ATTEMPTS):
        shutil.rmtree(case.out, ignore_errors=True)
        outcome = _run_case_once(case, seconds)
        if outcome.exit_code != STATUS_LOST:
            break
    return outcome


def _run_case_once(case: Case, seconds: float) -> Outcome:
    context = _fork_server()
    work = Path(tempfile.mkdtemp(prefix="usdksl-fuzz-run-"))
    temp_dir = work / "tmp"
    temp_dir.mkdir()
    digest = hashlib.sha256(case.shot.read_bytes()).hexdigest()
    process = context.Process(target=_child, args=(case.command(), str(work / "stdout"), str(work / "stderr"),
                                                   str(temp_dir)))
    started = time.monotonic()
    _start(process)
    process.join(seconds)
    hung = process.is_alive()
    if hung:
        process.kill()
        process.join()
    elapsed = time.monotonic() - started
    stderr = (work / "stderr").read_text(errors="replace") if (work / "stderr").exists() else ""
    outcome = Outcome(case=case, exit_code=None if hung else process.exitcode, stderr=stderr, seconds=elapsed,
                      hung=hung, input_changed=hashlib.sha256(case.shot.read_bytes()).hexdigest() != digest,
                      temp_left=sorted(p.name for p in temp_dir.iterdir()))
    shutil.rmtree(work, ignore_errors=True)
    return outcome


def run_cases(cases: Iterable[Case], workers: int = 2, seconds: float = CASE_SECONDS) -> List[Outcome]:
    """Every case, ``workers`` at a time, in order."""
    _fork_server()
    with ThreadPoolExecutor(max_workers=workers) as pool:
        return list(pool.map(lambda case: run_case(case, seconds), cases))


def _parse_csv(path: Path, header: List[str]) -> List[List[str]]:
    with open(path, newline="") as handle:
        rows = list(csv.reader(handle))
    if not rows or rows[0][:len(header)] != header:
        raise ValueError(f"header {rows[0] if rows else None}")
    return rows[1:]


def _output_problems(outcome: Outcome) -> List[str]:
    case = outcome.case
    stem = case.shot.name.rsplit(".", 1)[0]
    expected = [case.out / f"{stem}{suffix}" for suffix in OUTPUT_SUFFIXES]
    present = [path for path in expected if path.exists()]
    found = sorted(p.name for p in case.out.iterdir()) if case.out.exists() else []
    strays = [name for name in found if case.out / name not in expected]
    strays += [p.name for p in case.shot.parent.iterdir() if p.name.startswith(".usdksl-tmp-")]
    issues = [f"stray files: {strays}"] if strays else []
    if outcome.exit_code == 2:
        if present:
            issues.append(f"exit 2 but wrote {[p.name for p in present]}")
        return issues
    if len(present) != len(expected):
        return issues + [f"exit {outcome.exit_code} but only {[p.name for p in present]} written"]
    try:
        rows = _parse_csv(expected[0], CONTACTS_HEADER)
        for row in rows:
            if not math.isfinite(float(row[0])) or int(row[2]) < 0 or int(row[4]) < 0 or row[5] not in ("self", "inter"):
                raise ValueError(f"row {row}")
        _parse_csv(expected[1], SUMMARY_HEADER)
        regions = _parse_csv(expected[3], REGIONS_HEADER)
    except (ValueError, IndexError) as error:
        return issues + [f"unparseable CSV: {error}"]
    if (outcome.exit_code == 1) != bool(rows):
        issues.append(f"exit {outcome.exit_code} with {len(rows)} contact rows")
    if bool(regions) != bool(rows):
        issues.append(f"{len(regions)} regions for {len(rows)} contact rows")
    from pxr import Sdf, Tf

    try:
        layer = Sdf.Layer.OpenAsAnonymous(str(expected[2]))
    except Tf.ErrorException as error:
        layer = None
        issues.append(f"override layer does not open: {error}")
    if layer is None and not issues:
        issues.append("override layer does not open")
    return issues


def problems(outcome: Outcome) -> List[str]:
    """What is wrong with one run (empty: nothing)."""
    if outcome.hung:
        return [f"hang: still running after {outcome.seconds:.0f} s"]
    issues = []
    if outcome.exit_code not in (0, 1, 2):
        issues.append(f"exit code {outcome.exit_code}" + (" (killed by a signal: a crash)"
                                                          if outcome.exit_code is not None and outcome.exit_code < 0
                                                          else ""))
    for word in ("Traceback", "internal error"):
        if word in outcome.stderr:
            issues.append(f"'{word}' on stderr")
    if outcome.exit_code == 2:
        errors = [line for line in outcome.stderr.splitlines() if line.startswith("usdksl: error:")]
        if len(errors) != 1:
            issues.append(f"exit 2 with {len(errors)} error lines")
        elif str(outcome.case.shot) not in errors[0] and outcome.case.shot.name not in errors[0]:
            issues.append("the error line does not name the file")
    if outcome.input_changed:
        issues.append("the input file changed")
    if outcome.temp_left:
        issues.append(f"left in the temporary folder: {outcome.temp_left}")
    if outcome.exit_code in (0, 1, 2):
        issues.extend(_output_problems(outcome))
    return issues


def describe(outcome: Outcome) -> str:
    last = outcome.stderr.strip().splitlines()[-3:]
    return (f"{outcome.case.label or outcome.case.shot.name}: {'; '.join(outcome.problems())} "
            f"[exit {outcome.exit_code}, {outcome.seconds:.1f} s] stderr tail: {last}")


def _run_function_once(target, arguments: Sequence, seconds: float):
    context = _fork_server()
    work = Path(tempfile.mkdtemp(prefix="usdksl-fuzz-call-"))
    process = context.Process(target=_call_child, args=(target, tuple(arguments), str(work / "output")))
    _start(process)
    process.join(seconds)
    hung = process.is_alive()
    if hung:
        process.kill()
        process.join()
    output = (work / "output").read_text(errors="replace") if (work / "output").exists() else ""
    shutil.rmtree(work, ignore_errors=True)
    return (None if hung else process.exitcode), output


def run_function(target, arguments: Sequence, seconds: float = CASE_SECONDS):
    """``target(*arguments)`` in a forked child with fds 1 and 2 in a file: (exit code or None when it
    hung and was killed, what it printed); run again when the fork server lost the exit status."""
    for _ in range(ATTEMPTS):
        code, output = _run_function_once(target, arguments, seconds)
        if code != STATUS_LOST:
            break
    return code, output


def _call_child(target, arguments, output_path: str) -> None:
    handle = os.open(output_path, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o644)
    os.dup2(handle, 1)
    os.dup2(handle, 2)
    os.close(handle)
    target(*arguments)
    sys.stdout.flush()
    sys.stderr.flush()
