"""How every benchmark in benchmarks/ runs and times what it measures, and compares two builds.

    python benchmarks/harness.py [--rounds N] [--baseline OTHER] COMMAND...

The command line times COMMAND ``--rounds`` times (default 5) and, with ``--baseline``, the same
command of another build in alternating rounds: OTHER is that build's ``usdksl`` command or its
environment's ``python``, and a COMMAND starting with ``usdksl`` or ``python`` runs each build's own.
Printed: least and median wall and CPU seconds and peak memory of each build, and this build over the
baseline, measured in this one run.

From a script::

    harness.run([usdksl, "check", shot, "--out", out])    # a command, in a process of its own
    harness.call(function, *args)                          # a function, in this process
    harness.call_fresh(function, *args, python=...)        # a function, in a fresh interpreter
    with harness.measuring() as measured: ...              # a stretch of code
    harness.alternate({"this build": a, "baseline": b}, rounds)   # a, b, a, b, ...
    harness.summarise(measurements); harness.ratio_line(...)      # least, median, ratios

Units, everywhere: seconds for times, bytes for memory.

- Wall time: ``time.perf_counter`` around the run.
- CPU time: user + system seconds of every thread of the measured process and of the child processes it
  waited for.
- Peak memory: the resident set's high-water mark (Linux VmHWM, C++ allocations included). A
  measurement in this process first resets it to the current RSS (/proc/self/clear_refs), so it is the
  largest RSS while measured; ``rss_before_bytes`` is the RSS at the start, and ``peak_rise_bytes``
  what the run added. A command's is the largest RSS of its process or of any child it waited for.

A function whose memory must be its own runs in a fresh interpreter (``call_fresh``): interpreter start
and the import of its module are outside the clock, and its arguments and return value go through JSON.
A build is another checkout's install (``Build.of``): its ``usdksl`` command or its ``python``, so a
script compares two builds with the same code path as it measures one.
"""

from __future__ import annotations

import contextlib
import functools
import json
import math
import os
import resource
import signal
import sys
import time
from dataclasses import dataclass, field
from typing import Any, Callable, Dict, Hashable, Iterator, List, Mapping, Optional, Sequence, Tuple, TypeVar, Union

HERE = os.path.dirname(os.path.abspath(__file__))
HARNESS_FILE = os.path.abspath(__file__)
#: Bytes per MiB, for printing.
MIB = 2 ** 20
#: Seconds of CPU between the soft limit (SIGXCPU) and the hard one (SIGKILL) of a CPU budget: a process
#: that handles SIGXCPU still ends this soon after its budget.
CPU_HARD_LIMIT_GRACE_S = 5
#: Rounds of the command line when --rounds is not given.
DEFAULT_ROUNDS = 5
#: First argument of the fresh interpreter that ``call_fresh`` starts.
_CALL_FLAG = "--call"
#: ru_maxrss is in KiB on Linux, in bytes on macOS.
_MAXRSS_UNIT = 1 if sys.platform == "darwin" else 1024

Result = TypeVar("Result")


# --------------------------------------------------------------------------- one measurement

@dataclass
class Measurement:
    """One measured run: seconds and bytes (see the module docstring for what each counts)."""

    wall_s: float = 0.0
    cpu_s: float = 0.0
    #: RSS high-water mark while measured, bytes.
    peak_rss_bytes: int = 0
    #: RSS when the measurement started, bytes (0 for a command: its process starts empty).
    rss_before_bytes: int = 0
    #: False when the high-water mark could not be reset (no /proc): the peak is then the process's
    #: largest RSS since it started.
    peak_reset: bool = True
    #: A command's exit code (a negative number -N: ended by signal N); None for a function.
    exit_code: Optional[int] = None
    stdout: str = ""
    stderr: str = ""
    #: What a function returned (from a fresh interpreter: decoded from JSON).
    value: Any = None
    #: Ended by the wall-time limit (``timeout_s``).
    timed_out: bool = False
    #: Ended by the CPU-time budget (``cpu_budget_s``).
    over_cpu_budget: bool = False
    #: A fresh interpreter's function raised: the last line of its traceback.
    error: Optional[str] = None
    #: High-water mark seen before a nested measurement reset it, bytes.
    _peak_seen: int = field(default=0, repr=False, compare=False)

    @property
    def peak_rise_bytes(self) -> int:
        """What the run added to the RSS it started with, at its peak, bytes."""
        return max(0, self.peak_rss_bytes - self.rss_before_bytes)

    @property
    def completed(self) -> bool:
        """Neither stopped by a limit nor ended by an exception (a command's exit code is not judged)."""
        return not (self.timed_out or self.over_cpu_budget or self.error)


