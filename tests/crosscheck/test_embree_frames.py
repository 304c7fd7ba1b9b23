"""Intersecting triangle pairs of one static frame with Embree, against a brute-force double oracle."""

import numpy as np
import pytest

import usdksl.crosscheck.embree_frames as embree_frames
from usdksl.crosscheck.embree_frames import FrameTopology, intersecting_triangle_pairs
from brute_force import brute_force_pairs


def found_pairs(result):
    return set(zip(result.triangle_a.tolist(), result.triangle_b.tolist()))


def soup(rng, mesh_count, triangles_per_mesh, size=0.35):
    """Random unconnected triangles in the unit cube, `mesh_count` meshes."""
    meshes = []
    for _ in range(mesh_count):
        centres = rng.uniform(0, 1, (triangles_per_mesh, 1, 3))
        points = (centres + rng.uniform(-size, size, (triangles_per_mesh, 3, 3))).reshape(-1, 3)
        meshes.append((points, np.arange(3 * triangles_per_mesh).reshape(-1, 3)))
    return meshes


def topology_of(meshes):
    return FrameTopology.from_meshes([t for _, t in meshes], [np.arange(len(t)) for _, t in meshes],
                                     [len(p) for p, _ in meshes])


@pytest.mark.parametrize("seed", range(6))
def test_random_soup_matches_brute_force(seed):
    rng = np.random.default_rng(seed)
    meshes = soup(rng, 3, 40)
    topology = topology_of(meshes)
    vertices = np.concatenate([p for p, _ in meshes])
    expected = brute_force_pairs(topology, vertices)
    result = intersecting_triangle_pairs(topology, vertices)
    assert len(expected) > 20  # the soup is dense: the comparison is not vacuous
    assert found_pairs(result) == expected
    assert result.counters["rays_truncated"] == 0


def crumpled_sheet(count, amplitude, rng):
    ticks = np.linspace(0, 1, count + 1)
    x, y = np.meshgrid(ticks, ticks)
    z = amplitude * rng.standard_normal(x.shape)
    # in-plane jitter makes neighbouring triangles fold through each other
    points = np.stack([x.ravel() + 0.6 / count * rng.standard_normal(x.size),
                       y.ravel() + 0.6 / count * rng.standard_normal(x.size), z.ravel()], axis=1)
    ids = np.arange((count + 1) ** 2).reshape(count + 1, count + 1)
    a, b, c, d = (ids[:-1, :-1].ravel(), ids[:-1, 1:].ravel(), ids[1:, 1:].ravel(), ids[1:, :-1].ravel())
    triangles = np.concatenate([np.stack([a, b, c], 1), np.stack([a, c, d], 1)])
    return points, triangles


@pytest.mark.parametrize("seed", range(3))
def test_self_intersecting_connected_sheet_matches_brute_force(seed):
    rng = np.random.default_rng(100 + seed)
    points, triangles = crumpled_sheet(12, 0.05, rng)
    topology = topology_of([(points, triangles)])
    expected = brute_force_pairs(topology, points)
    result = intersecting_triangle_pairs(topology, points)
    assert len(expected) > 5
    assert found_pairs(result) == expected


def test_stacked_layers_collect_every_hit_along_an_edge():
    """One long edge pierces ten parallel sheets: every one must be found, not only the nearest."""
    layers = []
    for k in range(10):
        z = 0.1 * k
        layers.append((np.array([[-1, -1, z], [1, -1, z], [0, 1, z]], float), np.array([[0, 1, 2]])))
    needle = (np.array([[0.0, 0.0, -0.5], [0.01, 0.0, 1.5], [0.02, 0.0, -0.5]]), np.array([[0, 1, 2]]))
    meshes = layers + [needle]
    topology = topology_of(meshes)
    vertices = np.concatenate([p for p, _ in meshes])
    result = intersecting_triangle_pairs(topology, vertices)
    assert found_pairs(result) == {(k, 10) for k in range(10)}
    assert found_pairs(result) == brute_force_pairs(topology, vertices)


def test_allowed_mesh_pairs_restrict_what_is_reported():
    rng = np.random.default_rng(7)
    meshes = soup(rng, 3, 30)
    topology = topology_of(meshes)
    vertices = np.concatenate([p for p, _ in meshes])
    allowed = np.zeros((3, 3), bool)
    allowed[0, 2] = allowed[2, 0] = True
    result = intersecting_triangle_pairs(topology, vertices, allowed)
    expected = brute_force_pairs(topology, vertices, allowed)
    assert found_pairs(result) == expected and expected
    meshes_found = {(int(topology.triangle_mesh[a]), int(topology.triangle_mesh[b])) for a, b in expected}
    assert meshes_found == {(0, 2)}


def test_shared_vertex_hits_are_excluded_before_confirmation(monkeypatch):
    """With confirmation disabled (every candidate accepted), no lift and almost no end trimming, rays
    leaving a vertex of a closed surface hit the triangles around that vertex; those must never be pairs."""
    monkeypatch.setattr(embree_frames, "segments_cross_triangles",
                        lambda p, q, a, b, c: np.ones(len(p), dtype=bool))
    monkeypatch.setattr(embree_frames, "ADVANCE_NOISE_ULPS", 0.5)
    monkeypatch.setattr(embree_frames, "LIFT_NOISE_ULPS", 0.0)
    monkeypatch.setattr(embree_frames, "MAX_CAST_ROUNDS", 64)
    points = np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]], float)
    triangles = np.array([[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5],
                          [0, 3, 5]])
    topology = topology_of([(points, triangles)])
    result = intersecting_triangle_pairs(topology, points)
    assert result.counters["embree_hits"] > 0
    assert found_pairs(result) == set()


def test_pair_sharing_a_vertex_meets_through_its_other_parts():
    """Two triangles sharing vertex 0: the edge 3-4 (no shared vertex) pierces triangle 0: reported."""
    points = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0.4, 0.3, 0.5], [0.3, 0.4, -0.5]], float)
    triangles = np.array([[0, 1, 2], [0, 3, 4]])
    topology = FrameTopology.from_meshes([triangles], [np.array([0, 1])], [5])
    assert found_pairs(intersecting_triangle_pairs(topology, points)) == {(0, 1)}


def test_empty_and_no_partner_cases():
    points, triangles = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], float), np.array([[0, 1, 2]])
    topology = topology_of([(points, triangles), (points + [0.1, 0.1, 0], triangles)])
    vertices = np.concatenate([points, points + [0.1, 0.1, 0]])
    assert found_pairs(intersecting_triangle_pairs(topology, vertices, np.zeros((2, 2), bool))) == set()
    assert found_pairs(intersecting_triangle_pairs(topology, vertices)) == set()  # coplanar overlap
