"""Hand-made degenerate queries whose answers are known exactly."""

import numpy as np
import pytest

from usdksl import ccd

TOL = ccd.DEFAULT_TOLERANCE
TRIANGLE = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])


def vf_query(p0, p1, tri0=TRIANGLE, tri1=None):
    tri1 = tri0 if tri1 is None else tri1
    return np.vstack([np.asarray(p0, float)[None], tri0, np.asarray(p1, float)[None], tri1])[None]


def ee_query(a0, a1, b0, b1, a0_end=None, a1_end=None, b0_end=None, b1_end=None):
    start = [a0, a1, b0, b1]
    end = [a0_end, a1_end, b0_end, b1_end]
    end = [s if e is None else e for s, e in zip(start, end)]
    return np.array(start + end, dtype=float)[None]


def single(run, query, **kwargs):
    answers = run(query, **kwargs)
    return bool(answers.hit[0]), float(answers.toi[0]), bool(answers.undecided[0])


def assert_contact_at(run, query, expected, slack=0.0, **kwargs):
    hit, toi, undecided = single(run, query, **kwargs)
    assert hit and not undecided
    # A lower bound of the true time, within the tolerance (+ rounding slack).
    assert toi <= expected + 1e-15
    assert toi >= expected - 2 * kwargs.get("tolerance", TOL) - slack


def assert_no_contact(run, query, **kwargs):
    hit, _, _ = single(run, query, **kwargs)
    assert not hit


VF = ccd.vertex_face_detailed
EE = ccd.edge_edge_detailed


def test_coplanar_vertex_enters_triangle():
    assert_contact_at(VF, vf_query([-1, 0.25, 0], [1, 0.25, 0]), 0.5)


def test_coplanar_vertex_passes_beside_triangle():
    assert_no_contact(VF, vf_query([-1, 2, 0], [2, 2, 0]))


def test_vertex_sliding_along_edge_reaches_triangle():
    assert_contact_at(VF, vf_query([-1, 0, 0], [2, 0, 0]), 1.0 / 3.0)


def test_vertex_sliding_on_edge_touches_from_start():
    assert_contact_at(VF, vf_query([0.2, 0, 0], [0.8, 0, 0]), 0.0)


def test_contact_exactly_at_start_is_reported_with_zero_toi():
    hit, toi, _ = single(VF, vf_query([0.25, 0.25, 0], [0.25, 0.25, 1]))
    assert hit and toi == 0.0
    hit, toi, _ = single(EE, ee_query([0, 0, 0], [1, 0, 0], [0.5, -1, 0], [0.5, 1, 0],
                                      b0_end=[0.5, -1, 3], b1_end=[0.5, 1, 3]))
    assert hit and toi == 0.0


def test_contact_exactly_at_end():
    assert_contact_at(VF, vf_query([0.25, 0.25, 1], [0.25, 0.25, 0]), 1.0)
    assert_contact_at(EE, ee_query([0, 0, 0], [1, 0, 0], [3, 0, 0], [4, 0, 0],
                                   b0_end=[1, 0, 0], b1_end=[2, 0, 0]), 1.0)


def test_no_motion():
    assert_no_contact(VF, vf_query([0.25, 0.25, 0.5], [0.25, 0.25, 0.5]))
    hit, toi, _ = single(VF, vf_query([0.25, 0.25, 0.0], [0.25, 0.25, 0.0]))
    assert hit and toi == 0.0
    assert_no_contact(EE, ee_query([0, 0, 0], [1, 0, 0], [0, 0, 1], [1, 1, 1]))


def test_parallel_edges_meet_and_miss():
    moving_down = dict(a0_end=[0, 0, -1], a1_end=[1, 0, -1])
    assert_contact_at(EE, ee_query([0, 0, 1], [1, 0, 1], [0, 0, 0], [1, 0, 0], **moving_down), 0.5)
    offset = dict(a0_end=[0, 1, -1], a1_end=[1, 1, -1])
    assert_no_contact(EE, ee_query([0, 1, 1], [1, 1, 1], [0, 0, 0], [1, 0, 0], **offset))


def test_collinear_edges():
    # Edge b slides along the line of edge a and reaches it half way.
    assert_contact_at(EE, ee_query([0, 0, 0], [1, 0, 0], [2, 0, 0], [3, 0, 0],
                                   b0_end=[0, 0, 0], b1_end=[1, 0, 0]), 0.5)
    assert_no_contact(EE, ee_query([0, 0, 0], [1, 0, 0], [2, 0, 0], [3, 0, 0],
                                   b0_end=[1.5, 0, 0], b1_end=[2.5, 0, 0]))


