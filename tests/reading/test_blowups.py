"""Blow-up detection: a vertex far beyond its mesh's motion is named; ordinary motion never is."""

import numpy as np
import pytest
from pxr import UsdGeom, Vt

from builders import box, define_mesh, grid
from usdksl.pipeline import check_shot
from usdksl.reading import blowups
from usdksl.reading.blowups import BLOWUP_SIZE_FACTOR, describe_blowups, find_blowups, shot_blowups
from usdksl.warning_kinds import BLOW_UP, CACHE_GLITCH


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


@pytest.mark.parametrize("sizes, blows_up", [(20.0, True), (9.0, False)])
def test_a_vertex_twenty_sizes_beyond_its_mesh_blows_up_and_nine_sizes_does_not(sizes, blows_up):
    # docs/contracts.md, Blow-ups: more than 10 times the mesh's size beyond its common motion. The contract's
    # number, written out: a test reading BLOWUP_SIZE_FACTOR would follow a changed factor.
    times, points = waving_cloth()
    size = blowups.mesh_size(points)
    # One vertex jumps away at sample 15 and stays there (for too few samples to change the median size).
    points[15:, 14] += [0.0, sizes * size, 0.0]
    found = faults(times, points)
    assert found[1] == []                         # one vertex of 36 is no glitch
    assert [(b.vertex, b.time_before, b.time_after) for b in found[0]] == ([(14, 14.0, 15.0)] if blows_up else [])


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


# --------------------------------------------------------------------------- cache glitches
# New names are reached through the module (blowups.X) so that the tests above still run on a module
# without them.

class Mesh:
    """What the shot-level functions read of a loaded mesh."""

    def __init__(self, times, points, kind="deforming", path="/World/Cloth"):
        self.path, self.kind, self.times, self.points = path, kind, times, points


def faults(times, points, kind="deforming", path="/World/Cloth"):
    return blowups.shot_faults([Mesh(times, points, kind, path)])


def grid_ball(n=4):
    """Points of a small closed-ish blob (a cube's surface grid) of diagonal sqrt(3), centred at 0."""
    axis = np.linspace(-0.5, 0.5, n)
    x, y, z = np.meshgrid(axis, axis, axis, indexing="ij")
    cube = np.stack([x.ravel(), y.ravel(), z.ravel()], axis=1)
    return cube[(np.abs(cube) == 0.5).any(axis=1)]


def spin(points, angle, axis=(0.3, 1.0, 0.2)):
    axis = np.asarray(axis) / np.linalg.norm(axis)
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    rotation = np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * k @ k
    return points @ rotation.T


@pytest.mark.parametrize("kind", ["deforming", "rigid"])
def test_a_whole_mesh_jumping_for_one_sample_is_one_glitch_between_its_neighbours(kind):
    times, points = waving_cloth()
    points[9] += [1000.0, 0.0, 0.0]
    assert find_blowups("/World/Cloth", times, points) == []   # the median goes with the jump
    found_blowups, glitches = faults(times, points, kind)
    assert found_blowups == []
    assert [(g.time, g.time_last, g.time_before, g.time_after, g.whole_mesh) for g in glitches] == \
        [(9.0, 9.0, 8.0, 10.0, True)]
    assert glitches[0].distance == pytest.approx(1000.0, rel=0.01)
    lines = blowups.describe_glitches(glitches, "shot.usd")
    assert len(lines) == 1
    assert lines[0].startswith("shot.usd: /World/Cloth: cache glitch: the whole mesh jumps away and back "
                               "between time 8 and 10 (at time 9): it lies 1e+03 units off its motion")
    assert "contacts it causes are still reported" in lines[0]


