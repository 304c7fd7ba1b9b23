"""Above thickness 0, "within the thickness" is Euclidean distance (docs/contracts.md, Contacts).

The root finder bounds F per world axis, so its raw acceptance is the cube |F|inf <= T; a pair
diagonal to the axes can fit that cube while up to sqrt(3) T apart. These queries have closed-form
Euclidean answers that the cube gets wrong, and random ones are checked against ipctk's Euclidean
point-triangle and segment-segment distances.
"""

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from usdksl import ccd

ipctk = pytest.importorskip("ipctk")

TOLERANCE = 1e-6
THICKNESS = 1.0
#: The offset along (0, 1, 1) at which the pairs below are THICKNESS apart (Euclidean); at
#: THICKNESS itself they fit the cube while sqrt(2) THICKNESS apart.
TOUCH_OFFSET = THICKNESS / math.sqrt(2.0)
#: The diagonal offset closes from START_OFFSET to END_OFFSET over the step.
START_OFFSET, END_OFFSET = 2.0, 0.5
#: First Euclidean touch of the closing pairs (interval fraction); the cube would say 2/3.
CLOSED_FORM_TOI = (START_OFFSET - TOUCH_OFFSET) / (START_OFFSET - END_OFFSET)


def parallel_edges(offset_start, offset_end):
    """Edge A on the x axis; edge B parallel to it, offset by s (0, 1, 1) (Euclidean distance s sqrt(2))."""
    def at(s):
        return [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.2, s, s], [0.8, s, s]]
    return np.array(at(offset_start) + at(offset_end))


def vertex_beside_face(offset_start, offset_end):
    """Face in the z = 0 plane; the vertex at (-s, 0.3, s), beside the face's edge x = 0, so its
    nearest face point is (0, 0.3, 0), s sqrt(2) away."""
    face = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]
    return np.array([[-offset_start, 0.3, offset_start]] + face + [[-offset_end, 0.3, offset_end]] + face)


QUERIES = {"edge-edge": (parallel_edges, ccd.edge_edge_detailed),
           "vertex-face": (vertex_beside_face, ccd.vertex_face_detailed)}


def rotation(angles):
    a, b, c = angles
    rx = np.array([[1, 0, 0], [0, math.cos(a), -math.sin(a)], [0, math.sin(a), math.cos(a)]])
    ry = np.array([[math.cos(b), 0, math.sin(b)], [0, 1, 0], [-math.sin(b), 0, math.cos(b)]])
    rz = np.array([[math.cos(c), -math.sin(c), 0], [math.sin(c), math.cos(c), 0], [0, 0, 1]])
    return rz @ ry @ rx


@pytest.mark.parametrize("kind", sorted(QUERIES))
def test_a_pair_held_still_inside_the_cube_but_beyond_the_thickness_is_not_a_contact(kind):
    build, run = QUERIES[kind]
    # 0.8 per axis fits the cube of half-width 1; 0.8 sqrt(2) = 1.13 apart does not touch.
    assert not run(build(0.8, 0.8)[None], tolerance=TOLERANCE, thickness=THICKNESS).hit[0]
    # 0.7 sqrt(2) = 0.99 apart does.
    held = run(build(0.7, 0.7)[None], tolerance=TOLERANCE, thickness=THICKNESS)
    assert held.hit[0] and held.toi[0] == 0.0


@pytest.mark.parametrize("kind", sorted(QUERIES))
def test_a_pair_closing_diagonally_touches_when_its_euclidean_distance_reaches_the_thickness(kind):
    build, run = QUERIES[kind]
    answer = run(build(START_OFFSET, END_OFFSET)[None], tolerance=TOLERANCE, thickness=THICKNESS)
    assert answer.hit[0] and not answer.undecided[0]
    assert CLOSED_FORM_TOI - TOLERANCE <= answer.toi[0] <= CLOSED_FORM_TOI


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.sampled_from(sorted(QUERIES)),
       st.tuples(*[st.floats(0.0, 2.0 * math.pi, allow_nan=False)] * 3),
       st.floats(0.01, 100.0, allow_nan=False))
