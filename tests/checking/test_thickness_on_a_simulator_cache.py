"""At a thickness above 0 on the third-party Newton twist, reported contacts are within it by Euclidean
distance, computed independently with ipctk (issue 14, session 19).

The per-axis measure the narrow phase used before put this shot's first contact at 0.01 on frame 31.7,
33 frames before the sheet comes within 0.01 of itself by any frame's distance.
"""

import math

import numpy as np
import pytest

from usdksl import load_shot
from usdksl.checking.collision import find_contacts

ipctk = pytest.importorskip("ipctk")

THICKNESS = 0.01
#: Reported pairs whose distance at their time is checked.
SAMPLED_PAIRS = 40
#: A reported time is the start of a time box of the search's tolerance; over it the sheet moves by
#: far less than this fraction of the thickness.
RELATIVE_SLACK = 1e-6


@pytest.fixture(scope="module")
def twist(newton_twist_path):
    mesh = load_shot(newton_twist_path).meshes[0]
    return mesh, find_contacts([mesh], [(0, 0)], thickness=THICKNESS)


def positions(mesh, time):
    j = min(max(int(np.searchsorted(mesh.times, time, side="right")) - 1, 0), len(mesh.times) - 2)
    a = (time - mesh.times[j]) / (mesh.times[j + 1] - mesh.times[j])
    return (1.0 - a) * mesh.points[j].astype(float) + a * mesh.points[j + 1].astype(float)


def triangle_pair_distance(mesh, points, tri_a, tri_b):
    """Euclidean distance between two triangles of one mesh over their primitive pairs that share no vertex."""
    ia, ib = mesh.triangles[tri_a], mesh.triangles[tri_b]
    a, b = points[ia], points[ib]
    best = math.inf
    for i in range(3):
        if ia[i] not in ib:
            best = min(best, ipctk.point_triangle_distance(a[i], *b))
        if ib[i] not in ia:
            best = min(best, ipctk.point_triangle_distance(b[i], *a))
        for j in range(3):
            if {ia[i], ia[(i + 1) % 3]} & {ib[j], ib[(j + 1) % 3]}:
                continue
            best = min(best, ipctk.edge_edge_distance(a[i], a[(i + 1) % 3], b[j], b[(j + 1) % 3]))
    return math.sqrt(best)


def sheet_distance_at_frames(mesh):
    """ipctk's minimum distance over the sheet at each sample (adjacent primitives excluded)."""
    triangles = mesh.triangles.astype(np.int32)
    collision_mesh = ipctk.CollisionMesh(mesh.points[0].astype(float), ipctk.edges(triangles), triangles)
    distances = []
    for points in mesh.points:
        collisions = ipctk.NormalCollisions()
        collisions.build(collision_mesh, points.astype(float), 2 * THICKNESS)
        distances.append(math.sqrt(collisions.compute_minimum_distance(collision_mesh, points.astype(float)))
                         if len(collisions) else math.inf)
    return np.array(distances)


def test_reported_pairs_are_within_the_thickness_at_their_time(twist):
    mesh, result = twist
    assert len(result) > 10000 and not result.undecided.any()
    rng = np.random.default_rng(19)
    for i in rng.choice(len(result), size=SAMPLED_PAIRS, replace=False):
        time = float(result.time[i])
        distance = triangle_pair_distance(mesh, positions(mesh, time), int(result.tri_a[i]), int(result.tri_b[i]))
        assert distance <= THICKNESS * (1.0 + RELATIVE_SLACK), (time, int(result.tri_a[i]), int(result.tri_b[i]))


def test_the_first_contact_is_where_the_sheet_first_comes_within_the_thickness(twist):
    mesh, result = twist
    first = float(result.time.min())
    by_frame = sheet_distance_at_frames(mesh)
    within = np.flatnonzero(by_frame <= THICKNESS)
    assert within.size, "the sheet must come within the thickness"
    # Never later than the first sample where ipctk finds the sheet within it.
    assert first <= mesh.times[within[0]]
    i = int(np.argmin(result.time))
    distance = triangle_pair_distance(mesh, positions(mesh, first), int(result.tri_a[i]), int(result.tri_b[i]))
    assert distance <= THICKNESS * (1.0 + RELATIVE_SLACK)
