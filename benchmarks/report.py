"""benchmarks/results/REPORT.md: one page of the current benchmark results, each section naming the
command that produced it.

    python benchmarks/report.py                  # the page from the result files in benchmarks/results/
    python benchmarks/report.py --run            # re-run the quick benchmarks first (see QUICK_RUNS)
    python benchmarks/report.py RESULTS.json...  # accuracy/time rows of run.py --results instead of the page's own

The page assembles what the benchmarks wrote into benchmarks/results/ and re-runs nothing (unless
``--run``): run.py's accuracy/time rows (bench_results.json, rendered into headlines, a grid table, PNG plots
and per-shot tables), then each other benchmark's page as it is (``RESULT_PAGES``: newton.md, threads.md,
scale.md, thickness.md, coverage_cost.md, ...) when present. Each section says which command produced it,
read from the page itself. One result per benchmark: earlier ones are in git history.

Rows of one shot from several runs merge into one (see `merge_rows`); bench_results.json keeps every
run's command and source revision, so ``report.py benchmarks/results/bench_results.json NEW.json`` adds a
run without the raw contact files of earlier ones.

Plots (matplotlib, Agg): time against missed contacts (discrete, substepped, swept, KSL), KSL events
against swept-volume BV tests per sample interval over mesh size (paper Fig. 11), time against samples
per keyframe (paper Fig. 10). Every ratio on the page comes from one run.
"""

from __future__ import annotations

import argparse
import glob
import json
import math
import os
import re
import sys
from typing import Dict, List, Optional, Sequence, Tuple

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
RESULTS = os.path.join(HERE, "results")
sys.path.insert(0, HERE)
from harness import run  # noqa: E402
from suite import METHODS, REFERENCE, SCENE_SIZES, add_comparisons, ksl_events, ratio_rows, same_run_times  # noqa: E402

ACCURACY_METHODS = ("ksl", "swept", "discrete", "discrete x2", "discrete x4", "discrete x8")
SUMMARY_JSON = "bench_results.json"
REPORT_MD = "REPORT.md"
#: Hand-written findings about this page's numbers, embedded under "Investigations" when present.
NOTES_MD = "notes.md"
#: benchmarks/ccd_tolerance.py: per-query CCD against Tight-Inclusion over a sweep of tolerances.
CCD_TOLERANCE_MD, CCD_TOLERANCE_PNG = "ccd_tolerance.md", "ccd_tolerance.png"
#: Pages of other benchmarks embedded as they are, in this order, when present: (file, heading). Each
#: heading names the script that writes the page.
RESULT_PAGES = (("newton.md", "Newton simulator caches (benchmarks/newton_bench.py)"),
                ("newton_check_vs_sweep.md",
                 "check against ipctk's earliest-contact sweep on an idle machine (benchmarks/newton_bench.py)"),
                ("ksl_vs_swept_newton_single_thread.md",
                 "KSL against swept at one thread on the Newton caches (benchmarks/ksl_vs_swept.py)"),
                ("threads.md", "One thread against two on the largest Newton cache (benchmarks/ksl_vs_swept.py)"),
                ("exact_times.md", "Reported times against a tight reference (benchmarks/peer_ipctk.py)"),
                ("thickness.md", "Thickness above 0: what it costs and what it measures (benchmarks/thickness.py)"),
                ("scale.md", "10k to 1M faces (benchmarks/scale.py)"),
                ("coverage_cost.md", "What the trust checks cost (benchmarks/coverage_cost.py)"),
                ("batch_scaling.md", "Batches and long shots on Dask (benchmarks/batch_scaling.py)"),
                ("findings_cost.md", "What regions, depth and the report cost (benchmarks/findings_cost.py)"),
                ("discrete_embree.md", "Continuous against a per-frame discrete Embree check (benchmarks/discrete_embree.py)"),
                ("densify.md", "The same motion sampled ten times denser (benchmarks/densify.py)"),
                ("production_shot.md",
                 "A production-like shot, 240 and 480 frames: memory set by a window (benchmarks/production_shot.py)"),
                ("production_shot_1m.md", "1M triangles x 480 frames (benchmarks/production_shot.py)"))
#: Headings of the page's own sections.
ACCURACY_HEADING = "What accuracy costs in time: KSL against every method (benchmarks/run.py)"
PER_SHOT_HEADING = "Accuracy and time per shot (benchmarks/run.py)"
TOLERANCE_HEADING = "Narrow-phase tolerance sweep (benchmarks/ccd_tolerance.py)"
INVESTIGATIONS_HEADING = "Investigations"
#: benchmarks/ksl_vs_swept.py --baseline-python: KSL of an earlier core against this one on a subset of
#: the keyframed grid, in one run; embedded right after the grid it checks.
GRID_BEFORE_AFTER_PAGE = ("keyframed_before_after.md",
                          "The keyframed grid: KSL of an earlier core against this one (benchmarks/ksl_vs_swept.py)")


def _ok(row: Dict, label: str) -> Optional[Dict]:
    record = row["methods"].get(label)
    return record if record and record.get("status") == "ok" else None


def _cpu(record: Dict) -> float:
    return record.get("cpu_s") or float("nan")


def _shot_order(shot: Dict) -> tuple:
    """Scenes in the paper's order (tablecloth, swirl, character, then any other), then size, then sampling."""
    scenes = list(SCENE_SIZES)
    rank = scenes.index(shot["scene"]) if shot["scene"] in scenes else len(scenes)
    return rank, shot["scene"], shot.get("size") or 0, shot.get("samples_per_keyframe") or 0


def _groups(rows: Sequence[Dict]) -> Dict[str, List[Dict]]:
    """Rows of the same scene and size (differing only in samples per keyframe), in sampling order; groups
    in `_shot_order`."""
    groups: Dict[str, List[Dict]] = {}
    for row in sorted(rows, key=lambda r: _shot_order(r["shot"])):
        shot = row["shot"]
        key = f"{shot['scene']} {shot['size']}" if shot.get("size") else shot["scene"]
        groups.setdefault(key, []).append(row)
    for members in groups.values():
        members.sort(key=lambda r: r["shot"].get("samples_per_keyframe") or 0)
    return groups


