"""What accuracy costs in time: our CCD against Tight-Inclusion (ipctk) over
the shared ground-truth queries, tolerance swept from 1e-2 to 1e-8.

Both are timed one query per Python call (same call overhead, wall time,
benchmarks/harness.py), median per query; our batch time (one C++ loop) is
printed too. Note the tolerances are
not the same quantity: ours is a time-interval fraction, Tight-Inclusion's a
distance (co-domain) tolerance; they are compared at equal numbers.

    python benchmarks/ccd_tolerance.py [--data ../shared/data] [--max-queries N]
"""

import argparse
import shlex
import sys
from pathlib import Path

import numpy as np

from usdksl import ccd

from harness import call, time_each

TOLERANCES = [1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8]
MAX_ITERATIONS = ccd.DEFAULT_MAX_ITERATIONS


def load(data: Path, max_queries: int):
    sets = {"vf": [], "ee": []}
    files = sorted((data / "sample-queries").glob("*/*/*.csv")) + sorted((data / "scalable-ccd").glob("*/queries/*.csv"))
    for path in files:
        kind = "ee" if ("edge-edge" in path.parts or path.stem.endswith("ee")) else "vf"
        sets[kind].append(ccd.read_query_csv(path))
    out = {}
    rng = np.random.default_rng(0)
    for kind, parts in sets.items():
        queries = np.concatenate([q for q, _ in parts])
        truth = np.concatenate([t for _, t in parts])
        if max_queries and len(queries) > max_queries:
            pick = np.sort(rng.choice(len(queries), max_queries, replace=False))
            queries, truth = queries[pick], truth[pick]
        out[kind] = (queries, truth)
    return out


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--data", type=Path, default=Path(__file__).resolve().parents[2] / "shared" / "data")
    parser.add_argument("--max-queries", type=int, default=3000, help="per kind (vf, ee); 0 = all")
    parser.add_argument("--out", type=Path, default=Path(__file__).resolve().parent / "results")
    args = parser.parse_args()
    import ipctk

    ti = ipctk.tight_inclusion
    data = load(args.data, args.max_queries)
    ours_fn = {"vf": ccd.vertex_face_detailed, "ee": ccd.edge_edge_detailed}
    ti_fn = {"vf": ti.point_triangle_ccd, "ee": ti.edge_edge_ccd}
    rows = []
    for kind, (queries, truth) in data.items():
        for tolerance in TOLERANCES:
            measured = call(ours_fn[kind], queries, tolerance=tolerance, max_iterations=MAX_ITERATIONS)
            batch, batch_per_query = measured.value, measured.wall_s / len(queries)
            ours_hit, ours_t = time_each(
                lambda q: ours_fn[kind](q[None], tolerance=tolerance, max_iterations=MAX_ITERATIONS).hit[0], queries)
            ours_hit = np.asarray(ours_hit, dtype=bool)
            assert np.array_equal(ours_hit, batch.hit)
            ti_hit, ti_t = time_each(
                lambda q: ti_fn[kind](*q, 0.0, 1.0, tolerance, MAX_ITERATIONS)[0], queries)
            ti_hit = np.asarray(ti_hit, dtype=bool)
            row = dict(kind=kind, tolerance=tolerance, queries=len(queries),
                       ours_fn=int(np.sum(truth & ~ours_hit)), ours_fp=int(np.sum(~truth & ours_hit)),
                       ours_undecided=int(batch.undecided.sum()),
                       ti_fn=int(np.sum(truth & ~ti_hit)), ti_fp=int(np.sum(~truth & ti_hit)),
                       ours_median_us=1e6 * np.median(ours_t), ti_median_us=1e6 * np.median(ti_t),
                       ours_mean_us=1e6 * np.mean(ours_t), ti_mean_us=1e6 * np.mean(ti_t),
                       ours_batch_us=1e6 * batch_per_query)
            rows.append(row)
            print(f"{kind} tol={tolerance:.0e} n={row['queries']}  FN ours/TI {row['ours_fn']}/{row['ti_fn']}  "
                  f"FP ours/TI {row['ours_fp']}/{row['ti_fp']}  undecided {row['ours_undecided']}  "
                  f"median us ours/TI {row['ours_median_us']:.2f}/{row['ti_median_us']:.2f} "
                  f"(ratio {row['ours_median_us'] / row['ti_median_us']:.2f})  "
                  f"mean us ours/TI {row['ours_mean_us']:.1f}/{row['ti_mean_us']:.1f} "
                  f"(ratio {row['ours_mean_us'] / row['ti_mean_us']:.2f})  ours batch {row['ours_batch_us']:.2f} us",
                  flush=True)

    args.out.mkdir(parents=True, exist_ok=True)
    header = ("| kind | tolerance | queries | FN ours | FN TI | FP ours | FP TI | undecided ours | "
              "median us ours | median us TI | median ratio | mean us ours | mean us TI | mean ratio | batch us ours |")
    lines = [header, "|" + "---|" * 15]
    for r in rows:
        lines.append(f"| {r['kind']} | {r['tolerance']:.0e} | {r['queries']} | {r['ours_fn']} | {r['ti_fn']} | "
                     f"{r['ours_fp']} | {r['ti_fp']} | {r['ours_undecided']} | {r['ours_median_us']:.2f} | "
                     f"{r['ti_median_us']:.2f} | {r['ours_median_us'] / r['ti_median_us']:.2f} | "
                     f"{r['ours_mean_us']:.1f} | {r['ti_mean_us']:.1f} | {r['ours_mean_us'] / r['ti_mean_us']:.2f} | "
                     f"{r['ours_batch_us']:.2f} |")
    command = " ".join(["python benchmarks/ccd_tolerance.py"] + [shlex.quote(a) for a in sys.argv[1:]])
    (args.out / "ccd_tolerance.md").write_text(f"Command: `{command}`\n\n" + "\n".join(lines) + "\n")

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(11, 4.5))
    for ax, kind in zip(axes, ("vf", "ee")):
        sel = [r for r in rows if r["kind"] == kind]
        for who, marker in (("ours", "o-"), ("ti", "s--")):
            ax.plot([r[f"{who}_mean_us"] for r in sel], [r[f"{who}_fp"] for r in sel], marker,
                    label="usdksl" if who == "ours" else "Tight-Inclusion (ipctk)")
            for r in sel:
                ax.annotate(f"{r['tolerance']:.0e}", (r[f"{who}_mean_us"], r[f"{who}_fp"]), fontsize=7)
        ax.set_xscale("log")
        ax.set_xlabel("mean time per query (us, one Python call each)")
        ax.set_ylabel("false positives (false negatives: 0)")
        ax.set_title(f"{kind}: {sel[0]['queries']} queries")
        ax.legend()
    fig.tight_layout()
    fig.savefig(args.out / "ccd_tolerance.png", dpi=120)
    print(f"wrote {args.out / 'ccd_tolerance.md'} and {args.out / 'ccd_tolerance.png'}")


if __name__ == "__main__":
    main()
