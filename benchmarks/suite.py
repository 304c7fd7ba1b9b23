"""The benchmark's records and methods: which methods exist, how their contacts compare with KSL's, and the
ratios a record yields. ``run.py`` measures (and imports this), ``report.py`` renders (and imports this);
neither imports the other.

A record is one method on one shot, a dict as ``run.py`` writes it (label, status, wall_s, cpu_s,
peak_mem_bytes, counters, contacts_file, comparison, ...); a row is one shot with its records by label.
"""

from __future__ import annotations

from typing import Dict, List, Optional, Sequence, Tuple

import numpy as np

from usdksl.reading.loader import DEFORMING, STATIC

#: Counter names of the KSL events (all event types of the kinetic trees and separation lists).
KSL_EVENT_COUNTERS = ("kinetic_tree_events", "bv_overlap_events", "fathers_do_not_overlap_events",
                      "leaves_do_not_overlap_events", "plane_kept_steps", "polygons_collide_events",
                      "bv_change_events")


#: Method label -> (kind, discrete substeps). Labels are what tables and plots show.
METHODS: Dict[str, Tuple[str, int]] = {
    "read": ("read", 0),
    "ksl": ("ksl", 1),
    "swept": ("swept", 1),
    "discrete": ("discrete", 1),
    "discrete x2": ("discrete", 2),
    "discrete x4": ("discrete", 4),
    "discrete x8": ("discrete", 8),
    "ipctk": ("ipctk", 0),
    "check": ("check", 0),
}


#: The method every other is compared with.
REFERENCE = "ksl"


#: Methods whose work grows with the number of samples: one that timed out at a sparser sampling of a shot is
#: not run again at a denser one. KSL (and check, which runs it) is exempt: not growing is its point.
SAMPLE_BOUND_KINDS = ("swept", "discrete", "ipctk")


#: Scenes of samples/generate.py and the size option each takes.
SCENE_SIZES = {"tablecloth": (2000, 4000, 8000, 16000), "swirl": (4000, 8000, 16000, 33000),
               "character": (35000, 60000, 90000)}


def benchmark_pairs(kinds: Sequence[str]) -> List[Tuple[int, int]]:
    """Mesh pairs to check: self for deforming meshes, inter when at least one of the two moves.

    Never static-static; rigid meshes get no self pair (they cannot change shape).
    """
    moving = [kind != STATIC for kind in kinds]
    pairs = []
    for i, kind in enumerate(kinds):
        if kind == DEFORMING:
            pairs.append((i, i))
        pairs.extend((i, j) for j in range(i + 1, len(kinds)) if moving[i] or moving[j])
    return sorted(pairs)


def _pair_keys(contacts: Dict[str, np.ndarray]) -> np.ndarray:
    """One int64 structured key per face pair row, for set operations."""
    columns = [np.asarray(contacts[name], np.int64) for name in ("mesh_a", "face_a", "mesh_b", "face_b")]
    return np.stack(columns, axis=1) if columns[0].size else np.zeros((0, 4), np.int64)


def compare_contacts(reference: Dict[str, np.ndarray], other: Dict[str, np.ndarray]) -> Dict[str, float]:
    """Face-pair contacts of ``other`` against ``reference`` (dicts of time, mesh_a, face_a, mesh_b, face_b).

    Both hold the first contact per face pair. Returns found / missed / extra counts and the
    absolute error of the first-contact time over the pairs both report (max and mean; NaN if none).
    """
    ref_keys, other_keys = _pair_keys(reference), _pair_keys(other)
    both = np.concatenate([ref_keys, other_keys])
    _, inverse = np.unique(both, axis=0, return_inverse=True)
    inverse = inverse.reshape(-1)
    ref_ids, other_ids = inverse[:len(ref_keys)], inverse[len(ref_keys):]
    common, ref_at, other_at = np.intersect1d(ref_ids, other_ids, assume_unique=True, return_indices=True)
    errors = np.abs(np.asarray(other["time"], np.float64)[other_at] - np.asarray(reference["time"], np.float64)[ref_at])
    return {
        "found": int(len(other_keys)),
        "missed": int(len(ref_keys) - len(common)),
        "extra": int(len(other_keys) - len(common)),
        "time_error_max": float(errors.max()) if errors.size else float("nan"),
        "time_error_mean": float(errors.mean()) if errors.size else float("nan"),
    }


