"""Memory windows: the core handed a shot one stretch of samples after another gives the answer of the
whole shot, bit for bit (first and last contacts), and holds only the window's samples."""

from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from usdksl.checking.collision import MEMORY_WINDOWS_COUNTER, find_contacts
from usdksl.checking.last_contact import last_contacts
from usdksl.checking.memory_windows import MIN_STEPS_PER_WINDOW, plan_memory_windows, window_of
from usdksl.cli.main import main

from .test_exact_times import per_frame_cloth
from .test_ksl_random_animations import SEEDS, contact_columns, random_scene
from .test_threads import FIELDS

import sys
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from builders import animated  # noqa: E402

SAMPLES = Path(__file__).resolve().parents[2] / "samples"
#: Window lengths tried (sample steps): the shortest allowed, and one that does not divide the shots evenly.
WINDOW_STEPS = (MIN_STEPS_PER_WINDOW, 13)


def assert_same_rows(windowed, whole, where):
    for field in FIELDS:
        assert getattr(windowed, field).tobytes() == getattr(whole, field).tobytes(), (where, field)


@pytest.mark.parametrize("seed", SEEDS)
def test_random_animations_give_the_whole_shots_contacts_in_any_windows(seed):
    meshes, pairs, thickness = random_scene(seed)
    whole = find_contacts(meshes, pairs, thickness=thickness)
    brute = find_contacts(meshes, pairs, method="brute", thickness=thickness)
    assert contact_columns(whole) == contact_columns(brute), seed
    for steps in WINDOW_STEPS:
        for method in ("ksl", "swept"):
            windowed = find_contacts(meshes, pairs, method=method, thickness=thickness, steps_per_window=steps)
            reference = whole if method == "ksl" else find_contacts(meshes, pairs, method=method,
                                                                    thickness=thickness)
            assert_same_rows(windowed, reference, (seed, steps, method))


def test_the_random_scenes_are_cut_into_several_windows():
    """The scenes above only test windows if they are cut: most have samples shared far enough apart."""
    cut = 0
    for seed in SEEDS:
        meshes, pairs, thickness = random_scene(seed)
        result = find_contacts(meshes, pairs, thickness=thickness, steps_per_window=MIN_STEPS_PER_WINDOW)
        cut += result.counters.get(MEMORY_WINDOWS_COUNTER, 1) > 1
    assert cut >= len(SEEDS) // 2, cut


@pytest.mark.parametrize("thickness", [0.0, 0.03])
def test_a_cloth_resting_through_every_cut_keeps_its_first_contacts(thickness):
    meshes = per_frame_cloth()
    pairs = [(0, 0), (0, 1)]
    whole = find_contacts(meshes, pairs, thickness=thickness)
    assert len(whole) > 0
    for steps in WINDOW_STEPS:
        for threads in (1, 2):
            windowed = find_contacts(meshes, pairs, thickness=thickness, steps_per_window=steps, threads=threads)
            assert windowed.counters[MEMORY_WINDOWS_COUNTER] >= 3
            assert_same_rows(windowed, whole, (steps, threads))


def test_last_contacts_in_windows_are_those_of_the_whole_shot():
    meshes = per_frame_cloth()
    pairs = np.array([(0, 0), (0, 1)], np.int32)
    table = find_contacts(meshes, pairs).face_contacts(meshes)
    whole = last_contacts(meshes, pairs, table, None, "ksl", 1e-6, 0.0)
    assert np.any(whole.last_time > table.time), "some contact lasts"
    for steps in WINDOW_STEPS:
        windowed = last_contacts(meshes, pairs, table, None, "ksl", 1e-6, 0.0, steps_per_window=steps)
        assert windowed.last_time.tobytes() == whole.last_time.tobytes(), steps
        assert (windowed.missing_in_reverse, windowed.only_in_reverse) == (whole.missing_in_reverse,
                                                                          whole.only_in_reverse)


def _mover(times):
    triangles = np.array([[0, 1, 2]], np.int32)
    frames = [np.array([[0.0, 0, t], [1, 0, t], [0, 1, t]]) for t in times]
    return animated(np.asarray(times, np.float64), frames, triangles)