def cpu_seconds() -> float:
    """User + system CPU seconds of this process (all threads) and of the children it has waited for."""
    own, children = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + children.ru_utime + children.ru_stime


class Clock:
    """Wall and CPU seconds (``cpu_seconds``) since it was made; read as often as needed."""

    def __init__(self) -> None:
        self._wall = time.perf_counter()
        self._cpu = cpu_seconds()

    def wall_s(self) -> float:
        return time.perf_counter() - self._wall

    def cpu_s(self) -> float:
        return cpu_seconds() - self._cpu


def _status_bytes(field_name: str) -> Optional[int]:
    """A kB field of /proc/self/status in bytes; None where there is no /proc."""
    try:
        with open("/proc/self/status") as status:
            for line in status:
                if line.startswith(field_name + ":"):
                    return int(line.split()[1]) * 1024
    except OSError:
        pass
    return None


def current_rss_bytes() -> int:
    """This process's resident set now, bytes (the peak so far where /proc is missing)."""
    rss = _status_bytes("VmRSS")
    return rss if rss is not None else peak_rss_bytes()


def peak_rss_bytes() -> int:
    """This process's RSS high-water mark, bytes: since the last reset, or since it started."""
    peak = _status_bytes("VmHWM")
    return peak if peak is not None else resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * _MAXRSS_UNIT


def reset_peak_rss() -> bool:
    """Start the high-water mark afresh from the current RSS (Linux >= 4.0); False when not possible."""
    try:
        with open("/proc/self/clear_refs", "w") as handle:
            handle.write("5")
        return True
    except OSError:
        return False


#: Measurements under way in this process, outermost first (one thread measures at a time).
_open_measurements: List[Measurement] = []


@contextlib.contextmanager
def measuring() -> Iterator[Measurement]:
    """Measures the ``with`` block: the Measurement it yields is filled in when the block ends. Nests: an
    inner measurement's reset of the high-water mark does not hide the outer one's earlier peak."""
    measured = Measurement(rss_before_bytes=current_rss_bytes())
    peak_so_far = peak_rss_bytes()
    for outer in _open_measurements:
        outer._peak_seen = max(outer._peak_seen, peak_so_far)
    measured.peak_reset = reset_peak_rss()
    _open_measurements.append(measured)
    clock = Clock()
    try:
        yield measured
    finally:
        measured.wall_s, measured.cpu_s = clock.wall_s(), clock.cpu_s()
        _open_measurements.remove(measured)
        measured.peak_rss_bytes = max(peak_rss_bytes(), measured._peak_seen)


def call(function: Callable, *args, **kwargs) -> Measurement:
    """``function(*args, **kwargs)`` measured in this process; its return value is ``value``."""
    with measuring() as measured:
        measured.value = function(*args, **kwargs)
    return measured


def time_each(function: Callable[[Any], Any], items: Sequence) -> Tuple[List[Any], List[float]]:
    """``function(item)`` for every item, each timed alone: (results, wall seconds per item). For
    calls of microseconds, where ``measuring``'s own reads would outweigh the call."""
    results, seconds = [], []
    for item in items:
        started = time.perf_counter()
        results.append(function(item))
        seconds.append(time.perf_counter() - started)
    return results, seconds


class Stopwatch:
    """Adds up the wall seconds of every call of functions wrapped in their modules, per label; a
    context manager that puts the originals back when it ends."""

    def __init__(self) -> None:
        self.seconds: Dict[str, float] = {}
        self._restore: List[Callable[[], None]] = []

    def wrap(self, module, name: str, label: str) -> None:
        original = getattr(module, name)

        @functools.wraps(original)
        def timed(*args, **kwargs):
            started = time.perf_counter()
            try:
                return original(*args, **kwargs)
            finally:
                self.seconds[label] = self.seconds.get(label, 0.0) + time.perf_counter() - started

        setattr(module, name, timed)
        self._restore.append(lambda: setattr(module, name, original))

    def restore(self) -> None:
        for undo in reversed(self._restore):
            undo()
        self._restore.clear()

    def __enter__(self) -> "Stopwatch":
        return self

    def __exit__(self, *exc) -> None:
        self.restore()


