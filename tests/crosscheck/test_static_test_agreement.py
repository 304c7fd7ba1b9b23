"""Every triangle pair the Embree cross-check reports must also intersect by the narrow phase's static
triangle test (usdksl.ccd.triangles_intersect_static): the cross-check is the stricter of the two."""

import numpy as np
import pytest

from usdksl.crosscheck.embree_frames import FrameTopology, intersecting_triangle_pairs

ccd = pytest.importorskip("usdksl.ccd")


def reported_and_static(points, triangles, faces=None):
    faces = np.arange(len(triangles)) if faces is None else faces
    topology = FrameTopology.from_meshes([triangles], [faces], [len(points)])
    result = intersecting_triangle_pairs(topology, points)
    a = points[topology.triangles[result.triangle_a]]
    b = points[topology.triangles[result.triangle_b]]
    return result, ccd.triangles_intersect_static(a, b)


@pytest.mark.parametrize("seed", range(4))
def test_random_soup_pairs_all_intersect_statically(seed):
    rng = np.random.default_rng(seed)
    points = (rng.uniform(0, 1, (80, 1, 3)) + rng.uniform(-0.3, 0.3, (80, 3, 3))).reshape(-1, 3)
    result, static = reported_and_static(points, np.arange(240).reshape(-1, 3))
    assert len(static) > 20 and static.all()


def test_touching_and_coplanar_configurations(tmp_path):
    """Vertex on a face, edge on an edge, coplanar overlap, coplanar edge-sharing-line: the static test
    says they touch; the cross-check reports nothing (one-sided), and never crashes."""
    base = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]
    cases = {
        "vertex on face": base + [[0.2, 0.2, 0.0], [0.5, 0.5, 1.0], [0.2, 0.6, 1.0]],
        "edge on edge": base + [[0.5, -0.5, 0.0], [0.5, 0.5, 0.0], [0.5, 0.0, 1.0]],
        "coplanar overlap": base + [[0.1, 0.1, 0.0], [0.9, 0.05, 0.0], [0.2, 0.7, 0.0]],
        "coplanar touching edges": base + [[1, 0, 0.0], [0, 1, 0.0], [1, 1, 0.0]],
        "vertex on vertex": base + [[1, 0, 0.0], [2, 0, 1.0], [2, 1, 0.0]],
    }
    for name, corners in cases.items():
        points = np.array(corners, float)
        triangles = np.array([[0, 1, 2], [3, 4, 5]])
        result, _ = reported_and_static(points, triangles)
        assert len(result.triangle_a) == 0, name
        assert ccd.triangles_intersect_static(points[None, :3], points[None, 3:])[0], name


def test_crumpled_self_intersecting_sheet_pairs_intersect_statically():
    rng = np.random.default_rng(11)
    count = 14
    ticks = np.linspace(0, 1, count + 1)
    x, y = np.meshgrid(ticks, ticks)
    points = np.stack([x.ravel() + 0.06 * rng.standard_normal(x.size),
                       y.ravel() + 0.06 * rng.standard_normal(x.size), 0.05 * rng.standard_normal(x.size)], 1)
    ids = np.arange((count + 1) ** 2).reshape(count + 1, count + 1)
    a, b, c, d = ids[:-1, :-1].ravel(), ids[:-1, 1:].ravel(), ids[1:, 1:].ravel(), ids[1:, :-1].ravel()
    triangles = np.concatenate([np.stack([a, b, c], 1), np.stack([a, c, d], 1)])
    result, static = reported_and_static(points, triangles)
    assert len(static) > 5 and static.all()
    # The pair test that skips primitive pairs sharing a vertex (as the continuous check does) agrees too:
    # pairs of neighbouring triangles are reported only through their non-shared parts.
    ids_a, ids_b = triangles[result.triangle_a], triangles[result.triangle_b]
    sharing = (ids_a[:, :, None] == ids_b[:, None, :]).any(axis=(1, 2))
    assert sharing.any()
    pair_static = ccd.triangle_pair_intersect_static(ids_a, points[ids_a], ids_b, points[ids_b], same_mesh=True)
    assert pair_static.all()
