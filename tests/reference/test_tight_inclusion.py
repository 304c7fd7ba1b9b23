"""The ipctk reference (tests/reference/tight_inclusion.py) on shots whose answers are known by hand: it is
what the whole-shot tests hold the product to, so it is checked without the product."""

import math

import numpy as np
import pytest

from builders import animated

pytest.importorskip("ipctk")
from reference.tight_inclusion import (  # noqa: E402
    EDGE_EDGE, FACE_VERTEX, INITIAL, MAY_MARGIN, REFERENCE_LATE_SLACK, SEPARATION_TOLERANCE, ReferenceContacts,
    disagreements, first_contacts)

#: A still triangle in the plane z = 0 (mesh 0).
FLOOR = animated([0.0, 1.0], [[[0, 0, 0], [2, 0, 0], [0, 2, 0.0]]] * 2, [[0, 1, 2]])
#: Largest distance (time codes) of Tight-Inclusion's time from the exact one on these unit-speed shots.
EXACT = 1e-9


def falling_spike(drop=2.0):
    """A triangle whose lowest vertex (0.5, 0.5) falls from z = 1 by ``drop`` over [0, 1]; its other
    vertices stay outside the floor's footprint and above it."""
    start = np.array([[0.5, 0.5, 1.0], [0.5, 3.0, 2.0], [3.0, 0.5, 2.0]])
    return animated([0.0, 1.0], [start, start - [0, 0, drop]], [[0, 1, 2]])


def crossing_edges(heights=(-0.5, 0.5), times=(0.0, 1.0)):
    """Two triangles in perpendicular planes whose edges cross at the origin when the second, rising from
    z = heights[0] to heights[1], has its top edge at z = 0: an edge-edge contact that no vertex makes."""
    upright = animated(times, [[[-1, 0, 0], [1, 0, 0], [0, 0, 1.0]]] * 2, [[0, 1, 2]])
    across = [[[0, -1, h], [0, 1, h], [0, 0, h - 1.0]] for h in heights]
    return upright, animated(times, across, [[0, 1, 2]])


def test_a_vertex_through_a_face_touches_when_it_reaches_the_plane():
    found = first_contacts([FLOOR, falling_spike()], [(0, 1)])
    assert set(found.must) == set(found.may) == {(0, 0, 1, 0)}
    assert found.must[(0, 0, 1, 0)] == pytest.approx(0.5, abs=EXACT)
    assert found.must[(0, 0, 1, 0)] <= 0.5  # never late
    assert found.feature[(0, 0, 1, 0)] == FACE_VERTEX  # a vertex of the key's second face


def test_edges_crossing_without_a_vertex_touch_are_an_edge_edge_contact():
    found = first_contacts(list(crossing_edges()), [(0, 1)])
    assert set(found.must) == {(0, 0, 1, 0)}
    assert found.must[(0, 0, 1, 0)] == pytest.approx(0.5, abs=EXACT)
    assert found.feature[(0, 0, 1, 0)] == EDGE_EDGE


def test_faces_already_crossing_at_the_start_of_the_range_touch_then():
    # From 0.75 on the edges have crossed: the rising edge pierces the upright face, which no vertex-face
    # or edge-edge query sees.
    found = first_contacts(list(crossing_edges()), [(0, 1)], time_range=(0.75, 1.0))
    assert found.must == {(0, 0, 1, 0): 0.75}
    assert found.feature[(0, 0, 1, 0)] == INITIAL


def test_a_vertex_shared_within_a_mesh_is_never_a_contact_but_one_between_meshes_is():
    points = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [-1, 0, 1.0]]
    hinge = animated([0.0, 1.0], [points, points], [[0, 1, 2], [0, 3, 4]])
    assert not first_contacts([hinge], [(0, 0)]).may
    first = animated([0.0, 1.0], [points[:3]] * 2, [[0, 1, 2]])
    second = animated([0.0, 1.0], [[points[0], points[3], points[4]]] * 2, [[0, 1, 2]])
    assert first_contacts([first, second], [(0, 1)]).must == {(0, 0, 1, 0): 0.0}


def test_two_triangles_of_one_authored_face_never_touch():
    # A quad folded along its diagonal onto itself: its two triangles cross.
    flat = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0.0]])
    folded = flat.copy()
    folded[1] = [0, 1, 0.0]
    one_face = animated([0.0, 1.0], [flat, folded], [[0, 1, 2], [0, 2, 3]], faces=[0, 0])
    assert not first_contacts([one_face], [(0, 0)]).may
    two_faces = animated([0.0, 1.0], [flat, folded], [[0, 1, 2], [0, 2, 3]], faces=[0, 1])
    assert set(first_contacts([two_faces], [(0, 0)]).must) == {(0, 0, 0, 1)}


