"""A night's batch of shots on 1, 2, ... Dask workers: wall time and speedup, measured in one run.

    python benchmarks/batch_scaling.py [--shots 8] [--faces 2000] [--workers 1 2] [--out DIR]

Generates ``--shots`` small tablecloth shots (``samples/generate.py``, different seeds) into a scratch
folder, checks the whole batch with the library's batch runner in this process (the baseline) and on a
Dask LocalCluster of each worker count (the same code ``usdksl check --jobs N`` runs), verifies that every
run wrote byte-identical files, and prints wall time and speedup against the in-process run. Prints a
markdown table for benchmarks/results/REPORT.md with ``--markdown``. The machine is shared and has 2 cores:
read ratios, not seconds.
"""

from __future__ import annotations

import argparse
import functools
import hashlib
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Dict, List

from usdksl.checking.pipeline import CheckOptions
from usdksl.scale.batch import make_jobs, run_batch, run_here, worst_exit_code
from usdksl.scale.dask_runner import run_on_dask

HERE = Path(__file__).resolve().parent
GENERATE = HERE.parent / "samples" / "generate.py"


def generate_shots(folder: Path, count: int, faces: int) -> List[str]:
    paths = []
    for seed in range(count):
        path = folder / f"tablecloth_{faces}_seed{seed}.usdc"
        if not path.exists():
            subprocess.run([sys.executable, str(GENERATE), "tablecloth", "--faces", str(faces), "--seed", str(seed),
                            "--keyframes", "6", "--samples-per-keyframe", "2", "--out", str(path)],
                           check=True, capture_output=True)
        paths.append(str(path))
    return paths


def digests(folder: Path) -> Dict[str, str]:
    return {path.name: hashlib.sha256(path.read_bytes()).hexdigest() for path in sorted(folder.iterdir())}


def timed_batch(shots: List[str], out: Path, runner) -> float:
    out.mkdir(parents=True, exist_ok=True)
    started = time.perf_counter()
    outcomes = run_batch(make_jobs(shots, str(out)), CheckOptions(), runner=runner)
    seconds = time.perf_counter() - started
    assert worst_exit_code(outcomes) in (0, 1), [o.lines for o in outcomes]
    return seconds


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--shots", type=int, default=8)
    parser.add_argument("--faces", type=int, default=2000)
    parser.add_argument("--workers", type=int, nargs="+", default=[1, 2])
    parser.add_argument("--out", default=None, help="scratch folder (default: a temporary one)")
    parser.add_argument("--markdown", action="store_true")
    args = parser.parse_args(argv)

    scratch = Path(args.out) if args.out else Path(tempfile.mkdtemp(prefix="usdksl-batch-"))
    shots = generate_shots(scratch / "shots", args.shots, args.faces)
    baseline = timed_batch(shots, scratch / "here", run_here)
    reference = digests(scratch / "here")
    rows = [("in this process", baseline, 1.0)]
    for workers in args.workers:
        out = scratch / f"dask{workers}"
        seconds = timed_batch(shots, out, functools.partial(run_on_dask, workers=workers))
        assert digests(out) == reference, f"--jobs {workers} wrote different files"
        rows.append((f"Dask, {workers} worker{'s' if workers != 1 else ''}", seconds, baseline / seconds))
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    print(f"{args.shots} tablecloth shots of {args.faces} faces, {cores} cores; outputs byte-identical in every run")
    if args.markdown:
        print("| runner | wall s | speedup vs in-process |\n|---|---|---|")
        for name, seconds, speedup in rows:
            print(f"| {name} | {seconds:.1f} | {speedup:.2f}x |")
    else:
        for name, seconds, speedup in rows:
            print(f"{name:>20}: {seconds:7.1f} s wall  speedup {speedup:.2f}x")
    return 0


if __name__ == "__main__":
    sys.exit(main())