def compare_intervals(reference: Dict[str, np.ndarray], interval_start: np.ndarray, interval_time: np.ndarray,
                      sample_times: np.ndarray) -> Dict[str, float]:
    """An earliest-contact-per-interval answer (ipctk) against the reference's contacts.

    ``interval_start[k]`` indexes ``sample_times``; ``interval_time[k]`` is the contact time found there.
    A reference contact at time t belongs to the interval [t_k, t_k+1) that contains it (the last
    interval is closed).
    """
    times = np.asarray(reference["time"], np.float64)
    interval_of = np.clip(np.searchsorted(sample_times, times, side="right") - 1, 0, len(sample_times) - 2)
    ref_intervals = np.unique(interval_of)
    order = np.argsort(interval_of, kind="stable")
    earliest = np.minimum.reduceat(times[order], np.searchsorted(interval_of[order], ref_intervals)) \
        if ref_intervals.size else np.zeros(0)
    common, ref_at, other_at = np.intersect1d(ref_intervals, np.asarray(interval_start, np.int64),
                                              return_indices=True)
    errors = np.abs(np.asarray(interval_time, np.float64)[other_at] - earliest[ref_at])
    return {
        "found": int(len(interval_start)),
        "missed": int(len(ref_intervals) - len(common)),
        "extra": int(len(interval_start) - len(common)),
        "time_error_max": float(errors.max()) if errors.size else float("nan"),
        "time_error_mean": float(errors.mean()) if errors.size else float("nan"),
    }


def _load_contacts(path: str) -> Dict[str, np.ndarray]:
    with np.load(path) as data:
        return {name: data[name] for name in data.files}


def add_comparisons(records: Dict[str, Dict]) -> None:
    """Fill contacts found/missed/extra and time errors of every method against the KSL record."""
    reference = records.get(REFERENCE)
    if not reference or reference.get("status") != "ok":
        return
    ref = _load_contacts(reference["contacts_file"])
    for label, record in records.items():
        if record.get("status") != "ok" or METHODS[label][0] in ("read", "check"):
            continue
        other = _load_contacts(record["contacts_file"])
        if METHODS[label][0] == "ipctk":
            record["comparison"] = compare_intervals(ref, other["interval_start"], other["time"], ref["sample_times"])
            record["comparison"]["unit"] = "intervals"
        else:
            record["comparison"] = compare_contacts(ref, other)
            record["comparison"]["unit"] = "face pairs"


def ksl_events(counters: Dict[str, int]) -> int:
    return int(sum(counters.get(name, 0) for name in KSL_EVENT_COUNTERS))


def same_run_times(record: Dict, label: str, records: Dict[str, Dict]) -> Optional[Dict]:
    """Times of method `label` from the run that measured `record` (kept by report.py when it merges rows of
    several runs), else the row's own `label` record when it ran: ratios come from one run where they can."""
    own = record.get("same_run", {}).get(label)
    if own:
        return own
    other = records.get(label, {})
    return other if other.get("status") == "ok" else None


def ratio_rows(records: Dict[str, Dict]) -> List[Dict]:
    """One row per method: time and memory ratios to KSL, contacts found/missed/extra, time errors."""
    rows = []
    for label, record in records.items():
        row = {"method": label, "status": record.get("status"), "reason": record.get("reason", "")}
        if record.get("status") == "ok":
            reference = record if label == REFERENCE else same_run_times(record, REFERENCE, records) or {}
            ref_time = reference.get("wall_s")
            row["wall_s"] = record["wall_s"]
            row["cpu_s"] = record.get("cpu_s")
            ref_cpu = reference.get("cpu_s") if ref_time else None
            row["cpu_vs_ksl"] = record["cpu_s"] / ref_cpu if ref_cpu and record.get("cpu_s") else float("nan")
            row["time_vs_ksl"] = record["wall_s"] / ref_time if ref_time else float("nan")
            row["peak_mib"] = record["peak_mem_bytes"] / 2**20
            counters = record.get("counters", {})
            row["events"] = ksl_events(counters) if METHODS[label][0] == "ksl" else None
            row["bv_tests"] = counters.get("bv_tests")
            row["narrow_phase_tests"] = counters.get("narrow_phase_tests")
            row.update(record.get("comparison", {}))
        rows.append(row)
    return rows
