"""Pair rule and contact comparison of benchmarks/run.py on hand-made contact lists."""

import numpy as np
import pytest

import run
import suite


def contacts(rows):
    rows = np.asarray(rows, dtype=np.float64).reshape(-1, 5)
    return {"time": rows[:, 0], "mesh_a": rows[:, 1].astype(np.int32), "face_a": rows[:, 2].astype(np.int32),
            "mesh_b": rows[:, 3].astype(np.int32), "face_b": rows[:, 4].astype(np.int32)}


REFERENCE_ROWS = [(1.5, 0, 3, 1, 7), (2.25, 1, 0, 1, 4), (2.25, 0, 9, 1, 1), (4.0, 1, 2, 1, 8)]


def test_pairs_self_for_deforming_inter_when_one_moves_never_static_static():
    kinds = ["static", "static", "rigid", "deforming", "rigid"]
    assert suite.benchmark_pairs(kinds) == [(0, 2), (0, 3), (0, 4), (1, 2), (1, 3), (1, 4), (2, 3), (2, 4),
                                          (3, 3), (3, 4)]
    assert suite.benchmark_pairs(["static", "static"]) == []
    assert suite.benchmark_pairs(["deforming"]) == [(0, 0)]


def test_identical_contacts_miss_nothing():
    result = suite.compare_contacts(contacts(REFERENCE_ROWS), contacts(REFERENCE_ROWS))
    assert result == {"found": 4, "missed": 0, "extra": 0, "time_error_max": 0.0, "time_error_mean": 0.0}


@pytest.mark.parametrize("removed", range(len(REFERENCE_ROWS)))
def test_removing_one_contact_counts_one_missed(removed):
    other = [row for i, row in enumerate(REFERENCE_ROWS) if i != removed]
    result = suite.compare_contacts(contacts(REFERENCE_ROWS), contacts(other))
    assert (result["found"], result["missed"], result["extra"]) == (3, 1, 0)


def test_swapped_sides_are_a_different_pair_and_late_times_are_errors():
    # (0, 3, 1, 7) reported as (1, 7, 0, 3) is not the same row: the core and face_contacts order pairs.
    other = [(1.5, 1, 7, 0, 3), (2.5, 1, 0, 1, 4), (2.25, 0, 9, 1, 1), (4.0, 1, 2, 1, 8), (5.0, 0, 0, 0, 1)]
    result = suite.compare_contacts(contacts(REFERENCE_ROWS), contacts(other))
    assert (result["found"], result["missed"], result["extra"]) == (5, 1, 2)
    assert result["time_error_max"] == pytest.approx(0.25)
    assert result["time_error_mean"] == pytest.approx(0.25 / 3)


def test_nothing_found_misses_everything_with_no_time_error():
    result = suite.compare_contacts(contacts(REFERENCE_ROWS), contacts([]))
    assert (result["found"], result["missed"], result["extra"]) == (0, 4, 0)
    assert np.isnan(result["time_error_max"])


def test_interval_comparison_uses_the_earliest_reference_contact_of_each_interval():
    samples = np.array([1.0, 2.0, 3.0, 4.0, 5.0])
    # reference intervals: 1.5 -> [1,2), 2.25 twice -> [2,3), 4.0 -> last interval [4,5] (closed) -> index 3
    # the peer finds [1,2) at 1.25, [2,3) at 2.0, and [3,4) which the reference has no first contact in
    result = suite.compare_intervals(contacts(REFERENCE_ROWS), np.array([0, 1, 2]), np.array([1.25, 2.0, 3.5]),
                                   samples)
    assert (result["found"], result["missed"], result["extra"]) == (3, 1, 1)
    assert result["time_error_max"] == pytest.approx(0.25)


def test_substep_runs_are_predicted_from_cheaper_ones_and_timeouts_carry_to_denser_sampling():
    done = {"discrete": {"label": "discrete", "status": "ok", "wall_s": 20.0}}
    assert run._skip_reason("discrete x2", done, {}, "g", 1, budget_s=60.0) is None
    reason = run._skip_reason("discrete x4", done, {}, "g", 1, budget_s=60.0)
    assert reason is not None and "predicted 80 s" in reason
    history = {("g", "swept"): 2}
    assert run._skip_reason("swept", {}, history, "g", 1, budget_s=60.0) is None
    assert "at 2 samples/keyframe" in run._skip_reason("swept", {}, history, "g", 5, budget_s=60.0)
    assert run._skip_reason("swept", {}, history, "other", 5, budget_s=60.0) is None
    ksl_history = {("g", "ksl"): 1, ("g", "check"): 1}
    assert run._skip_reason("ksl", {}, ksl_history, "g", 10, budget_s=60.0) is None
    assert run._skip_reason("check", {}, ksl_history, "g", 10, budget_s=60.0) is None
