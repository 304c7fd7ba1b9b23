"""Reported first-contact times are exact on the raw samples (docs/contracts.md, Contacts).

The contract: a reported time is the first instant at which two faces come
within the thickness on the piecewise-linear trajectories through the
authored samples, to the CCD tolerance (a fraction of one sample interval),
never later. Merged flightplans and their slack may find candidates; they must
neither move a time earlier nor turn a near miss into a contact.

Every answer here is known in closed form on the sample polyline.
"""

import numpy as np
import pytest

from usdksl.checking.collision import find_contacts

from builders import animated

#: Default CCD tolerance (fraction of one sample interval); intervals here are 1 time code.
TOLERANCE = 1e-6
#: Coordinates are multiplied by these: metres, centimetres, kilometres.
UNIT_SCALES = (1.0, 100.0, 1e-3)
#: Times across scalings must agree to this relative precision.
CROSS_SCALE_RELATIVE = 1e-9
#: Tolerance for the cross-scale comparison: fine enough that any two
#: conservative answers within it agree to CROSS_SCALE_RELATIVE.
CROSS_SCALE_TOLERANCE = 1e-11


def sheet(half_width=3.0, y=0.0, samples=None):
    """A static square (two triangles) in the plane y = `y`, centred on the origin."""
    w = half_width
    verts = np.array([[-w, y, -w], [w, y, -w], [w, y, w], [-w, y, w]], dtype=float)
    tris = np.array([[0, 1, 2], [0, 2, 3]], dtype=np.int32)
    times = [0.0] if samples is None else samples
    return animated(times, [verts] * len(times), tris, faces=[0, 0])


def tip_down_triangle(tip):
    """A triangle with its lowest corner at `tip`, the other two 0.5 higher."""
    tip = np.asarray(tip, dtype=float)
    return np.stack([tip, tip + [0.3, 0.5, 0.0], tip + [-0.3, 0.5, 0.1]])


def scaled(meshes, factor):
    return [animated(m.times, m.points * factor, m.triangles, m.triangle_face) for m in meshes]


def first_contact(meshes, pairs, method="ksl", tolerance=TOLERANCE, thickness=0.0):
    result = find_contacts(meshes, pairs, method=method, tolerance=tolerance, thickness=thickness)
    return result


def grazing_shot():
    """The tip follows a parabola sampled every frame and touches y = 0 at sample 10 only.

    Also swings in x and z on a circle, so the path is curved in every axis.
    """
    times = np.arange(0.0, 21.0)
    frames = []
    for t in times:
        angle = 0.3 * (t - 10.0)
        tip = [0.8 * np.sin(angle), 0.01 * (t - 10.0) ** 2, 0.8 * (1.0 - np.cos(angle))]
        frames.append(tip_down_triangle(tip))
    mover = animated(times, frames, [[0, 1, 2]])
    return [sheet(), mover], 10.0


@pytest.mark.parametrize("method", ["ksl", "swept", "brute"])
def test_grazing_contact_is_reported_at_the_touching_instant(method):
    meshes, touch = grazing_shot()
    result = first_contact(meshes, [(0, 1)], method=method)
    assert len(result) >= 1
    first = float(result.time.min())
    assert first <= touch
    assert first >= touch - TOLERANCE


def resting_shot(thickness, far_offset=0.0):
    """A triangle descends linearly and then rests with its tip exactly `thickness` above the sheet.

    The descent reaches the resting height at sample 12 and stays there for 60 frames; the descent
    samples lie on one straight line, so flightplans merge them. ``far_offset`` moves the whole shot
    away from the origin (large coordinates make merging looser).
    """
    times = np.arange(0.0, 73.0)
    rest_at = 12.0
    frames = []
    for t in times:
        height = thickness + 0.05 * max(rest_at - t, 0.0)
        frames.append(tip_down_triangle([0.2 + far_offset, height, 0.1]))
    mover = animated(times, frames, [[0, 1, 2]])
    base = sheet(samples=None)
    base = animated(base.times, base.points + [far_offset, 0.0, 0.0], base.triangles, base.triangle_face)
    return [base, mover], rest_at


@pytest.mark.parametrize("method", ["ksl", "swept", "brute"])
def test_resting_contact_starts_when_the_gap_first_equals_the_thickness(method):
    thickness = 0.01
    meshes, rest_at = resting_shot(thickness)
    result = first_contact(meshes, [(0, 1)], method=method, thickness=thickness)
    assert len(result) >= 1
    first = float(result.time.min())
    assert rest_at - TOLERANCE <= first <= rest_at


def hovering_shot(gap, wobble, far_offset):
    """A triangle hovers `gap` above a sheet far from the origin, wobbling by `wobble` on a
    nearly straight path: close enough to straight for flightplans to merge it with slack,
    never closer to the sheet than `gap`."""
    times = np.arange(0.0, 41.0)
    frames = []
    for t in times:
        # A slow straight glide plus a tiny zig-zag: every other sample off the line.
        zig = wobble * (t % 2.0)
        frames.append(tip_down_triangle([far_offset + 0.01 * t, gap + zig, 0.1]))
    mover = animated(times, frames, [[0, 1, 2]])
    base = sheet(half_width=3.0)
    base = animated(base.times, base.points + [far_offset, 0.0, 0.0], base.triangles, base.triangle_face)
    return [base, mover]