# --------------------------------------------------------------------------- commands

def run(command: Sequence[str], *, timeout_s: Optional[float] = None, cpu_budget_s: Optional[float] = None,
        cwd: Optional[str] = None, env: Optional[Mapping[str, str]] = None) -> Measurement:
    """Runs ``command`` in a process of its own and measures it from outside: wall seconds from start to
    end, CPU seconds and peak RSS of that process (and of the children it waited for) from its own
    resource usage, so other children of this process never count. Output is captured (``stdout``,
    ``stderr``). ``timeout_s``: wall seconds before it is killed (``timed_out``); ``cpu_budget_s``: CPU
    seconds before the kernel ends it (RLIMIT_CPU; ``over_cpu_budget``)."""
    import subprocess
    import tempfile

    limit = None if cpu_budget_s is None else max(1, int(math.ceil(cpu_budget_s)))

    def set_cpu_limit() -> None:
        resource.setrlimit(resource.RLIMIT_CPU, (limit, limit + CPU_HARD_LIMIT_GRACE_S))

    with tempfile.TemporaryFile() as out, tempfile.TemporaryFile() as err:
        started = time.perf_counter()
        process = subprocess.Popen(list(command), stdin=subprocess.DEVNULL, stdout=out, stderr=err, cwd=cwd,
                                   env=None if env is None else dict(env),
                                   preexec_fn=set_cpu_limit if limit is not None else None)
        status, usage, killed = _wait_measuring(process.pid, timeout_s)
        wall = time.perf_counter() - started
        process.returncode = os.waitstatus_to_exitcode(status)   # reaped here: Popen must not wait again
        out.seek(0)
        err.seek(0)
        measured = Measurement(wall_s=wall, cpu_s=usage.ru_utime + usage.ru_stime,
                               peak_rss_bytes=usage.ru_maxrss * _MAXRSS_UNIT, exit_code=process.returncode,
                               stdout=out.read().decode(errors="replace"),
                               stderr=err.read().decode(errors="replace"), timed_out=killed)
    measured.over_cpu_budget = (limit is not None and not killed
                                and process.returncode in (-signal.SIGXCPU, -signal.SIGKILL))
    return measured


def _wait_measuring(pid: int, timeout_s: Optional[float]) -> Tuple[int, resource.struct_rusage, bool]:
    """(wait status, the child's resource usage, killed by the timeout) of child ``pid``, reaped."""
    import threading

    lock, state = threading.Lock(), {"ended": False, "killed": False}

    def kill() -> None:
        with lock:
            if not state["ended"]:
                os.kill(pid, signal.SIGKILL)
                state["killed"] = True

    timer = threading.Timer(timeout_s, kill) if timeout_s is not None else None
    if timer is not None:
        timer.daemon = True
        timer.start()
    try:
        # waited for without reaping first, so the timer can never signal a reused process id
        os.waitid(os.P_PID, pid, os.WEXITED | os.WNOWAIT)
        with lock:
            state["ended"] = True
        _, status, usage = os.wait4(pid, 0)
    except BaseException:
        with contextlib.suppress(OSError):
            os.kill(pid, signal.SIGKILL)
            os.wait4(pid, 0)
        raise
    finally:
        if timer is not None:
            timer.cancel()
    return status, usage, state["killed"]


# --------------------------------------------------------------------------- functions in a fresh interpreter

FunctionReference = Union[Callable, str]


def _reference(function: FunctionReference) -> Tuple[str, str]:
    """(module file, function name) of a module-level function, or of "path/to/module.py:name"."""
    if isinstance(function, str):
        path, _, name = function.rpartition(":")
        return os.path.abspath(path), name
    import inspect

    if function.__qualname__ != function.__name__:
        raise ValueError(f"{function.__qualname__} is not a module-level function: a fresh interpreter "
                         "cannot import it")
    return os.path.abspath(inspect.getfile(function)), function.__name__