def test_windows_are_cut_only_where_every_animated_mesh_has_a_sample():
    every_frame = _mover(np.arange(0.0, 101.0))
    every_fifth = _mover(np.arange(0.0, 101.0, 5.0))
    still = animated(np.array([0.0]), [np.zeros((3, 3))], np.array([[0, 1, 2]], np.int32))
    meshes = [every_frame, every_fifth, still]
    windows = plan_memory_windows(meshes, [(0, 1), (0, 2)], (0.0, 100.0), 12)
    assert windows[0][0] == 0.0 and windows[-1][1] == 100.0
    assert all(a[1] == b[0] for a, b in zip(windows, windows[1:]))
    assert all(end % 5.0 == 0.0 for _, end in windows), windows
    assert all(MIN_STEPS_PER_WINDOW <= end - start <= 12 for start, end in windows), windows
    # a mesh that is not checked does not constrain the cuts; a still mesh never does
    alone = plan_memory_windows(meshes, [(0, 2)], (0.0, 100.0), 12)
    assert all(end - start == 12 for start, end in alone[:-2]), alone
    assert all(MIN_STEPS_PER_WINDOW <= end - start <= 12 for start, end in alone[-2:]), alone
    # short ranges, no window length, and no shared sample give the range whole
    assert plan_memory_windows(meshes, [(0, 1)], (0.0, 10.0), 12) == [(0.0, 10.0)]
    assert plan_memory_windows(meshes, [(0, 1)], (0.0, 100.0), None) == [(0.0, 100.0)]
    offset = _mover(np.arange(0.5, 100.0))
    assert plan_memory_windows([every_frame, offset], [(0, 1)], (0.0, 100.0), 12) == [(0.0, 100.0)]


def test_a_window_holds_views_of_its_samples_only():
    mesh = _mover(np.arange(0.0, 50.0))
    part = window_of(mesh, (10.0, 20.0))
    assert part.times.tolist() == list(np.arange(10.0, 21.0))
    assert np.shares_memory(part.points, mesh.points) and part.points.shape[0] == 11
    with pytest.raises(ValueError, match="between two samples"):
        window_of(mesh, (10.5, 20.0))
    # outside its samples a mesh holds its first or last one
    late = _mover(np.arange(30.0, 40.0))
    assert window_of(late, (0.0, 20.0)).times.tolist() == [30.0]
    assert window_of(late, (45.0, 50.0)).times.tolist() == [39.0]


@pytest.mark.parametrize("name", ["fold", "drape", "pass_through"])
def test_sample_shot_files_are_byte_identical_in_any_windows(name, tmp_path):
    path = SAMPLES / f"{name}.usda"
    outputs = {}
    for steps in (MIN_STEPS_PER_WINDOW, 1_000_000):
        out = tmp_path / str(steps)
        result = CliRunner().invoke(main, ["check", str(path), "--out", str(out), "--window", str(steps),
                                           "--last-contact"], catch_exceptions=False)
        assert result.exit_code == 1, result.stderr
        outputs[steps] = {suffix: (out / f"{name}.{suffix}").read_bytes()
                          for suffix in ("contacts.csv", "regions.csv", "summary.csv", "usdksl.usda")}
    assert outputs[MIN_STEPS_PER_WINDOW] == outputs[1_000_000]


def test_a_window_shorter_than_the_minimum_is_a_usage_error(tmp_path):
    result = CliRunner().invoke(main, ["check", str(SAMPLES / "fold.usda"), "--out", str(tmp_path / "x"),
                                       "--window", str(MIN_STEPS_PER_WINDOW - 1)])
    assert result.exit_code == 2 and not (tmp_path / "x").exists()


def test_a_window_leaves_alone_the_pairs_found_before_it_and_confirms_each_once():
    """The cloth rests on the slab across every cut: its pairs are confirmed once, in the window that
    first finds them, not again in each later one."""
    meshes = per_frame_cloth()
    pairs = [(0, 0), (0, 1)]
    whole = find_contacts(meshes, pairs, threads=1)
    windowed = find_contacts(meshes, pairs, threads=1, steps_per_window=MIN_STEPS_PER_WINDOW)
    assert windowed.counters[MEMORY_WINDOWS_COUNTER] >= 3
    assert windowed.counters["raw_confirmations"] == whole.counters["raw_confirmations"]
    assert_same_rows(windowed, whole, "settled")


def test_settled_pairs_are_not_found_again_and_out_of_range_ones_are_refused():
    meshes = per_frame_cloth()
    pairs = [(0, 0), (0, 1)]
    whole = find_contacts(meshes, pairs)
    settled = np.stack([whole.mesh_a, whole.tri_a, whole.mesh_b, whole.tri_b], axis=1)[::2]
    rest = find_contacts(meshes, pairs, settled=settled)
    assert len(rest) == len(whole) - len(settled)
    kept = np.ones(len(whole), bool)
    kept[::2] = False
    assert rest.time.tobytes() == whole.time[kept].tobytes()
    # the reference tests every pair itself
    assert len(find_contacts(meshes, pairs, method="brute", settled=settled)) == len(whole)
    with pytest.raises(ValueError, match="out of range"):
        find_contacts(meshes, pairs, settled=np.array([[0, 10 ** 6, 1, 0]]))
