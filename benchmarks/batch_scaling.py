"""A batch of shots, and one long shot, on 1, 2 and all Dask workers: wall time, speedup and CPU time, one run.

    python benchmarks/batch_scaling.py [--shots 8] [--faces 2000] [--workers 1 2] [--long-faces F]
                                       [--long-keyframes 11] [--repeat 1] [--out DIR] [--markdown]
                                       [--write benchmarks/results]

Generates ``--shots`` small tablecloth shots and one long one (``samples/generate.py``, scratch folder),
then checks

* the batch with the library's batch runner in this process (the core on every core, usdksl --threads)
  and on a Dask LocalCluster of each worker count (what ``usdksl check --jobs N`` runs): more shots than
  workers, one task per shot;
* the long shot the same ways: on N >= 2 workers it is split into time windows (usdksl.scale.windows).

Every run must write byte-identical files (checked). Printed per run: wall seconds, speedup against one
worker and against the in-process run, and CPU seconds (this process and its worker processes, user +
system) with CPU / wall, the cores kept busy. Worker counts default to 1, 2 and all cores. The machine's
load average is printed before and after: the machines are shared and have 2 cores, so read the ratios
of one run, not the seconds. ``--markdown`` prints markdown tables; ``--write benchmarks/results`` also
writes them with the command to batch_scaling.md, which benchmarks/report.py embeds in REPORT.md.
"""

from __future__ import annotations

import argparse
import functools
import hashlib
import multiprocessing
import os
import subprocess
import sys
import tempfile
import time
from multiprocessing import resource_tracker
from pathlib import Path
from typing import Dict, List, Optional, Set, Tuple

from usdksl.checking.collision import default_threads
from usdksl.pipeline.options import CheckOptions
from usdksl.scale.batch import make_jobs, run_batch, run_here, worst_exit_code
from usdksl.scale.dask_runner import run_on_dask
from usdksl.scale.local_cluster import default_workers

from harness import Clock, git_revision

HERE = Path(__file__).resolve().parent
GENERATE = HERE.parent / "samples" / "generate.py"
#: Samples between two keyframes of the generated shots.
BATCH_SAMPLES_PER_KEYFRAME = 2
LONG_SAMPLES_PER_KEYFRAME = 10
#: How long to wait for a closed cluster's worker processes to end before reading their CPU time.
REAP_TIMEOUT_SECONDS = 30
REAP_POLL_SECONDS = 0.05
#: The markdown this benchmark writes for benchmarks/results/REPORT.md.
REPORT_MD = "batch_scaling.md"


def generate(path: Path, faces: int, seed: int, keyframes: int, samples_per_keyframe: int) -> str:
    if not path.exists():
        subprocess.run([sys.executable, str(GENERATE), "tablecloth", "--faces", str(faces), "--seed", str(seed),
                        "--keyframes", str(keyframes), "--samples-per-keyframe", str(samples_per_keyframe),
                        "--out", str(path)], check=True, capture_output=True)
    return str(path)


def digests(folder: Path) -> Dict[str, str]:
    return {path.name: hashlib.sha256(path.read_bytes()).hexdigest() for path in sorted(folder.iterdir())}


def reap_workers(before: Set[int]) -> None:
    """Wait (untimed) until the worker processes started since ``before`` have ended and been reaped, so
    that their CPU time is in RUSAGE_CHILDREN; gives up after REAP_TIMEOUT_SECONDS."""
    import psutil   # a dependency of distributed

    deadline = time.monotonic() + REAP_TIMEOUT_SECONDS
    while time.monotonic() < deadline:
        multiprocessing.active_children()   # joins the processes that ended
        if not {child.pid for child in psutil.Process().children()} - before:
            return
        time.sleep(REAP_POLL_SECONDS)
    print(f"warning: worker processes still running after {REAP_TIMEOUT_SECONDS} s; CPU time is low",
          file=sys.stderr)


def timed_batch(shots: List[str], out: Path, runner) -> Tuple[float, float, List[int]]:
    """(wall seconds, CPU seconds, windows per shot) of one checked batch written to ``out``. CPU: this
    process and its worker processes, which end with their cluster inside the run and are reaped
    (:func:`reap_workers`, after the wall clock stops) before it is read."""
    import psutil   # a dependency of distributed

    out.mkdir(parents=True, exist_ok=True)
    children = {child.pid for child in psutil.Process().children()}
    clock = Clock()
    outcomes = run_batch(make_jobs(shots, str(out)), CheckOptions(), runner=runner)
    seconds = clock.wall_s()
    reap_workers(children)
    cpu = clock.cpu_s()
    assert worst_exit_code(outcomes) in (0, 1), [outcome.line() for outcome in outcomes]
    return seconds, cpu, [outcome.windows for outcome in outcomes]


def measure(shots: List[str], scratch: Path, label: str, workers: List[int], repeat: int) -> List[tuple]:
    """Rows (runner, windows, wall, speedup vs 1 worker, speedup vs in-process, CPU, CPU / wall); each
    run is the best of ``repeat`` wall times, and every run's files equal the in-process run's."""
    runs: List[Tuple[str, Optional[int], object]] = [("in this process", None, run_here)]
    runs += [(f"Dask, {count} worker{'s' if count != 1 else ''}", count, functools.partial(run_on_dask, workers=count))
             for count in workers]
    reference = None
    measured = []
    for name, count, runner in runs:
        best = None
        for attempt in range(repeat):
            out = scratch / f"{label}-{count or 'here'}-{attempt}"
            seconds, cpu, windows = timed_batch(shots, out, runner)
            files = digests(out)
            reference = reference or files
            assert files == reference, f"{name} wrote other files than the in-process run"
            if best is None or seconds < best[0]:
                best = (seconds, cpu, windows)
        measured.append((name, count, *best))
    in_process = measured[0][2]
    one_worker = next((seconds for _, count, seconds, _, _ in measured if count == 1), None)
    return [(name, "/".join(str(w) for w in sorted(set(windows))), seconds,
             None if one_worker is None or count is None else one_worker / seconds, in_process / seconds,
             cpu, cpu / seconds)
            for name, count, seconds, cpu, windows in measured]


