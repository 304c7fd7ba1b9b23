"""What one exploded vertex costs the narrow phase, per primitive query.

    python benchmarks/blowup_ccd.py [SHOT] [--vertex V] [--time T] [--heights 1e3 1e5 1e7 1e9]
                                    [--tolerance 1e-6] [--thickness 0]

Moves vertex V of the shot's first deforming mesh to y = H at the sample nearest time T (default:
the middle vertex and sample, as benchmarks/blowup.py), and runs every vertex-face and edge-edge
query between a triangle holding V and any triangle of that mesh, over the two steps into and out
of that sample, whose swept boxes overlap (the unmodified shot: the same construction without the
blow-up). Prints per height: the number of queries, CPU time per query and parameter boxes
(iterations) per query as ratios of the unmodified shot's, the largest iteration count of one query,
hits and undecided queries; then how much iterations per query vary across heights (machine-
independent; near 1 when the root finder copes with huge slivers as with ordinary triangles). Ratios come from one run; the machine is shared, so read
ratios and iteration counts, not seconds.
"""

from __future__ import annotations

import argparse
import os
import sys

import numpy as np

import usdksl
from usdksl import ccd

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from blowup_setup import add_blowup_arguments, blowup_target  # noqa: E402
from harness import call  # noqa: E402

DEFAULT_SHOT = os.path.join(HERE, "..", "samples", "fold.usda")
#: Relative padding of the swept-box filter (to the coordinates' magnitude), as the core pads boxes.
BOX_PADDING = 1e-10
#: Edge (i, i+1) of a triangle, as corner indices.
EDGES = np.array([[0, 1], [1, 2], [2, 0]])


def swept_boxes_overlap(first: np.ndarray, second: np.ndarray) -> np.ndarray:
    """first (Q, n, 3) and second (Q, m, 3) point sets at both times -> bool[Q] boxes touch."""
    lo_a, hi_a = first.min(axis=1), first.max(axis=1)
    lo_b, hi_b = second.min(axis=1), second.max(axis=1)
    magnitude = np.maximum(np.abs(np.concatenate([first, second], axis=1)).max(axis=(1, 2)), 1.0)
    reach = BOX_PADDING * magnitude[:, None]
    return np.all((lo_a <= hi_b + reach) & (lo_b <= hi_a + reach), axis=1)


def step_queries(start: np.ndarray, end: np.ndarray, triangles: np.ndarray, pairs: np.ndarray):
    """Vertex-face (Q, 8, 3) and edge-edge (Q, 8, 3) queries of triangle pairs over one step.

    Primitive pairs sharing a vertex are left out (they touch by construction), as the core does.
    """
    tri_a, tri_b = triangles[pairs[:, 0]], triangles[pairs[:, 1]]
    vertex_face, edge_edge = [], []
    for vertices, faces in ((tri_a, tri_b), (tri_b, tri_a)):
        for corner in range(3):
            vertex = vertices[:, corner]
            keep = ~(faces == vertex[:, None]).any(axis=1)
            ids = np.column_stack([vertex, faces])[keep]
            vertex_face.append(np.concatenate([start[ids], end[ids]], axis=1))
    for edge_a in EDGES:
        for edge_b in EDGES:
            ids_a, ids_b = tri_a[:, edge_a], tri_b[:, edge_b]
            keep = ~(ids_a[:, :, None] == ids_b[:, None, :]).any(axis=(1, 2))
            ids = np.column_stack([ids_a, ids_b])[keep]
            edge_edge.append(np.concatenate([start[ids], end[ids]], axis=1))
    vertex_face, edge_edge = np.concatenate(vertex_face), np.concatenate(edge_edge)
    vf_near = swept_boxes_overlap(vertex_face[:, [0, 4]], vertex_face[:, [1, 2, 3, 5, 6, 7]])
    ee_near = swept_boxes_overlap(edge_edge[:, [0, 1, 4, 5]], edge_edge[:, [2, 3, 6, 7]])
    return vertex_face[vf_near], edge_edge[ee_near]


def run_queries(points: np.ndarray, sample: int, triangles: np.ndarray, pairs: np.ndarray, args):
    """CPU seconds, iterations[Q], hit[Q], undecided[Q] of every query around `sample`."""
    steps = [(s, s + 1) for s in (sample - 1, sample) if 0 <= s and s + 1 < points.shape[0]]
    batches = [step_queries(points[s0], points[s1], triangles, pairs) for s0, s1 in steps]
    seconds, iterations, hits, undecided = 0.0, [], [], []
    for vertex_face, edge_edge in batches:
        for run, queries in ((ccd.vertex_face_detailed, vertex_face), (ccd.edge_edge_detailed, edge_edge)):
            measured = call(run, queries, tolerance=args.tolerance, thickness=args.thickness)
            seconds += measured.cpu_s
            answers = measured.value
            iterations.append(answers.iterations)
            hits.append(answers.hit)
            undecided.append(answers.undecided)
    return seconds, np.concatenate(iterations), np.concatenate(hits), np.concatenate(undecided)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    add_blowup_arguments(parser, DEFAULT_SHOT)
    parser.add_argument("--tolerance", type=float, default=ccd.DEFAULT_TOLERANCE)
    parser.add_argument("--thickness", type=float, default=0.0)
    args = parser.parse_args(argv)

    shot = usdksl.load_shot(args.shot)
    blowup = blowup_target(shot.meshes, args)
    mesh, vertex, sample = blowup.mesh, blowup.vertex, blowup.sample
    triangles = mesh.triangles
    blown = np.flatnonzero((triangles == vertex).any(axis=1))
    grid = np.stack(np.meshgrid(blown, np.arange(len(triangles)), indexing="ij"), axis=-1).reshape(-1, 2)
    pairs = grid[grid[:, 0] != grid[:, 1]]

    base_seconds, base_iterations, base_hits, _ = run_queries(mesh.points, sample, triangles, pairs, args)
    base_per_query = base_seconds / len(base_iterations)
    base_mean = base_iterations.mean()
    print(f"shot {args.shot}: {mesh.path} vertex {vertex} at time {mesh.times[sample]:g}, "
          f"{len(blown)} triangles hold it; tolerance {args.tolerance:g}, thickness {args.thickness:g}")
    print(f"unmodified: {len(base_iterations)} queries, {base_mean:.1f} iterations per query "
          f"(max {base_iterations.max()}), {1e6 * base_per_query:.2f} us CPU per query, {base_hits.sum()} hits")
    print(f"{'height':>8} {'queries':>8} {'cpu/query ratio':>15} {'iter/query ratio':>16} "
          f"{'max iter':>9} {'hits':>6} {'undecided':>9}")
    per_query = []
    for height in args.heights:
        seconds, iterations, hits, undecided = run_queries(blowup.blown_points(height), sample, triangles, pairs,
                                                           args)
        cpu_ratio = (seconds / len(iterations)) / base_per_query
        iteration_ratio = iterations.mean() / base_mean
        per_query.append(iterations.mean())
        print(f"{height:8.0e} {len(iterations):8d} {cpu_ratio:15.2f} {iteration_ratio:16.2f} "
              f"{iterations.max():9d} {hits.sum():6d} {undecided.sum():9d}")
    print(f"iterations per query across heights: {min(per_query):.2f} .. {max(per_query):.2f} "
          f"(largest / smallest {max(per_query) / min(per_query):.2f}; a blown-up vertex sweeps through "
          f"its neighbours, so real contacts make it exceed the unmodified shot's)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
