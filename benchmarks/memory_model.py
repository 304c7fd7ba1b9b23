"""Peak memory of ``check`` against the estimate of usdksl.checking.memory_budget, and a new fit of it.

    python benchmarks/memory_model.py [--quick] [--methods ksl,swept] [--threads 1,2]

Generates tablecloth shots (samples/generate.py) over a grid of sizes and sample counts into a
temporary folder, checks each in a fresh interpreter and measures the peak RSS the check adds
(benchmarks/harness.py: the RSS high-water mark during the check minus the RSS just before it, imports
done). Prints, per shot and method, the scan's counts, the measured rise, the estimate and their ratio,
then the least-squares fit of bytes = fixed + a * vertex_samples + b * triangles * threads (per method;
each thread checks a time window with trees and lists of its own) to compare with the constants in
memory_budget.py. The model is meant to stay within 2x of the measurement (tests hold it to that on two
sizes); heavy self contact adds memory per contact that no scan can know.
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile

from harness import call_fresh, measuring

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
#: (faces, keyframes, samples per keyframe) of the tablecloth grid.
GRID = [(2000, 11, 1), (2000, 11, 10), (8000, 11, 1), (8000, 11, 5), (8000, 11, 10), (16000, 11, 1)]
QUICK_GRID = [(2000, 11, 1), (2000, 11, 5), (4000, 11, 1), (4000, 11, 5)]
TARGET_RATIO = 2.0


def measure(path: str, method: str, threads: int) -> dict:
    """Runs in a fresh interpreter, so the RSS before the check is the imports' and nothing else."""
    import numpy  # noqa: F401
    from pxr import Usd  # noqa: F401

    from usdksl import _native  # noqa: F401
    from usdksl.pipeline.check import check_shot
    from usdksl.pipeline.memory_budget import estimated_bytes, scan_shot
    from usdksl.pipeline.options import CheckOptions

    size = scan_shot(path)
    counts = {"meshes": size.meshes, "vertex_samples": size.vertex_samples, "triangles": size.triangles,
              "estimate": estimated_bytes(size, method, threads)}
    del size
    with measuring() as measured:
        result = check_shot(path, CheckOptions(method=method, memory_limit="off", threads=threads))
    return dict(counts, rise=measured.peak_rise_bytes, contacts=int(result.table.count))


def measure_in_subprocess(path: str, method: str, threads: int) -> dict:
    measured = call_fresh(measure, path, method, threads)
    if measured.error:
        raise RuntimeError(f"{method} check of {path} failed: {measured.error}\n{measured.stderr}")
    return measured.value


def fit(rows):
    """Least squares of rise = fixed + a * vertex_samples + b * triangles * threads: (fixed, a, b)."""
    import numpy as np

    matrix = np.array([[1.0, row["vertex_samples"], row["triangles"] * row["threads"]] for row in rows])
    rises = np.array([row["rise"] for row in rows], dtype=float)
    solution, *_ = np.linalg.lstsq(matrix, rises, rcond=None)
    return solution


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--methods", default="ksl,swept")
    parser.add_argument("--threads", default="1,2", help="thread counts to measure (comma-separated)")
    parser.add_argument("--quick", action="store_true", help="small shots only (a few minutes)")
    args = parser.parse_args(argv)

    sys.path.insert(0, os.path.join(REPO, "samples"))
    import generate

    methods = args.methods.split(",")
    thread_counts = [int(count) for count in args.threads.split(",")]
    rows = []
    mib = 2.0 ** 20
    with tempfile.TemporaryDirectory(prefix="usdksl-memory-model-") as folder:
        for faces, keyframes, spk in QUICK_GRID if args.quick else GRID:
            path = os.path.join(folder, f"tablecloth_{faces}_{keyframes}_{spk}.usdc")
            generate.generate("tablecloth", faces, keyframes=keyframes, samples_per_keyframe=spk, seed=7,
                              out=path)
            for method in methods:
                for threads in thread_counts:
                    row = dict(measure_in_subprocess(path, method, threads), shot=os.path.basename(path),
                               method=method, threads=threads)
                    rows.append(row)
                    ratio = row["estimate"] / row["rise"]
                    print(f"{row['shot']:<28} {method:<6} {threads} thr {row['vertex_samples']:>9,} vertex samples "
                          f"{row['triangles']:>7,} triangles  measured {row['rise'] / mib:7.1f} MiB  estimate "
                          f"{row['estimate'] / mib:7.1f} MiB  ratio {ratio:4.2f}", flush=True)
    for method in methods:
        chosen = [row for row in rows if row["method"] == method]
        if len(chosen) >= 3:
            fixed, per_vertex_sample, per_triangle = fit(chosen)
            print(f"fit {method}: fixed {fixed / mib:.1f} MiB, {per_vertex_sample:.0f} B per vertex sample, "
                  f"{per_triangle:.0f} B per triangle and thread")
    worst = max(max(row["estimate"] / row["rise"], row["rise"] / row["estimate"]) for row in rows)
    print(f"worst ratio {worst:.2f} ({'within' if worst <= TARGET_RATIO else 'OUTSIDE'} the "
          f"{TARGET_RATIO:g}x target)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
