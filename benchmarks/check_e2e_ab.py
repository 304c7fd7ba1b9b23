"""``usdksl check`` end to end, this build against another one, in alternating fresh processes.

    python benchmarks/check_e2e_ab.py ../shared/data/newton/newton_viewerusd_cloth_twist.usd \\
        --baseline ../main/.venv/bin/usdksl --rounds 10

Each round runs ``usdksl check SHOT --out DIR`` once with this build's command (beside this interpreter)
and once with ``--baseline`` (another checkout's command), in turn, timed from outside: interpreter start,
imports, load, plan, the core, the reports, the process's end -- what a user waits for. Printed: the least
and the median wall seconds of each build and their ratios (this build / baseline, measured in this run;
the machine is a shared 2-core box, so the least is the steadiest figure), CPU seconds, and whether every
output file of the two builds is byte for byte the same (exit code 1 when one differs or the exit codes
do). This build's modules are byte-compiled first, as ``pip install`` does; the baseline's are used as
they are (compile them there first, or its start-up includes compiling).
"""

from __future__ import annotations

import argparse
import filecmp
import os
import resource
import shlex
import statistics
import subprocess
import sys
import tempfile
import time
from typing import Dict, List

from newton_bench import byte_compile_usdksl

DEFAULT_ROUNDS = 10
THIS_BUILD = "this build"
BASELINE = "baseline"


def this_build_command() -> str:
    """The ``usdksl`` console script installed beside this interpreter."""
    return os.path.join(os.path.dirname(sys.executable), "usdksl")


def timed_check(command: str, shot: str, out_dir: str, extra: List[str]) -> Dict:
    """One ``command check SHOT --out out_dir`` in a fresh process: wall and CPU seconds, exit code."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    completed = subprocess.run([command, "check", shot, "--out", out_dir, *extra], capture_output=True, text=True)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return {"wall_s": wall, "cpu_s": (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime),
            "exit_code": completed.returncode, "stderr": completed.stderr}


def differing_files(first: str, second: str) -> List[str]:
    """Names of the files that are not byte-identical in the two folders (or are in only one)."""
    names = sorted(set(os.listdir(first)) | set(os.listdir(second)))
    return [name for name in names
            if not (os.path.isfile(os.path.join(first, name)) and os.path.isfile(os.path.join(second, name))
                    and filecmp.cmp(os.path.join(first, name), os.path.join(second, name), shallow=False))]


def run(shot: str, baseline: str, rounds: int, extra: List[str]) -> int:
    commands = {THIS_BUILD: this_build_command(), BASELINE: baseline}
    runs: Dict[str, List[Dict]] = {name: [] for name in commands}
    load = os.getloadavg()[0]
    with tempfile.TemporaryDirectory(prefix="check-e2e-ab-") as folder:
        outs = {name: os.path.join(folder, name.replace(" ", "_")) for name in commands}
        for _ in range(rounds):
            for name, command in commands.items():
                runs[name].append(timed_check(command, shot, outs[name], extra))
        differ = differing_files(outs[THIS_BUILD], outs[BASELINE])
        files = sorted(os.listdir(outs[THIS_BUILD]))
    codes = {name: sorted({r["exit_code"] for r in records}) for name, records in runs.items()}
    print(f"usdksl check {shlex.quote(shot)} --out DIR {' '.join(map(shlex.quote, extra))}".rstrip()
          + f"  ({rounds} alternating rounds, load average {load:.2f} at the start)")
    summary = {}
    for name, records in runs.items():
        walls = [r["wall_s"] for r in records]
        cpus = [r["cpu_s"] for r in records]
        summary[name] = (min(walls), statistics.median(walls))
        print(f"  {name:10s} wall least {min(walls):.3f} s, median {statistics.median(walls):.3f} s; "
              f"CPU median {statistics.median(cpus):.3f} s; exit codes {codes[name]}  ({commands[name]})")
    (least, median), (base_least, base_median) = summary[THIS_BUILD], summary[BASELINE]
    print(f"  this build / baseline: least {least / base_least:.3f}, median {median / base_median:.3f}")
    same = not differ and codes[THIS_BUILD] == codes[BASELINE]
    print(f"  outputs: {len(files)} files ({', '.join(files)}), "
          + ("all byte-identical" if not differ else f"DIFFERENT: {', '.join(differ)}")
          + ("" if codes[THIS_BUILD] == codes[BASELINE] else "; exit codes DIFFER"))
    return 0 if same else 1


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("shot")
    parser.add_argument("--baseline", required=True, help="the other build's usdksl command")
    parser.add_argument("--rounds", type=int, default=DEFAULT_ROUNDS)
    parser.add_argument("--check-args", default="", help="more arguments for both checks (one string)")
    args = parser.parse_args(argv)
    if args.rounds < 1:
        parser.error("--rounds must be at least 1")
    byte_compile_usdksl()
    return run(args.shot, args.baseline, args.rounds, shlex.split(args.check_args))


if __name__ == "__main__":
    sys.exit(main())