def test_the_time_of_contact_does_not_depend_on_how_the_pair_is_turned_or_scaled(kind, angles, scale):
    """The Euclidean answer is invariant under rotation and scaling; the cube's is not (its time
    ranges from 2/3 to that of the Euclidean ball as the pair turns)."""
    build, run = QUERIES[kind]
    query = build(START_OFFSET, END_OFFSET) @ rotation(angles).T * scale
    answer = run(query[None], tolerance=TOLERANCE, thickness=THICKNESS * scale)
    assert answer.hit[0] and not answer.undecided[0]
    assert CLOSED_FORM_TOI - 2 * TOLERANCE <= answer.toi[0] <= CLOSED_FORM_TOI + 1e-9


# Random queries: grid values make parallel, coplanar and diagonal configurations likely.
GRID = st.sampled_from([-1.0, -0.5, 0.0, 0.25, 0.5, 1.0])
QUERY = st.lists(st.lists(GRID, min_size=3, max_size=3), min_size=8, max_size=8).map(
    lambda rows: np.array(rows, dtype=float))
#: Distance slack of a reported contact: the root finder narrows each parameter box to the
#: tolerance, so F over the answering box varies by about tolerance x the pair's extent (about 4
#: here); well below the cube's error, which on these queries reaches 0.5 (scene units).
SPATIAL_SLACK = 50 * TOLERANCE
#: Time samples of the reference.
REFERENCE_SAMPLES = 400


def point_segment_distance(p, a, b):
    ab = b - a
    length_squared = ab @ ab
    u = 0.0 if length_squared == 0.0 else min(max((p - a) @ ab / length_squared, 0.0), 1.0)
    return float(np.linalg.norm(p - a - u * ab))


def point_triangle_distance(p, a, b, c):
    """ipctk's where the face has an area (it is NaN on a degenerate one); else the nearest edge."""
    normal = np.cross(b - a, c - a)
    if normal @ normal > 1e-24:
        return math.sqrt(ipctk.point_triangle_distance(p, a, b, c))
    return min(point_segment_distance(p, a, b), point_segment_distance(p, b, c), point_segment_distance(p, c, a))


def segment_segment_distance(a0, a1, b0, b1):
    """ipctk's where both edges have a length; else a point against the other edge."""
    if (a1 - a0) @ (a1 - a0) > 0.0 and (b1 - b0) @ (b1 - b0) > 0.0:
        return math.sqrt(ipctk.edge_edge_distance(a0, a1, b0, b1))
    return min(point_segment_distance(a0, b0, b1), point_segment_distance(a1, b0, b1),
               point_segment_distance(b0, a0, a1), point_segment_distance(b1, a0, a1))


def euclidean_distance(kind, query, s):
    p = (1.0 - s) * query[:4] + s * query[4:]
    if kind == "vertex-face":
        return point_triangle_distance(*p)
    return segment_segment_distance(*p)


@settings(max_examples=200, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.sampled_from(sorted(QUERIES)), QUERY, st.sampled_from([0.1, 0.25, 0.5]))
def test_random_queries_agree_with_euclidean_distances(kind, query, thickness):
    _, run = QUERIES[kind]
    answer = run(query[None], tolerance=TOLERANCE, thickness=thickness)
    samples = np.linspace(0.0, 1.0, REFERENCE_SAMPLES + 1)
    distances = np.array([euclidean_distance(kind, query, s) for s in samples])
    touching = samples[distances <= thickness]
    if not answer.hit[0]:
        assert touching.size == 0, f"missed a touch at {touching[:3]}:\n{query!r}"
        return
    toi = answer.toi[0]
    # Never late: no sampled touch before the reported time.
    assert touching.size == 0 or touching[0] >= toi, (toi, touching[:3])
    # A real touch: within the thickness (plus the search's spatial slack) right there.
    assert answer.undecided[0] or euclidean_distance(kind, query, toi) <= \
        thickness + SPATIAL_SLACK, (toi, query)