def call_fresh(function: FunctionReference, *args, python: Optional[str] = None,
               timeout_s: Optional[float] = None, cpu_budget_s: Optional[float] = None,
               env: Optional[Mapping[str, str]] = None, **kwargs) -> Measurement:
    """``function(*args, **kwargs)`` in a fresh interpreter (``python``, default this one; another
    build's to measure that build), measured there around the call alone, so its peak memory is its own.
    ``function``: a module-level function (the child imports its module by name from the module's
    folder) or "path/to/module.py:name". Arguments and the return value (``value``) are JSON. When the
    function raises, ``error`` holds the last line of its traceback and ``stderr`` all of it; limits as
    in ``run`` (wall, CPU and peak then describe the whole child process)."""
    import tempfile

    path, name = _reference(function)
    with tempfile.TemporaryDirectory(prefix="harness-") as folder:
        result_path = os.path.join(folder, "result.json")
        command = [python or sys.executable, HARNESS_FILE, _CALL_FLAG, path, name,
                   json.dumps({"args": list(args), "kwargs": kwargs}, default=_jsonable), result_path]
        outer = run(command, timeout_s=timeout_s, cpu_budget_s=cpu_budget_s, env=env)
        if not outer.completed or outer.exit_code != 0 or not os.path.exists(result_path):
            lines = outer.stderr.strip().splitlines()
            if outer.completed:
                outer.error = (lines[-1] if lines else f"exit {outer.exit_code}")[:300]
            return outer
        with open(result_path) as handle:
            inner = json.load(handle)
    return Measurement(wall_s=inner["wall_s"], cpu_s=inner["cpu_s"], peak_rss_bytes=inner["peak_rss_bytes"],
                       rss_before_bytes=inner["rss_before_bytes"], peak_reset=inner["peak_reset"],
                       exit_code=outer.exit_code, stdout=outer.stdout, stderr=outer.stderr, value=inner["value"])


def _jsonable(value):
    """numpy scalars and arrays as Python numbers and lists."""
    if hasattr(value, "tolist"):
        return value.tolist()
    raise TypeError(f"{type(value).__name__} is not JSON serialisable")


def _child(path: str, name: str, arguments: str, result_path: str) -> int:
    """The fresh interpreter of ``call_fresh``: imports the module, measures the call, writes the result."""
    import importlib

    folder, module_name = os.path.split(os.path.splitext(path)[0])
    if folder not in sys.path:
        sys.path.insert(0, folder)
    function = getattr(importlib.import_module(module_name), name)
    given = json.loads(arguments)
    with measuring() as measured:
        value = function(*given["args"], **given["kwargs"])
    record = {"wall_s": measured.wall_s, "cpu_s": measured.cpu_s, "peak_rss_bytes": measured.peak_rss_bytes,
              "rss_before_bytes": measured.rss_before_bytes, "peak_reset": measured.peak_reset, "value": value}
    with open(result_path, "w") as handle:
        json.dump(record, handle, default=_jsonable)
    return 0


# --------------------------------------------------------------------------- builds

def _shebang_python(command: str) -> Optional[str]:
    """The interpreter a console script (a pip-installed ``usdksl``) starts, if it names a python."""
    try:
        with open(command, "rb") as handle:
            first = handle.readline().decode(errors="replace").strip()
    except OSError:
        return None
    if not first.startswith("#!"):
        return None
    interpreter = first[2:].split()[0] if first[2:].split() else ""
    return interpreter if os.path.basename(interpreter).startswith("python") else None


@dataclass(frozen=True)
class Build:
    """An installed build of usdksl: its ``usdksl`` command and its environment's python (None when it
    cannot be found: such a build runs commands only)."""

    name: str
    usdksl: str
    python: Optional[str]

    @classmethod
    def current(cls, name: str = "this build") -> "Build":
        """The build of this interpreter."""
        beside = os.path.join(os.path.dirname(sys.executable), "usdksl")
        return cls(name, beside if os.path.exists(beside) else "usdksl", sys.executable)

    @classmethod
    def of(cls, path: str, name: str = "baseline") -> "Build":
        """Another build, from its ``usdksl`` command or its environment's ``python``: the other is found
        beside it (a command's python also from the console script's first line)."""
        if os.path.basename(path).startswith("python"):
            return cls(name, os.path.join(os.path.dirname(path), "usdksl"), path)
        beside = os.path.join(os.path.dirname(path), "python")
        return cls(name, path, beside if os.path.exists(beside) else _shebang_python(path))

    def command(self, *args: str) -> List[str]:
        """``usdksl ARGS`` of this build."""
        return [self.usdksl, *args]

    def run(self, *args: str, **limits) -> Measurement:
        """``usdksl ARGS`` of this build, measured (``run``)."""
        return run(self.command(*args), **limits)

    def call(self, function: FunctionReference, *args, **kwargs) -> Measurement:
        """``function`` with this build's usdksl, in a fresh interpreter of its python (``call_fresh``)."""
        if not self.python:
            raise ValueError(f"{self.name} ({self.usdksl}): no python found beside it to call a function with")
        return call_fresh(function, *args, python=self.python, **kwargs)

    def source(self) -> Tuple[str, str]:
        """(folder of the usdksl package this build imports, its checkout's revision)."""
        folder = self.call(_usdksl_folder).value if self.python else os.path.dirname(self.usdksl)
        return folder, git_revision(folder)


