"""A face with one corner blown far away (a simulation blow-up) is a huge, fast sliver.

Its queries must stay conservative (never miss a contact, never report one
late) and cost about what an ordinary query costs, whatever the height: the
iteration count (parameter boxes examined, machine-independent) is bounded by
a constant, not checked by timing. Each query is tried with the blow-up at
the start and at the end of the step and with every rotation of the face's
corner order (the root finder chooses its own parameter origin).
"""

import numpy as np
import pytest

from usdksl import ccd

HEIGHTS = [1e3, 1e5, 1e7, 1e9]
#: Powers of two of about the same heights, so that planted contacts are exact.
DYADIC_HEIGHTS = [2.0**10, 2.0**17, 2.0**23, 2.0**30]
TOLERANCES = [1e-2, 1e-6, 1e-9]
#: Boxes any one of these queries may take at any height. Before the root
#: finder chose its own parameter origin, the fold near miss took 2e4 boxes
#: at height 1e5 and 2e5 at 1e7, the thickness case about 1e5 at every height
#: (in the corner order given).
MAX_ITERATIONS_AT_ANY_HEIGHT = 100

# From samples/fold.usda: vertex 94 of /World/Strip blown up at sample 18
# makes triangle 180 a sliver; a vertex of triangle 184 slides in the plane
# z = 0.1 of the sliver's short edge, barycentrically within H^-1 of the
# sliver but never touching it (all values are float32, as USD stores them).
FOLD_VERTEX = np.array([[0.03935956954956055, 0.2493383288383484, 0.10000000149011612],
                        [0.018399514257907867, 0.24231424927711487, 0.10000000149011612]])
FOLD_SHORT_EDGE = np.array([[0.0, 0.0, 0.10000000149011612],
                            [0.0759187713265419, 0.054774209856987, 0.10000000149011612]])


def _sliver_queries(vertex, far_corner_start, far_corner_end, short_edge):
    """(3, 8, 3): vertex-face queries for each rotation of the face's corners."""
    faces = np.array([[far_corner_start, *short_edge], [far_corner_end, *short_edge]])
    rows = []
    for shift in range(3):
        rotated = np.roll(faces, shift, axis=1)
        rows.append(np.concatenate([vertex[:1], rotated[0], vertex[1:], rotated[1]]))
    return np.array(rows)


def _blown(height, at_start):
    far = np.array([0.0, height, 0.0])
    return (far, np.zeros(3)) if at_start else (np.zeros(3), far)


def _fold_near_miss(height, at_start):
    return _sliver_queries(FOLD_VERTEX, *_blown(height, at_start), FOLD_SHORT_EDGE)


# A sliver with dyadic corners, and a vertex crossing it at t* = 1/2 at a
# point of barycentric weights (far corner, first, second short-edge corner):
# inside near the short edge, on the short edge, and on either long edge
# (each edge is the one opposite the root finder's parameter origin for some
# choice of origin). The contact is exact in double precision, so the first
# contact is at or before t*.
PLANTED_TIME = 0.5
PLANTED_WEIGHTS = [(2.0**-40, 5.0 / 8.0 - 2.0**-40, 3.0 / 8.0), (0.0, 5.0 / 8.0, 3.0 / 8.0),
                   (2.0**-40, 1.0 - 2.0**-40, 0.0), (2.0**-40, 0.0, 1.0 - 2.0**-40)]
PLANTED_SHORT_EDGE = np.array([[0.0, 0.0, 0.125], [5.0 / 64.0, 1.0 / 16.0, 0.125]])
PLANTED_VELOCITY = np.array([-1.0 / 32.0, -1.0 / 128.0, -0.25])


def _planted_crossing(height, at_start, weights):
    far_start, far_end = _blown(height, at_start)
    far_at_contact = 0.5 * (far_start + far_end)
    far, u, v = weights
    contact = far * far_at_contact + u * PLANTED_SHORT_EDGE[0] + v * PLANTED_SHORT_EDGE[1]
    vertex = np.array([contact - PLANTED_TIME * PLANTED_VELOCITY, contact + PLANTED_TIME * PLANTED_VELOCITY])
    # The construction is exact only if moving back to the contact is.
    assert np.array_equal(vertex[0] + PLANTED_TIME * PLANTED_VELOCITY, contact)
    return _sliver_queries(vertex, far_start, far_end, PLANTED_SHORT_EDGE)


@pytest.mark.parametrize("at_start", [True, False])
@pytest.mark.parametrize("tolerance", TOLERANCES)
def test_fold_near_miss_costs_a_bounded_number_of_boxes_at_every_height(tolerance, at_start):
    for height in HEIGHTS:
        answers = ccd.vertex_face_detailed(_fold_near_miss(height, at_start), tolerance=tolerance)
        assert not answers.undecided.any()
        assert answers.iterations.max() <= MAX_ITERATIONS_AT_ANY_HEIGHT, (height, answers.iterations)


@pytest.mark.parametrize("weights", PLANTED_WEIGHTS)
@pytest.mark.parametrize("at_start", [True, False])
@pytest.mark.parametrize("tolerance", TOLERANCES)
def test_planted_crossing_of_a_blown_up_sliver_is_found_in_time(tolerance, at_start, weights):
    for height in DYADIC_HEIGHTS:
        answers = ccd.vertex_face_detailed(_planted_crossing(height, at_start, weights), tolerance=tolerance)
        assert answers.hit.all(), height
        assert (answers.toi <= PLANTED_TIME).all(), (height, answers.toi)
        assert not answers.undecided.any()
        assert answers.iterations.max() <= MAX_ITERATIONS_AT_ANY_HEIGHT, (height, answers.iterations)


def _euclidean_distances(ipctk, query, times):
    """Euclidean vertex-face distances at the given times (ipctk)."""
    positions = query[None, :4] + times[:, None, None] * (query[None, 4:] - query[None, :4])
    # ipctk returns squared distances.
    return np.sqrt([ipctk.point_triangle_distance(*p) for p in positions])


@pytest.mark.parametrize("at_start", [True, False])
def test_sliver_with_thickness_hits_no_later_than_the_first_sampled_contact(at_start):
    ipctk = pytest.importorskip("ipctk")
    thickness = 1e-3
    times = np.linspace(0.0, 1.0, 2049)
    for height in HEIGHTS:
        # The fold vertex moved off the sliver's plane: it starts 0.05 above
        # the short edge and descends through the sliver.
        queries = _fold_near_miss(height, at_start)
        queries[:, 0, 2] += 0.05
        queries[:, 4, 2] -= 0.05
        answers = ccd.vertex_face_detailed(queries, tolerance=1e-6, thickness=thickness)
        distances = _euclidean_distances(ipctk, queries[0], times)
        touching = np.flatnonzero(distances <= thickness)
        assert touching.size, "the construction must come within the thickness"
        first = times[touching[0]]
        assert answers.hit.all(), height
        assert (answers.toi <= first).all(), (height, answers.toi, first)
        assert answers.iterations.max() <= MAX_ITERATIONS_AT_ANY_HEIGHT, (height, answers.iterations)
