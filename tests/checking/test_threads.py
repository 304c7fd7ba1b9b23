"""Checking on several threads splits the range into time windows; the answer is the same bit for bit.

Every reported time is computed on raw sample steps, which a window tests exactly as one whole run
does, and windows merge by the earliest contact per triangle pair: so the contacts (times, pairs,
features) must not depend on the thread count. The shots below have enough samples for every count
here to cut them into several windows.
"""

from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings

from usdksl import load_shot
from usdksl.checking.collision import find_contacts
from usdksl.cli.main import main

from .test_exact_times import per_frame_cloth
from .test_methods_agree import pairs_of, random_scenes

THREAD_COUNTS = (1, 2, 3)
FIELDS = ("time", "mesh_a", "tri_a", "mesh_b", "tri_b", "feature", "undecided")
SAMPLES = Path(__file__).resolve().parents[2] / "samples"


def answers_by_thread_count(meshes, pairs, method, **kwargs):
    return {threads: find_contacts(meshes, pairs, method=method, threads=threads, **kwargs)
            for threads in THREAD_COUNTS}


def assert_identical(results):
    first = results[THREAD_COUNTS[0]]
    for threads, result in results.items():
        for field in FIELDS:
            assert getattr(result, field).tobytes() == getattr(first, field).tobytes(), (threads, field)


@pytest.mark.parametrize("method", ["ksl", "swept", "brute"])
def test_per_frame_cloth_contacts_do_not_depend_on_the_thread_count(method):
    meshes = per_frame_cloth()
    results = answers_by_thread_count(meshes, [(0, 0), (0, 1)], method)
    assert len(results[1]) > 0, "the shot must have contacts"
    assert_identical(results)


def test_a_contact_that_lasts_over_several_windows_is_confirmed_once():
    """Windows are confirmed in time order: a pair confirmed in an earlier window is not confirmed again
    in a later one (the cloth rests on the table through every window)."""
    meshes = per_frame_cloth()
    results = answers_by_thread_count(meshes, [(0, 0), (0, 1)], "ksl")
    pairs = len(results[1])
    assert pairs > 0
    for threads, result in results.items():
        confirmations = result.counters["raw_confirmations"]
        assert confirmations == results[1].counters["raw_confirmations"], (threads, confirmations, pairs)


def test_a_time_range_inside_the_shot_is_split_the_same_way():
    meshes = per_frame_cloth()
    results = answers_by_thread_count(meshes, [(0, 0), (0, 1)], "ksl", time_range=(7.5, 33.0))
    assert len(results[1]) > 0
    assert float(results[1].time.min()) >= 7.5
    assert_identical(results)


@pytest.mark.parametrize("name", ["fold", "drape", "pass_through"])
def test_sample_shot_outputs_are_byte_identical_for_any_thread_count(name, tmp_path):
    from click.testing import CliRunner
    path = SAMPLES / f"{name}.usda"
    if not path.is_file():
        pytest.skip(f"{path} not shipped")
    shot = load_shot(path)
    assert max(m.times.shape[0] for m in shot.meshes) > 2 * max(THREAD_COUNTS), "too few samples to split"
    outputs = {}
    for threads in THREAD_COUNTS:
        out = tmp_path / str(threads)
        result = CliRunner().invoke(main, ["check", str(path), "--out", str(out), "--threads", str(threads)],
                                    catch_exceptions=False)
        assert result.exit_code == 1, result.stderr
        outputs[threads] = {suffix: (out / f"{name}.{suffix}").read_bytes()
                            for suffix in ("contacts.csv", "summary.csv", "usdksl.usda")}
    for threads in THREAD_COUNTS[1:]:
        assert outputs[threads] == outputs[1], threads


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(random_scenes())
def test_random_animations_give_the_same_contacts_on_any_thread_count(meshes):
    pairs = pairs_of(meshes)
    for method in ("ksl", "swept"):
        assert_identical(answers_by_thread_count(meshes, pairs, method))


def test_threads_must_be_positive():
    with pytest.raises(ValueError):
        find_contacts(per_frame_cloth(), [(0, 0)], threads=0)


@pytest.mark.parametrize("thickness", [0.01, 0.03])
def test_contacts_within_a_thickness_do_not_depend_on_the_thread_count(thickness):
    """Above thickness 0 a pair can come within it exactly at a sample where a window begins; the
    window must test it there as a whole run does (on the raw steps around it), not held still."""
    meshes = per_frame_cloth()
    results = answers_by_thread_count(meshes, [(0, 0), (0, 1)], "ksl", thickness=thickness)
    assert len(results[1]) > 0
    assert_identical(results)


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(random_scenes())
def test_random_animations_within_a_thickness_give_the_same_contacts_on_any_thread_count(meshes):
    assert_identical(answers_by_thread_count(meshes, pairs_of(meshes), "ksl", thickness=0.02))


def test_a_simulator_cache_within_a_thickness_gives_the_same_contacts_on_any_thread_count(newton_twist_within_1cm):
    """The third-party twist at thickness 0.01: its cloth rests within the thickness of itself from
    frame to frame, so window begins fall on pairs that just came within it: their feature must not
    depend on where a window begins."""
    twist = newton_twist_within_1cm
    assert len(twist.result) > 10000
    assert_identical({1: twist.result, 2: find_contacts([twist.mesh], [(0, 0)], threads=2, thickness=twist.thickness)})
