"""What accuracy costs in time: KSL against every baseline and the ipctk peer, on the same shots.

    python benchmarks/run.py --quick            # ~10 minutes on 2 cores
    python benchmarks/run.py --headline         # tablecloth 16k at 1 and 10 samples/keyframe (~5 minutes)
    python benchmarks/run.py --full             # the paper's grid (hours)
    python benchmarks/run.py SHOT.usdc ...      # given shots (also: usdksl bench SHOT...)

Every method runs in a fresh interpreter (one subprocess per shot and method, one after the other,
never in parallel; benchmarks/harness.py), so its peak memory can be read from the kernel (VmHWM, reset
after loading; C++ allocations included, which tracemalloc would not see). Wall and CPU times are
measured around the method call only; the shot is loaded before the clock starts,
except for ``read`` (the loader alone: the I/O baseline) and ``check`` (the whole ``usdksl check``
without interpreter start-up: load, scoping, KSL, CSV and override layer). Each method has a wall
time budget; a method that exceeds it is killed and reported as skipped, and a method whose cheaper
sibling already exceeded it (more substeps, more samples per keyframe) is skipped without running.

Contacts are compared as authored face pairs against the KSL result of the same run: found, missed
(in KSL, not in the method), extra (in the method, not in KSL) and the error of first-contact times
on the pairs both found. ``ipctk`` answers one number per sample interval (the collision-free step
size), so it is compared per interval: intervals where KSL has a contact and ipctk does not are
missed, and the time error is that of the earliest contact of the interval.

Results go to benchmarks/results/raw/ (git-ignored); ``--report`` writes benchmarks/results/REPORT.md,
the PNG plots and the summary JSON they are made from (see report.py).
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import tempfile
import time
from dataclasses import dataclass
from typing import Dict, List, Optional, Sequence, Tuple

import numpy as np

from harness import Measurement, call_fresh, git_revision, measuring
# compare_contacts and compare_intervals are imported for scripts that reach them as run.<name>.
from suite import (METHODS, REFERENCE, SAMPLE_BOUND_KINDS, SCENE_SIZES, add_comparisons,  # noqa: F401
                   benchmark_pairs, compare_contacts, compare_intervals, ksl_events, ratio_rows, same_run_times)

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
RESULTS = os.path.join(HERE, "results")
RAW = os.path.join(RESULTS, "raw")
GENERATED = os.path.join(REPO, "samples", "generated")

#: Names this run's raw contact files, so runs never overwrite each other's (report.py re-reads them).
RUN_ID = time.strftime("%Y%m%d-%H%M%S") + f"-{os.getpid()}"
KEYFRAMES = 11


@dataclass(frozen=True)
class Preset:
    shots: Tuple[Tuple[str, int], ...]
    samples_per_keyframe: Tuple[int, ...]
    methods: Tuple[str, ...]
    budget_s: float


PRESETS = {
    "quick": Preset(shots=(("tablecloth", 2000), ("tablecloth", 4000), ("swirl", 4000), ("character", 35000)),
                    samples_per_keyframe=(1, 10),
                    methods=("read", "ksl", "swept", "discrete", "discrete x2", "ipctk", "check"),
                    budget_s=60.0),
    "headline": Preset(shots=(("tablecloth", 16000),),
                       samples_per_keyframe=(1, 10),
                       methods=("read", "ksl", "swept", "ipctk", "check"),
                       budget_s=900.0),
    "full": Preset(shots=tuple((scene, size) for scene, sizes in SCENE_SIZES.items() for size in sizes),
                   samples_per_keyframe=(1, 2, 5, 10),
                   methods=tuple(METHODS),
                   budget_s=1800.0),
}


# --------------------------------------------------------------------------- pairs and comparison


# --------------------------------------------------------------------------- one method in a worker

def _mesh_points_at(mesh, times: np.ndarray) -> np.ndarray:
    """float64[T, N, 3]: a mesh's points linearly interpolated at the given times (held outside its samples)."""
    if len(mesh.times) == 1:
        return np.broadcast_to(mesh.points[0], (len(times),) + mesh.points.shape[1:])
    segment = np.clip(np.searchsorted(mesh.times, times, side="right") - 1, 0, len(mesh.times) - 2)
    t0, t1 = mesh.times[segment], mesh.times[segment + 1]
    weight = np.clip((times - t0) / (t1 - t0), 0.0, 1.0)[:, None, None]
    return (1.0 - weight) * mesh.points[segment] + weight * mesh.points[segment + 1]