def test_zero_area_triangle_and_zero_length_edge():
    sliver = np.array([[0.0, 0, 0], [1.0, 0, 0], [2.0, 0, 0]])
    assert_contact_at(VF, vf_query([0.5, -1, 0], [0.5, 1, 0], sliver), 0.5)
    assert_no_contact(VF, vf_query([0.5, -1, 1], [0.5, 1, 1], sliver))
    point_edge = ee_query([0.5, 0, 0], [0.5, 0, 0], [0, 0, 1], [1, 0, 1],
                          b0_end=[0, 0, -1], b1_end=[1, 0, -1])
    assert_contact_at(EE, point_edge, 0.5)


def test_large_coordinates_small_motion():
    offset = np.array([1e5, -1e5, 1e5])
    tri = TRIANGLE + offset
    # Starts 5e-4 above, moves 1e-3 down: crosses at t = 0.5. Rounding of the
    # coordinates (~1e-11) is ~1e-8 of the motion.
    assert_contact_at(VF, vf_query(offset + [0.25, 0.25, 5e-4], offset + [0.25, 0.25, -5e-4], tri), 0.5,
                      slack=1e-6)
    assert_no_contact(VF, vf_query(offset + [0.25, 0.25, 2e-3], offset + [0.25, 0.25, 1e-3], tri))
    a = offset + np.array([[0, 0, 5e-4], [1, 0, 5e-4]])
    b = offset + np.array([[0.5, -1, 0], [0.5, 1, 0]])
    assert_contact_at(EE, ee_query(a[0], a[1], b[0], b[1], a[0] - [0, 0, 1e-3], a[1] - [0, 0, 1e-3]), 0.5,
                      slack=1e-6)


def test_tiny_motion():
    assert_contact_at(VF, vf_query([0.25, 0.25, 0.5e-12], [0.25, 0.25, -0.5e-12]), 0.5, slack=0.05)
    assert_no_contact(VF, vf_query([0.25, 0.25, 1e-9], [0.25, 0.25, 1e-9 - 1e-12]))


def test_thickness():
    static_gap = vf_query([0.25, 0.25, 0.1], [0.25, 0.25, 0.1])
    hit, toi, _ = single(VF, static_gap, thickness=0.2)
    assert hit and toi == 0.0
    assert_no_contact(VF, static_gap, thickness=0.05)
    # Falls from z=1 to z=-1: within 0.5 at t = 0.25.
    assert_contact_at(VF, vf_query([0.25, 0.25, 1], [0.25, 0.25, -1]), 0.25, thickness=0.5)
    assert_contact_at(EE, ee_query([0, 0, 1], [1, 0, 1], [0.5, -1, 0], [0.5, 1, 0],
                                   a0_end=[0, 0, -1], a1_end=[1, 0, -1]), 0.45, thickness=0.1)


def test_iteration_cap_gives_undecided_contact():
    # Slides in the triangle's plane and enters it at t = 0.5: the contact
    # region is a whole face of the parameter box, so no clip can pin it and
    # the search needs far more than 3 boxes.
    query = vf_query([-1, 0.25, 0], [1, 0.25, 0])
    answers = VF(query, max_iterations=3)
    assert answers.hit[0] and answers.undecided[0]
    assert answers.toi[0] <= 0.5
    assert answers.reached_tolerance[0] > TOL


def test_tolerance_knob_controls_time_accuracy():
    query = vf_query([0.25, 0.25, 1], [0.25, 0.25, -2])  # true toi = 1/3
    for tolerance in (1e-2, 1e-4, 1e-8):
        answers = VF(query, tolerance=tolerance)
        assert answers.hit[0]
        assert 1 / 3 - 2 * tolerance <= answers.toi[0] <= 1 / 3
        assert answers.reached_tolerance[0] <= tolerance


def test_simple_api_shapes_and_validation():
    hit, toi = ccd.vertex_face(np.repeat(vf_query([0.25, 0.25, 1], [0.25, 0.25, -1]), 4, axis=0))
    assert hit.dtype == bool and hit.shape == (4,) and toi.dtype == np.float64
    assert hit.all() and np.allclose(toi, 0.5, atol=1e-5)
    with pytest.raises(ValueError):
        ccd.edge_edge(np.zeros((2, 7, 3)))
    with pytest.raises(ValueError):
        ccd.vertex_face(np.zeros((1, 8, 3)), thickness=-1.0)
