"""Triangle-pair CCD = min over its primitive queries; shared vertices skipped."""

import numpy as np

from usdksl import ccd

EDGES = [(0, 1), (1, 2), (2, 0)]


def _primitive_minimum(a0, a1, b0, b1):
    """(hit[Q], toi[Q]) of the 15 primitive queries run one by one."""
    queries_vf = [np.concatenate([a0[:, [i]], b0, a1[:, [i]], b1], axis=1) for i in range(3)]
    queries_fv = [np.concatenate([b0[:, [i]], a0, b1[:, [i]], a1], axis=1) for i in range(3)]
    queries_ee = [np.concatenate([a0[:, list(ea)], b0[:, list(eb)], a1[:, list(ea)], b1[:, list(eb)]], axis=1)
                  for ea in EDGES for eb in EDGES]
    tois = [np.where(h, t, np.inf) for h, t in
            [ccd.vertex_face(q) for q in queries_vf + queries_fv] + [ccd.edge_edge(q) for q in queries_ee]]
    tois = np.stack(tois)
    return np.isfinite(tois).any(axis=0), tois.min(axis=0)


def test_equals_minimum_over_primitives():
    rng = np.random.default_rng(3)
    count = 600
    a0 = rng.uniform(-1, 1, (count, 3, 3))
    b0 = rng.uniform(-1, 1, (count, 3, 3)) + [0.5, 0, 0]
    a1 = a0 + rng.uniform(-1, 1, (count, 1, 3)) + rng.normal(0, 0.1, (count, 3, 3))
    b1 = b0 + rng.uniform(-1, 1, (count, 1, 3))
    hit, toi, feature, undecided, queries = ccd.triangle_pair(a0, a1, b0, b1)
    expected_hit, expected_toi = _primitive_minimum(a0, a1, b0, b1)
    assert np.array_equal(hit, expected_hit)
    assert 50 < hit.sum() < count  # both outcomes exercised
    assert np.allclose(toi[hit], expected_toi[hit], atol=4 * ccd.DEFAULT_TOLERANCE)
    assert np.all(toi[~hit] == 1.0)
    assert set(np.unique(feature[hit])) <= {0, 1, 2}
    assert np.all(queries <= 15)


def test_feature_names_the_primitive():
    tri = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0]])
    falling = np.array([[0.2, 0.2, 1.0], [5, 5, 5], [5, 6, 5]])
    # Vertex 0 of A falls onto B: feature 0 (vertex of A on face of B), toi 0.5.
    hit, toi, feature, _, _ = ccd.triangle_pair(falling, falling - [0, 0, 2], tri, tri)
    assert hit[0] and feature[0] == 0 and abs(toi[0] - 0.5) <= 2e-6
    hit, toi, feature, _, _ = ccd.triangle_pair(tri, tri, falling, falling - [0, 0, 2])
    assert hit[0] and feature[0] == 1
    # Two edges crossing: A's edge sweeps down through B's edge.
    a = np.array([[0.5, -1, 1.0], [0.5, 1, 1.0], [0.5, 0, 3.0]])
    b = np.array([[0.0, 0, 0], [1, 0, 0], [0.5, 0, -2.0]])
    hit, toi, feature, _, _ = ccd.triangle_pair(a, a - [0, 0, 2], b, b)
    assert hit[0] and feature[0] == 2 and abs(toi[0] - 0.5) <= 2e-6


def test_shared_vertex_pairs_are_skipped_in_the_same_mesh():
    # Two triangles of one mesh sharing vertex 7 at the origin: they always
    # touch there, which must not count; the fold at t=0.5 through the rest must.
    a = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0]])
    b_open = np.array([[0.0, 0, 0], [-1, 0, 0.5], [0, -1, 0.5]])
    ids_a, ids_b = np.array([7, 1, 2]), np.array([7, 3, 4])
    hit, _, _, _, _ = ccd.triangle_pair(a, a, b_open, b_open, ids_a, ids_b, same_mesh=True)
    assert not hit[0]
    hit, toi, _, _, _ = ccd.triangle_pair(a, a, b_open, b_open, ids_a, ids_b, same_mesh=False)
    assert hit[0] and toi[0] == 0.0
    # B folds over onto A: its free vertices cross A's plane inside A.
    b_start = np.array([[0.0, 0, 0], [0.3, 0.2, 1.0], [0.2, 0.3, 1.0]])
    b_end = np.array([[0.0, 0, 0], [0.3, 0.2, -1.0], [0.2, 0.3, -1.0]])
    hit, toi, _, _, _ = ccd.triangle_pair(a, a, b_start, b_end, ids_a, ids_b, same_mesh=True)
    assert hit[0] and abs(toi[0] - 0.5) <= 2e-6
