"""Blow-up detection: a vertex far beyond its mesh's motion is named; ordinary motion never is."""

import numpy as np
import pytest

from usdksl.reading import blowups
from usdksl.reading.blowups import BLOWUP_SIZE_FACTOR, describe_blowups, find_blowups, shot_blowups


def waving_cloth(frames=20, n=6):
    xs, zs = np.meshgrid(np.linspace(0, 1, n), np.linspace(0, 1, n), indexing="ij")
    rest = np.stack([xs.ravel(), np.zeros(xs.size), zs.ravel()], axis=1)
    times = np.arange(float(frames))
    points = np.stack([rest + [0.0, 0.1 * np.sin(0.5 * t), 0.0] + 0.05 * np.sin(rest * 3 + t) for t in times])
    return times, points


@pytest.mark.parametrize("height", [1e3, 1e5, 1e7, 1e9])
def test_one_vertex_blown_at_one_sample_is_named_with_both_steps(height):
    times, points = waving_cloth()
    points[9, 14, 1] = height
    found = find_blowups("/World/Cloth", times, points)
    assert {b.vertex for b in found} == {14}
    assert [(b.time_before, b.time_after) for b in found] == [(8.0, 9.0), (9.0, 10.0)]
    lines = describe_blowups(found, "shot.usd")
    assert len(lines) == 1
    assert "/World/Cloth" in lines[0] and "vertex 14" in lines[0] and "between time 8 and 10" in lines[0]


def test_fast_rigid_motion_and_half_turns_are_not_blowups():
    times, cloth = waving_cloth()
    # Translate by 50 mesh sizes per frame and turn half a revolution per frame about y.
    moving = []
    for k, t in enumerate(times):
        angle = np.pi * t
        c, s = np.cos(angle), np.sin(angle)
        rotation = np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])
        moving.append(cloth[k] @ rotation.T + [50.0 * t, 0.0, 0.0])
    assert find_blowups("/World/Spinner", times, np.asarray(moving)) == []


def test_threshold_is_relative_to_the_mesh_size():
    times, points = waving_cloth()
    size = np.linalg.norm(points[0].max(axis=0) - points[0].min(axis=0))
    below, above = points.copy(), points.copy()
    below[5, 3, 1] += 0.5 * BLOWUP_SIZE_FACTOR * size
    above[5, 3, 1] += 2.0 * BLOWUP_SIZE_FACTOR * size
    assert find_blowups("/m", times, below) == []
    assert {b.vertex for b in find_blowups("/m", times, above)} == {3}


def test_many_blown_vertices_are_summarised():
    times, points = waving_cloth()
    points[4, :12, 1] = 1e6
    lines = describe_blowups(find_blowups("/World/Cloth", times, points), "shot.usd")
    assert len(lines) == 6
    assert "7 more vertices blow up" in lines[-1]


def test_static_and_rigid_meshes_are_not_scanned():
    class Mesh:
        def __init__(self, kind):
            self.path, self.kind = "/m", kind
            self.times, self.points = waving_cloth()
            self.points[3, 0, 0] = 1e9
    assert shot_blowups([Mesh("rigid"), Mesh("static")]) == []
    assert len(shot_blowups([Mesh("deforming")])) == 2


def _blowups_step_by_step(prim, times, points):
    """The detection rule (module docstring) applied one step at a time, as the reference."""
    size = float(np.median(np.linalg.norm(points.max(axis=1) - points.min(axis=1), axis=1)))
    found = []
    for k in range(points.shape[0] - 1):
        step = points[k + 1] - points[k]
        excess = np.linalg.norm(step - np.median(step, axis=0), axis=1)
        found += [(int(v), float(times[k]), float(times[k + 1]), float(excess[v]), size)
                  for v in np.flatnonzero(excess > BLOWUP_SIZE_FACTOR * size)]
    return found


@pytest.mark.parametrize("block_values", [None, 7, 3 * 36 * 4])
def test_blocks_of_steps_find_exactly_what_single_steps_find(monkeypatch, block_values):
    if block_values is not None:   # blocks of one step, and blocks of four steps that leave a remainder
        monkeypatch.setattr(blowups, "BLOWUP_BLOCK_VALUES", block_values)
    times, points = waving_cloth(frames=23)
    rng = np.random.default_rng(7)
    for frame, vertex in zip(rng.integers(0, 23, 9), rng.integers(0, 36, 9)):
        points[frame, vertex] += rng.normal(size=3) * 10.0 ** rng.integers(2, 6)
    found = find_blowups("/World/Cloth", times, points)
    expected = _blowups_step_by_step("/World/Cloth", times, points)
    assert len(expected) >= 9
    assert [(b.vertex, b.time_before, b.time_after, b.excess, b.mesh_size) for b in found] == expected


@pytest.mark.parametrize("fraction", [0.6, 0.75, 0.9])
def test_a_vertex_moving_against_its_mesh_is_found_though_no_vertex_moves_the_threshold(fraction):
    """The cheap bound that skips quiet steps must count the common motion: every vertex moves by T,
    one by -T, so its excess is 2|T| while no displacement exceeds |T| (here under the threshold)."""
    times, points = waving_cloth(frames=12)
    size = blowups.mesh_size(points)
    threshold = BLOWUP_SIZE_FACTOR * size
    shove = np.array([fraction * threshold, 0.0, 0.0])
    points[9:] += shove
    points[9:, 20] -= 2.0 * shove   # 3 of 12 samples stretched: the median size hardly moves
    threshold = BLOWUP_SIZE_FACTOR * blowups.mesh_size(points)
    assert np.linalg.norm(shove) < threshold < 2.0 * np.linalg.norm(shove)
    found = find_blowups("/World/Cloth", times, points)
    assert [(b.vertex, b.time_before, b.time_after) for b in found] == [(20, 8.0, 9.0)]
    assert found[0].excess > threshold
    assert [(b.vertex, b.time_before, b.time_after, b.excess, b.mesh_size) for b in found] == \
        _blowups_step_by_step("/World/Cloth", times, points)


def test_steps_near_the_threshold_give_what_the_median_of_every_step_gives():
    rng = np.random.default_rng(11)
    for trial in range(40):
        times, points = waving_cloth(frames=12)
        threshold = BLOWUP_SIZE_FACTOR * blowups.mesh_size(points)
        for k in rng.integers(1, 12, 4):
            common = rng.normal(size=3)
            points[k:] += common / np.linalg.norm(common) * rng.uniform(0.0, 0.7) * threshold
            vertex = rng.integers(0, 36)
            kick = rng.normal(size=3)
            points[k:, vertex] += kick / np.linalg.norm(kick) * rng.uniform(0.8, 1.2) * threshold
        found = find_blowups("/World/Cloth", times, points)
        assert [(b.vertex, b.time_before, b.time_after, b.excess, b.mesh_size) for b in found] == \
            _blowups_step_by_step("/World/Cloth", times, points), trial