def test_a_near_miss_inside_the_merge_slack_is_not_reported():
    # Far from the origin, float32-level merging accepts deviations of about 2^-22 * 1e4 = 2.4e-3.
    far = 1e4
    meshes = hovering_shot(gap=2e-3, wobble=1e-3, far_offset=far)
    result = find_contacts(meshes, [(0, 1)], method="ksl", tolerance=TOLERANCE)
    assert result.counters["raw_confirmations"] > 0, "the shot must exercise merged flightplans with slack"
    assert len(result) == 0, f"reported a pair that never comes within the thickness: {result.time}"
    reference = find_contacts(meshes, [(0, 1)], method="brute", tolerance=TOLERANCE)
    assert len(reference) == 0


def test_merge_slack_of_one_mesh_does_not_make_another_pair_early():
    # Pair A rests exactly at the thickness from frame 12 on; a far-away pair B wobbles inside its
    # merge slack. A's reported time must be its own exact time.
    thickness = 0.01
    resting, rest_at = resting_shot(thickness)
    hovering = hovering_shot(gap=2e-3, wobble=1e-3, far_offset=1e4)
    meshes = resting + hovering
    result = find_contacts(meshes, [(0, 1), (2, 3)], method="ksl", tolerance=TOLERANCE, thickness=thickness)
    pair_a = result.time[(result.mesh_a == 0) & (result.mesh_b == 1)]
    assert pair_a.size >= 1
    assert rest_at - TOLERANCE <= float(pair_a.min()) <= rest_at


def rotating_blade_shot():
    """A rigid triangle (a blade) rotates about the z axis at height 1; its tip sweeps down
    through a sheet at y = 0. Sampled every frame, so its vertices move on a polygon
    inscribed in a circle. Returns the meshes and the closed-form first touch on that polygon."""
    times = np.arange(0.0, 31.0)
    omega = 0.1  # radians per time code
    hub_height, radius = 1.0, 1.5
    local = np.array([[radius, 0.0, 0.05], [0.2, 0.0, -0.2], [0.2, 0.0, 0.3]])
    frames = []
    for t in times:
        angle = -omega * t  # clockwise: the tip descends from the +x axis
        c, s = np.cos(angle), np.sin(angle)
        rotation = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
        frames.append(local @ rotation.T + [0.0, hub_height, 0.0])
    frames = np.asarray(frames)
    blade = animated(times, frames, [[0, 1, 2]])
    # Only the tip ever reaches y = 0: on the chord between the last sample above and the first below.
    tip_height = frames[:, 0, 1]
    k = int(np.argmax(tip_height <= 0.0))
    touch = times[k - 1] + tip_height[k - 1] / (tip_height[k - 1] - tip_height[k])
    return [sheet(), blade], float(touch)


@pytest.mark.parametrize("method", ["ksl", "swept", "brute"])
def test_rotating_blade_touches_the_sheet_on_its_sampled_polygon(method):
    meshes, touch = rotating_blade_shot()
    result = first_contact(meshes, [(0, 1)], method=method)
    assert len(result) >= 1
    first = float(result.time.min())
    assert touch - TOLERANCE <= first <= touch


SHOTS = {
    "grazing": lambda: (grazing_shot()[0], 0.0),
    "resting": lambda: (resting_shot(0.01)[0], 0.01),
    "rotating": lambda: (rotating_blade_shot()[0], 0.0),
}


@pytest.mark.parametrize("name", sorted(SHOTS))
def test_times_do_not_depend_on_the_unit(name):
    meshes, thickness = SHOTS[name]()
    answers = []
    for factor in UNIT_SCALES:
        result = find_contacts(scaled(meshes, factor), [(0, 1)], method="ksl", tolerance=CROSS_SCALE_TOLERANCE,
                               thickness=thickness * factor)
        answers.append(float(result.time.min()) if len(result) else None)
    assert None not in answers, f"a scaling lost the contact: {answers}"
    for answer in answers[1:]:
        assert answer == pytest.approx(answers[0], rel=CROSS_SCALE_RELATIVE)


