"""What a hit costs the root search, in parameter boxes (machine-independent).

On simulation caches and generated cloth most hits are contacts that go on
after they begin: a card sinking slowly onto another stays within the
thickness for a while, a vertex sliding in a face's plane stays inside the
face. Clipping then pins the box's early end at the first contact but cannot
move its late end, and halving in time took about log2(1 / tolerance) boxes
before the earliest part was narrow enough to answer. Time is now split near
the early end (TIME_SPLIT_FRACTION).

On a face whose normal turns during the step (a shirt on a moving body) the
fixed separating directions, taken at the step's ends, no longer isolate
time, and boxes shrank only as fast as (u, v) did. Boxes are now also
clipped along the rows of F's inverse Jacobian at their centre.

Each case is planted so that its first contact is known; the answers must
stay conservative and tight, and the mean cost well below what it was (mean
boxes before: 38 for the resting edges, 46 for the sliding vertex, 66 for the
turning face).
"""

import sys
from pathlib import Path

import numpy as np
import pytest

from usdksl import ccd

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from builders import rotation  # noqa: E402

TOLERANCE = 1e-6
COUNT = 400
COORDINATE_STEP = 1.0 / 1024.0
PLANTED_TIME = 0.5
#: Mean boxes per query these may take (38, 46 and 66 before the changes).
MEAN_BOXES_RESTING_EDGES = 28.0
MEAN_BOXES_SLIDING_VERTEX = 28.0
MEAN_BOXES_TURNING_FACE = 12.0


def _dyadic(values):
    return np.round(np.asarray(values) / COORDINATE_STEP) * COORDINATE_STEP


def _turning_face_crossings(rng, count):
    """Vertex-face queries: the face turns by 0.5 to 1.5 rad about a random
    axis while its corners move linearly, and the vertex passes through it at
    PLANTED_TIME at a point of 1/16-grid barycentric weights. All values are
    dyadic, so the planted contact is exact: the first one is at or before it."""
    queries = []
    for _ in range(count):
        start = _dyadic(rng.uniform(-1.0, 1.0, (3, 3)))
        axis = rng.normal(size=3)
        turned = start @ rotation(axis / np.linalg.norm(axis), rng.uniform(0.5, 1.5)).T
        end = _dyadic(turned + rng.uniform(-0.5, 0.5, 3))
        first, second = rng.integers(1, 8, 2) / 16.0
        weights = np.array([first, second, 1.0 - first - second])
        contact = weights @ (0.5 * (start + end))
        velocity = _dyadic(rng.uniform(-2.0, 2.0, 3))
        vertex = [contact - PLANTED_TIME * velocity, contact + PLANTED_TIME * velocity]
        queries.append(np.concatenate([vertex[:1], start, vertex[1:], end]))
    return np.array(queries)


def _resting_edges(rng, count, thickness):
    """Edge-edge queries: edge A crosses over edge B (perpendicular in plan)
    and sinks at 2^-15 to 2^-8 per step, reaching the thickness at
    PLANTED_TIME and staying within it for the rest of the step. Returns the
    queries and each one's first contact from the float heights."""
    queries, first_contacts = [], []
    for _ in range(count):
        sink = 2.0 ** -float(rng.integers(8, 16))
        height = thickness + PLANTED_TIME * sink
        direction = rng.uniform(-1.0, 1.0, 2)
        direction /= np.linalg.norm(direction)
        edge_a = 0.3 * np.array([[-direction[0], -direction[1], 0.0], [direction[0], direction[1], 0.0]])
        edge_b = np.array([[-direction[1], direction[0], 0.0], [direction[1], -direction[0], 0.0]])
        start = edge_a + [0.0, 0.0, height]
        end = edge_a + [0.0, 0.0, height - sink]
        queries.append(np.concatenate([start, edge_b, end, edge_b]))
        first_contacts.append((start[0, 2] - thickness) / (start[0, 2] - end[0, 2]))
    return np.array(queries), np.array(first_contacts)


def _vertex_sliding_into_a_face(rng, count):
    """Vertex-face queries in one plane (z = 0): the face translates and the
    vertex crosses its edge (corner 1 to corner 2) inward at PLANTED_TIME at
    a 1/16-grid point, then stays inside. All values are dyadic, so the first
    contact is exactly PLANTED_TIME."""
    queries = []
    for _ in range(count):
        start = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
        start[:, :2] += _dyadic(rng.uniform(-0.5, 0.5, 2))
        shift = np.zeros(3)
        shift[:2] = _dyadic(rng.uniform(-0.3, 0.3, 2))
        end = start + shift
        along = rng.integers(1, 16) / 16.0
        entry = (1.0 - along) * 0.5 * (start[0] + end[0]) + along * 0.5 * (start[1] + end[1])
        inward = np.array([_dyadic(rng.uniform(-0.5, 0.5)), _dyadic(rng.uniform(0.125, 1.0)), 0.0])
        velocity = inward + shift
        vertex = [entry - PLANTED_TIME * velocity, entry + PLANTED_TIME * velocity]
        queries.append(np.concatenate([vertex[:1], start, vertex[1:], end]))
    return np.array(queries)


def test_a_vertex_sliding_into_a_face_in_its_plane_answers_in_few_boxes_at_its_first_contact():
    queries = _vertex_sliding_into_a_face(np.random.default_rng(5), COUNT)
    answers = ccd.vertex_face_detailed(queries, tolerance=TOLERANCE)
    assert answers.hit.all()
    assert (answers.toi <= PLANTED_TIME).all(), answers.toi.max()
    assert (answers.toi >= PLANTED_TIME - 2.0 * TOLERANCE).all(), answers.toi.min()
    assert not answers.undecided.any()
    assert answers.iterations.mean() <= MEAN_BOXES_SLIDING_VERTEX, answers.iterations.mean()


@pytest.mark.parametrize("thickness", [1e-4, 1e-7])
def test_edges_resting_within_the_thickness_answer_in_few_boxes_at_their_first_contact(thickness):
    queries, first_contacts = _resting_edges(np.random.default_rng(11), COUNT, thickness)
    answers = ccd.edge_edge_detailed(queries, tolerance=TOLERANCE, thickness=thickness)
    assert answers.hit.all()
    # Never late (the first contact is known to about 1e-12 of the step from
    # the float heights), and no earlier than the tolerance allows.
    assert (answers.toi <= first_contacts + 1e-12).all(), (answers.toi - first_contacts).max()
    assert (answers.toi >= first_contacts - 2.0 * TOLERANCE).all(), (first_contacts - answers.toi).max()
    assert not answers.undecided.any()
    assert answers.iterations.mean() <= MEAN_BOXES_RESTING_EDGES, answers.iterations.mean()


def test_a_turning_face_is_crossed_in_few_boxes_and_never_late():
    queries = _turning_face_crossings(np.random.default_rng(7), COUNT)
    answers = ccd.vertex_face_detailed(queries, tolerance=TOLERANCE)
    assert answers.hit.all()
    assert (answers.toi <= PLANTED_TIME).all(), answers.toi.max()
    assert not answers.undecided.any()
    assert answers.iterations.mean() <= MEAN_BOXES_TURNING_FACE, answers.iterations.mean()