def _usdksl_folder() -> str:
    import usdksl

    return os.path.dirname(usdksl.__file__)


def git_revision(folder: str) -> str:
    """Short commit of the checkout holding ``folder``, with '+changes' when its tracked files differ
    from it (what was measured); 'unknown' outside a checkout."""
    import subprocess

    def git(*args: str) -> str:
        try:
            return subprocess.run(["git", "-C", folder, *args], capture_output=True, text=True).stdout.strip()
        except OSError:
            return ""

    commit = git("rev-parse", "--short", "HEAD")
    if not commit:
        return "unknown"
    return commit + ("+changes" if git("status", "--porcelain", "--untracked-files=no") else "")


def load_average() -> float:
    """The machine's 1-minute load average (runs on a shared machine are read against it)."""
    return os.getloadavg()[0]


def byte_compile_usdksl() -> None:
    """Writes the .pyc files of the installed usdksl package (and of these benchmarks), as ``pip install``
    does: in an editable install run with PYTHONDONTWRITEBYTECODE, every ``usdksl`` process would
    otherwise compile its modules again, about 0.1 s that no installed copy pays."""
    import compileall
    import importlib.util

    # located, not imported: only the command line imports the command line package
    folders = [location for package in ("usdksl", "usdksl.cli")
               for location in importlib.util.find_spec(package).submodule_search_locations]
    for folder in folders + [HERE]:
        compileall.compile_dir(folder, quiet=1)


# --------------------------------------------------------------------------- repeats and comparisons

def alternate(runs: Mapping[Hashable, Callable[[], Result]], rounds: int) -> Dict[Hashable, List[Result]]:
    """Every run once per round, in turn (a, b, a, b, ...), so that each sees the same stretch of
    machine load; {name: what its calls returned (usually Measurements), in order}."""
    measured: Dict[Hashable, List[Result]] = {name: [] for name in runs}
    for _ in range(rounds):
        for name, measure in runs.items():
            measured[name].append(measure())
    return measured


@dataclass(frozen=True)
class Summary:
    """Least and median of repeated measurements: seconds and bytes."""

    runs: int
    wall_least_s: float
    wall_median_s: float
    cpu_least_s: float
    cpu_median_s: float
    peak_least_bytes: float
    peak_median_bytes: float

    def describe(self) -> str:
        return (f"wall least {self.wall_least_s:.3f} s, median {self.wall_median_s:.3f} s; "
                f"CPU least {self.cpu_least_s:.3f} s, median {self.cpu_median_s:.3f} s; "
                f"peak median {self.peak_median_bytes / MIB:.0f} MiB")


def summarise(measurements: Sequence[Measurement]) -> Summary:
    import statistics

    walls = [m.wall_s for m in measurements]
    cpus = [m.cpu_s for m in measurements]
    peaks = [m.peak_rss_bytes for m in measurements]
    return Summary(len(measurements), min(walls), statistics.median(walls), min(cpus), statistics.median(cpus),
                   min(peaks), statistics.median(peaks))