def test_most_of_a_mesh_jumping_is_a_glitch_of_that_part_and_the_still_vertices_are_not_blowups():
    times, points = waving_cloth()
    part = np.arange(36) < 22        # 3 columns of 6 and 4 vertices of the next: 61%, one connected piece
    points[9, part] += [0.0, 1000.0, 0.0]
    # a vertex of the part that also shoots off beyond the glitch is still a blow-up
    points[9, 3] += [0.0, 0.0, 1e5]
    found_blowups, glitches = faults(times, points)
    assert [(b.vertex, b.time_before, b.time_after) for b in found_blowups] == [(3, 8.0, 9.0), (3, 9.0, 10.0)]
    assert len(glitches) == 1 and not glitches[0].whole_mesh
    assert np.array_equal(glitches[0].jumped, part)
    lines = blowups.describe_glitches(glitches, "shot.usd")
    assert lines == [lines[0]] and "part of the mesh (22 of 36 vertices) jumps away and back between time 8 and 10" \
        in lines[0]
    assert len(describe_blowups(found_blowups, "shot.usd")) == 1
    # without the part's own blow-up, the 14 still vertices are named nowhere
    points[9, 3] -= [0.0, 0.0, 1e5]
    assert blowups.shot_blowups([Mesh(times, points)]) == []


@pytest.mark.parametrize("kind", ["deforming", "rigid"])
def test_twenty_sizes_away_warn_and_nine_do_not(kind):
    times, points = waving_cloth()
    size = blowups.mesh_size(points)
    nine, twenty = points.copy(), points.copy()
    nine[12] += [0.0, 9.0 * size, 0.0]
    twenty[12] += [0.0, 20.0 * size, 0.0]
    assert faults(times, nine, kind) == ([], [])
    assert [g.time for g in faults(times, twenty, kind)[1]] == [12.0]


def test_a_jump_held_for_two_samples_is_one_glitch_and_its_neighbours_are_not_named():
    times, points = waving_cloth()
    points[9:11] += [0.0, 0.0, -500.0]
    glitches = faults(times, points)[1]
    assert [(g.time, g.time_last, g.time_before, g.time_after) for g in glitches] == [(9.0, 10.0, 8.0, 11.0)]
    assert "between time 8 and 11 (at times 9 to 10)" in blowups.describe_glitches(glitches, "s.usd")[0]


def test_uneven_samples_weigh_the_line_by_time():
    times, points = waving_cloth()
    times = times ** 1.5                                 # samples further and further apart
    moving = points + 30.0 * times[:, None, None] * [1.0, 0.0, 0.0]   # 30 units per time code
    assert faults(times, moving) == ([], [])
    moving[7] += [0.0, 50.0, 0.0]
    assert [(g.time_before, g.time, g.time_after) for g in faults(times, moving)[1]] == \
        [(times[6], times[7], times[8])]


def test_the_first_and_last_samples_are_not_tested():
    times, points = waving_cloth()
    points[0] += [1000.0, 0.0, 0.0]
    points[-1] -= [1000.0, 0.0, 0.0]
    assert faults(times, points) == ([], [])


def test_honest_fast_rigid_motion_is_no_glitch():
    ball = grid_ball()
    size = np.linalg.norm(ball.max(axis=0) - ball.min(axis=0))
    times = np.arange(48.0)
    # thrown: 50 sizes per frame forward under gravity (24 fps), spinning half a turn per frame
    thrown = np.stack([spin(ball, np.pi * t) + [50.0 * size * t, 20.0 * t - 9.81 / 24 ** 2 * t * t / 2, 0.0]
                       for t in times])
    # bouncing between two walls 3 sizes per frame, turning round exactly at samples, spinning as fast
    phase = times % 16
    x = 3.0 * size * np.where(phase < 8, phase, 16 - phase)
    bouncing = np.stack([spin(ball, np.pi * t) + [x[k], 0.0, 0.0] for k, t in enumerate(times)])
    # running: a body 1.8 high at 8 m/s (24 fps), bobbing and turning half a radian each way
    runner = np.stack([spin(ball * [0.4, 1.8, 0.3], 0.5 * np.sin(t / 3.0), (0, 1, 0))
                       + [8.0 / 24 * t, 0.1 * abs(np.sin(t / 3.0)), 0.0] for t in times])
    for motion in (thrown, bouncing, runner):
        assert faults(times, motion, "rigid") == ([], [])
        assert faults(times, motion, "deforming") == ([], [])


def test_a_fast_swinging_cloth_is_no_glitch():
    """A cloth hanging from a bar swings 80 degrees each way, a full swing in four frames, and ripples."""
    xs, ys = np.meshgrid(np.linspace(-1.0, 1.0, 11), np.linspace(0.0, -2.0, 11), indexing="ij")
    hanging = np.stack([xs.ravel(), ys.ravel(), np.zeros(xs.size)], axis=1)
    times = np.arange(40.0)
    frames = []
    for t in times:
        angle = np.radians(80.0) * np.sin(np.pi * t / 2.0)
        swung = spin(hanging, angle, (1.0, 0.0, 0.0))
        frames.append(swung + 0.2 * np.sin(3.0 * hanging[:, [1, 0, 0]] + t) * [0.0, 0.0, 1.0])
    assert faults(times, np.asarray(frames)) == ([], [])


