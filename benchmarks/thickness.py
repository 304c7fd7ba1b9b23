"""What a thickness above 0 costs and what it measures, on simulator caches, in one run.

    .venv/bin/python benchmarks/thickness.py SHOT[,SHOT...] --thickness 0.002,0.01 \
        [--baseline-python ../other-worktree/.venv/bin/python] [--sampled 40] [--markdown PAGE.md]

For every shot and thickness, ``find_contacts`` (KSL, one thread) runs in a fresh process on this build and,
with --baseline-python (another build's python, or its usdksl command), on that build, one after the other
(benchmarks/harness.py). Printed per run: process time (CPU seconds of find_contacts), pairs, undecided queries,
primitive queries. Then, independently of the root finder, ``--sampled`` random reported triangle pairs of
each build are measured with ipctk's point-triangle and segment-segment distances (primitive pairs sharing a
vertex skipped, as the check skips them) at their reported time: the largest distance over the thickness.
A Euclidean narrow phase keeps it at 1 (up to its tolerance); one that accepts the per-axis thickness cube
reaches up to sqrt(3). The ratio line compares process times, this build over the baseline.
"""

import argparse
import math
import os
import shlex
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from harness import Build, git_revision, measuring  # noqa: E402
from ksl_vs_swept import checked_pairs, load_meshes  # noqa: E402
from peer_ipctk import _mesh_points_at  # noqa: E402


def triangle_pair_distance(mesh_a, tri_a, mesh_b, tri_b, time_code, same_mesh):
    """Euclidean distance between two triangles at a time, over the primitive pairs the check tests."""
    import ipctk
    ia, ib = mesh_a.triangles[tri_a], mesh_b.triangles[tri_b]
    at = np.array([time_code])
    a, b = _mesh_points_at(mesh_a, at)[0][ia], _mesh_points_at(mesh_b, at)[0][ib]
    best = math.inf
    for i in range(3):
        if not (same_mesh and ia[i] in ib):
            best = min(best, ipctk.point_triangle_distance(a[i], *b))
        if not (same_mesh and ib[i] in ia):
            best = min(best, ipctk.point_triangle_distance(b[i], *a))
        for j in range(3):
            if same_mesh and {ia[i], ia[(i + 1) % 3]} & {ib[j], ib[(j + 1) % 3]}:
                continue
            best = min(best, ipctk.edge_edge_distance(a[i], a[(i + 1) % 3], b[j], b[(j + 1) % 3]))
    return math.sqrt(best)


def run_one(shot, thickness, sampled):
    """One check in this process; the measurements as a dict."""
    import usdksl
    meshes = load_meshes(shot)
    with measuring() as measured:
        result = usdksl.find_contacts(meshes, checked_pairs(meshes), method="ksl", threads=1, thickness=thickness)
    rng = np.random.default_rng(19)
    decided = np.flatnonzero(~result.undecided)
    largest = 0.0
    for i in rng.choice(decided, size=min(sampled, decided.size), replace=False):
        ma, mb = int(result.mesh_a[i]), int(result.mesh_b[i])
        distance = triangle_pair_distance(meshes[ma], int(result.tri_a[i]), meshes[mb], int(result.tri_b[i]),
                                          float(result.time[i]), ma == mb)
        largest = max(largest, distance / thickness)
    return {"cpu": measured.cpu_s, "pairs": len(result), "undecided": int(result.undecided.sum()),
            "queries": int(result.counters.get("primitive_queries", 0)), "largest_distance": largest,
            "first": float(result.time.min()) if len(result) else None}


def run_isolated(build, shot, thickness, sampled):
    """``run_one`` with ``build``'s usdksl, in a fresh interpreter."""
    measured = build.call(run_one, shot, thickness, sampled)
    if measured.error:
        raise RuntimeError(f"{build.name} on {shot} at {thickness:g} failed: {measured.error}\n{measured.stderr}")
    return measured.value


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("shots", nargs="?")
    parser.add_argument("--thickness", default="0.002,0.01", help="comma-separated thicknesses (scene units)")
    parser.add_argument("--baseline-python", help="interpreter (or usdksl command) of another build of usdksl")
    parser.add_argument("--sampled", type=int, default=40, help="reported pairs measured per run")
    parser.add_argument("--markdown", help="write the results as a markdown page here")
    args = parser.parse_args()
    builds = [Build.current("current")] + ([Build.of(args.baseline_python, "baseline")] if args.baseline_python else [])
    here = os.path.dirname(os.path.abspath(__file__))
    lines = ["| shot | thickness | build | process s | pairs | undecided | primitive queries | first contact "
             "| largest distance / thickness (sampled) |", "|---|---|---|---|---|---|---|---|---|"]
    ratios = []
    for shot in args.shots.split(","):
        for thickness in (float(t) for t in args.thickness.split(",")):
            measured = {}
            for build in builds:
                r = run_isolated(build, shot, thickness, args.sampled)
                measured[build.name] = r
                first = "-" if r["first"] is None else f"{r['first']:.3f}"
                row = (f"| {os.path.basename(shot)} | {thickness:g} | {build.name} | {r['cpu']:.2f} | {r['pairs']} | "
                       f"{r['undecided']} | {r['queries']} | {first} | {r['largest_distance']:.4f} |")
                lines.append(row)
                print(row, flush=True)
            if "baseline" in measured:
                ratio = measured["current"]["cpu"] / measured["baseline"]["cpu"]
                ratios.append(f"- {os.path.basename(shot)} at {thickness:g}: current / baseline process time "
                              f"{ratio:.2f}")
                print(ratios[-1], flush=True)
    if args.markdown:
        revision = git_revision(here)
        baseline = f" against the baseline build at {builds[1].source()[1]}" if len(builds) > 1 else ""
        command = "python benchmarks/thickness.py " + " ".join(shlex.quote(a) for a in sys.argv[1:])
        page = ["# Thickness above 0: cost and measure", "", f"Command: `{command}`", "",
                f"`benchmarks/thickness.py` at {revision}{baseline}; KSL, one thread, each run in a fresh process. "
                f"The last column measures {args.sampled} random reported triangle pairs per run with ipctk's "
                "Euclidean distances at their reported time.", ""] + lines + [""] + ratios + [""]
        with open(args.markdown, "w") as out:
            out.write("\n".join(page))


if __name__ == "__main__":
    main()
