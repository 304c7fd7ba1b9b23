"""What accounting for every prim and stretch costs, and whether it changes any answer, in one run per shot.

    python benchmarks/coverage_cost.py benchmarks/caches/*.usdc ../shared/data/newton/newton_viewerusd_cloth_twist.usd \\
        --baseline /path/to/other/venv/bin/usdksl

For each shot, ``usdksl.check_shot`` runs once in this process with the trust checks timed from inside (the
coverage account, the composition scan for unresolved assets, the blow-up and cache-glitch scan;
benchmarks/harness.py), and the printed ratio is their time over the whole check's (wall, the same run). With
``--baseline`` (the ``usdksl`` command of another build, e.g. the commit before these checks, or its
environment's python), ``usdksl check`` runs with both
builds on the shot and the SHA-256 of their contacts.csv, keyed by the first seven columns
(time,prim_a,face_a,prim_b,face_b,kind,feature: the answer), are compared. Results go to
benchmarks/results/coverage_cost.md. The machine is a shared 2-core box: ratios measured in one run are the
result, not absolute seconds.
"""

from __future__ import annotations

import argparse
import csv
import hashlib
import io
import os
import sys
import tempfile
from typing import Dict

from harness import Build, Stopwatch, call

HERE = os.path.dirname(os.path.abspath(__file__))
RESULTS = os.path.join(HERE, "results", "coverage_cost.md")
#: The columns of contacts.csv that are the answer (the rest, frames and seconds, follow from them).
ANSWER_COLUMNS = 7


def answer_hash(contacts_csv: str) -> str:
    """SHA-256 of the answer columns of a contacts.csv text."""
    rows = list(csv.reader(io.StringIO(contacts_csv)))
    text = "\n".join(",".join(row[:ANSWER_COLUMNS]) for row in rows)
    return hashlib.sha256(text.encode()).hexdigest()


def measure(shot: str) -> Dict:
    import usdksl
    from usdksl.pipeline import check as pipeline
    from usdksl.reading import blowups, composition

    with Stopwatch() as watch:
        watch.wrap(pipeline, "shot_coverage", "coverage account")
        watch.wrap(composition, "unresolved_assets", "unresolved-asset scan")
        watch.wrap(blowups, "find_glitches", "cache-glitch scan")
        checked = call(usdksl.check_shot, shot, usdksl.CheckOptions())
    result, total = checked.value, checked.wall_s
    contacts = next(text for path, text in result.files.items() if str(path).endswith(".contacts.csv"))
    return {"shot": shot, "total": total, "parts": watch.seconds, "contacts": result.table.count,
            "answer": answer_hash(contacts), "complete": result.coverage.complete,
            "entries": len(result.coverage.entries)}


def baseline_answer(command: str, shot: str) -> str:
    """The answer hash of ``usdksl check SHOT`` run by another build (its usdksl command or python)."""
    with tempfile.TemporaryDirectory() as out:
        Build.of(command).run("check", shot, "--out", out, "-q")
        stem = os.path.splitext(os.path.basename(shot))[0]
        with open(os.path.join(out, f"{stem}.contacts.csv")) as handle:
            return answer_hash(handle.read())


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("shots", nargs="+")
    parser.add_argument("--baseline", default=None,
                        help="usdksl command (or python) of another build to compare answers with")
    parser.add_argument("--output", default=RESULTS)
    args = parser.parse_args(argv)
    lines = ["# What the trust checks cost", "",
             f"`python benchmarks/coverage_cost.py {' '.join(args.shots)}"
             + (" --baseline BASELINE" if args.baseline else "") + "`, one run per shot, 2-core shared machine.", "",
             "| shot | check (s) | coverage account | unresolved-asset scan | cache-glitch scan | all three / check "
             "| contacts | answer same as baseline |", "|---|---|---|---|---|---|---|---|"]
    worst = 0.0
    same_everywhere = True
    for shot in args.shots:
        record = measure(shot)
        parts = record["parts"]
        share = sum(parts.values()) / record["total"]
        worst = max(worst, share)
        same = "-"
        if args.baseline:
            same_answer = baseline_answer(args.baseline, shot) == record["answer"]
            same_everywhere &= same_answer
            same = "yes" if same_answer else "NO"
        cells = [f"{parts.get(label, 0.0) * 1e3:.1f} ms" for label in
                 ("coverage account", "unresolved-asset scan", "cache-glitch scan")]
        lines.append(f"| {os.path.basename(shot)} | {record['total']:.2f} | {' | '.join(cells)} | {share:.2%} | "
                     f"{record['contacts']} | {same} |")
        print(lines[-1], flush=True)
    lines += ["", f"Largest share of check's time: {worst:.2%} (target: at most 5%)."]
    if args.baseline:
        lines.append(f"Answers identical to the baseline build on every shot: {'yes' if same_everywhere else 'NO'}.")
    text = "\n".join(lines) + "\n"
    print(text)
    os.makedirs(os.path.dirname(args.output), exist_ok=True)
    with open(args.output, "w") as handle:
        handle.write(text)
    return 0 if worst <= 0.05 and same_everywhere else 1


if __name__ == "__main__":
    sys.exit(main())
