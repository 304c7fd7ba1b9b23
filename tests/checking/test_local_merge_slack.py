"""Merge slack is local to a triangle's own vertices: a pair is tested at the thickness plus the merge
deviation of its six vertices, not of the whole mesh. Both halves of that claim are checked against brute
force on the raw samples: a triangle whose merged flightplan hides a touch still finds it through its own
slack, and a triangle of the same mesh whose vertices merged nothing gets its own exact time."""

import numpy as np

from usdksl.checking.collision import find_contacts

from builders import animated

TOLERANCE = 1e-6
#: Far from the origin, float32-level merging (2^-22 relative) accepts deviations up to about 2.4e-3.
FAR = 1e4
GAP = 1e-3


def two_triangle_mover():
    """One mesh, two tip-down triangles gliding over a sheet far from the origin. Triangle 0 zig-zags:
    its tip hovers GAP above the sheet, touching it at every other sample (a detour of GAP off the
    straight path, which merging drops, so the merged flightplan never touches). Triangle 1, 2 units
    away, sinks on a straight path and meets the sheet at time 10.5 (its vertices merge at most
    rounding-level deviations, a million times less than triangle 0's)."""
    times = np.arange(0.0, 21.0)
    frames = []
    for t in times:
        zig_tip = [FAR + 0.01 * t, GAP * (1.0 - t % 2.0), 0.1]
        straight_tip = [FAR + 2.0 + 0.01 * t, 0.21 - 0.02 * t, 0.1]
        triangles = []
        for tip in (zig_tip, straight_tip):
            tip = np.asarray(tip)
            triangles += [tip, tip + [0.3, 0.5, 0.0], tip + [-0.3, 0.5, 0.1]]
        frames.append(np.asarray(triangles))
    mover = animated(times, frames, [[0, 1, 2], [3, 4, 5]], faces=[0, 1])
    w = 3.0
    verts = np.array([[-w, 0.0, -w], [w, 0.0, -w], [w, 0.0, w], [-w, 0.0, w]]) + [FAR + 1.0, 0.0, 0.0]
    base = animated([0.0], [verts], np.array([[0, 1, 2], [0, 2, 3]], dtype=np.int32), faces=[0, 0])
    return [base, mover]


def first_time_per_face(result, meshes):
    faces = result.face_contacts(meshes)
    return {(int(a), int(fa), int(b), int(fb)): float(t)
            for t, a, fa, b, fb in zip(faces.time, faces.mesh_a, faces.face_a, faces.mesh_b, faces.face_b)}


def test_each_triangle_of_a_merged_mesh_gets_brute_force_s_answer():
    meshes = two_triangle_mover()
    ksl = find_contacts(meshes, [(0, 1)], method="ksl", tolerance=TOLERANCE)
    brute = find_contacts(meshes, [(0, 1)], method="brute", tolerance=TOLERANCE)
    assert ksl.counters["raw_confirmations"] > 0
    found, reference = first_time_per_face(ksl, meshes), first_time_per_face(brute, meshes)
    # The zig-zagging face touches at sample 1 (on the raw samples only); the straight one at 10.5.
    assert {key[3] for key in reference} == {0, 1}
    assert 1.0 - 2 * TOLERANCE <= min(t for key, t in reference.items() if key[3] == 0) <= 1.0
    assert set(found) == set(reference), "a face pair brute force reports is missing, or one is extra"
    for key, t in reference.items():
        assert t - 2 * TOLERANCE <= found[key] <= t, (key, found[key], t)
    straight = min(t for key, t in found.items() if key[3] == 1)
    assert 10.5 - 2 * TOLERANCE <= straight <= 10.5
