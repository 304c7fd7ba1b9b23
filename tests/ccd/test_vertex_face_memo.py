"""Repeated vertex-face queries answered from the memo give the answers a fresh search gives, bit for bit."""

import numpy as np

from usdksl import _native, ccd

from builders import triangle_grid


def _wavy_sheets(n, seed):
    """All triangle pairs of two n x n sheets, the upper one falling through the lower one with a random
    wave, listed pair after pair so that each vertex-face primitive comes up once per triangle holding
    the vertex (as in the narrow phase of a cloth)."""
    rng = np.random.default_rng(seed)
    verts, tris = triangle_grid(n, n)
    lower0 = verts + rng.normal(0.0, 0.02, verts.shape)
    lower1 = lower0 + rng.normal(0.0, 0.02, verts.shape)
    upper0 = verts + [0.03, 0.02, 0.1] + rng.normal(0.0, 0.02, verts.shape)
    upper1 = upper0 - [0.0, 0.0, 0.2] + rng.normal(0.0, 0.05, verts.shape)
    a, b = np.meshgrid(np.arange(len(tris)), np.arange(len(tris)), indexing="ij")
    a, b = a.ravel(), b.ravel()
    return (lower0[tris[a]], lower1[tris[a]], upper0[tris[b]], upper1[tris[b]]), (tris[a], tris[b])


def _batch(triangles, ids, same_mesh, reuse, thickness=0.0):
    return _native.triangle_pair_ccd_batch(*triangles, *ids, same_mesh, ccd.DEFAULT_TOLERANCE, thickness,
                                           ccd.DEFAULT_MAX_ITERATIONS, reuse)


def _assert_bit_identical(reused, fresh):
    hit, toi, feature, undecided, queries, _ = reused
    fresh_hit, fresh_toi, fresh_feature, fresh_undecided, fresh_queries, fresh_reused = fresh
    assert np.array_equal(hit, fresh_hit)
    assert np.array_equal(toi.view(np.int64), fresh_toi.view(np.int64)), "toi must match bit for bit"
    assert np.array_equal(feature, fresh_feature)
    assert np.array_equal(undecided, fresh_undecided)
    assert np.array_equal(queries, fresh_queries)
    assert not fresh_reused.any(), "without reuse, nothing may come from the memo"


def test_repeats_between_two_sheets_answer_as_fresh_searches():
    triangles, ids = _wavy_sheets(8, seed=5)
    reused = _batch(triangles, ids, False, True)
    fresh = _batch(triangles, ids, False, False)
    _assert_bit_identical(reused, fresh)
    hit, queries, reused_queries = reused[0], reused[4], reused[5]
    assert 100 < hit.sum() < len(hit), "both outcomes must be exercised"
    # Hits make later queries of a pair search up to an earlier t_max: repeats at a different t_max
    # must be searched again, not taken from the memo.
    assert reused_queries[hit].sum() > 0 and reused_queries.sum() > queries.sum() // 10


def test_self_pairs_of_one_sheet_with_thickness():
    triangles, ids = _wavy_sheets(6, seed=9)
    lower0, lower1 = triangles[0], triangles[1]
    order = np.random.default_rng(2).permutation(len(lower0))
    self_pairs = (lower0, lower1, lower0[order], lower1[order])
    self_ids = (ids[0], ids[0][order])
    for thickness in (0.0, 0.01):
        reused = _batch(self_pairs, self_ids, True, True, thickness)
        _assert_bit_identical(reused, _batch(self_pairs, self_ids, True, False, thickness))
        assert reused[5].sum() > 0


def test_more_distinct_queries_than_the_memo_holds():
    triangles, ids = _wavy_sheets(24, seed=1)  # 1152^2 pairs would be too many: keep every 13th
    keep = np.arange(0, len(ids[0]), 13)
    triangles = tuple(t[keep] for t in triangles)
    ids = tuple(i[keep] for i in ids)
    repeated = tuple(np.concatenate([t, t[::-1]]) for t in triangles)
    repeated_ids = tuple(np.concatenate([i, i[::-1]]) for i in ids)
    reused = _batch(repeated, repeated_ids, False, True)
    assert reused[4].sum() > 4 * 4096, "the batch must overflow the memo"
    _assert_bit_identical(reused, _batch(repeated, repeated_ids, False, False))
