"""The double-precision confirmation rule: proper interior crossings only."""

import numpy as np

from usdksl.crosscheck.segment_crossing import CROSSING_MARGIN_RELATIVE, segments_cross_triangles

A, B, C = np.array([0.0, 0, 0]), np.array([1.0, 0, 0]), np.array([0.0, 1, 0])


def cross(p, q, a=A, b=B, c=C):
    return bool(segments_cross_triangles(np.array([p]), np.array([q]), np.array([a]), np.array([b]),
                                         np.array([c]))[0])


def test_proper_crossing_in_either_direction_and_winding():
    assert cross([0.2, 0.2, -1], [0.2, 0.2, 1])
    assert cross([0.2, 0.2, 1], [0.3, 0.1, -1])
    assert cross([0.2, 0.2, 1], [0.2, 0.2, -1], A, C, B)


def test_misses_outside_the_triangle_or_short_of_the_plane():
    assert not cross([0.6, 0.6, -1], [0.6, 0.6, 1])     # beyond the hypotenuse
    assert not cross([0.2, 0.2, 0.5], [0.2, 0.2, 1])    # both ends above
    assert not cross([-0.1, 0.2, -1], [-0.1, 0.2, 1])   # beside the y axis edge


def test_touching_and_coplanar_configurations_are_not_confirmed():
    assert not cross([0.2, 0.2, 0.0], [0.2, 0.2, 1])    # end point on the triangle
    assert not cross([0.5, 0.5, -1], [0.5, 0.5, 1])     # through the hypotenuse exactly
    assert not cross([0.0, 0.0, -1], [0.0, 0.0, 1])     # through a corner
    assert not cross([0.1, 0.1, 0.0], [0.3, 0.2, 0.0])  # coplanar, inside
    assert not cross([-1, 0.2, 0.0], [2, 0.2, 0.0])     # coplanar, through


def test_margin_is_relative_to_scale():
    inside_by = 10 * CROSSING_MARGIN_RELATIVE
    assert cross([inside_by, 0.3, -1], [inside_by, 0.3, 1])
    assert not cross([0.1 * CROSSING_MARGIN_RELATIVE, 0.3, -1], [0.1 * CROSSING_MARGIN_RELATIVE, 0.3, 1])
    scale = 1e4
    assert cross(np.array([0.2, 0.2, -1]) * scale, np.array([0.2, 0.2, 1]) * scale, A * scale, B * scale,
                 C * scale)


def test_degenerate_triangle_and_vectorised_shapes():
    assert not cross([0.2, 0.0, -1], [0.2, 0.0, 1], A, B, 2 * B)
    rng = np.random.default_rng(3)
    p = rng.uniform(0, 0.8, (50, 3)); p[:, 2] = -1
    q = p.copy(); q[:, 2] = 1
    tri = np.broadcast_to(np.stack([A, B, C]), (50, 3, 3))
    result = segments_cross_triangles(p, q, tri[:, 0], tri[:, 1], tri[:, 2])
    assert result.shape == (50,)
    assert np.array_equal(result, (p[:, 0] + p[:, 1]) < 1)
    assert segments_cross_triangles(np.zeros((0, 3)), np.zeros((0, 3)), np.zeros((0, 3)), np.zeros((0, 3)),
                                    np.zeros((0, 3))).shape == (0,)