def _glitches_window_by_window(times, points):
    """The glitch rule (module docstring) on every window and both end samples, without the bounding-box
    bound, one pair of windows at a time, as the reference."""
    size = float(np.median(np.linalg.norm(points.max(axis=1) - points.min(axis=1), axis=1)))
    threshold = blowups.GLITCH_SIZE_FACTOR * size
    last_sample = len(times) - 1

    def common(j, start, end):
        w = (times[j] - times[start]) / (times[end] - times[start])
        return np.linalg.norm(np.median(points[j] - (points[start] + w * (points[end] - points[start])), axis=0))

    windows = [(0, 0, common(0, 1, 2)), (last_sample, last_sample, common(last_sample, last_sample - 2,
                                                                          last_sample - 1))]
    for length in range(1, blowups.GLITCH_MAX_SAMPLES + 1):
        for first in range(1, len(times) - length):
            last = first + length - 1
            windows.append((first, last, min(common(j, first - 1, last + 1) for j in range(first, last + 1))))
    windows = [w for w in windows if w[2] > threshold]
    meet = lambda a, b: a[0] <= b[1] + 1 and b[0] <= a[1] + 1   # noqa: E731
    kept = [w for w in windows if not any(o is not w and meet(w, o) and o[2] > blowups.GLITCH_DOMINANCE * w[2]
                                          for o in windows)]
    taken = []
    for window in sorted(kept, key=lambda w: (w[1] - w[0], -w[2], w[0])):
        if not any(meet(window, other) for other in taken):
            taken.append(window)
    return [(float(times[a]), float(times[b])) for a, b, _ in sorted(taken) if a > 0 and b < last_sample]


def test_the_bounding_box_bound_leaves_out_no_glitch():
    rng = np.random.default_rng(5)
    for trial in range(30):
        times, points = waving_cloth(frames=30)
        times = np.cumsum(rng.uniform(0.5, 2.0, 30))
        threshold = blowups.GLITCH_SIZE_FACTOR * blowups.mesh_size(points)
        for _ in range(3):
            first = int(rng.integers(1, 28))
            held = int(rng.integers(1, 4))
            direction = rng.normal(size=3)
            part = rng.uniform(0.0, 1.0, 36) < rng.uniform(0.4, 1.0)
            jump = direction / np.linalg.norm(direction) * rng.uniform(0.5, 2.5) * threshold
            points[first:first + held, part] += jump
        expected = _glitches_window_by_window(times, points)
        found = blowups.find_glitches("/m", times, points)
        assert [(g.time, g.time_last) for g in found] == expected, trial


def test_glitches_are_named_at_most_five_per_mesh():
    times, points = waving_cloth(frames=40)
    for k in range(3, 37, 4):
        points[k] += [1000.0, 0.0, 0.0]
    glitches = faults(times, points)[1]
    assert len(glitches) == 9
    lines = blowups.describe_glitches(glitches, "shot.usd")
    assert len(lines) == 6 and lines[-1] == "shot.usd: /World/Cloth: 4 more cache glitches (first 5 named)"


# --------------------------------------------------------------------------- glitches in `usdksl check`

CLOTH = "/World/Cloth"
GLITCH_SHIFT = (1000.0, 0.0, 0.0)


def falling_cloth_onto_box(glitch_time=None):
    """fill(stage): a 2 x 2 cloth falling straight down through a unit box, sampled at every frame 1..24;
    at ``glitch_time`` the whole cloth sits GLITCH_SHIFT away."""
    def fill(stage):
        cloth, counts, indices = grid(8, 8, 2.0, 2.0)
        samples = {}
        for t in range(1, 25):
            samples[t] = cloth + [0.0, 3.0 - 4.0 * (t - 1) / 23.0, 0.0]
            if t == glitch_time:
                samples[t] = samples[t] + GLITCH_SHIFT
        define_mesh(stage, CLOTH, None, counts, indices, samples=samples)
        points, counts, indices = box(1.0)
        define_mesh(stage, "/World/Box", points, counts, indices)
    return fill


