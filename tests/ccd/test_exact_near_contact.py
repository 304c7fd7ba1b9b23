"""Queries on the exact side of the root finder: flat and nearly flat cloth, where a gap far below the
float rounding bound decides contact (thickness 0), so only exact arithmetic answers right. Shortcuts in
front of the exact arithmetic (an axis on which all four points share their coordinates, float corner
values far from the thickness) must leave these answers as they are."""

import numpy as np

from usdksl import ccd

TRIANGLE = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
#: A gap (scene units) far below the corner rounding bound at unit coordinates (about 1e-14).
TINY_GAP = 1e-20


def vf_query(p0, p1, tri0=TRIANGLE, tri1=None):
    tri1 = tri0 if tri1 is None else tri1
    return np.vstack([np.asarray(p0, float)[None], tri0, np.asarray(p1, float)[None], tri1])[None]


def answer(query, **kwargs):
    result = ccd.vertex_face_detailed(query, **kwargs)
    return bool(result.hit[0]), float(result.toi[0])


def test_vertex_gliding_a_tiny_gap_above_a_flat_face_never_touches():
    assert answer(vf_query([-1, 0.25, TINY_GAP], [1, 0.25, TINY_GAP]))[0] is False
    assert answer(vf_query([-1, 0.25, -TINY_GAP], [1, 0.25, -TINY_GAP]))[0] is False


def test_vertex_in_the_face_plane_touches_when_it_enters_the_face():
    # Every point has z = 0 at both ends: that component of the distance is exactly zero throughout.
    hit, toi = answer(vf_query([-1, 0.25, 0.0], [1, 0.25, 0.0]))
    assert hit and 0.5 - 2 * ccd.DEFAULT_TOLERANCE <= toi <= 0.5 + 1e-15


def test_vertex_in_the_face_plane_beside_the_face_never_touches():
    assert answer(vf_query([-1, 2.0, 0.0], [2, 2.0, 0.0]))[0] is False


def test_face_and_vertex_rising_together_stay_a_tiny_gap_apart():
    lifted = TRIANGLE + [0.0, 0.0, 0.5]
    assert answer(vf_query([-1, 0.25, TINY_GAP], [1, 0.25, 0.5 + TINY_GAP], TRIANGLE, lifted))[0] is False
    hit, toi = answer(vf_query([-1, 0.25, 0.0], [1, 0.25, 0.5], TRIANGLE, lifted))
    assert hit and 0.5 - 2 * ccd.DEFAULT_TOLERANCE <= toi <= 0.5 + 1e-15


def test_vertex_closing_a_tiny_gap_touches_exactly_when_it_reaches_the_face():
    # Starts TINY_GAP above the face and ends on it (t = 1), or ends TINY_GAP above it (never).
    hit, toi = answer(vf_query([0.25, 0.25, TINY_GAP], [0.25, 0.25, 0.0]))
    assert hit and toi >= 1.0 - 2 * ccd.DEFAULT_TOLERANCE
    assert answer(vf_query([0.25, 0.25, 2 * TINY_GAP], [0.25, 0.25, TINY_GAP]))[0] is False
