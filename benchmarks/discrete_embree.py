"""``usdksl check`` against what a QA script does today: a per-frame discrete check with Embree, end to end.

    python benchmarks/discrete_embree.py benchmarks/caches/newton_*.usdc ../shared/data/newton/newton_viewerusd_cloth_twist.usd

For each cache, one run each, one after the other, both end to end in a process of their own (interpreter
start, imports, reading the stage; benchmarks/harness.py ``run`` measures wall and CPU from outside):

- ``check``: ``usdksl check CACHE`` (continuous: every contact between the samples too, reports written);
- ``discrete``: this script with ``--frames CACHE``: the stage read with usdksl's loader, the mesh pairs
  ``usdksl check`` plans, and at every sample the triangle pairs that intersect, found with Embree
  (usdksl.crosscheck: every edge cast as a ray segment against the frame, hits confirmed in double
  precision). It finds what intersects *at* the samples and misses what passes between them.

The printed ratio is check / discrete (wall, the same run); the target of continuous checking is at most
0.5. On a shared machine one run of each moves by tenths from run to run; ``--rounds N`` runs the two in
turn N times per cache (benchmarks/harness.py ``alternate``) and judges the ratio of the median walls,
printing each round's ratio too. Results go to benchmarks/results/discrete_embree.md. The machine is a
shared 2-core box: ratios measured in one run are the result, not absolute seconds.
"""

from __future__ import annotations

import argparse
import os
import re
import sys
import tempfile

from harness import Build, alternate, median_run, round_ratios, rounds_description, run

HERE = os.path.dirname(os.path.abspath(__file__))
RESULTS = os.path.join(HERE, "results", "discrete_embree.md")
#: check / discrete (wall) that continuous checking is held to.
TARGET_RATIO = 0.5


def discrete_frames(shot_path: str) -> None:
    """The per-frame discrete check of one cache; prints the face pairs found intersecting at some sample,
    the seconds of the whole discrete check and how many of them went to filling embreex's triangle meshes
    (``TriangleMesh``, timed around each call: embreex copies vertices and indices into Embree's buffers one
    element at a time, a cost a native Embree binding would not have)."""
    import time

    import embreex.mesh_construction as construction

    import usdksl
    from usdksl.crosscheck.shot import intersecting_face_pairs
    from usdksl.reading.scope import ScopeOptions, plan_shot
    from usdksl.unmasked import distinct_sorted

    filling = [0.0]
    untimed = construction.TriangleMesh

    def timed(*args, **kwargs):
        started = time.perf_counter()
        try:
            return untimed(*args, **kwargs)
        finally:
            filling[0] += time.perf_counter() - started

    construction.TriangleMesh = timed   # looked up by usdksl.crosscheck at each frame
    shot = usdksl.load_shot(shot_path)
    plan = plan_shot(shot, ScopeOptions())
    started = time.perf_counter()
    _, keys, _ = intersecting_face_pairs(shot.meshes, shot.times, plan.pairs)
    seconds = time.perf_counter() - started
    print(f"{len(distinct_sorted(keys))} face pairs intersect at some of {len(shot.times)} samples; the frames "
          f"took {seconds:.2f} s, {filling[0]:.2f} s of it filling embreex meshes")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("shots", nargs="*")
    parser.add_argument("--frames", metavar="CACHE", help="run the discrete check of CACHE in this process")
    parser.add_argument("--output", default=RESULTS)
    parser.add_argument("--rounds", type=int, default=1,
                        help="run check and discrete this many times in turn per cache; compare the median walls")
    args = parser.parse_args(argv)
    if args.frames:
        discrete_frames(args.frames)
        return 0
    rounds = max(1, args.rounds)
    command = f"python benchmarks/discrete_embree.py {' '.join(args.shots)}" + (
        f" --rounds {rounds}" if rounds > 1 else "")
    lines = ["# Continuous check against a per-frame discrete Embree check", "",
             f"`{command}`, {rounds_description(rounds)}, end to end, 2-core shared machine; wall seconds "
             "(CPU seconds).", "",
             "| cache | check | discrete (Embree, every sample) | check / discrete (wall) | check found | "
             "discrete found |", "|---|---|---|---|---|---|"]
    worst = 0.0
    rounds_seen = []
    filling_shares = []
    for shot in args.shots:
        def check_run(shot=shot):
            with tempfile.TemporaryDirectory() as out:
                return Build.current().run("check", shot, "--out", out, "-q")

        runs = alternate({"check": check_run,
                          "discrete": lambda shot=shot: run([sys.executable, os.path.abspath(__file__), "--frames",
                                                             shot])}, rounds)
        for check, discrete in zip(runs["check"], runs["discrete"]):
            if check.exit_code not in (0, 1) or discrete.exit_code != 0:
                raise RuntimeError(f"{shot}: check exit {check.exit_code}, discrete exit {discrete.exit_code}: "
                                   f"{(check.stderr + discrete.stderr).strip()[-300:]}")
        check, discrete = median_run(runs["check"]), median_run(runs["discrete"])
        ratio = check.wall_s / discrete.wall_s
        worst = max(worst, ratio)
        with tempfile.TemporaryDirectory() as out:
            summary = Build.current().run("check", shot, "--out", out).stderr.strip().splitlines()[-1]
        found = summary.split(";")[0].replace("usdksl: ", "")
        lines.append(f"| {os.path.basename(shot)} | {check.wall_s:.2f} ({check.cpu_s:.2f}) | "
                     f"{discrete.wall_s:.2f} ({discrete.cpu_s:.2f}) | {ratio:.2f} | {found} | "
                     f"{discrete.stdout.strip()} |")
        print(lines[-1], flush=True)
        took = re.search(r"took ([0-9.]+) s, ([0-9.]+) s of it filling", discrete.stdout)
        if took and float(took.group(1)) > 0:
            filling_shares.append(float(took.group(2)) / float(took.group(1)))
        if rounds > 1:
            rounds_seen.append(f"{os.path.basename(shot)}: {round_ratios(runs['check'], runs['discrete'])}")
    lines += ["", f"Largest check / discrete: {worst:.2f} (target: at most {TARGET_RATIO:g})."]
    if filling_shares:
        lines += ["", "Filling embreex's triangle meshes (it copies vertices and indices into Embree one element at "
                  f"a time) takes {100 * min(filling_shares):.0f}% to {100 * max(filling_shares):.0f}% of the "
                  "discrete check's frames: a discrete check on a native Embree binding would be that much faster, "
                  "and check / discrete that much higher."]
    if rounds_seen:
        lines += ["", "Each round's check / discrete:", ""] + [f"- {line}" for line in rounds_seen]
    text = "\n".join(lines) + "\n"
    print(text)
    os.makedirs(os.path.dirname(args.output), exist_ok=True)
    with open(args.output, "w") as handle:
        handle.write(text)
    return 0 if worst <= TARGET_RATIO else 1


if __name__ == "__main__":
    sys.exit(main())
