"""usdksl against its baselines and the ipctk peer on simulator caches, each method in one run per cache.

    python benchmarks/newton_bench.py benchmarks/caches/*.usdc ../shared/data/newton/newton_viewerusd_cloth_twist.usd
    python benchmarks/newton_bench.py CACHE --methods ksl,swept,tight --budget 300

Methods (each in a fresh interpreter, one after the other, killed past ``--budget`` CPU seconds; timed with
benchmarks/harness.py):

- ``ksl``, ``swept``, ``discrete``: ``usdksl.find_contacts`` on the pairs ``usdksl check`` plans
  (``usdksl.reading.scope.plan_shot``, default options), then face pairs; the shot is loaded before the clock starts.
- ``check``: the ``usdksl check`` command end to end (interpreter start, load, plan, KSL, CSV, override
  layer), timed from outside; its contacts CSV is what a user gets.
- ``ipctk``: benchmarks/peer_ipctk.py's all-first-contacts pipeline with ipctk's default CCD settings
  (the same answer as check: every face pair and its first-contact time), arrays prepared inside the clock.
- ``ipctk-sweep``: ipctk's earliest-contact sweep (compute_collision_free_stepsize per interval), the shot
  already loaded like the other in-process methods.
- ``ipctk-sweep-e2e``: the same sweep end to end as a user runs it, ``python benchmarks/peer_ipctk.py CACHE
  --mode sweep`` (interpreter start, imports, the same USD loader, the sweep), timed from outside like
  ``check``: the like-for-like peer of ``check``.
- ``tight``: the same pipeline at Tight-Inclusion tolerance 1e-9: the reference for every reported time.

Reported per cache: wall and CPU seconds per method, ksl/swept and check/ipctk ratios (measured in this
run), the native counters (events, narrow_phase_tests, primitive_queries), microseconds of CPU per
narrow-phase test, and each method's first-contact times against the tight reference (pairs within
1e-3 time codes, largest early and late error, reported pairs the reference never sees touch, reference
pairs the method misses). Results are merged into benchmarks/results/newton.json (one entry per cache)
and benchmarks/results/newton.md. The machine is a shared 2-core box: absolute times are noise, ratios
measured in one run are the result; the load average at the start of each cache is recorded.
"""

from __future__ import annotations

import argparse
import json
import os
import shlex
import sys
import tempfile
import time
from typing import Callable, Dict, List, Optional

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import peer_ipctk  # noqa: E402
from harness import Build, Measurement, byte_compile_usdksl, call_fresh, measuring, run  # noqa: E402

RESULTS = os.path.join(HERE, "results")
DEFAULT_JSON = os.path.join(RESULTS, "newton.json")
DEFAULT_MARKDOWN = os.path.join(RESULTS, "newton.md")
METHODS = ("ksl", "swept", "discrete", "check", "ipctk", "ipctk-sweep", "ipctk-sweep-e2e", "tight")
USDKSL_METHODS = ("ksl", "swept", "discrete")
#: CPU-time budget of one method on one cache (seconds, all its threads; RLIMIT_CPU): a method past it is
#: killed and reported as over budget. CPU time, not wall time, because the shared machine can give a
#: process a small fraction of a core; a wall-time cap of WALL_BUDGET_FACTOR times it still ends a hang.
DEFAULT_BUDGET_S = 600.0
WALL_BUDGET_FACTOR = 12.0
MACHINE_NOTE = "2-core shared machine (other sessions run builds and benchmarks beside it): absolute times are " \
               "noise; compare the ratios measured in one run"


# --------------------------------------------------------------------------- one method, in a worker

def _save_faces(path: str, paths: List[str], time_, mesh_a, face_a, mesh_b, face_b) -> None:
    np.savez(path, paths=np.asarray(paths, dtype=str), time=np.asarray(time_, np.float64),
             mesh_a=np.asarray(mesh_a, np.int64), face_a=np.asarray(face_a, np.int64),
             mesh_b=np.asarray(mesh_b, np.int64), face_b=np.asarray(face_b, np.int64))


def _timed_process(command: List[str], record: Dict) -> Measurement:
    """Runs ``command`` and records its wall seconds and CPU seconds (all its threads) in ``record``."""
    completed = run(command)
    record["wall_s"], record["cpu_s"] = completed.wall_s, completed.cpu_s
    return completed


