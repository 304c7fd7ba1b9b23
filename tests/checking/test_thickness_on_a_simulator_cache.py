"""At a thickness above 0 on the third-party Newton twist, reported contacts are within it by Euclidean
distance, computed independently with ipctk (docs/contracts.md, Contacts).

A per-axis measure (Tight-Inclusion's box) would put this shot's first contact at 0.01 on frame 31.7,
33 frames before the sheet comes within 0.01 of itself by any frame's distance.
"""

import math
import sys
from pathlib import Path

import numpy as np
import pytest

ipctk = pytest.importorskip("ipctk")
# The thickness benchmark's independent distance check (ipctk's point-triangle and segment-segment).
sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "benchmarks"))
from thickness import triangle_pair_distance  # noqa: E402

#: Reported pairs whose distance at their time is checked.
SAMPLED_PAIRS = 40
#: A reported time is the start of a time box of the search's tolerance; over it the sheet moves by
#: far less than this fraction of the thickness.
RELATIVE_SLACK = 1e-6


def sheet_distance_at_frames(mesh, reach):
    """ipctk's minimum distance over the sheet at each sample (adjacent primitives excluded), where
    it is below `reach`; infinite elsewhere."""
    triangles = mesh.triangles.astype(np.int32)
    collision_mesh = ipctk.CollisionMesh(mesh.points[0].astype(float), ipctk.edges(triangles), triangles)
    distances = []
    for points in mesh.points:
        collisions = ipctk.NormalCollisions()
        collisions.build(collision_mesh, points.astype(float), reach)
        distances.append(math.sqrt(collisions.compute_minimum_distance(collision_mesh, points.astype(float)))
                         if len(collisions) else math.inf)
    return np.array(distances)


def test_reported_pairs_are_within_the_thickness_at_their_time(newton_twist_within_1cm):
    twist = newton_twist_within_1cm
    mesh, result, thickness = twist.mesh, twist.result, twist.thickness
    assert len(result) > 10000 and not result.undecided.any()
    rng = np.random.default_rng(19)
    for i in rng.choice(len(result), size=SAMPLED_PAIRS, replace=False):
        time, tri_a, tri_b = float(result.time[i]), int(result.tri_a[i]), int(result.tri_b[i])
        distance = triangle_pair_distance(mesh, tri_a, mesh, tri_b, time, same_mesh=True)
        assert distance <= thickness * (1.0 + RELATIVE_SLACK), (time, tri_a, tri_b)


def test_the_first_contact_is_where_the_sheet_first_comes_within_the_thickness(newton_twist_within_1cm):
    twist = newton_twist_within_1cm
    mesh, result, thickness = twist.mesh, twist.result, twist.thickness
    first = float(result.time.min())
    by_frame = sheet_distance_at_frames(mesh, 2 * thickness)
    within = np.flatnonzero(by_frame <= thickness)
    assert within.size, "the sheet must come within the thickness"
    # Never later than the first sample where ipctk finds the sheet within it.
    assert first <= mesh.times[within[0]]
    i = int(np.argmin(result.time))
    distance = triangle_pair_distance(mesh, int(result.tri_a[i]), mesh, int(result.tri_b[i]), first, same_mesh=True)
    assert distance <= thickness * (1.0 + RELATIVE_SLACK)
