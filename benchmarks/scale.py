"""How `usdksl check` scales with the cloth's size: generated tablecloths of 10k, 100k and 1M faces.

    python benchmarks/scale.py                          # 10k, 100k, 1M faces, 10 samples each
    python benchmarks/scale.py --faces 10000 100000 --threads 1 --markdown benchmarks/results/scale.md

Each shot is made once by ``samples/generate.py tablecloth --faces N --keyframes 10
--samples-per-keyframe 1`` (10 samples, into samples/generated/) and checked end to end as
``usdksl check`` does it (the library's check_shot and its files written, in a process of its own measured
by benchmarks/harness.py, so its peak resident memory is its own; the core's work counters are recorded
too). Printed per shot: wall and CPU seconds, CPU microseconds per face and its ratio to the smallest shot
(target: at most 2x at 1M faces), face pairs in contact per face (the answer grows with the cloth's resolution:
finer wrinkles touch more), peak memory, and bytes per triangle sample above :data:`MEMORY_BASE_MB`
against :data:`MEMORY_BUDGET_PER_TRIANGLE_SAMPLE`. The machine is shared and has 2 cores: compare the ratios of
one run, not seconds across runs.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
from typing import Dict, List, Optional

from harness import run

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)

#: Faces of the default shots.
DEFAULT_FACES = (10_000, 100_000, 1_000_000)
#: Samples per shot (keyframes at every sample: the flightplans have a breakpoint at each).
SAMPLES = 10
#: Peak resident memory of a check that has loaded nothing: interpreter, USD, numpy, the native module
#: (a 2k-face shot peaks at about 160 MB).
MEMORY_BASE_MB = 256
#: Most bytes of peak resident memory per triangle sample (triangles x samples of every mesh, static
#: ones included) above MEMORY_BASE_MB, single thread (each thread's time window has its own trees).
MEMORY_BUDGET_PER_TRIANGLE_SAMPLE = 1024
#: Counters shown per face: box tests and overlaps of the separation lists, narrow-phase calls,
#: primitive distance queries, triangle pairs confirmed on raw samples.
PER_FACE_COUNTERS = ("bv_tests", "bv_overlap_events", "polygons_collide_events", "narrow_phase_tests",
                     "primitive_queries", "raw_confirmations")
#: Largest CPU time per face at the biggest shot, relative to the smallest (the target of the core's
#: scaling: time per face may grow, but not past twice the smallest shot's).
TIME_PER_FACE_TARGET = 2.0


def shot_path(faces: int) -> str:
    return os.path.join(REPO, "samples", "generated", f"tablecloth_{faces}_s{SAMPLES}.usdc")


def make_shot(faces: int) -> str:
    path = shot_path(faces)
    if not os.path.exists(path):
        os.makedirs(os.path.dirname(path), exist_ok=True)
        subprocess.run([sys.executable, os.path.join(REPO, "samples", "generate.py"), "tablecloth",
                        "--faces", str(faces), "--keyframes", str(SAMPLES), "--samples-per-keyframe", "1",
                        "--out", path], check=True, capture_output=True)
    return path


def shot_size(path: str) -> Dict[str, int]:
    """Triangles (all meshes) and samples of the shot, as the check loads it."""
    import usdksl

    shot = usdksl.load_shot(path)
    triangles = int(sum(len(mesh.triangles) for mesh in shot.meshes))
    return {"triangles": triangles, "samples": int(len(shot.times)),
            "triangle_samples": int(sum(len(mesh.triangles) * len(mesh.times) for mesh in shot.meshes))}


#: What ``usdksl check SHOT --out OUT [--threads N]`` runs (the library's check_shot, then its files
#: written), with the core's work counters dumped as JSON to COUNTERS: events and narrow-phase tests per
#: face say why time per face grows. argv: SHOT OUT COUNTERS THREADS (0: all cores).
_CHECK = (
    "import json, sys\n"
    "from usdksl.pipeline import CheckOptions, check_shot, output_targets\n"
    "from usdksl.reports.output import write_files\n"
    "shot, out, counters_path, threads = sys.argv[1], sys.argv[2], sys.argv[3], int(sys.argv[4])\n"
    "result = check_shot(shot, CheckOptions(threads=threads or None), output_targets(shot, out))\n"
    "write_files(result.files)\n"
    "json.dump(result.counters, open(counters_path, 'w'))\n"
    "sys.exit(result.exit_code)\n"
)


def measure(path: str, threads: Optional[int], budget_s: float) -> Dict:
    with tempfile.TemporaryDirectory(prefix="usdksl-scale-") as out_dir:
        counters_path = os.path.join(out_dir, "counters.json")
        # -P: the checkout's folder must not shadow the installed usdksl
        command = [sys.executable, "-P", "-c", _CHECK, path, out_dir, counters_path, str(threads or 0)]
        measured = run(command, timeout_s=budget_s)
        if measured.timed_out:
            return {"skipped": f"over the {budget_s:g} s budget"}
        record = {"exit_code": measured.exit_code, "wall_s": measured.wall_s, "cpu_s": measured.cpu_s,
                  "peak_kb": measured.peak_rss_bytes // 1024, "stderr": measured.stderr[-2000:]}
        if os.path.exists(counters_path):
            with open(counters_path) as stream:
                record["counters"] = json.load(stream)
        contacts = [name for name in os.listdir(out_dir) if name.endswith(".contacts.csv")]
        if contacts:
            with open(os.path.join(out_dir, contacts[0])) as stream:
                record["face_pairs"] = sum(1 for _ in stream) - 1
        else:
            record["face_pairs"] = 0
    if record["exit_code"] not in (0, 1):
        raise RuntimeError(f"usdksl check exited {record['exit_code']} on {path}: {record['stderr'][-300:]}")
    return record


def render(rows: List[Dict], threads: Optional[int]) -> str:
    base = next((row for row in rows if "cpu_s" in row), None)
    lines = [f"usdksl check on generated tablecloths ({SAMPLES} samples), threads={threads or 'all'}, "
             f"load average {os.getloadavg()[0]:.2f}",
             "",
             "| faces | triangles x samples | wall s | CPU s | CPU us/face | per face vs smallest | contacts/face | "
             "peak MB | B/triangle sample above base | within budget |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for row in rows:
        if "cpu_s" not in row:
            lines.append(f"| {row['faces']} | {row['triangles']} x {row['samples']} | {row['skipped']} | | | | | | | |")
            continue
        per_face = row["cpu_s"] / row["faces"] * 1e6
        ratio = per_face / (base["cpu_s"] / base["faces"] * 1e6)
        bytes_per = max(0.0, row["peak_kb"] / 1024 - MEMORY_BASE_MB) * 2**20 / row["triangle_samples"]
        lines.append(f"| {row['faces']} | {row['triangles']} x {row['samples']} | {row['wall_s']:.1f} | "
                     f"{row['cpu_s']:.1f} | {per_face:.1f} | {ratio:.2f} | {row['face_pairs'] / row['faces']:.2f} | "
                     f"{row['peak_kb'] / 1024:.0f} | "
                     f"{bytes_per:.0f} | {'yes' if bytes_per <= MEMORY_BUDGET_PER_TRIANGLE_SAMPLE else 'NO'} |")
    counted = [row for row in rows if row.get("counters")]
    if counted:
        lines += ["", "Work of the core per face (counters of the check):", "",
                  "| faces | " + " | ".join(PER_FACE_COUNTERS) + " |",
                  "|---|" + "---|" * len(PER_FACE_COUNTERS)]
        for row in counted:
            lines.append(f"| {row['faces']} | " + " | ".join(
                f"{row['counters'].get(name, 0) / row['faces']:.1f}" for name in PER_FACE_COUNTERS) + " |")
    lines += ["", f"Targets: CPU per face at the largest shot <= {TIME_PER_FACE_TARGET:g}x the smallest's; peak "
              f"memory <= {MEMORY_BASE_MB} MB + {MEMORY_BUDGET_PER_TRIANGLE_SAMPLE} B per triangle sample."]
    return "\n".join(lines)


def main(argv: Optional[List[str]] = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--faces", type=int, nargs="+", default=list(DEFAULT_FACES))
    parser.add_argument("--threads", type=int, default=1, help="threads of the core (0: all cores)")
    parser.add_argument("--budget", type=float, default=3600.0, help="wall seconds per shot")
    parser.add_argument("--markdown", help="also write the table to this file")
    args = parser.parse_args(argv)
    rows = []
    for faces in sorted(args.faces):
        path = make_shot(faces)
        row = {"faces": faces, **shot_size(path)}
        row.update(measure(path, args.threads or None, args.budget))
        rows.append(row)
        print(json.dumps({k: v for k, v in row.items() if k != "stderr"}), flush=True)
    table = render(rows, args.threads or None)
    print(table)
    if args.markdown:
        with open(args.markdown, "w") as stream:
            stream.write(f"# Scale\n\nCommand: `python benchmarks/scale.py {' '.join(argv or sys.argv[1:])}`\n\n"
                         + table + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