def worker(method: str, shot_path: str, out_prefix: str) -> Dict:
    """Run one method on one shot in this fresh process; contacts go to ``out_prefix``.npz."""
    record: Dict = {"method": method}
    if method in ("check",) + USDKSL_METHODS:   # both use the default: every core this process may use
        from usdksl.checking.collision import default_threads
        record["threads"] = default_threads()
    if method == "ipctk-sweep-e2e":
        completed = _timed_process([sys.executable, os.path.join(HERE, "peer_ipctk.py"), shot_path,
                                    "--mode", "sweep"], record)
        if completed.exit_code != 0:
            raise RuntimeError(f"peer_ipctk.py --mode sweep exited {completed.exit_code}: "
                               f"{completed.stderr.strip()[-300:]}")
        record["summary"] = completed.stdout.strip().splitlines()[-1] if completed.stdout.strip() else ""
        return record
    if method == "check":
        with tempfile.TemporaryDirectory(prefix="newton-bench-") as out_dir:
            completed = _timed_process(Build.current().command("check", shot_path, "--out", out_dir), record)
            record["exit_code"] = completed.exit_code
            record["summary"] = completed.stderr.strip().splitlines()[-1] if completed.stderr.strip() else ""
            if completed.exit_code not in (0, 1):
                raise RuntimeError(f"usdksl check exited {completed.exit_code}: {completed.stderr.strip()[-300:]}")
            stem = os.path.splitext(os.path.basename(shot_path))[0]
            keys, times = peer_ipctk.read_contacts_csv(os.path.join(out_dir, f"{stem}.contacts.csv"))
        np.savez(out_prefix + ".npz", keys=keys, time=times)
        record["face_pairs"] = int(len(keys))
        return record

    import usdksl
    from usdksl.reading.scope import ScopeOptions, plan_shot

    with measuring() as loading:
        shot = usdksl.load_shot(shot_path)
        plan = plan_shot(shot, ScopeOptions())
    record["load_s"] = loading.wall_s
    paths = [mesh.path for mesh in shot.meshes]
    with measuring() as measured:
        if method in USDKSL_METHODS:
            result = usdksl.find_contacts(shot.meshes, plan.pairs, method=method)
            faces = result.face_contacts(shot.meshes)
        else:
            combined = peer_ipctk.combine(shot.meshes, plan.pairs, plan.moving)
            if method == "ipctk-sweep":
                starts, times, counters = peer_ipctk.earliest_contact_sweep(combined)
            else:
                contacts = peer_ipctk.all_first_contacts(combined,
                                                         peer_ipctk.MODES["tight" if method == "tight" else "default"])
    record.update(wall_s=measured.wall_s, cpu_s=measured.cpu_s, peak_rss_bytes=measured.peak_rss_bytes)
    if method in USDKSL_METHODS:
        record["counters"] = {key: int(value) for key, value in result.counters.items()}
        record["face_pairs"] = len(faces)
        _save_faces(out_prefix + ".npz", paths, faces.time, faces.mesh_a, faces.face_a, faces.mesh_b, faces.face_b)
    elif method == "ipctk-sweep":
        record["counters"] = counters
        np.savez(out_prefix + ".npz", interval_start=starts, time=times)
    else:
        record["counters"] = contacts.counters
        record["face_pairs"] = len(contacts)
        _save_faces(out_prefix + ".npz", contacts.paths, contacts.time, contacts.mesh_a, contacts.face_a,
                    contacts.mesh_b, contacts.face_b)
    return record


def describe(shot_path: str) -> Dict:
    """Sizes of a cache as usdksl check sees it (in a worker, so the parent stays small)."""
    import usdksl
    from usdksl.reading.scope import ScopeOptions, plan_shot

    shot = usdksl.load_shot(shot_path)
    plan = plan_shot(shot, ScopeOptions())
    checked = sorted(set(plan.pairs.reshape(-1).tolist()))
    return {"meshes": len(shot.meshes), "checked_meshes": len(checked), "checked_pairs": plan.checked_pairs,
            "triangles": int(sum(len(m.triangles) for m in shot.meshes)),
            "moving_triangles": int(sum(len(m.triangles) for m in shot.meshes if m.kind != "static")),
            "samples": int(len(shot.times)), "time_range": [float(shot.times[0]), float(shot.times[-1])]}