def _triangle_edges(triangles: np.ndarray) -> np.ndarray:
    edges = np.concatenate([triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]])
    return np.unique(np.sort(edges, axis=1), axis=0).astype(np.int32)


def _ipctk_sweep(shot) -> Tuple[np.ndarray, np.ndarray, Dict[str, int]]:
    """ipctk as its users would run it: one CollisionMesh, an LBVH broad phase and
    compute_collision_free_stepsize per sample interval. Returns (interval index, contact time) of every
    interval whose step is below 1."""
    import ipctk

    times = np.asarray(shot.times, np.float64)
    offsets = np.cumsum([0] + [m.vertex_count for m in shot.meshes])
    faces = np.concatenate([m.triangles.astype(np.int64) + offsets[i] for i, m in enumerate(shot.meshes)])
    faces = np.asfortranarray(faces.astype(np.int32))
    positions = np.concatenate([_mesh_points_at(m, times) for m in shot.meshes], axis=1)  # [T, V, 3]
    mesh = ipctk.CollisionMesh(np.asfortranarray(positions[0]), np.asfortranarray(_triangle_edges(faces)), faces)
    broad_phase = ipctk.LBVH()
    starts, contact_times = [], []
    for k in range(len(times) - 1):
        step = ipctk.compute_collision_free_stepsize(mesh, np.asfortranarray(positions[k]),
                                                     np.asfortranarray(positions[k + 1]), 0.0, broad_phase)
        if step < 1.0:
            starts.append(k)
            contact_times.append(times[k] + step * (times[k + 1] - times[k]))
    return np.asarray(starts, np.int64), np.asarray(contact_times, np.float64), {"intervals": len(times) - 1}


def _record_measurement(record: Dict, measured: Measurement) -> None:
    """Wall and CPU seconds of the method, and its peak memory above the RSS it started from (bytes)."""
    record.update(wall_s=measured.wall_s, cpu_s=measured.cpu_s, peak_mem_bytes=measured.peak_rise_bytes,
                  peak_reset=measured.peak_reset)


def worker(shot_path: str, label: str, out_prefix: str) -> Dict:
    """Run one method on one shot in this (fresh) process; write contacts to ``out_prefix``.npz."""
    kind, substeps = METHODS[label]
    record: Dict = {"label": label}
    if kind == "read":
        from usdksl.reading.loader import load_shot
        with measuring() as measured:
            shot = load_shot(shot_path)
        _record_measurement(record, measured)
        record["points_bytes"] = int(sum(m.points.nbytes for m in shot.meshes))
        np.savez(out_prefix + ".npz", time=np.zeros(0))
        return record
    if kind == "check":
        from usdksl.pipeline import check_shot, output_targets
        from usdksl.reports.output import write_files
        with tempfile.TemporaryDirectory(prefix="usdksl-bench-") as out_dir:
            with measuring() as measured:
                result = check_shot(shot_path, targets=output_targets(shot_path, out_dir))
                write_files(result.files)
        _record_measurement(record, measured)
        record["exit_code"] = int(result.exit_code)
        np.savez(out_prefix + ".npz", time=np.zeros(0))
        return record

    from usdksl.reading.loader import load_shot
    with measuring() as loading:
        shot = load_shot(shot_path)
    record["load_s"] = loading.wall_s
    if kind == "ipctk":
        with measuring() as measured:
            interval_start, interval_time, counters = _ipctk_sweep(shot)
        _record_measurement(record, measured)
        record["counters"] = counters
        np.savez(out_prefix + ".npz", interval_start=interval_start, time=interval_time,
                 sample_times=np.asarray(shot.times, np.float64))
        return record

    from usdksl.checking.collision import find_contacts
    pairs = benchmark_pairs([m.kind for m in shot.meshes])
    with measuring() as measured:
        result = find_contacts(shot.meshes, pairs, method=kind, discrete_substeps=max(substeps, 1))
        faces = result.face_contacts(shot.meshes)
    _record_measurement(record, measured)
    record["counters"] = {k: int(v) for k, v in result.counters.items()}
    record["triangle_contacts"] = len(result)
    np.savez(out_prefix + ".npz", time=faces.time, mesh_a=faces.mesh_a, face_a=faces.face_a,
             mesh_b=faces.mesh_b, face_b=faces.face_b, sample_times=np.asarray(shot.times, np.float64))
    return record


# --------------------------------------------------------------------------- the suite

@dataclass
class ShotInfo:
    path: str
    scene: str
    size: Optional[int]
    samples_per_keyframe: Optional[int]
    triangles: int = 0
    moving_triangles: int = 0
    samples: int = 0
    points_bytes: int = 0


