"""KSL against its swept-volume baseline on one or more shots, in one run: times, ratios, counters.

    .venv/bin/python benchmarks/ksl_vs_swept.py SHOT[,SHOT...] swept,ksl [--threads 1,2] [--repeat 1]

SHOT is a USD file (loaded with usdksl.load_shot; every deforming mesh is checked against itself and
every pair with at least one deforming mesh is checked) or a generated per-frame shot:

    perframe:N:F   a cloth of 2*N*N triangles sampled at every one of F frames, waving on curves, sinking
                   onto a static slab and folding over itself (self and inter contacts; no Newton needed).

Each (shot, method, threads) run happens in a fresh subprocess so that its peak memory (ru_maxrss,
reported in MB and in bytes per triangle-sample) is its own; the time is measured around
find_contacts alone: process time (all threads added up) and wall time. Every run's answer (the first
contact time of every triangle pair) must equal the first run's bit for bit, or the script says so and
exits 1. Printed per run: seconds, narrow-phase tests and us per test, event counts; then per shot the
ratios ksl/swept (process time, one thread) and the wall-time speed-up of each thread count over one.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import os
import resource
import subprocess
import sys
import time

import numpy as np

EVENT_COUNTERS = ("kinetic_tree_events", "bv_overlap_events", "fathers_do_not_overlap_events",
                  "leaves_do_not_overlap_events", "polygons_collide_events", "bv_change_events")


class GeneratedMesh:
    """The fields find_contacts reads, plus the loader's path and kind."""

    def __init__(self, path, kind, times, points, triangles, triangle_face):
        self.path, self.kind = path, kind
        self.times = np.asarray(times, dtype=np.float64)
        self.points = np.ascontiguousarray(points, dtype=np.float64)
        self.triangles = np.asarray(triangles, dtype=np.int32)
        self.triangle_face = np.asarray(triangle_face, dtype=np.int32)


def per_frame_cloth(n, frames):
    """A cloth (n x n quads, two triangles each) sampled at every frame on curved paths: it waves,
    sinks onto a static slab and folds its right half over its left (like
    tests/collision/test_exact_times.py::per_frame_cloth, scaled up)."""
    xs, zs = np.meshgrid(np.linspace(0.0, 1.0, n + 1), np.linspace(0.0, 1.0, n + 1), indexing="ij")
    rest = np.stack([xs.ravel(), np.zeros(xs.size), zs.ravel()], axis=1)
    idx = np.arange((n + 1) ** 2).reshape(n + 1, n + 1)
    a, b, c, d = idx[:-1, :-1].ravel(), idx[1:, :-1].ravel(), idx[1:, 1:].ravel(), idx[:-1, 1:].ravel()
    tris = np.concatenate([np.stack([a, b, c], 1), np.stack([a, c, d], 1)])
    quads = np.concatenate([np.arange(n * n), np.arange(n * n)])
    times = np.arange(0.0, float(frames))
    samples = np.empty((frames, rest.shape[0], 3))
    right = rest[:, 0] > 0.5
    dx = rest[right, 0] - 0.5
    for k, t in enumerate(times):
        u = t * 40.0 / frames  # the motion of the 40-frame test shot, spread over `frames`
        p = rest.copy()
        p[:, 1] = 0.35 - 0.012 * u + 0.04 * np.sin(3.0 * p[:, 0] + 0.4 * u) * np.cos(2.0 * p[:, 2] + 0.3 * u)
        fold = 1.15 * np.pi * min(u / 32.0, 1.0) ** 2
        p[right, 0] = 0.5 + dx * np.cos(fold)
        p[right, 1] += dx * np.sin(fold) + 0.03 * dx
        samples[k] = p
    cloth = GeneratedMesh("/cloth", "deforming", times, samples, tris, quads)
    w = 0.4
    slab_points = np.array([[[-w, 0.0, -w], [w, 0.0, -w], [w, 0.0, w], [-w, 0.0, w]]]) + [0.5, 0.0, 0.5]
    slab = GeneratedMesh("/slab", "static", [0.0], slab_points, [[0, 1, 2], [0, 2, 3]], [0, 0])
    return [cloth, slab]


def load_meshes(shot):
    if shot.startswith("perframe:"):
        _, n, frames = shot.split(":")
        return per_frame_cloth(int(n), int(frames))
    import usdksl
    return usdksl.load_shot(shot).meshes


def checked_pairs(meshes):
    deforming = [m.kind == "deforming" for m in meshes]
    pairs = [(i, i) for i, d in enumerate(deforming) if d]
    pairs += [(i, j) for i in range(len(meshes)) for j in range(i + 1, len(meshes)) if deforming[i] or deforming[j]]
    return pairs