@pytest.mark.parametrize("glitch_time", [6, 18])   # above the box, and while the cloth passes through it
def test_check_names_a_glitched_cloth_and_keeps_every_contact_it_does_not_touch(build, check, glitch_time):
    reference, reference_contacts, _ = check(build("clean.usda", falling_cloth_onto_box()))
    result, contacts, _ = check(build("glitched.usda", falling_cloth_onto_box(glitch_time)))
    assert reference.exit_code == result.exit_code == 1, result.stderr
    glitch_lines = [line for line in result.stderr.splitlines() if "glitch" in line]
    assert len(glitch_lines) == 1, result.stderr
    assert CLOTH in glitch_lines[0] and "the whole mesh jumps away and back" in glitch_lines[0]
    assert f"between time {glitch_time - 1} and {glitch_time + 1} (at time {glitch_time})" in glitch_lines[0]
    assert "blows up" not in result.stderr and "glitch" not in reference.stderr
    assert reference_contacts
    if glitch_time == 6:   # the cloth jumps sideways above the box: it touches nothing on the way
        assert contacts == reference_contacts
    else:                  # every face pair that touched before the glitch, at the same time
        before = {pair: time for pair, time in reference_contacts.items() if time < glitch_time - 1}
        assert before and before == {pair: time for pair, time in contacts.items() if time < glitch_time - 1}


def test_strict_refuses_a_glitched_cache_with_one_line_and_writes_nothing(build, check, tmp_path):
    result, contacts, summary = check(build("glitched.usda", falling_cloth_onto_box(6)), "--strict")
    assert result.exit_code == 2
    errors = [line for line in result.stderr.splitlines() if line.startswith("usdksl: error:")]
    assert len(errors) == 1 and CLOTH in errors[0] and "cache glitch" in errors[0] and "time 6" in errors[0]
    assert contacts is None and summary is None


def test_glitch_and_blowup_messages_carry_their_kinds(build):
    def fill(stage):
        falling_cloth_onto_box(6)(stage)
        attribute = UsdGeom.Mesh(stage.GetPrimAtPath(CLOTH)).GetPointsAttr()
        value = np.array(attribute.Get(12.0), dtype=np.float64)
        value[40] += [0.0, 1e5, 0.0]
        attribute.Set(Vt.Vec3fArray.FromNumpy(value.astype(np.float32)), 12.0)

    result = check_shot(build("both.usda", fill))
    kinds = {message.kind for message in result.messages if "glitch" in message.text or "blows up" in message.text}
    assert kinds == {BLOW_UP, CACHE_GLITCH}
    assert [m.kind for m in result.messages if "blows up" in m.text] == [BLOW_UP]


def test_the_native_motion_summary_equals_numpy_on_float_and_double_points():
    from usdksl import _native
    rng = np.random.default_rng(7)
    for points in (rng.normal(size=(30, 200, 3)) * 10.0 ** rng.integers(-6, 6, size=(30, 1, 1)),
                   rng.normal(size=(25, 99, 3)).astype(np.float32),
                   rng.normal(size=(25, 99, 3)).astype(np.float32)[:, ::2]):   # strided: read as doubles
        doubles = points.astype(np.float64)
        steps = doubles[1:] - doubles[:-1]
        lengths = np.sqrt((steps * steps).sum(axis=2).max(axis=1))
        # the sums of three squares may round differently: a few ulps, far inside EXCESS_BOUND_FACTOR's margin
        np.testing.assert_allclose(_native.longest_steps(points), lengths, rtol=4 * np.finfo(float).eps, atol=0)
        lowest, highest = _native.sample_boxes(points)
        assert np.array_equal(lowest, doubles.min(axis=1)) and np.array_equal(highest, doubles.max(axis=1))
    # integer coordinates: every sum is exact, so the lengths are
    whole = rng.integers(-1000, 1000, size=(12, 40, 3)).astype(np.float32)
    exact = np.sqrt(np.max(np.sum((whole[1:].astype(np.int64) - whole[:-1].astype(np.int64)) ** 2, axis=2), axis=1))
    assert np.array_equal(_native.longest_steps(whole), exact)