def describe_shot(path: str, scene: str = "", size: Optional[int] = None,
                  samples_per_keyframe: Optional[int] = None) -> ShotInfo:
    """Sizes of a shot; scene, size and sampling default to those in a samples/generate.py file name."""
    import re
    from usdksl.reading.loader import STATIC, load_shot
    named = re.fullmatch(r"([a-z]+)_(\d+)_k\d+_s(\d+)", os.path.splitext(os.path.basename(path))[0])
    if named and not scene:
        scene, size, samples_per_keyframe = named.group(1), int(named.group(2)), int(named.group(3))
    shot = load_shot(path)
    return ShotInfo(path=path, scene=scene or os.path.splitext(os.path.basename(path))[0], size=size,
                    samples_per_keyframe=samples_per_keyframe,
                    triangles=int(sum(len(m.triangles) for m in shot.meshes)),
                    moving_triangles=int(sum(len(m.triangles) for m in shot.meshes if m.kind != STATIC)),
                    samples=int(len(shot.times)),
                    points_bytes=int(sum(m.points.nbytes for m in shot.meshes)))


def generated_shot(scene: str, size: int, samples_per_keyframe: int, keyframes: int = KEYFRAMES) -> str:
    """Path of a samples/generate.py shot, generated when missing (same keyframes for every sampling)."""
    path = os.path.join(GENERATED, f"{scene}_{size}_k{keyframes}_s{samples_per_keyframe}.usdc")
    if not os.path.exists(path):
        sys.path.insert(0, os.path.join(REPO, "samples"))
        from generate import generate  # noqa: E402  (samples/ is a script folder)
        generate(scene, size, keyframes=keyframes, samples_per_keyframe=samples_per_keyframe, out=path)
    return path


def run_method(shot_path: str, label: str, budget_s: float, raw_dir: str) -> Dict:
    """One method on one shot in a fresh interpreter, killed after ``budget_s`` seconds."""
    os.makedirs(raw_dir, exist_ok=True)
    stem = os.path.splitext(os.path.basename(shot_path))[0]
    prefix = os.path.join(raw_dir, f"{stem}.{label.replace(' ', '_')}.{RUN_ID}")
    measured = call_fresh(worker, shot_path, label, prefix, timeout_s=budget_s)
    if measured.timed_out:
        return {"label": label, "status": "skipped", "reason": f"exceeded the {budget_s:g} s budget"}
    if measured.error:
        return {"label": label, "status": "failed", "reason": measured.error}
    record = measured.value
    record["status"] = "ok"
    record["contacts_file"] = prefix + ".npz"
    return record


def _skip_reason(label: str, done: Dict[str, Dict], history: Dict[Tuple[str, str], int],
                 group: str, samples_per_keyframe: Optional[int], budget_s: float) -> Optional[str]:
    kind, substeps = METHODS[label]
    if kind == "discrete" and substeps > 1:
        fewer = [l for l in done if METHODS[l][0] == "discrete" and METHODS[l][1] < substeps]
        for other in fewer:
            cheaper = done[other]
            if cheaper.get("status") == "skipped":
                return f"{other} already exceeded the {budget_s:g} s budget"
            if cheaper.get("status") == "ok" and \
                    cheaper["wall_s"] * substeps / max(METHODS[other][1], 1) > budget_s:
                return (f"predicted {cheaper['wall_s'] * substeps / max(METHODS[other][1], 1):.0f} s "
                        f"from {other} (budget {budget_s:g} s)")
    timed_out_at = history.get((group, label)) if kind in SAMPLE_BOUND_KINDS else None
    if timed_out_at is not None and samples_per_keyframe is not None and samples_per_keyframe >= timed_out_at:
        return f"exceeded the {budget_s:g} s budget at {timed_out_at} samples/keyframe"
    return None