def _run_worker(function: Callable[..., Dict], args: List[str], budget_s: float) -> Dict:
    """``function(*args)`` in a fresh interpreter, ended past ``budget_s`` CPU seconds (or WALL_BUDGET_FACTOR
    times that in wall seconds): its record, or why there is none."""
    measured = call_fresh(function, *args, cpu_budget_s=budget_s, timeout_s=budget_s * WALL_BUDGET_FACTOR)
    if measured.timed_out:
        return {"skipped": f"over the {budget_s * WALL_BUDGET_FACTOR:g} s wall-time cap"}
    if measured.over_cpu_budget:
        return {"skipped": f"over the {budget_s:g} s CPU budget"}
    if measured.error:
        return {"error": measured.error}
    return measured.value


# --------------------------------------------------------------------------- comparing

def _keys_of(npz) -> np.ndarray:
    if "keys" in npz.files:
        return npz["keys"]
    paths = np.asarray(npz["paths"], dtype=object)
    if len(npz["time"]) == 0:
        return np.zeros(0, str)
    return peer_ipctk.pair_keys(paths[npz["mesh_a"]].astype(str), npz["face_a"], paths[npz["mesh_b"]].astype(str),
                                npz["face_b"])


def compare_to_reference(npz, reference) -> Dict:
    report = peer_ipctk.compare_times(_keys_of(npz), npz["time"], _keys_of(reference), reference["time"])
    for key in ("examples_without_reference_touch", "examples_missing_from_report"):
        report[key] = report[key][:3]
    return report


def compare_sweep(npz, reference, sample_times: np.ndarray) -> Dict:
    """Per interval: the sweep's earliest time against the reference's earliest contact in that interval."""
    times = np.asarray(reference["time"], np.float64)
    interval_of = np.clip(np.searchsorted(sample_times, times, side="right") - 1, 0, len(sample_times) - 2)
    intervals = np.unique(interval_of)
    earliest = np.array([times[interval_of == k].min() for k in intervals]) if len(intervals) else np.zeros(0)
    common, at_reference, at_sweep = np.intersect1d(intervals, npz["interval_start"], return_indices=True)
    error = npz["time"][at_sweep] - earliest[at_reference]
    return {"intervals_with_contact": int(len(npz["interval_start"])), "reference_intervals": int(len(intervals)),
            "missed_intervals": int(len(intervals) - len(common)),
            "extra_intervals": int(len(npz["interval_start"]) - len(common)),
            "largest_early_error": float(max(0.0, -error.min())) if len(error) else 0.0,
            "largest_late_error": float(max(0.0, error.max())) if len(error) else 0.0}


# --------------------------------------------------------------------------- one cache

def bench_cache(shot_path: str, methods: List[str], budget_s: float, raw_dir: str) -> Dict:
    entry: Dict = {"cache": shot_path, "name": os.path.splitext(os.path.basename(shot_path))[0],
                   "load_average_at_start": [round(x, 2) for x in os.getloadavg()],
                   "started": time.strftime("%Y-%m-%dT%H:%M:%S"), "budget_s": budget_s}
    entry["recording"] = _recording_metadata(shot_path)
    entry["shot"] = _run_worker(describe, [shot_path], budget_s)
    print(f"\n== {shot_path}: {entry['shot']}", file=sys.stderr, flush=True)
    records = {}
    for method in methods:
        prefix = os.path.join(raw_dir, f"{entry['name']}.{method}")
        record = _run_worker(worker, [method, shot_path, prefix], budget_s)
        records[method] = record
        shown = {k: v for k, v in record.items() if k in ("wall_s", "cpu_s", "face_pairs", "skipped", "error")}
        print(f"   {method:12s} {shown}", file=sys.stderr, flush=True)
    entry["methods"] = records
    reference_path = os.path.join(raw_dir, f"{entry['name']}.tight.npz")
    if "wall_s" in records.get("tight", {}) and os.path.exists(reference_path):
        reference = np.load(reference_path)
        sample_times = None
        for method, record in records.items():
            path = os.path.join(raw_dir, f"{entry['name']}.{method}.npz")
            if method == "tight" or "wall_s" not in record or not os.path.exists(path):
                continue
            data = np.load(path)
            if method == "ipctk-sweep":
                if sample_times is None:
                    sample_times = _sample_times(shot_path)
                record["vs_tight"] = compare_sweep(data, reference, sample_times)
            else:
                record["vs_tight"] = compare_to_reference(data, reference)
    entry["ratios"] = ratios(records)
    return entry