def median_run(runs: Sequence[Measurement]) -> Measurement:
    """The run of median wall time (the lower middle one of an even count): one whole run, so that its CPU
    time and output belong together."""
    ordered = sorted(runs, key=lambda run: run.wall_s)
    return ordered[(len(ordered) - 1) // 2]


def rounds_description(rounds: int) -> str:
    """How a benchmark that runs two commands ``rounds`` times in turn (``alternate``) and keeps each one's
    ``median_run`` says what its table shows."""
    return "one run each" if rounds == 1 else f"{rounds} rounds of both in turn, the run of median wall time of each"


def round_ratios(numerators: Sequence[Measurement], denominators: Sequence[Measurement]) -> str:
    """Wall-time ratio of each round of two alternated runs, as a comma-separated list."""
    return ", ".join(f"{a.wall_s / b.wall_s:.2f}" for a, b in zip(numerators, denominators))


def _ratio(a: float, b: float) -> float:
    return a / b if b else float("nan")


def ratio_line(name: str, reference: str, measured: Summary, baseline: Summary) -> str:
    """``name / reference`` ratios of wall (least, median), CPU and peak memory, from one run's summaries."""
    return (f"{name} / {reference}: least {_ratio(measured.wall_least_s, baseline.wall_least_s):.3f}, "
            f"median {_ratio(measured.wall_median_s, baseline.wall_median_s):.3f} (wall); CPU least "
            f"{_ratio(measured.cpu_least_s, baseline.cpu_least_s):.3f}, median "
            f"{_ratio(measured.cpu_median_s, baseline.cpu_median_s):.3f}; peak median "
            f"{_ratio(measured.peak_median_bytes, baseline.peak_median_bytes):.3f}")


def compare_builds(measure: Callable[[Build], Measurement], builds: Sequence[Build],
                   rounds: int) -> Dict[str, List[Measurement]]:
    """``measure(build)`` for every build, alternating, ``rounds`` rounds: {build name: measurements}."""
    return alternate({build.name: functools.partial(measure, build) for build in builds}, rounds)


def comparison_lines(measured: Mapping[str, Sequence[Measurement]], reference: str) -> List[str]:
    """A summary line per name, then each other name over ``reference``."""
    summaries = {name: summarise(runs) for name, runs in measured.items()}
    width = max(len(name) for name in summaries)
    lines = [f"  {name:{width}s}  {summary.describe()}" for name, summary in summaries.items()]
    lines += [f"  {ratio_line(name, reference, summary, summaries[reference])}"
              for name, summary in summaries.items() if name != reference]
    return lines


# --------------------------------------------------------------------------- command line

def _build_command(words: Sequence[str], build: Build) -> List[str]:
    """COMMAND with a leading ``usdksl`` or ``python`` replaced by the build's own."""
    first, rest = words[0], list(words[1:])
    if first == "usdksl":
        return [build.usdksl] + rest
    if first == "python":
        if not build.python:
            raise SystemExit(f"{build.name} ({build.usdksl}) has no python beside it")
        return [build.python] + rest
    return list(words)


def main(argv: Optional[Sequence[str]] = None) -> int:
    import argparse
    import shlex

    argv = list(sys.argv[1:] if argv is None else argv)
    if argv[:1] == [_CALL_FLAG]:
        return _child(*argv[1:5])
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--rounds", type=int, default=DEFAULT_ROUNDS, help="runs of each build")
    parser.add_argument("--baseline", default=None,
                        help="another build's usdksl command or its environment's python")
    parser.add_argument("command", nargs=argparse.REMAINDER, help="the command (usdksl ... or python ...)")
    args = parser.parse_args(argv)
    words = args.command[1:] if args.command[:1] == ["--"] else args.command
    if not words or args.rounds < 1:
        parser.error("give a command, and --rounds of at least 1")
    builds = [Build.current()] + ([Build.of(args.baseline)] if args.baseline else [])
    load = load_average()
    measured = compare_builds(lambda build: run(_build_command(words, build)), builds, args.rounds)
    print(f"{shlex.join(words)}  ({args.rounds} {'alternating ' if len(builds) > 1 else ''}rounds, load average "
          f"{load:.2f} at the start)")
    for build in builds:
        codes = sorted({m.exit_code for m in measured[build.name]})
        print(f"  {build.name}: {shlex.join(_build_command(words, build))}  (exit codes {codes})")
    for line in comparison_lines(measured, builds[-1].name if len(builds) > 1 else builds[0].name):
        print(line)
    return 0


if __name__ == "__main__":
    # through the importable module, so that a benchmark's own `import harness` shares its measurements
    import harness

    sys.exit(harness.main())