def run_suite(shots: Sequence[ShotInfo], methods: Sequence[str], budget_s: float, raw_dir: str = RAW,
              echo=print) -> List[Dict]:
    """Every method on every shot (one shot after the other, methods in the given order, KSL first)."""
    methods = [REFERENCE] + [m for m in methods if m != REFERENCE]
    history: Dict[Tuple[str, str], int] = {}
    rows = []
    for shot in shots:
        group = f"{shot.scene}:{shot.size}"
        echo(f"== {os.path.basename(shot.path)}: {shot.triangles} triangles ({shot.moving_triangles} moving), "
             f"{shot.samples} samples")
        done: Dict[str, Dict] = {}
        for label in methods:
            reason = _skip_reason(label, done, history, group, shot.samples_per_keyframe, budget_s)
            if reason:
                done[label] = {"label": label, "status": "skipped", "reason": reason}
            else:
                done[label] = run_method(shot.path, label, budget_s, raw_dir)
                if done[label]["status"] == "skipped" and shot.samples_per_keyframe is not None:
                    history.setdefault((group, label), shot.samples_per_keyframe)
            echo("   " + format_record(done[label]))
        add_comparisons(done)
        rows.append({"shot": shot.__dict__, "methods": done})
        echo(format_ratios(done))
    return rows


# --------------------------------------------------------------------------- printing


def format_record(record: Dict) -> str:
    if record.get("status") != "ok":
        return f"{record['label']:<12} {record.get('status')}: {record.get('reason', '')}"
    counters = record.get("counters", {})
    parts = [f"{record['label']:<12} {record['wall_s']:9.3f} s", f"CPU {record.get('cpu_s', float('nan')):9.3f} s",
             f"peak {record['peak_mem_bytes'] / 2**20:7.1f} MiB"]
    if counters:
        if record["label"] == "ksl":
            parts.append(f"events {ksl_events(counters)}")
        if "bv_tests" in counters:
            parts.append(f"bv_tests {counters['bv_tests']}  narrow {counters['narrow_phase_tests']}")
    return "  ".join(parts)


def format_ratios(records: Dict[str, Dict]) -> str:
    lines = []
    for row in ratio_rows(records):
        if row["status"] != "ok":
            continue
        text = f"   {row['method']}/KSL time {row['time_vs_ksl']:.3g}x (CPU {row['cpu_vs_ksl']:.3g}x)"
        if "missed" in row:
            text += (f", found {row['found']} missed {row['missed']} extra {row['extra']} {row['unit']}"
                     f", first-contact time error max {row['time_error_max']:.3g}")
        lines.append(text)
    return "\n".join(lines)


# --------------------------------------------------------------------------- command line

def source_revision() -> str:
    """The checkout's commit, with '+changes' when tracked files differ from it (what was measured)."""
    return git_revision(REPO)


def preset_shots(preset: Preset) -> List[ShotInfo]:
    shots = []
    for scene, size in preset.shots:
        for samples in preset.samples_per_keyframe:
            path = generated_shot(scene, size, samples)
            shots.append(describe_shot(path, scene, size, samples))
    return shots


def main(argv: Optional[Sequence[str]] = None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("shots", nargs="*", help="USD shots (instead of a preset)")
    group = parser.add_mutually_exclusive_group()
    group.add_argument("--quick", action="store_true", help="small preset (~10 minutes)")
    group.add_argument("--full", action="store_true", help="the paper's grid (hours)")
    group.add_argument("--headline", action="store_true",
                       help="the target shot: tablecloth 16k at 1 and 10 samples/keyframe with read, KSL, "
                            "swept, ipctk, check (swirl: give its shots explicitly)")
    parser.add_argument("--methods", default=None,
                        help=f"comma-separated subset of: {', '.join(METHODS)}")
    parser.add_argument("--budget", type=float, default=None, help="wall seconds per method and shot")
    parser.add_argument("--results", default=None, help="write the rows as JSON to this file")
    parser.add_argument("--report", action="store_true",
                        help="also write benchmarks/results/REPORT.md and plots from these rows")
    args = parser.parse_args(argv)
    preset = PRESETS["full" if args.full else "headline" if args.headline else "quick"]
    methods = args.methods.split(",") if args.methods else list(preset.methods)
    unknown = [m for m in methods if m not in METHODS]
    if unknown:
        parser.error(f"unknown methods: {', '.join(unknown)}")
    budget = args.budget if args.budget is not None else preset.budget_s
    shots = [describe_shot(path) for path in args.shots] if args.shots else preset_shots(preset)
    command = "python benchmarks/run.py " + " ".join(argv)
    revision = source_revision()
    rows = run_suite(shots, methods, budget)
    if args.results:
        with open(args.results, "w") as handle:
            json.dump({"budget_s": budget, "command": command, "revision": revision, "rows": rows}, handle,
                      indent=1, default=float)
    if args.report:
        sys.path.insert(0, HERE)
        from report import write_report  # noqa: E402  (benchmarks/ is a script folder)
        print("wrote", write_report(rows, budget, RESULTS, command))
    return 0


if __name__ == "__main__":
    sys.exit(main())