def run_one(shot, method, threads):
    """Runs one check in this process and returns its measurements as a dict."""
    import usdksl
    meshes = load_meshes(shot)
    pairs = checked_pairs(meshes)
    kwargs = {} if threads is None else {"threads": threads}
    cpu, wall = time.process_time(), time.perf_counter()
    result = usdksl.find_contacts(meshes, pairs, method=method, **kwargs)
    cpu, wall = time.process_time() - cpu, time.perf_counter() - wall
    answer = hashlib.sha256()
    for column in (result.time, result.mesh_a, result.tri_a, result.mesh_b, result.tri_b, result.feature):
        answer.update(np.ascontiguousarray(column).tobytes())
    triangle_samples = sum(int(m.triangles.shape[0]) * int(m.times.shape[0]) for m in meshes)
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
    return {"cpu": cpu, "wall": wall, "counters": result.counters, "pairs": len(result),
            "face_pairs": len(result.face_contacts(meshes)), "answer": answer.hexdigest()[:16],
            "peak_bytes": peak, "triangle_samples": triangle_samples,
            "triangles": sum(int(m.triangles.shape[0]) for m in meshes)}


def run_isolated(shot, method, threads):
    command = [sys.executable, os.path.abspath(__file__), "--one", shot, method, str(threads or 0)]
    out = subprocess.run(command, check=True, capture_output=True, text=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def describe(shot, method, threads, r):
    c = r["counters"]
    tests = max(1, c["narrow_phase_tests"])
    events = sum(c[k] for k in EVENT_COUNTERS)
    return (f"{os.path.basename(shot):32s} {method:6s} thr={threads or 1:<2d} cpu={r['cpu']:8.2f}s "
            f"wall={r['wall']:8.2f}s tests={c['narrow_phase_tests']:>10d} us/test={1e6 * r['cpu'] / tests:6.2f} "
            f"queries={c['primitive_queries']:>10d} events={events:>9d} (tree={c['kinetic_tree_events']} "
            f"pc={c['polygons_collide_events']} bvchg={c['bv_change_events']} overlap={c['bv_overlap_events']} "
            f"fathers={c['fathers_do_not_overlap_events']} leaves={c['leaves_do_not_overlap_events']}) "
            f"confirm={c['raw_confirmations']} reject={c['raw_rejections']} tri_pairs={r['pairs']} "
            f"face_pairs={r['face_pairs']} peak={r['peak_bytes'] / 2**20:.0f}MB "
            f"({r['peak_bytes'] / max(1, r['triangle_samples']):.0f} B/tri-sample) answer={r['answer']}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--one", nargs=3, metavar=("SHOT", "METHOD", "THREADS"), help=argparse.SUPPRESS)
    parser.add_argument("shots", nargs="?")
    parser.add_argument("methods", nargs="?", default="swept,ksl")
    parser.add_argument("--threads", default=None,
                        help="comma-separated thread counts (default: the core's default, one run)")
    parser.add_argument("--repeat", type=int, default=1, help="runs per setting; the fastest counts")
    args = parser.parse_args()
    if args.one:
        shot, method, threads = args.one
        print(json.dumps(run_one(shot, method, int(threads) or None)))
        return 0
    thread_counts = [int(t) for t in args.threads.split(",")] if args.threads else [None]
    status = 0
    for shot in args.shots.split(","):
        results = {}
        for method in args.methods.split(","):
            for threads in thread_counts:
                best = None
                for _ in range(args.repeat):
                    r = run_isolated(shot, method, threads)
                    if best is None or r["wall"] < best["wall"]:
                        best = r
                results[(method, threads)] = best
                print(describe(shot, method, threads, best), flush=True)
        answers = {r["answer"] for r in results.values()}
        if len(answers) != 1:
            print(f"{shot}: ANSWERS DIFFER between runs: {sorted(answers)}")
            status = 1
        else:
            print(f"{shot}: every run gave the same answer ({answers.pop()})")
        single = thread_counts[0]
        if ("ksl", single) in results and ("swept", single) in results:
            ratio = results[("ksl", single)]["cpu"] / results[("swept", single)]["cpu"]
            print(f"{shot}: ksl/swept process time at threads={single or 'default'}: {ratio:.3f}")
        for method in args.methods.split(","):
            base = results.get((method, thread_counts[0]))
            for threads in thread_counts[1:]:
                r = results[(method, threads)]
                print(f"{shot}: {method} wall speed-up threads={threads} over threads={thread_counts[0]}: "
                      f"{base['wall'] / r['wall']:.2f}x")
    return status


if __name__ == "__main__":
    sys.exit(main())
