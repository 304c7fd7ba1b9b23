"""A cache resampled denser along the same motion: what sub-frame samples (motion blur) do to a check.

    python benchmarks/densify.py benchmarks/caches/newton_tablecloth_f150.usdc --factor 10
    python benchmarks/densify.py CACHE --factor 10 --compare      # also time usdksl check on both, one run each
    python benchmarks/densify.py CACHE --factor 10 --compare --rounds 5   # both in turn, five rounds: medians
    python benchmarks/densify.py FRAMES --dense SUBSTEPS --rounds 5       # a simulator's sub-frame samples

Writes ``<cache stem>_x<factor>.usdc`` beside the cache: the stage flattened, and every attribute with two or
more time samples given ``factor - 1`` more between each pair, the values USD itself interpolates there
(linear for points and translations), so the motion is the same and only the sampling is denser. With
``--compare`` ``usdksl check`` runs end to end on the original and on the dense copy (benchmarks/harness.py
``run``; one run each) and the ratio dense / original (wall) is printed with both answers' face pair
counts. The target of continuous checking is a ratio of at most 1.3: the same motion should cost about the
same however finely it is sampled. On a shared machine one run of each moves by tenths from run to run;
``--rounds N`` runs the two in turn N times (benchmarks/harness.py ``alternate``, so that both see the same
stretch of load) and judges the ratio of the median walls, printing each round's ratio too.

``--dense SUBSTEPS`` compares against a cache a simulator wrote with its sub-frame samples instead of
writing in-betweens: ``python benchmarks/record_newton.py twist --every-substep`` writes one run twice,
``..._sub10.usdc`` (a sample after each of 10 substeps a frame, on the simulator's curves) and
``..._sub10_frames.usdc`` (its whole frames), the pair to pass as SUBSTEPS and FRAMES. Between frames the
dense cache moves on curves the frames-only one draws as lines, so the two answers may differ slightly
(both are printed); the cost target is the same. Its table goes to benchmarks/results/densify_simulator.md.
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile

from harness import Build, alternate, median_run, round_ratios, rounds_description

HERE = os.path.dirname(os.path.abspath(__file__))
RESULTS = os.path.join(HERE, "results", "densify.md")
SIMULATOR_RESULTS = os.path.join(HERE, "results", "densify_simulator.md")
#: dense / original check time (wall) that continuous checking is held to.
TARGET_RATIO = 1.3


def densify(cache: str, factor: int, target: str) -> str:
    """Write ``cache`` with ``factor - 1`` in-between samples per interval of every animated attribute."""
    import numpy as np
    from pxr import Usd

    flat = Usd.Stage.Open(cache).Flatten()
    stage = Usd.Stage.Open(flat)
    for prim in stage.Traverse():
        for attribute in prim.GetAttributes():
            times = attribute.GetTimeSamples()
            if len(times) < 2:
                continue
            fractions = np.arange(1, factor) / factor
            between = [(t0 + (t1 - t0) * fractions).tolist() for t0, t1 in zip(times[:-1], times[1:])]
            values = [(time, attribute.Get(time)) for chunk in between for time in chunk]
            for time, value in values:
                attribute.Set(value, time)
    stage.GetRootLayer().Export(target)
    return target


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("cache")
    parser.add_argument("--factor", type=int, default=10)
    parser.add_argument("--compare", action="store_true")
    parser.add_argument("--dense", metavar="SUBSTEPS",
                        help="compare with this cache of the same motion (a simulator's sub-frame samples) "
                             "instead of writing in-betweens; implies --compare")
    parser.add_argument("--output", default=None,
                        help="where the comparison writes its table (markdown; default "
                             "benchmarks/results/densify.md, densify_simulator.md with --dense)")
    parser.add_argument("--rounds", type=int, default=1,
                        help="--compare: run both this many times in turn and compare the median walls")
    args = parser.parse_args(argv)
    if args.dense:
        target = args.dense
    else:
        stem, _ = os.path.splitext(args.cache)
        target = densify(args.cache, args.factor, f"{stem}_x{args.factor}.usdc")
        print(f"wrote {target}")
        if not args.compare:
            return 0
    output = args.output or (SIMULATOR_RESULTS if args.dense else RESULTS)
    rounds = max(1, args.rounds)
    shots = {"original": args.cache, "dense": target}

    def check(shot: str):
        with tempfile.TemporaryDirectory() as out:
            run = Build.current().run("check", shot, "--out", out)
        if run.exit_code not in (0, 1):
            raise RuntimeError(f"usdksl check {shot} exited {run.exit_code}: {run.stderr.strip()[-300:]}")
        return run

    runs = alternate({name: (lambda shot=shot: check(shot)) for name, shot in shots.items()}, rounds)
    how = f"--dense {args.dense}" if args.dense else f"--factor {args.factor} --compare"
    command = f"python benchmarks/densify.py {args.cache} {how}" + (f" --rounds {rounds}" if rounds > 1 else "")
    title = ("# The same simulation with its sub-frame samples" if args.dense
             else "# The same motion sampled denser")
    lines = [title, "",
             f"`{command}`, {rounds_description(rounds)}, end to end, 2-core shared machine.", "",
             "| shot | wall (s) | CPU (s) | answer |", "|---|---|---|---|"]
    measured = {}
    for name, shot in shots.items():
        measured[name] = median_run(runs[name])
        run = measured[name]
        lines.append(f"| {name} ({os.path.basename(shot)}) | {run.wall_s:.2f} | {run.cpu_s:.2f} | "
                     f"{run.stderr.strip().splitlines()[-1].split(';')[0]} |")
        print(lines[-1], flush=True)
    ratio = measured["dense"].wall_s / measured["original"].wall_s
    lines += ["", f"dense / original (wall): {ratio:.2f} (target: at most {TARGET_RATIO:g})."]
    if rounds > 1:
        lines.append(f"Each round: {round_ratios(runs['dense'], runs['original'])}.")
    text = "\n".join(lines) + "\n"
    print(text)
    with open(output, "w") as handle:
        handle.write(text)
    return 0 if ratio <= TARGET_RATIO else 1


if __name__ == "__main__":
    sys.exit(main())