def test_triangles_of_one_face_are_one_face_pair_at_the_earliest_time():
    # The spike as two triangles of one authored face, the second reaching the floor later.
    start = np.array([[0.5, 0.5, 1.0], [0.5, 3.0, 2.0], [3.0, 0.5, 2.0], [1.0, 0.2, 1.5]])
    spike = animated([0.0, 1.0], [start, start - [0, 0, 2.0]], [[1, 3, 2], [0, 1, 2]], faces=[4, 4])
    found = first_contacts([FLOOR, spike], [(0, 1)])
    assert set(found.must) == {(0, 0, 1, 4)}
    assert found.must[(0, 0, 1, 4)] == pytest.approx(0.5, abs=EXACT)


def test_a_thickness_brackets_the_euclidean_contact_between_may_and_must():
    # The spike's vertex falls straight onto the floor at 2 units per time code from 1 above it: within
    # thickness h of it at t = (1 - h) / 2.
    thickness = 0.1
    found = first_contacts([FLOOR, falling_spike()], [(0, 1)], thickness=thickness)
    exact = (1.0 - thickness) / 2.0
    assert found.may[(0, 0, 1, 0)] <= exact <= found.must[(0, 0, 1, 0)]
    # must's box lies inside the ball, so its gap is below h / sqrt(3) (minus its tolerance)
    assert found.must[(0, 0, 1, 0)] >= (1.0 - thickness / math.sqrt(3.0)) / 2.0
    # early by at most the time the vertex takes to close the tolerance (a share of the separation)
    assert found.may[(0, 0, 1, 0)] >= exact - SEPARATION_TOLERANCE * (thickness + MAY_MARGIN) / 2.0


def test_a_range_of_one_instant_tests_the_pair_held_still():
    upright, across = crossing_edges(heights=(0.25, 0.25))
    assert first_contacts([upright, across], [(0, 1)], time_range=(0.5, 0.5)).must == {(0, 0, 1, 0): 0.5}


def test_each_pair_steps_on_its_own_samples_and_holds_still_outside_them():
    # The spike's samples are at 10 and 11 only; the floor is sampled over a longer span.
    start = np.array([[0.5, 0.5, 1.0], [0.5, 3.0, 2.0], [3.0, 0.5, 2.0]])
    spike = animated([10.0, 11.0], [start, start - [0, 0, 2.0]], [[0, 1, 2]])
    floor = animated([0.0, 20.0], [FLOOR.points[0]] * 2, [[0, 1, 2]])
    found = first_contacts([floor, spike], [(0, 1)])
    assert found.must[(0, 0, 1, 0)] == pytest.approx(10.5, abs=EXACT)
    assert found.must_step[(0, 0, 1, 0)] == 1.0


def reference_with(must=None, may=None, step=1.0, late_slack=0.0):
    must = must or {}
    may = may if may is not None else dict(must)
    return ReferenceContacts(must=must, must_step={k: step for k in must}, may=may,
                             may_step={k: step for k in may}, late_slack=late_slack)


def test_disagreements_name_what_is_missed_late_extra_and_early():
    key, other = (0, 1, 1, 2), (0, 3, 1, 4)
    reference = reference_with(must={key: 5.0})
    assert disagreements(reference, {key: (5.0, 0)}, 1e-6) == []
    assert disagreements(reference, {}, 1e-6)[0].startswith("missed")
    assert disagreements(reference, {key: (5.001, 0)}, 1e-6)[0].startswith("late")
    assert disagreements(reference, {key: (5.0, 0), other: (6.0, 0)}, 1e-6)[0].startswith("extra")
    assert disagreements(reference, {key: (5.0 - 2e-6, 0)}, 1e-6)[0].startswith("early")
    assert disagreements(reference, {key: (5.0 - 0.9e-6, 0)}, 1e-6) == []  # early within the tolerance


def test_at_thickness_0_the_product_may_be_late_by_the_reference_s_slack_only():
    key = (0, 1, 1, 2)
    reference = reference_with(must={key: 5.0}, step=2.0, late_slack=REFERENCE_LATE_SLACK)
    assert disagreements(reference, {key: (5.0 + 0.9 * REFERENCE_LATE_SLACK * 2.0, 0)}, 1e-6) == []
    assert disagreements(reference, {key: (5.0 + 1.1 * REFERENCE_LATE_SLACK * 2.0, 0)}, 1e-6)
    # a pair that only may touch (the product decides a graze to its tolerance) may be reported or not
    graze = reference_with(may={key: 5.0})
    assert disagreements(graze, {}, 1e-6) == [] and disagreements(graze, {key: (5.0, 0)}, 1e-6) == []