def table_lines(rows: List[tuple], markdown: bool) -> List[str]:
    lines = []
    if markdown:
        lines += ["| runner | windows per shot | wall s | speedup vs 1 worker | speedup vs in-process | CPU s | "
                  "CPU / wall |", "|---|---|---|---|---|---|---|"]
    for name, windows, seconds, vs_one, vs_here, cpu, busy in rows:
        one = "-" if vs_one is None else f"{vs_one:.2f}x"
        if markdown:
            lines.append(f"| {name} | {windows} | {seconds:.1f} | {one} | {vs_here:.2f}x | {cpu:.1f} | {busy:.2f} |")
        else:
            lines.append(f"{name:>20}: windows {windows:>3}  {seconds:7.1f} s wall  speedup {one:>6} vs 1 worker, "
                         f"{vs_here:.2f}x vs in-process  CPU {cpu:7.1f} s ({busy:.2f} cores busy)")
    return lines


def load_average() -> str:
    return " ".join(f"{value:.2f}" for value in os.getloadavg())


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--shots", type=int, default=8)
    parser.add_argument("--faces", type=int, default=2000)
    parser.add_argument("--keyframes", type=int, default=6, help="keyframes of each batch shot")
    parser.add_argument("--long-faces", type=int, default=None, help="faces of the long shot (default: --faces)")
    parser.add_argument("--long-keyframes", type=int, default=11,
                        help=f"keyframes of the long shot ({LONG_SAMPLES_PER_KEYFRAME} samples each); 0: no long shot")
    parser.add_argument("--workers", type=int, nargs="+", default=None,
                        help="worker counts (default: 1, 2 and all cores)")
    parser.add_argument("--repeat", type=int, default=1, help="runs of each, the best wall time kept")
    parser.add_argument("--out", default=None, help="scratch folder (default: a temporary one)")
    parser.add_argument("--markdown", action="store_true")
    parser.add_argument("--write", default=None, metavar="DIR",
                        help=f"also write DIR/{REPORT_MD} (markdown), which benchmarks/report.py embeds in REPORT.md "
                             "(DIR: benchmarks/results)")
    args = parser.parse_args(argv)

    workers = sorted(set(args.workers or [1, 2, default_workers()]))
    # multiprocessing's resource tracker outlives every cluster: started now, it is not taken for a worker
    resource_tracker.ensure_running()
    scratch = Path(args.out) if args.out else Path(tempfile.mkdtemp(prefix="usdksl-batch-"))
    (scratch / "shots").mkdir(parents=True, exist_ok=True)
    shots = [generate(scratch / "shots" / f"tablecloth_{args.faces}_seed{seed}.usdc", args.faces, seed, args.keyframes,
                      BATCH_SAMPLES_PER_KEYFRAME) for seed in range(args.shots)]
    before = load_average()
    print(f"{default_threads()} cores, all = {default_workers()} workers; load average before: {before}")
    markdown = args.markdown or args.write is not None
    sections = []
    batch = measure(shots, scratch, "batch", workers, args.repeat)
    sections.append((f"{args.shots} tablecloth shots of {args.faces} faces, {args.keyframes} keyframes x "
                     f"{BATCH_SAMPLES_PER_KEYFRAME} samples", batch))
    if args.long_keyframes:
        faces = args.long_faces or args.faces
        long_shot = generate(scratch / "shots" / f"long_tablecloth_{faces}_{args.long_keyframes}.usdc", faces, 0,
                             args.long_keyframes, LONG_SAMPLES_PER_KEYFRAME)
        rows = measure([long_shot], scratch, "long", workers, args.repeat)
        sections.append((f"1 long tablecloth shot of {faces} faces, {args.long_keyframes} keyframes x "
                         f"{LONG_SAMPLES_PER_KEYFRAME} samples", rows))
    after = load_average()
    lines = []
    for title, rows in sections:
        lines += ["", f"{title}; outputs byte-identical in every run:", ""] + table_lines(rows, markdown)
    lines += ["", f"Load average (1, 5, 15 min) before: {before}; after: {after}."]
    print("\n".join(lines))
    if args.write is not None:
        command = "python benchmarks/batch_scaling.py " + " ".join(argv if argv is not None else sys.argv[1:])
        page = [f"`{command}` (source: {git_revision(str(HERE))}), {default_threads()} cores, shared with other jobs.",
                "Wall seconds include starting the Dask cluster (what `usdksl check --jobs N` pays); CPU seconds "
                "are this process and its worker processes, user + system; CPU / wall is the cores kept busy. "
                "The in-process run checks one shot after the other with the core on every core (`--threads`)."]
        Path(args.write).mkdir(parents=True, exist_ok=True)
        (Path(args.write) / REPORT_MD).write_text("\n".join(page + lines) + "\n")
        print(f"wrote {Path(args.write) / REPORT_MD}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