def _sample_times(shot_path: str) -> np.ndarray:
    import usdksl
    return np.asarray(usdksl.load_shot(shot_path).times, np.float64)


def _recording_metadata(shot_path: str) -> Optional[Dict]:
    sidecar = os.path.splitext(shot_path)[0] + ".json"
    if os.path.exists(sidecar):
        with open(sidecar) as handle:
            return json.load(handle)
    readme = os.path.join(os.path.dirname(shot_path), "README.md")
    return {"readme": os.path.relpath(readme, os.path.dirname(HERE))} if os.path.exists(readme) else None


def ratios(records: Dict[str, Dict]) -> Dict[str, Optional[float]]:
    def value(method, key="wall_s"):
        return records.get(method, {}).get(key)

    def ratio(a, b, key="wall_s"):
        x, y = value(a, key), value(b, key)
        return round(x / y, 3) if x is not None and y else None

    out = {"ksl/swept wall": ratio("ksl", "swept"), "ksl/swept cpu": ratio("ksl", "swept", "cpu_s"),
           "check/ipctk wall": ratio("check", "ipctk"), "check/ipctk cpu": ratio("check", "ipctk", "cpu_s"),
           "check/ipctk-sweep wall": ratio("check", "ipctk-sweep"),
           "check/ipctk-sweep cpu": ratio("check", "ipctk-sweep", "cpu_s"),
           "check/ipctk-sweep-e2e wall": ratio("check", "ipctk-sweep-e2e"),
           "check/ipctk-sweep-e2e cpu": ratio("check", "ipctk-sweep-e2e", "cpu_s"),
           "ksl/ipctk wall": ratio("ksl", "ipctk")}
    for method in USDKSL_METHODS:
        record = records.get(method, {})
        tests = record.get("counters", {}).get("narrow_phase_tests")
        if tests and record.get("cpu_s") is not None:
            out[f"{method} us/narrow-phase test"] = round(record["cpu_s"] / tests * 1e6, 3)
    return out


# --------------------------------------------------------------------------- output

def _seconds(record: Dict) -> str:
    if "wall_s" in record:
        return f"{record['wall_s']:.1f} ({record['cpu_s']:.1f})"
    if "skipped" in record:
        return "> budget"
    return "error" if "error" in record else "-"


def _time_error(record: Dict) -> str:
    vs = record.get("vs_tight")
    if not vs or "within_agreement" not in vs:
        return "-"
    return (f"{vs['within_agreement']}/{vs['common_pairs']} within; early {vs['largest_early_error']:.2g}, "
            f"late {vs['largest_late_error']:.2g}; no touch {vs['reported_without_reference_touch']}, "
            f"missed {vs['reference_pairs_missing_from_report']}")


