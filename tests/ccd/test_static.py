"""Static triangle-triangle test: exact on coplanar and touching cases."""

from fractions import Fraction

import numpy as np

from usdksl import ccd

A = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0]])


def static(a, b, thickness=0.0):
    return bool(ccd.triangles_intersect_static(np.asarray(a, float), np.asarray(b, float), thickness)[0])


def test_coplanar_overlapping_and_separated():
    assert static(A, A + [0.2, 0.2, 0])
    assert static(A, A * 0.1 + [0.1, 0.1, 0])  # contained, no edge crossing
    assert not static(A, A + [1.5, 0, 0])


def test_touching_at_a_vertex_exactly_and_one_ulp_away():
    touching = np.array([[0.5, 0.5, 0], [2, 2, 0], [2, 1, 1]])
    assert static(A, touching)
    away = touching.copy()
    away[0, 0] = np.nextafter(0.5, 1.0)  # x + y = 1 + ulp: strictly outside A
    assert not static(A, away)
    assert static(A, away, thickness=1e-9)


def test_edge_through_face_and_separated_in_space():
    through = np.array([[0.25, 0.25, -1], [0.25, 0.25, 1], [3, 3, 0]])
    assert static(A, through)
    assert not static(A, through + [0, 0, 1.5])


def test_thickness_gap():
    above = A + [0, 0, 0.1]
    assert not static(A, above)
    assert static(A, above, thickness=0.2)
    assert not static(A, above, thickness=0.05)


def test_zero_area_triangles():
    sliver = np.array([[0.25, 0.25, -1], [0.25, 0.25, 0], [0.25, 0.25, 1]])
    assert static(A, sliver)
    assert not static(A, sliver + [1, 1, 0])


def test_shared_vertex_exclusion():
    b_touching_only_at_shared = np.array([[0.0, 0, 0], [-1, 0, 0.5], [0, -1, 0.5]])
    ids_a, ids_b = np.array([[7, 1, 2]]), np.array([[7, 3, 4]])
    assert not ccd.triangle_pair_intersect_static(ids_a, A, ids_b, b_touching_only_at_shared, True)[0]
    assert ccd.triangle_pair_intersect_static(ids_a, A, ids_b, b_touching_only_at_shared, False)[0]
    b_folded_through = np.array([[0.0, 0, 0], [0.3, 0.2, 1.0], [0.2, 0.3, -1.0]])
    assert ccd.triangle_pair_intersect_static(ids_a, A, ids_b, b_folded_through, True)[0]
    assert ccd.triangle_pair_intersect_static(ids_a, A, ids_b, b_folded_through, True, thickness=0.01)[0]


def test_orient3d_is_exact_on_nearly_coplanar_points():
    rng = np.random.default_rng(11)
    count = 300
    base = rng.uniform(-1, 1, (count, 3, 3))
    # d on the plane of a, b, c up to rounding: the float filter cannot decide.
    weights = rng.uniform(0, 1, (count, 3))
    weights /= weights.sum(axis=1, keepdims=True)
    d = np.einsum("qi,qik->qk", weights, base)
    points = np.concatenate([base, d[:, None]], axis=1)
    ours = ccd.orient3d(points)
    exact = np.frompyfunc(lambda x: Fraction(x), 1, 1)(points)
    ad, bd, cd = exact[:, 0] - exact[:, 3], exact[:, 1] - exact[:, 3], exact[:, 2] - exact[:, 3]
    det = (ad[:, 0] * (bd[:, 1] * cd[:, 2] - bd[:, 2] * cd[:, 1])
           + bd[:, 0] * (cd[:, 1] * ad[:, 2] - cd[:, 2] * ad[:, 1])
           + cd[:, 0] * (ad[:, 1] * bd[:, 2] - ad[:, 2] * bd[:, 1]))
    expected = np.sign(det.astype(float)).astype(np.int8)
    expected[np.array([v == 0 for v in det])] = 0
    assert np.array_equal(ours, expected)