def per_frame_cloth(n=8, frames=40):
    """A cloth sampled at every frame: it waves on curves, sinks onto a static slab and folds its
    right half over its left, so it has cloth-slab contacts and self contacts."""
    xs, zs = np.meshgrid(np.linspace(0.0, 1.0, n + 1), np.linspace(0.0, 1.0, n + 1), indexing="ij")
    rest = np.stack([xs.ravel(), np.zeros(xs.size), zs.ravel()], axis=1)
    idx = np.arange((n + 1) ** 2).reshape(n + 1, n + 1)
    a, b, c, d = idx[:-1, :-1].ravel(), idx[1:, :-1].ravel(), idx[1:, 1:].ravel(), idx[:-1, 1:].ravel()
    tris = np.concatenate([np.stack([a, b, c], 1), np.stack([a, c, d], 1)]).astype(np.int32)
    quads = np.concatenate([np.arange(n * n), np.arange(n * n)]).astype(np.int32)
    times = np.arange(0.0, float(frames))
    samples = []
    for t in times:
        p = rest.copy()
        p[:, 1] = 0.35 - 0.012 * t + 0.04 * np.sin(3.0 * p[:, 0] + 0.4 * t) * np.cos(2.0 * p[:, 2] + 0.3 * t)
        fold = 1.15 * np.pi * min(t / (frames - 8.0), 1.0) ** 2
        right = rest[:, 0] > 0.5
        dx = rest[right, 0] - 0.5
        p[right, 0] = 0.5 + dx * np.cos(fold)
        p[right, 1] += dx * np.sin(fold) + 0.03 * dx
        samples.append(p)
    cloth = animated(times, samples, tris, quads)
    slab = sheet(half_width=0.4, y=0.0)
    slab = animated(slab.times, slab.points + [0.5, 0.0, 0.5], slab.triangles, slab.triangle_face)
    return [cloth, slab]


def face_pairs(result, meshes):
    faces = result.face_contacts(meshes)
    return {(int(ma), int(fa), int(mb), int(fb)): float(t)
            for t, ma, fa, mb, fb in zip(faces.time, faces.mesh_a, faces.face_a, faces.mesh_b, faces.face_b)}


#: Tolerance of the brute-force reference (fraction of a sample interval).
REFERENCE_TOLERANCE = 1e-9
#: Reported times must match the reference within this many time codes.
REFERENCE_TIME_SLACK = 1e-6


def test_check_equals_a_tight_brute_force_reference_on_a_per_frame_cloth():
    meshes = per_frame_cloth()
    pairs = [(0, 0), (0, 1)]
    reference = face_pairs(find_contacts(meshes, pairs, method="brute", tolerance=REFERENCE_TOLERANCE), meshes)
    found = face_pairs(find_contacts(meshes, pairs, method="ksl"), meshes)
    assert any(key[0] == key[2] for key in reference), "the cloth must touch itself"
    assert any(key[0] != key[2] for key in reference), "the cloth must touch the slab"
    assert set(found) == set(reference), (sorted(set(reference) - set(found))[:5], sorted(set(found) - set(reference))[:5])
    worst = max(abs(found[key] - reference[key]) for key in reference)
    assert worst <= REFERENCE_TIME_SLACK, worst


def triangle_pair_times(result):
    return {(int(ma), int(ta), int(mb), int(tb)): float(t)
            for t, ma, ta, mb, tb in zip(result.time, result.mesh_a, result.tri_a, result.mesh_b, result.tri_b)}


@pytest.mark.parametrize("shot", ["per-frame cloth", "resting", "rotating"])
def test_every_continuous_method_reports_bit_identical_times(shot):
    # Every reported time is computed on the same raw sample interval with the pair the same way
    # round, whatever method found the candidate: the answers are equal, not merely close.
    meshes, pairs, thickness = {
        "per-frame cloth": lambda: (per_frame_cloth(), [(0, 0), (0, 1)], 0.0),
        "resting": lambda: (resting_shot(0.01)[0], [(0, 1)], 0.01),
        "rotating": lambda: (rotating_blade_shot()[0], [(0, 1)], 0.0),
    }[shot]()
    answers = {method: triangle_pair_times(find_contacts(meshes, pairs, method=method, thickness=thickness))
               for method in ("brute", "ksl", "swept")}
    assert answers["brute"], "the shot must have contacts"
    assert answers["ksl"] == answers["brute"]
    assert answers["swept"] == answers["brute"]


def hover_then_touch_shot(gap):
    """A triangle descends, hovers `gap` above a 6-unit sheet from frame 5 to frame 29 (drifting
    sideways so every sample differs), and touches it at frame 30 exactly."""
    times = np.arange(0.0, 36.0)
    frames = []
    for t in times:
        height = 0.2 * (5.0 - t) + gap if t < 5.0 else (gap if t < 30.0 else 0.0)
        frames.append(tip_down_triangle([0.01 * t, height, 0.2]))
    return [sheet(), animated(times, frames, [[0, 1, 2]])], 30.0


@pytest.mark.parametrize("method", ["ksl", "swept", "brute"])
def test_a_long_near_approach_is_not_the_first_touch(method):
    # At the default tolerance the search cannot tell a gap of 1e-7 on a 6-unit sheet from contact;
    # the confirming search can, so the reported time is the touch at frame 30, not frame 5.
    meshes, touch = hover_then_touch_shot(gap=1e-7)
    result = find_contacts(meshes, [(0, 1)], method=method)
    assert len(result) >= 1
    first = float(result.time.min())
    assert touch - TOLERANCE <= first <= touch