def markdown(entries: List[Dict], command: str) -> str:
    lines = ["# usdksl on Newton simulator caches", "",
             f"Command: `{command}`", "",
             "Runs made one process per cache are merged with `python benchmarks/newton_bench.py --render "
             "PART.json ...`.", "",
             f"{MACHINE_NOTE}. Wall seconds, CPU seconds in parentheses; `check` is the `usdksl check` command "
             "end to end (a separate process), the other usdksl methods are `usdksl.find_contacts` on "
             "check's planned pairs with the shot already loaded; `ipctk` is benchmarks/peer_ipctk.py's "
             "all-first-contacts pipeline (same answer as check), `ipctk-sweep` its earliest-contact sweep (shot "
             "already loaded), `ipctk-sweep-e2e` that sweep end to end in its own process like check "
             "(`python benchmarks/peer_ipctk.py CACHE --mode sweep`: interpreter, imports, the same USD loader), "
             "`tight` the Tight-Inclusion 1e-9 reference. Produced by benchmarks/newton_bench.py; raw numbers in "
             "newton.json.", "",
             "Ratios are given for wall time and, in parentheses, CPU time (CPU seconds add up all threads: ipctk "
             "runs TBB on every core; `check` runs with its default `--threads`, every core the process may use, "
             "and ksl/swept/discrete call `find_contacts` with its default, also every core; the thread count of "
             "each run is in newton.json; check's CPU includes interpreter start, imports, loading the cache, "
             "planning, confirmation on raw samples and writing the CSV/USD outputs).", "",
             f"The last column is check's time error vs the tight reference: face pairs within "
             f"{peer_ipctk.AGREEMENT_TIME_CODES:g} time codes of it (of the pairs both report), largest early and "
             "late error (time codes), reported pairs the reference never sees touch, reference pairs check "
             "misses.", "",
             "| cache | triangles x samples | ksl | swept | discrete | check | ipctk | ipctk-sweep | ipctk-sweep-e2e | "
             "tight | ksl/swept | check/ipctk | check/ipctk-sweep | check/ipctk-sweep-e2e | ksl us/test | swept us/test | load avg | "
             "check: time error vs tight reference |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for entry in entries:
        shot, records, r = entry.get("shot", {}), entry["methods"], entry["ratios"]
        size = f"{shot.get('triangles', '?')} x {shot.get('samples', '?')}"
        cells = [_seconds(records.get(m, {})) for m in METHODS]
        fmt = lambda x: "-" if x is None else f"{x:g}"  # noqa: E731
        both = lambda name: f"{fmt(r.get(name + ' wall'))} ({fmt(r.get(name + ' cpu'))})"  # noqa: E731
        lines.append(f"| {entry['name']} | {size} | " + " | ".join(cells) + f" | {both('ksl/swept')} | "
                     f"{both('check/ipctk')} | {both('check/ipctk-sweep')} | {both('check/ipctk-sweep-e2e')} | {fmt(r.get('ksl us/narrow-phase test'))} | "
                     f"{fmt(r.get('swept us/narrow-phase test'))} | {entry['load_average_at_start'][0]:g} | "
                     f"{_time_error(records.get('check', {}))} |")
    lines += ["", "Caches (recording metadata from each cache's sidecar JSON / customLayerData):", "",
              "| cache | recorded with | frames | scale | cloth triangles | meshes (checked pairs) | simulation s |",
              "|---|---|---|---|---|---|---|"]
    for entry in entries:
        recording, shot = entry.get("recording") or {}, entry.get("shot", {})
        made = (f"`{recording['command']}` (Newton {recording.get('newtonVersion')})" if "command" in recording
                else f"third party, see {recording.get('readme', '?')}")
        lines.append(f"| {entry['name']} | {made} | {recording.get('frames', shot.get('samples', '?'))} | "
                     f"{recording.get('scale', '-')} | {recording.get('clothTriangles', shot.get('moving_triangles', '?'))} | "
                     f"{shot.get('meshes', '?')} ({shot.get('checked_pairs', '?')}) | "
                     f"{recording.get('simulationSeconds', '-')} |")
    lines += ["", "Counters and face pairs:", "",
              "| cache | method | face pairs | narrow_phase_tests | primitive_queries | events (polygons_collide) |",
              "|---|---|---|---|---|---|"]
    for entry in entries:
        for method in METHODS:
            record = entry["methods"].get(method, {})
            if "wall_s" not in record:
                continue
            c = record.get("counters", {})
            lines.append(f"| {entry['name']} | {method} | {record.get('face_pairs', '-')} | "
                         f"{c.get('narrow_phase_tests', c.get('ccd_queries', '-'))} | {c.get('primitive_queries', '-')} | "
                         f"{c.get('polygons_collide_events', '-')} |")
    lines += ["", f"First-contact times against the tight reference (pairs within "
              f"{peer_ipctk.AGREEMENT_TIME_CODES:g} time codes, of the pairs both report; largest early/late error "
              "in time codes; reported pairs the reference never sees touch; reference pairs the method misses):",
              "",
              "| cache | ksl | swept | discrete | check | ipctk |", "|---|---|---|---|---|---|"]
    for entry in entries:
        lines.append(f"| {entry['name']} | " + " | ".join(_time_error(entry["methods"].get(m, {}))
                                                          for m in ("ksl", "swept", "discrete", "check", "ipctk"))
                     + " |")
    lines += ["", "ipctk-sweep per sample interval: intervals where it finds any contact (a first contact or one that "
              "persists), intervals holding a first contact of the tight reference, those it misses, those with "
              "contact but no new first contact, and its time against the earliest first contact of the interval "
              "(persisting contacts make it early):", "",
              "| cache | intervals with contact | reference intervals | missed | without a first contact | largest early | largest late |",
              "|---|---|---|---|---|---|---|"]
    for entry in entries:
        vs = entry["methods"].get("ipctk-sweep", {}).get("vs_tight")
        if vs:
            lines.append(f"| {entry['name']} | {vs['intervals_with_contact']} | {vs['reference_intervals']} | "
                         f"{vs['missed_intervals']} | {vs['extra_intervals']} | {vs['largest_early_error']:.3g} | "
                         f"{vs['largest_late_error']:.3g} |")
    return "\n".join(lines) + "\n"


def print_table(entries: List[Dict]) -> None:
    print(f"# {MACHINE_NOTE}")
    header = f"{'cache':34s} {'tri x samples':>14s} " + " ".join(f"{m:>15s}" for m in METHODS)
    print(header)
    for entry in entries:
        shot = entry.get("shot", {})
        size = f"{shot.get('triangles', '?')}x{shot.get('samples', '?')}"
        print(f"{entry['name'][:34]:34s} {size:>14s} " + " ".join(f"{_seconds(entry['methods'].get(m, {})):>15s}"
                                                                   for m in METHODS))
        print("    ratios: " + ", ".join(f"{k} {v}" for k, v in entry["ratios"].items() if v is not None))
        for method in ("ksl", "swept", "discrete", "check", "ipctk"):
            if entry["methods"].get(method, {}).get("vs_tight"):
                print(f"    {method} vs tight: {_time_error(entry['methods'][method])}")


def write_outputs(document: Dict, json_path: str, markdown_path: str) -> None:
    document["machine"] = MACHINE_NOTE
    for entry in document["entries"].values():
        entry["ratios"] = ratios(entry["methods"])
    os.makedirs(os.path.dirname(os.path.abspath(json_path)), exist_ok=True)
    with open(json_path, "w") as handle:
        json.dump(document, handle, indent=1, sort_keys=True)
    entries = sorted(document["entries"].values(), key=lambda e: e["name"])
    with open(markdown_path, "w") as handle:
        handle.write(markdown(entries, "; ".join(sorted({e.get("command", "") for e in entries}))))


def render(argv: List[str]) -> int:
    """``--render PART.json ...``: merge the entries of runs made separately (e.g. one process per cache)
    into --json (default benchmarks/results/newton.json) and rewrite --markdown from it."""
    parser = argparse.ArgumentParser(prog="newton_bench.py --render")
    parser.add_argument("parts", nargs="*")
    parser.add_argument("--json", default=DEFAULT_JSON)
    parser.add_argument("--markdown", default=DEFAULT_MARKDOWN)
    args = parser.parse_args(argv)
    document = {"entries": {}}
    for path in ([args.json] if os.path.exists(args.json) else []) + args.parts:
        with open(path) as handle:
            document["entries"].update(json.load(handle)["entries"])
    for entry in document["entries"].values():
        entry.setdefault("merged_by", "python benchmarks/newton_bench.py --render PART.json ...")
    write_outputs(document, args.json, args.markdown)
    return 0


def main(argv=None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    if argv and argv[0] == "--render":
        return render(argv[1:])
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("caches", nargs="+")
    parser.add_argument("--methods", default=",".join(METHODS), help=f"comma-separated subset of {','.join(METHODS)}")
    parser.add_argument("--budget", type=float, default=DEFAULT_BUDGET_S,
                        help="CPU seconds per method and cache (wall-time cap: 12 times that)")
    parser.add_argument("--json", default=DEFAULT_JSON, help="results JSON (entries merged by cache name)")
    parser.add_argument("--markdown", default=DEFAULT_MARKDOWN)
    parser.add_argument("--raw", default=None, help="folder for per-method contacts (default: a temporary one)")
    args = parser.parse_args(argv)
    methods = [m for m in args.methods.split(",") if m]
    unknown = set(methods) - set(METHODS)
    if unknown:
        parser.error(f"unknown methods {sorted(unknown)}")
    command = "python benchmarks/newton_bench.py " + " ".join(shlex.quote(a) for a in argv)
    document = {"entries": {}}
    if os.path.exists(args.json):
        with open(args.json) as handle:
            document = json.load(handle)
    raw = args.raw or tempfile.mkdtemp(prefix="newton-bench-raw-")
    os.makedirs(raw, exist_ok=True)
    byte_compile_usdksl()
    entries = []
    for cache in args.caches:
        entry = bench_cache(cache, methods, args.budget, raw)
        entry["command"] = command
        entries.append(entry)
        document["entries"][entry["name"]] = entry
        write_outputs(document, args.json, args.markdown)
    print_table(entries)
    return 0


if __name__ == "__main__":
    sys.exit(main())
