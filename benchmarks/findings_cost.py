"""What regions, depth and the illustrated report cost next to the check, in one run per shot.

    python benchmarks/findings_cost.py benchmarks/caches/newton_*.usdc ../shared/data/newton/newton_viewerusd_cloth_twist.usd

For each shot, ``usdksl.check_shot`` runs once in this process with the region work timed from inside
(benchmarks/harness.py Stopwatch): finding the regions (grouping contacts, their depth, one table of them),
joining the pieces of a shot cut at gaps, their console lines and regions.csv. The printed ratio is that time over the rest of the check (the check without regions, the same
run). A second call renders the report's pictures of the worst regions and the HTML page for the same shot
(``--report``), timed as the seconds it adds. Results go to benchmarks/results/findings_cost.md. The machine
is a shared 2-core box: ratios measured in one run are the result, not absolute seconds.
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time
from pathlib import Path
from typing import Dict

from harness import Stopwatch, call

HERE = os.path.dirname(os.path.abspath(__file__))
RESULTS = os.path.join(HERE, "results", "findings_cost.md")
#: Targets: regions and depth at most this share of the check without them; the report at most this many seconds.
REGION_SHARE_TARGET = 0.25
REPORT_SECONDS_TARGET = 10.0


def measure(shot: str) -> Dict:
    import usdksl
    from usdksl.pipeline import check as pipeline_check
    from usdksl.pipeline import files as pipeline_files
    from usdksl.pipeline import report as pipeline_report
    from usdksl.pipeline.files import OutputTargets
    from usdksl.regions import find as regions_find

    with tempfile.TemporaryDirectory() as out:
        targets = OutputTargets(out_dir=Path(out), report_path=Path(out) / "report.html")
        with Stopwatch() as watch:
            watch.wrap(regions_find, "group_regions", "grouping")
            watch.wrap(regions_find, "region_depths", "depth")
            watch.wrap(pipeline_check, "find_regions", "all regions")
            watch.wrap(pipeline_check, "concatenate_regions", "joining pieces")
            watch.wrap(pipeline_check, "region_lines", "console lines")
            watch.wrap(pipeline_files, "regions_csv", "regions.csv")
            watch.wrap(pipeline_report, "region_pictures_of", "pictures")
            checked = call(usdksl.check_shot, shot, usdksl.CheckOptions(), targets)
        result, total = checked.value, checked.wall_s
        started = time.perf_counter()
        page = usdksl.report_for_results([result])
        page_s = time.perf_counter() - started
    parts = dict(watch.seconds)
    pictures_s = parts.pop("pictures", 0.0)
    # grouping and depth run inside find_regions ("all regions"): counted once
    regions_s = sum(value for label, value in parts.items() if label not in ("grouping", "depth"))
    return {"shot": shot, "total": total - pictures_s, "regions_s": regions_s, "parts": parts,
            "contacts": result.table.count, "regions": result.regions.count, "report_s": pictures_s + page_s,
            "page_bytes": len(page)}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("shots", nargs="+")
    parser.add_argument("--output", default=RESULTS)
    args = parser.parse_args(argv)
    lines = ["# What regions, depth and the report cost", "",
             f"`python benchmarks/findings_cost.py {' '.join(args.shots)}`, one run per shot, 2-core shared machine.",
             "", "| shot | contacts | regions | check without regions (s) | grouping (s) | depth (s) | all region work (s) "
             "| regions / check without | report adds (s) |", "|---|---|---|---|---|---|---|---|---|"]
    worst_share, worst_report = 0.0, 0.0
    for shot in args.shots:
        record = measure(shot)
        without = record["total"] - record["regions_s"]
        share = record["regions_s"] / without
        worst_share, worst_report = max(worst_share, share), max(worst_report, record["report_s"])
        parts = record["parts"]
        lines.append(f"| {os.path.basename(shot)} | {record['contacts']} | {record['regions']} | {without:.2f} | "
                     f"{parts.get('grouping', 0.0):.2f} | {parts.get('depth', 0.0):.2f} | "
                     f"{record['regions_s']:.2f} | {share:.2%} | {record['report_s']:.1f} |")
        print(lines[-1], flush=True)
    lines += ["", f"Largest share of the check: {worst_share:.2%} (target: at most {REGION_SHARE_TARGET:.0%}).",
              f"Most the report adds to one shot: {worst_report:.1f} s (target: at most {REPORT_SECONDS_TARGET:g} s)."]
    text = "\n".join(lines) + "\n"
    print(text)
    os.makedirs(os.path.dirname(args.output), exist_ok=True)
    with open(args.output, "w") as handle:
        handle.write(text)
    return 0 if worst_share <= REGION_SHARE_TARGET and worst_report <= REPORT_SECONDS_TARGET else 1


if __name__ == "__main__":
    sys.exit(main())
