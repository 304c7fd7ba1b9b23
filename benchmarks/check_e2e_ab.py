"""``usdksl check`` end to end, this build against another one, in alternating fresh processes.

    python benchmarks/check_e2e_ab.py ../shared/data/newton/newton_viewerusd_cloth_twist.usd \\
        --baseline ../main/.venv/bin/usdksl --rounds 10

Each round runs ``usdksl check SHOT --out DIR`` once with this build's command (beside this interpreter)
and once with ``--baseline`` (another checkout's command, or its environment's python), in turn, timed
from outside by benchmarks/harness.py: interpreter start, imports, load, plan, the core, the reports, the
process's end -- what a user waits for. Printed: the least and the median wall and CPU seconds and the
peak memory of each build, their ratios (this build / baseline, measured in this run; the machine is a
shared 2-core box, so the least is the steadiest figure), and whether every output file of the two
builds is byte for byte the same (exit code 1 when one differs or the exit codes do). This build's
modules are byte-compiled first, as ``pip install`` does; the baseline's are used as they are (compile
them there first, or its start-up includes compiling).
"""

from __future__ import annotations

import argparse
import filecmp
import os
import shlex
import sys
import tempfile
from typing import List

from harness import Build, byte_compile_usdksl, compare_builds, load_average, ratio_line, summarise

DEFAULT_ROUNDS = 10
THIS_BUILD = "this build"
BASELINE = "baseline"


def differing_files(first: str, second: str) -> List[str]:
    """Names of the files that are not byte-identical in the two folders (or are in only one)."""
    names = sorted(set(os.listdir(first)) | set(os.listdir(second)))
    return [name for name in names
            if not (os.path.isfile(os.path.join(first, name)) and os.path.isfile(os.path.join(second, name))
                    and filecmp.cmp(os.path.join(first, name), os.path.join(second, name), shallow=False))]


def run(shot: str, baseline: str, rounds: int, extra: List[str]) -> int:
    builds = [Build.current(THIS_BUILD), Build.of(baseline, BASELINE)]
    load = load_average()
    with tempfile.TemporaryDirectory(prefix="check-e2e-ab-") as folder:
        outs = {build.name: os.path.join(folder, build.name.replace(" ", "_")) for build in builds}
        runs = compare_builds(lambda build: build.run("check", shot, "--out", outs[build.name], *extra), builds,
                              rounds)
        differ = differing_files(outs[THIS_BUILD], outs[BASELINE])
        files = sorted(os.listdir(outs[THIS_BUILD]))
    codes = {name: sorted({r.exit_code for r in records}) for name, records in runs.items()}
    summaries = {name: summarise(records) for name, records in runs.items()}
    print(f"usdksl check {shlex.quote(shot)} --out DIR {' '.join(map(shlex.quote, extra))}".rstrip()
          + f"  ({rounds} alternating rounds, load average {load:.2f} at the start)")
    for build in builds:
        print(f"  {build.name:10s} {summaries[build.name].describe()}; exit codes {codes[build.name]}  "
              f"({build.usdksl})")
    print("  " + ratio_line(THIS_BUILD, BASELINE, summaries[THIS_BUILD], summaries[BASELINE]))
    same = not differ and codes[THIS_BUILD] == codes[BASELINE]
    print(f"  outputs: {len(files)} files ({', '.join(files)}), "
          + ("all byte-identical" if not differ else f"DIFFERENT: {', '.join(differ)}")
          + ("" if codes[THIS_BUILD] == codes[BASELINE] else "; exit codes DIFFER"))
    return 0 if same else 1


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("shot")
    parser.add_argument("--baseline", required=True,
                        help="the other build's usdksl command (or its environment's python)")
    parser.add_argument("--rounds", type=int, default=DEFAULT_ROUNDS)
    parser.add_argument("--check-args", default="", help="more arguments for both checks (one string)")
    args = parser.parse_args(argv)
    if args.rounds < 1:
        parser.error("--rounds must be at least 1")
    byte_compile_usdksl()
    return run(args.shot, args.baseline, args.rounds, shlex.split(args.check_args))


if __name__ == "__main__":
    sys.exit(main())