def _shot_title(shot: Dict) -> str:
    spk = shot.get("samples_per_keyframe")
    head = f"{shot['scene']} {shot['size']}" if shot.get("size") else shot["scene"]
    sampling = f", {spk} samples/keyframe" if spk else ""
    return (f"{head}{sampling}: {shot['triangles']} triangles ({shot['moving_triangles']} moving), "
            f"{shot['samples']} samples")


def _fmt(value, spec: str = ".3g") -> str:
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return ""
    return format(value, spec)


def method_table(row: Dict) -> List[str]:
    lines = ["| method | time (s) | x KSL | CPU (s) | CPU x KSL | peak mem (MiB) | KSL events | BV tests | narrow-phase tests "
             "| found | missed vs KSL | extra vs KSL | max abs first-contact error (time codes) |",
             "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for r in ratio_rows(row["methods"]):
        if r["status"] != "ok":
            lines.append(f"| {r['method']} | {r['status']}: {r['reason']} |  |  |  |  |  |  |  |  |  |  |  |")
            continue
        unit = " intervals" if r.get("unit") == "intervals" else ""
        lines.append(
            f"| {r['method']} | {r['wall_s']:.3f} | {r['time_vs_ksl']:.2f} | {_fmt(r.get('cpu_s'), '.3f')} | {_fmt(r.get('cpu_vs_ksl'), '.2f')} "
            f"| {r['peak_mib']:.1f} "
            f"| {_fmt(r['events'], 'd')} | {_fmt(r['bv_tests'], 'd')} | {_fmt(r['narrow_phase_tests'], 'd')} "
            f"| {_fmt(r.get('found'), 'd')}{unit if 'found' in r else ''} | {_fmt(r.get('missed'), 'd')} "
            f"| {_fmt(r.get('extra'), 'd')} | {_fmt(r.get('time_error_max'))} |")
    unavailable = [(label, record["comparison_unavailable"]) for label, record in row["methods"].items()
                   if record.get("comparison_unavailable")]
    if unavailable:
        lines.append("")
        lines += [f"- {label}: not compared against KSL ({reason})" for label, reason in unavailable]
    return lines


# --------------------------------------------------------------------------- headlines

def headlines(rows: Sequence[Dict]) -> List[str]:
    """The benchmark's targets, each with what the rows reached (or why they cannot say)."""
    lines = []
    groups = _groups(rows)

    def largest_first(scene: str) -> List[List[Dict]]:
        """The shot groups of `scene`, largest size first."""
        return sorted((members for members in groups.values() if members[0]["shot"]["scene"] == scene),
                      key=lambda members: -(members[0]["shot"].get("size") or 0))

    def largest(scene: str) -> Optional[List[Dict]]:
        return next(iter(largest_first(scene)), None)

    def densest_pair(members, a, b) -> Optional[tuple]:
        for row in reversed(members):
            ra, rb = _ok(row, a), _ok(row, b)
            if ra and rb:
                return row, ra, rb
        return None

    def largest_with(scene: str, a: str, b: str) -> Optional[tuple]:
        """Densest sampling of the largest shot of `scene` on which both methods ran."""
        for members in largest_first(scene):
            found = densest_pair(members, a, b)
            if found:
                return members, found
        return None

    for scene, target in (("tablecloth", 20.0), ("swirl", 2.0)):
        located = largest_with(scene, "ksl", "swept")
        if not located:
            lines.append(f"- KSL vs swept on {scene}: not measured in this run.")
            continue
        members, found = located
        row, ksl, swept = found
        ksl = dict(ksl, **same_run_times(swept, REFERENCE, row["methods"]))  # swept's own run's KSL times
        ratio = swept["wall_s"] / ksl["wall_s"]
        cpu_ratio = _cpu(swept) / _cpu(ksl)
        judged = cpu_ratio if not math.isnan(cpu_ratio) else ratio
        verdict = "met" if judged >= target else f"missed by {target / judged:.1f}x"
        lines.append(f"- KSL vs swept on {_shot_title(row['shot'])}: swept/KSL time **{ratio:.2f}x** "
                     f"(CPU {cpu_ratio:.2f}x; target >= {target:g}x: {verdict}); KSL {ksl['wall_s']:.2f} s, "
                     f"swept {swept['wall_s']:.2f} s; primitive CCD queries KSL {ksl['counters']['primitive_queries']} "
                     f"vs swept {swept['counters']['primitive_queries']}; "
                     f"narrow-phase tests KSL {ksl['counters']['narrow_phase_tests']} vs swept "
                     f"{swept['counters']['narrow_phase_tests']}, KSL events {ksl_events(ksl['counters'])} vs swept "
                     f"BV tests {swept['counters']['bv_tests']}.")
        lines.append("  " + counter_reading(ksl, swept, _sibling(members, row, "swept")))
    for key, members in groups.items():
        with_ksl = [(r["shot"].get("samples_per_keyframe"), _ok(r, "ksl")) for r in members]
        with_ksl = [(s, k) for s, k in with_ksl if s and k]
        if len(with_ksl) >= 2:
            (s0, k0), (s1, k1) = with_ksl[0], with_ksl[-1]
            growth = k1["wall_s"] / k0["wall_s"] - 1.0
            cpu_growth = _cpu(k1) / _cpu(k0) - 1.0
            verdict = "met" if (cpu_growth if not math.isnan(cpu_growth) else growth) <= 0.20 else "missed"
            lines.append(f"- KSL time growth on {key} from {s0} to {s1} samples/keyframe: **{growth:+.0%}** "
                         f"({'CPU ' + format(cpu_growth, '+.0%') if not math.isnan(cpu_growth) else 'CPU not measured'}; {k0['wall_s']:.2f} s -> {k1['wall_s']:.2f} s; target within 20%: "
                         f"{verdict}).")
    members = largest("tablecloth")
    found = densest_pair(members, "ksl", "read") if members else None
    if found:
        row, ksl, read = found
        ratio = ksl["wall_s"] / read["wall_s"]
        cpu_ratio = _cpu(ksl) / _cpu(read)
        judged = cpu_ratio if not math.isnan(cpu_ratio) else ratio
        verdict = "met" if judged <= 1.0 else f"missed: CCD is {judged:.1f}x the read in CPU time"
        lines.append(f"- CCD vs USD read on {_shot_title(row['shot'])}: KSL {ksl['wall_s']:.2f} s = **{ratio:.2f}x** "
                     f"the read time {read['wall_s']:.2f} s (target <= 1x: {verdict}).")
    by_scene: Dict[str, List[str]] = {}
    for key, members in groups.items():
        for row in members:
            ksl = _ok(row, "ksl")
            if ksl and "peak_mem_bytes" in ksl:
                per_k = ksl["peak_mem_bytes"] / 2**20 / (row["shot"]["moving_triangles"] / 1000)
                by_scene.setdefault(row["shot"]["scene"], []).append(
                    f"{row['shot']['moving_triangles']} tris x {row['shot']['samples']} samples: "
                    f"{ksl['peak_mem_bytes'] / 2**20:.0f} MiB ({per_k:.1f} MiB per 1k triangles)")
    for scene, items in by_scene.items():
        lines.append(f"- KSL peak memory above the loaded shot on {scene} (target: linear in mesh size): "
                     + "; ".join(items) + ".")
    ipc_rows = [(r, _ok(r, "ipctk")) for r in rows]
    ipc_rows = [(r, same_run_times(ip, "check", r["methods"]), ip) for r, ip in ipc_rows if ip]
    ipc_rows = [item for item in ipc_rows if item[1]]
    if ipc_rows:
        ratios = [(ip["load_s"] + ip["wall_s"]) / ch["wall_s"] for _, ch, ip in ipc_rows]
        cpu_ratios = [c for c in ((ip["load_s"] + _cpu(ip)) / _cpu(ch) for _, ch, ip in ipc_rows)
                      if not math.isnan(c)] or [float("nan")]
        best = max(range(len(ratios)), key=lambda i: ratios[i])
        worst = min(range(len(ratios)), key=lambda i: ratios[i])
        lines.append(f"- End-to-end `usdksl check` vs the ipctk sweep (load + LBVH + collision-free step size per "
                     f"interval, which answers only the earliest contact per interval): ipctk/check time from "
                     f"**{ratios[worst]:.2f}x** ({_shot_title(ipc_rows[worst][0]['shot'])}) to "
                     f"**{ratios[best]:.2f}x** ({_shot_title(ipc_rows[best][0]['shot'])}) in wall time; in CPU time "
                     f"{min(cpu_ratios):.2f}x to {max(cpu_ratios):.2f}x (ipctk's CPU may include a second thread) "
                     f"(target >= 10x: {'met' if min(cpu_ratios) >= 10 else 'missed'}).")
    lines += ipctk_over_budget(rows)
    if ipc_rows:
        lines.append("  ipctk's `compute_collision_free_stepsize` needs one number per interval: the earliest time of "
                     "impact, so it can stop searching each candidate past the smallest time found so far; `check` finds the first "
                     "contact of every face pair over the whole shot, and also writes CSV and a USD layer. The "
                     "'same contacts' comparison the target asks for would need ipctk to be re-run from each "
                     "contact onward, which this benchmark does not do (its time is a lower bound).")
    return lines


def ipctk_over_budget(rows: Sequence[Dict]) -> List[str]:
    """Shots where ipctk ran out of its own budget while `check` finished in the same run: the budget is a
    lower bound on ipctk's wall time there, so budget / check is a lower bound on ipctk/check."""
    bounds = []
    for row in rows:
        record = row["methods"].get("ipctk", {})
        over = _over_budget(record)
        check = record.get("same_run", {}).get("check")
        if over and over[1] and check:
            budget = over[0]
            bounds.append((budget / check["wall_s"],
                           f"{_shot_title(row['shot'])}: ipctk over its {budget:g} s budget, `check` "
                           f"{check['wall_s']:.1f} s wall ({check.get('cpu_s', float('nan')):.1f} s CPU) in the same "
                           f"run, so ipctk/check >= **{budget / check['wall_s']:.1f}x** in wall time"))
    if not bounds:
        return []
    met = sum(ratio >= 10.0 for ratio, _ in bounds)
    return [f"- Where ipctk did not finish within its budget (lower bounds; target >= 10x: met on {met} of "
            f"{len(bounds)}): " + "; ".join(text for _, text in bounds) + ".",
            "  The collision-free step size assumes every interval starts free of contact. A cache that is already "
            "in contact at an interval's start breaks that assumption, so such a bound says ipctk cannot check that "
            "cache within the budget, not that `check` does ipctk's job that much faster."]


def _sibling(members: Sequence[Dict], row: Dict, label: str) -> Optional[Dict]:
    """The same method on the sparsest sampling of the same shot, if it ran and differs from ``row``."""
    for other in members:
        if other is not row and _ok(other, label):
            return _ok(other, label)
    return None


def counter_reading(ksl: Dict, swept: Dict, sparse_swept: Optional[Dict]) -> str:
    """What the counters say about a KSL/swept ratio: work ratios and cost per unit of work."""
    k, w = ksl["counters"], swept["counters"]

    def per(record, name):
        count = record["counters"].get(name, 0)
        return 1e6 * _cpu(record) / count if count else float("nan")

    share = k["polygons_collide_events"] / max(ksl_events(k), 1)
    text = (f"Counters: swept does {w['bv_tests'] / max(k['bv_tests'], 1):.1f}x the BV tests, "
            f"{w['narrow_phase_tests'] / max(k['narrow_phase_tests'], 1):.1f}x the narrow-phase tests and "
            f"{w['primitive_queries'] / max(k['primitive_queries'], 1):.1f}x the primitive CCD queries of KSL, "
            f"but KSL's CPU time divided by its primitive queries is {per(ksl, 'primitive_queries'):.2f} us against "
            f"{per(swept, 'primitive_queries'):.2f} us for swept (all work of each method, events and queue "
            f"included); {share:.0%} of KSL's events are polygons-collide events (leaf BVs that start to "
            f"overlap){', so leaf-level close contact dominates' if share > 0.5 else ''}.")
    if sparse_swept:
        gain = _cpu(swept) / _cpu(sparse_swept)
        text += (f" KSL's narrow-phase tests ({k['narrow_phase_tests']}) compare with swept's at the sparsest "
                 f"sampling ({sparse_swept['counters']['narrow_phase_tests']}): the flightplans merge the dense "
                 f"samples, so the most KSL can gain here is swept(dense)/swept(sparse) = {gain:.1f}x in CPU "
                 f"unless its cost per query drops.")
        if gain < 1.0:
            text += (f" Here swept gets cheaper with denser sampling: its primitive CCD queries drop from "
                     f"{sparse_swept['counters']['primitive_queries']} to {w['primitive_queries']}, because "
                     f"shorter intervals sweep smaller boxes around fast-moving triangles.")
    return text


# --------------------------------------------------------------------------- plots

def _save(fig, path, layout: bool = True) -> bool:
    """Lay out (unless the caller did), write the PNG and free the figure; True so plot functions can
    return it."""
    import matplotlib.pyplot as plt
    if layout:
        fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return True


#: Marker of each sampling (samples per keyframe) in the plots.
SAMPLING_MARKERS = {1: "^", 2: "s", 5: "D", 10: "o"}


def _uses_cpu(records) -> bool:
    """CPU time when every plotted record has it (steadier on a shared machine), else wall time."""
    return all(record.get("cpu_s") for record in records)


def _plot_time_vs_missed(rows, path) -> bool:
    import matplotlib.pyplot as plt
    from matplotlib.lines import Line2D
    from matplotlib.ticker import FormatStrFormatter
    panels = [[r for r in members if _ok(r, "ksl")] for members in _groups(rows).values()]
    panels = [members for members in panels if members]
    if not panels:
        return False
    plotted = [_ok(r, label) for members in panels for r in members for label in ACCURACY_METHODS if _ok(r, label)]
    time_key = "cpu_s" if _uses_cpu(plotted) else "wall_s"
    columns = min(len(panels), 4)
    lines_count = math.ceil(len(panels) / columns)
    fig, axes = plt.subplots(lines_count, columns, figsize=(4.2 * columns, 3.4 * lines_count + 0.8), squeeze=False)
    colors = {label: f"C{i}" for i, label in enumerate(ACCURACY_METHODS)}
    methods_seen, samplings_seen = set(), set()
    for ax, members in zip(axes.flat, panels):
        for row in members:
            spk = row["shot"].get("samples_per_keyframe")
            for label in ACCURACY_METHODS:
                record = _ok(row, label)
                if not record or (label != REFERENCE and "comparison" not in record):
                    continue
                methods_seen.add(label)
                samplings_seen.add(spk)
                ax.scatter(record[time_key], record.get("comparison", {}).get("missed", 0), s=36,
                           color=colors[label], marker=SAMPLING_MARKERS.get(spk, "x"), alpha=0.85)
        ax.set_xscale("log")
        ax.xaxis.set_minor_formatter(FormatStrFormatter("%g"))
        ax.xaxis.set_major_formatter(FormatStrFormatter("%g"))
        ax.tick_params(axis="x", which="minor", labelsize=6)
        ax.set_xlabel("CPU time (s)" if time_key == "cpu_s" else "wall time (s)")
        ax.set_ylabel("face pairs missed vs KSL")
        shot = members[0]["shot"]
        ax.set_title(f"{shot['scene']} {shot.get('size') or ''} ({shot['triangles']} triangles)", fontsize=9)
        ax.grid(True, alpha=0.3)
    for ax in list(axes.flat)[len(panels):]:
        ax.axis("off")
    handles = [Line2D([], [], color=colors[label], marker="o", linestyle="", label=label)
               for label in ACCURACY_METHODS if label in methods_seen]
    handles += [Line2D([], [], color="grey", marker=SAMPLING_MARKERS.get(spk, "x"), linestyle="",
                       label=f"{spk} samples/keyframe") for spk in sorted(s for s in samplings_seen if s)]
    fig.legend(handles=handles, loc="upper center", ncol=min(len(handles), 6), fontsize=8, frameon=False)
    fig.tight_layout(rect=(0, 0, 1, 1 - 0.7 / fig.get_figheight()))
    return _save(fig, path, layout=False)


def _plot_events_vs_bv(rows, path) -> bool:
    """Per sample interval, over mesh size: one line per scene and sampling (the densest one where both
    methods ran on a size), so sizes measured at different samplings are not joined."""
    import matplotlib.pyplot as plt
    series: Dict[tuple, Dict[str, list]] = {}
    for members in _groups(rows).values():
        with_both = [r for r in members if _ok(r, "ksl") and _ok(r, "swept")]
        if not with_both:
            continue
        row = with_both[-1]
        ksl, swept = _ok(row, "ksl"), _ok(row, "swept")
        intervals = max(row["shot"]["samples"] - 1, 1)
        line = series.setdefault((row["shot"]["scene"], row["shot"].get("samples_per_keyframe")),
                                 {"n": [], "ksl": [], "swept": []})
        line["n"].append(row["shot"]["moving_triangles"])
        line["ksl"].append(ksl_events(ksl["counters"]) / intervals)
        line["swept"].append(swept["counters"]["bv_tests"] / intervals)
    if not series:
        return False
    scenes = list(dict.fromkeys(scene for scene, _ in series))
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    for (scene, spk), line in series.items():
        order = sorted(range(len(line["n"])), key=lambda i: line["n"][i])
        n = [line["n"][i] for i in order]
        color = f"C{scenes.index(scene)}"
        marker = SAMPLING_MARKERS.get(spk, "x")
        ax.plot(n, [line["ksl"][i] for i in order], "-", marker=marker, color=color,
                label=f"{scene} ({spk} spk): KSL events")
        ax.plot(n, [line["swept"][i] for i in order], "--", marker=marker, color=color, markerfacecolor="none",
                label=f"{scene} ({spk} spk): swept BV tests")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("moving triangles")
    ax.set_ylabel("per sample interval")
    ax.set_title("KSL events vs swept-volume BV tests (paper Fig. 11)", fontsize=10)
    ax.legend(fontsize=7)
    ax.grid(True, which="both", alpha=0.3)
    return _save(fig, path)


def _plot_time_vs_samples(rows, path) -> bool:
    """One panel per scene, one colour per size: KSL solid, swept dashed."""
    import matplotlib.pyplot as plt
    by_scene: Dict[str, List[tuple]] = {}
    for members in _groups(rows).values():
        shot = members[0]["shot"]
        for label, style in (("ksl", "o-"), ("swept", "s--")):
            points = [(r["shot"]["samples_per_keyframe"], _ok(r, label)) for r in members
                      if r["shot"].get("samples_per_keyframe")]
            points = [(spk, record) for spk, record in points if record]
            if len(points) >= 2:
                by_scene.setdefault(shot["scene"], []).append((shot.get("size") or 0, label, style, points))
    if not by_scene:
        return False
    time_key = "cpu_s" if _uses_cpu([rec for series in by_scene.values() for *_, points in series
                                     for _, rec in points]) else "wall_s"
    fig, axes = plt.subplots(1, len(by_scene), figsize=(4.6 * len(by_scene), 4.0), squeeze=False)
    for ax, (scene, series) in zip(axes.flat, by_scene.items()):
        sizes = sorted({size for size, *_ in series})
        cmap = plt.get_cmap("viridis")
        for size, label, style, points in series:
            color = cmap(0.85 * sizes.index(size) / max(len(sizes) - 1, 1))
            ax.plot([spk for spk, _ in points], [rec[time_key] for _, rec in points], style, color=color,
                    label=f"{size} {label}")
        ax.set_yscale("log")
        ax.set_xticks(sorted({spk for *_, points in series for spk, _ in points}))
        ax.set_xlabel("samples per keyframe (same keyframes)")
        ax.set_ylabel("CPU time (s)" if time_key == "cpu_s" else "wall time (s)")
        ax.set_title(f"{scene}: KSL (solid) vs swept (dashed)", fontsize=9)
        ax.legend(fontsize=7, ncol=2)
        ax.grid(True, which="both", alpha=0.3)
    fig.suptitle("Time vs samples per keyframe (paper Fig. 10)", fontsize=10)
    return _save(fig, path)


# --------------------------------------------------------------------------- the page

def grid_table(rows: Sequence[Dict]) -> List[str]:
    """One line per shot size, one column per sampling: KSL CPU seconds and swept/KSL CPU ratio, or why not."""
    groups = _groups(rows)
    samplings = sorted({r["shot"].get("samples_per_keyframe") or 0 for r in rows} - {0})
    if not samplings:
        return []
    lines = ["| shot | triangles | " + " | ".join(f"{s} spk" for s in samplings) + " |",
             "|---|---|" + "---|" * len(samplings)]
    for key, members in groups.items():
        cells = []
        for spk in samplings:
            row = next((r for r in members if r["shot"].get("samples_per_keyframe") == spk), None)
            if row is None:
                cells.append("not run")
                continue
            ksl, swept = _ok(row, "ksl"), _ok(row, "swept")
            if not ksl:
                reason = row["methods"].get("ksl", {}).get("reason", "not run")
                cells.append(f"KSL skipped ({reason})")
                continue
            cell = f"KSL {_cpu(ksl):.3g} s"
            if swept:
                cell += f", swept/KSL **{_cpu(swept) / _cpu(same_run_times(swept, REFERENCE, row['methods'])):.2f}x**"
            else:
                record = row["methods"].get("swept")
                cell += f", swept {'skipped: ' + record.get('reason', '') if record else 'not run'}"
            cells.append(cell)
        triangles = members[0]["shot"]["triangles"]
        lines.append(f"| {key} | {triangles} | " + " | ".join(cells) + " |")
    return lines


#: A page's own line giving its command: ``Command: `...` `` or ``Command (run under `nice`): `...` ``.
_COMMAND_LINE = re.compile(r"Command( \(run under `nice`\))?: `([^`]+)`")
#: Where a page names a command: in backticks, or alone on an indented (code block) line.
_QUOTED = re.compile(r"`([^`\n]+)`|^ {4}(\S[^\n]*)$", re.MULTILINE)


def _script_of(heading: str) -> str:
    """The script a section's heading names: 'X (benchmarks/newton_bench.py)' -> 'newton_bench.py'."""
    named = re.search(r"benchmarks/(\w+\.py)\)$", heading)
    return named.group(1) if named else ""


def _commands_in(text: str, script: str) -> List[str]:
    """Command lines of ``script`` that ``text`` quotes, in order, each once."""
    found = (quoted or block for quoted, block in _QUOTED.findall(text))
    return list(dict.fromkeys(command.strip() for command in found
                              if re.search(rf"\bpython3?\b\S*\s+(\S*/)?benchmarks/{re.escape(script)}\b", command)))


def produced_by(text: str, script: str) -> Tuple[str, str]:
    """(the sentence naming the command that produced a page, the page without its own command line).

    The page's top part (before its first section) names the command: its one ``Command: `...` `` line of
    ``script``, which is lifted into the sentence, or else the one command of ``script`` it quotes. A page
    that quotes several, or quotes them in its sections only, keeps them where they are; a page that quotes
    none is named by its script."""
    top = re.split(r"^## ", text, maxsplit=1, flags=re.MULTILINE)[0]
    own_lines = [match for match in map(_COMMAND_LINE.fullmatch, (line.strip() for line in top.split("\n")))
                 if match and _commands_in(f"`{match.group(2)}`", script)]
    if len(own_lines) == 1:
        command, nice = own_lines[0].group(2), bool(own_lines[0].group(1))
        lines = text.split("\n")
        at = next(index for index, line in enumerate(lines) if line.strip() == own_lines[0].group(0))
        kept = "\n".join(lines[:at] + lines[at + 1:]).strip()
        return f"Produced by `{command}`{' (run under `nice`)' if nice else ''}.", kept
    quoted = _commands_in(top, script)
    if len(quoted) == 1:
        return f"Produced by `{quoted[0]}`.", text
    if _commands_in(text, script):
        return f"Produced by `python benchmarks/{script}`; the page quotes its command lines.", text
    return f"Produced by `python benchmarks/{script}` (the page does not record its arguments).", text


def embedded_page(out_dir: str, name: str, heading: str, level: int = 2) -> List[str]:
    """Lines of the page ``name`` in ``out_dir`` as a section under ``heading`` at ``level`` (its own title
    dropped, its sections one level below), opened by the command that produced it; none when the page
    is absent."""
    page = os.path.join(out_dir, name)
    if not os.path.exists(page):
        return []
    with open(page) as handle:
        body = handle.read().strip().split("\n", 1)
    text = body[1].strip() if body[0].startswith("# ") and len(body) > 1 else "\n".join(body)
    sentence, text = produced_by(text, _script_of(heading)) if _script_of(heading) else ("", text)
    text = re.sub(r"^(#+) ", lambda m: "#" * (len(m.group(1)) + level - 1) + " ", text, flags=re.MULTILINE)
    return [f"{'#' * level} {heading}", "", f"From [{name}]({name}). {sentence}".rstrip(), "", text, ""]


def _anchor(heading: str) -> str:
    """The link target GitHub gives a heading."""
    return re.sub(r"[^\w\- ]", "", heading.strip().lower()).replace(" ", "-")


def _accuracy_runs(command: str) -> Tuple[List[str], str]:
    """(bullet lines of run.py's runs, the source revision they share or ''), from one
    "command<TAB>source revision" per line of ``command``."""
    runs = [line.partition("\t")[::2] for line in (command or "python benchmarks/run.py").split("\n")]
    sources = {source for _, source in runs}
    shared = sources.pop() if len(sources) == 1 else ""
    bullets = [f"- `{text}`" + (f" (source: {source})" if source and not shared else "") for text, source in runs]
    return bullets, shared


def accuracy_sections(rows: Sequence[Dict], budget_s, plots: Dict[str, bool], out_dir: str, command: str,
                      machine: str) -> List[str]:
    """run.py's rows: how they were measured, headlines, the grid, its before/after page and the plots."""
    budget = budget_s if isinstance(budget_s, str) else format(budget_s, "g") + " s"
    runs, source = _accuracy_runs(command)
    lines = [f"## {ACCURACY_HEADING}", "",
             f"Produced by these runs of `python benchmarks/run.py`{', all of build ' + source if source else ''}"
             f"{' on ' + machine if machine else ''} (rows of one shot from several runs merged; per-shot tables "
             f"under [{PER_SHOT_HEADING}](#{_anchor(PER_SHOT_HEADING)})):", ""] + runs
    lines += ["", "Every method ran in its own fresh interpreter, one after the other, on the same shots; time is "
              "wall time of the method call (shot already loaded) except `read` (the loader alone) and `check` "
              "(the whole `usdksl check` without interpreter start-up). Peak memory is the kernel's VmHWM above "
              f"the RSS after loading (C++ allocations included). Per-method budget: {budget}; methods over "
              "budget are listed as skipped with the reason, never dropped. Timings are from a shared 2-core "
              "machine on which other jobs ran at the same time: wall times carry noise of up to ~2x between "
              "runs and budgets (wall time) cut runs that would fit on an idle machine; the CPU column (process "
              "time; our core is single-threaded, ipctk may use a second thread) is steadier.", "",
              "Contacts are compared as authored face pairs (first contact per pair) against KSL on the same shot "
              "with the same build (rows of several runs on one shot file are merged; a method that ran replaces "
              "a skip; KSL is deterministic for one build, so a comparison made against any KSL run of that build "
              "is kept). `ipctk` (Tight-Inclusion CCD, LBVH broad phase, `compute_collision_free_stepsize` per "
              "sample interval over one CollisionMesh of all meshes) answers only the earliest contact of each "
              "interval, so it is compared per interval and its time is a lower bound on what our full answer "
              "would cost it; its 'extra' intervals are intervals where meshes are still in contact after their "
              "first contact, which KSL reports once.", ""]
    lines += ["### Headlines", "",
              "Verdicts use CPU time where measured (wall time is shown too; see the noise note above).", ""]
    lines += headlines(rows) + [""]
    table = grid_table(rows)
    if table:
        lines += ["### KSL against swept across the grid", "",
                  "CPU seconds of KSL per shot and sampling (samples per keyframe, spk), and swept's CPU time as a "
                  "multiple of it; details and every other method per shot.", ""] + table + [""]
    lines += embedded_page(out_dir, *GRID_BEFORE_AFTER_PAGE, level=3)
    captions = {"time_vs_missed.png": "Time against missed contacts (every sampling of each shot where KSL ran)",
                "events_vs_bv_tests.png": "KSL events vs swept BV tests per interval over mesh size (Fig. 11)",
                "time_vs_samples.png": "Time against samples per keyframe (Fig. 10)"}
    shown = [name for name in captions if plots.get(name)]
    lines += ["### Plots", ""] + ([line for name in shown for line in (f"![{captions[name]}]({name})", "")]
                                  or ["None: the rows hold too little to plot.", ""])
    return lines


def tolerance_section(out_dir: str) -> List[str]:
    """ccd_tolerance.py's table and plot, when present."""
    table, plot = os.path.join(out_dir, CCD_TOLERANCE_MD), os.path.join(out_dir, CCD_TOLERANCE_PNG)
    if not (os.path.exists(table) or os.path.exists(plot)):
        return []
    text = ""
    if os.path.exists(table):
        with open(table) as handle:
            text = handle.read().strip()
    sentence, text = produced_by(text, "ccd_tolerance.py")
    lines = [f"## {TOLERANCE_HEADING}", "", sentence, "",
             "Per-query CCD on the shared ground-truth queries, ours against Tight-Inclusion; FN = missed "
             "contacts.", ""]
    if os.path.exists(plot):
        lines += [f"![CCD tolerance sweep]({CCD_TOLERANCE_PNG})", ""]
    if text:
        lines += [f"From [{CCD_TOLERANCE_MD}]({CCD_TOLERANCE_MD}):", "", text, ""]
    return lines


def per_shot_section(rows: Sequence[Dict]) -> List[str]:
    lines = [f"## {PER_SHOT_HEADING}", "",
             f"Produced by the runs listed under [{ACCURACY_HEADING}](#{_anchor(ACCURACY_HEADING)}). The 'x KSL' "
             "columns divide each method's time by the KSL time of the same run. Where a shot's methods come "
             "from several runs, that can differ from the KSL row (the KSL of the earliest run).", ""]
    for row in sorted(rows, key=lambda r: _shot_order(r["shot"])):
        sources = row.get("revisions") or []
        note = [f"Source: {'; '.join(sources)}" + (" (methods from different builds: compare with care)"
                                                     if len(sources) > 1 else ""), ""] if sources else []
        lines += [f"### {_shot_title(row['shot'])}", ""] + note + method_table(row) + [""]
    return lines


def render(rows: Sequence[Dict], budget_s, plots: Dict[str, bool], out_dir: str,
           command: str = "", machine: str = "") -> str:
    """The page: run.py's ``rows`` (when there are any), then every result page present in ``out_dir``."""
    sections: List[List[str]] = []
    if rows:
        sections.append(accuracy_sections(rows, budget_s, plots, out_dir, command, machine))
    sections.append(tolerance_section(out_dir))
    sections += [embedded_page(out_dir, name, heading) for name, heading in RESULT_PAGES]
    notes = os.path.join(out_dir, NOTES_MD)
    if os.path.exists(notes):
        with open(notes) as handle:
            sections.append([f"## {INVESTIGATIONS_HEADING}", "", f"From [{NOTES_MD}]({NOTES_MD}), written by hand "
                             "with the commands that check each finding.", "", handle.read().strip(), ""])
    if rows:
        sections.append(per_shot_section(rows))
    sections = [section for section in sections if section]
    headings = [section[0][3:] for section in sections]
    lines = ["# usdksl benchmarks: the current results", "",
             "Assembled by `python benchmarks/report.py` from the result files beside this page, as they are "
             "now: one section per benchmark, each naming the command that produced it (and, where its page "
             "records it, the build it measured). Earlier results are in the git history of this folder. The "
             "machine is a shared 2-core box: read the ratios measured within one run, not seconds across "
             "sections.", ""]
    lines += [f"- [{heading}](#{_anchor(heading)})" for heading in headings] + [""]
    for section in sections:
        lines += section
    return "\n".join(lines).rstrip("\n") + "\n"


def write_report(rows: Sequence[Dict], budget_s, out_dir: str, command: str = "",
                 measured_here: bool = True) -> str:
    """Writes ``out_dir``/REPORT.md with the plots of ``rows``; returns the page's path. Rows
    ``measured_here`` (from run.py --report, ``usdksl bench --report`` or run files given to report.py) are
    saved to bench_results.json, so that the page can be assembled again without them, and the page names
    this machine; rows read back from bench_results.json are neither saved again nor given a machine."""
    import platform

    import matplotlib
    matplotlib.use("Agg")
    os.makedirs(out_dir, exist_ok=True)
    plots = {
        "time_vs_missed.png": _plot_time_vs_missed(rows, os.path.join(out_dir, "time_vs_missed.png")),
        "events_vs_bv_tests.png": _plot_events_vs_bv(rows, os.path.join(out_dir, "events_vs_bv_tests.png")),
        "time_vs_samples.png": _plot_time_vs_samples(rows, os.path.join(out_dir, "time_vs_samples.png")),
    } if rows else {}
    machine = f"{platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}"
    page = render(rows, budget_s, plots, out_dir, command, machine if measured_here else "")
    report_path = os.path.join(out_dir, REPORT_MD)
    with open(report_path, "w") as handle:
        handle.write(page)
    if measured_here and rows:
        with open(os.path.join(out_dir, SUMMARY_JSON), "w") as handle:
            json.dump({"budget_s": budget_s, "command": command, "rows": rows}, handle, indent=1, default=float)
    return report_path


def shot_key(shot: Dict) -> tuple:
    """Which rows describe the same shot: the generated file's name (scene, size, sampling) with its
    triangle and sample counts. Not its path: runs measured through another checkout or a removed
    worktree name the same shot by a different path."""
    return os.path.basename(shot["path"]), shot.get("triangles"), shot.get("samples")


def _comparison_still_valid(record: Dict, reference: Dict) -> bool:
    """KSL is deterministic for one build on one shot, so a comparison made against any KSL run of the
    same build stays valid when another run's KSL record is kept."""
    return ("comparison" in record and record.get("revision") is not None
            and record.get("revision") == reference.get("revision"))


def _recompare(methods: Dict[str, Dict]) -> None:
    """Compare the merged methods against the KSL record that was kept, re-reading raw contact files
    only where a stored comparison was made against a different build."""
    reference = methods.get(REFERENCE)
    if not reference or reference.get("status") != "ok":
        for label, record in methods.items():
            record.pop("comparison", None)
        return
    stale = {label: record for label, record in methods.items()
             if label != REFERENCE and record.get("status") == "ok" and METHODS[label][0] not in ("read", "check")
             and not _comparison_still_valid(record, reference)}
    for label, record in stale.items():
        record.pop("comparison", None)
        missing = [path for path in (reference.get("contacts_file"), record.get("contacts_file"))
                   if not path or not os.path.exists(path)]
        if missing:
            record["comparison_unavailable"] = f"raw contacts file missing: {missing[0]}"
        else:
            add_comparisons({REFERENCE: reference, label: record})


#: How run.py words a skip for time: its own budget, or one a sparser sampling of the shot already exceeded.
_OVER_BUDGET = re.compile(r"exceeded the ([0-9.]+) s budget( at .+)?")


def _over_budget(record: Dict) -> Optional[tuple]:
    """(budget in seconds, whether this run itself spent it) for a skip over budget, else None."""
    match = _OVER_BUDGET.fullmatch(record.get("reason", "")) if record.get("status") == "skipped" else None
    return (float(match.group(1)), match.group(2) is None) if match else None


def _merge_rank(label: str, record: Dict) -> tuple:
    """Which of two records of one method a merged row keeps: one that ran beside KSL in its own run (its
    ratios and comparison come from one run), then one that ran at all, then the skip with the largest
    budget (the strongest lower bound), then a failure."""
    if record.get("status") != "ok":
        return 0, (_over_budget(record) or (0.0, False))[0]
    return 2 if label == REFERENCE or REFERENCE in record.get("same_run", {}) else 1, 0.0


def merge_rows(rows: Sequence[Dict]) -> List[Dict]:
    """Rows of the same shot (see `shot_key`) from several runs become one row. Per method the best-ranked
    record is kept (`_merge_rank`), the earliest run among equals, so a later run fills what earlier ones
    lacked without replacing what they measured; each record keeps its own run's times of the other
    methods (`same_run`) for ratios. Comparisons against the kept KSL record are kept when made by the
    same build and recomputed otherwise."""
    merged: Dict[tuple, Dict] = {}
    for row in rows:
        target = merged.setdefault(shot_key(row["shot"]),
                                   {"shot": row["shot"], "methods": {}, "sources": 0, "revisions": []})
        target["sources"] += 1
        revisions = row.get("revisions", [])
        for revision in revisions:
            if revision not in target["revisions"]:
                target["revisions"].append(revision)
        for label, record in row["methods"].items():
            record = dict(record)
            if len(revisions) == 1:
                record.setdefault("revision", revisions[0])
            if "same_run" not in record:
                record["same_run"] = {other: {key: peer[key] for key in ("wall_s", "cpu_s", "load_s") if key in peer}
                                      for other, peer in row["methods"].items()
                                      if other != label and peer.get("status") == "ok"}
            kept = target["methods"].get(label)
            if kept is None or _merge_rank(label, record) > _merge_rank(label, kept):
                target["methods"][label] = record
    result = []
    for row in merged.values():
        ordered = {label: row["methods"][label] for label in METHODS if label in row["methods"]}
        if row["sources"] > 1:
            _recompare(ordered)
        result.append({"shot": row["shot"], "methods": ordered, "revisions": row["revisions"]})
    return result


def quick_runs(out_dir: str) -> List[List[str]]:
    """The benchmarks that take minutes, not hours, on the inputs this checkout has, writing into
    ``out_dir``: coverage_cost.py on the Newton caches (or the samples without them), and ccd_tolerance.py
    when the shared query data and ipctk are there."""
    import importlib.util

    shots = sorted(glob.glob(os.path.join(HERE, "caches", "*.usdc"))) or sorted(
        glob.glob(os.path.join(REPO, "samples", "*.usda")))
    commands = [["python", "benchmarks/coverage_cost.py", *(os.path.relpath(shot, REPO) for shot in shots),
                 "--output", os.path.join(out_dir, "coverage_cost.md")]]
    if os.path.isdir(os.path.join(os.path.dirname(REPO), "shared", "data", "sample-queries")) \
            and importlib.util.find_spec("ipctk") is not None:
        commands.append(["python", "benchmarks/ccd_tolerance.py", "--out", out_dir])
    return commands


def run_quick(out_dir: str) -> None:
    """Runs ``quick_runs`` one after the other from the checkout's root, saying what each took."""
    for command in quick_runs(out_dir):
        print("running", " ".join(command), flush=True)
        measured = run([sys.executable] + command[1:], cwd=REPO)
        print(f"  exit {measured.exit_code} after {measured.wall_s:.0f} s", flush=True)
        if measured.exit_code not in (0, 1):   # 1: a target missed, the page is written all the same
            print(measured.stderr.strip()[-2000:], file=sys.stderr)


def load_runs(paths: Sequence[str]) -> Tuple[List[Dict], str, str]:
    """(merged rows, budgets, run lines "command<TAB>source") of run.py result files."""
    runs = []
    for path in paths:
        with open(path) as handle:
            runs.append(json.load(handle))
    for entry in runs:
        for row in entry["rows"]:
            if not row.get("revisions") and entry.get("revision"):
                row["revisions"] = [entry["revision"]]
    rows = merge_rows([row for entry in runs for row in entry["rows"]])
    budgets = ", ".join(entry["budget_s"] if isinstance(entry["budget_s"], str) else f"{entry['budget_s']:g} s"
                        for entry in runs)
    # a bench_results.json written by this page already lists its runs, one "command<TAB>source" per line
    commands = "\n".join(entry.get("command", "") if "\t" in entry.get("command", "")
                         else f"{entry.get('command', '')}\t{entry.get('revision', 'unknown')}" for entry in runs)
    return rows, budgets, commands


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("results", nargs="*",
                        help="run.py --results files (default: the results folder's bench_results.json)")
    parser.add_argument("--run", action="store_true", help="re-run the quick benchmarks first (minutes)")
    parser.add_argument("--dir", default=RESULTS, help="the results folder (default: benchmarks/results)")
    args = parser.parse_args(argv)
    if args.run:
        run_quick(args.dir)
    own = os.path.join(args.dir, SUMMARY_JSON)
    paths = args.results or ([own] if os.path.exists(own) else [])
    rows, budgets, commands = load_runs(paths)
    print(write_report(rows, budgets, args.dir, commands, measured_here=bool(args.results)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
