"""Intersecting triangle pairs of one static frame, found with Embree (through the ``embreex`` wheel).

Every unique triangle edge is cast as a ray segment (origin at one end, direction to the other end, so the
ray parameter is the fraction of the edge) against one Embree scene holding every triangle of the frame.
Embree returns only the nearest hit, so every hit along the segment is collected in rounds: each round
casts only the rays still active, each from just past its previous hit (a loop over rounds, never over
rays). A hit (edge, triangle) is a candidate for every triangle that owns the edge.

Rules, matching the continuous check:

* primitive pairs that share a vertex are never tested: an edge that hits a triangle containing one of the
  edge's end points is ignored;
* every candidate is confirmed in double precision (:mod:`usdksl.crosscheck.segment_crossing`): the edge must cross
  the triangle's interior by a clear margin. Unconfirmed candidates are counted, never reported.

Limits, by design one-sided (the cross-check may miss, it never raises a false alarm): a crossing within
the single-precision noise band of an edge's end points (``ADVANCE_NOISE_ULPS`` float32 ulps of the scene's
coordinate scale), or within that band of another hit along the same edge, is not searched for, and a
crossing exactly through another triangle's edge or vertex is not confirmed, and a crossing shallower than
the lift of the rays off their own surface (``LIFT_NOISE_ULPS`` float32 ulps) may be missed. Triangle pairs that intersect
only in such ways are left to the continuous check.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Dict, List, Optional, Sequence

import numpy as np

from .segment_crossing import segments_cross_triangles

#: How far (in float32 ulps of the frame's largest absolute coordinate) a ray restarts past its previous
#: hit, and how far both ends of every edge are trimmed. Below this distance float32 cannot tell hits apart
#: from each other or from the edge's own end points (where the edge's own neighbour triangles are hit).
ADVANCE_NOISE_ULPS = 16.0

#: How far (in float32 ulps of the frame's largest absolute coordinate) every ray is lifted off its own
#: surface, along the edge's normal (the sign-agreed sum of its owner triangles' normals). An edge lies in the
#: planes of the triangles that own it, and on flat or ruled parts of a mesh in the planes of its neighbours:
#: cast exactly along the surface, float32 noise makes it graze them at every step. Lifted, it passes above.
LIFT_NOISE_ULPS = 64.0

#: Safety stop for the rounds of multi-hit casting. Rays still active after this many rounds are counted
#: (``rays_truncated``) and their remaining length is not searched.
MAX_CAST_ROUNDS = 4096


@dataclass(frozen=True)
class FrameTopology:
    """The triangles of a set of meshes, numbered globally, with their unique edges.

    Global vertex ``g`` of mesh ``m`` is ``vertex_offset[m] + local``; triangles likewise. Built once per
    shot (topology does not change over time) and reused for every frame.
    """

    vertex_offset: np.ndarray     # int64[meshes + 1]
    triangle_offset: np.ndarray   # int64[meshes + 1]
    triangles: np.ndarray         # int64[T, 3] global vertex ids
    triangle_mesh: np.ndarray     # int32[T]
    triangle_face: np.ndarray     # int32[T] authored face within its mesh
    edges: np.ndarray             # int64[E, 2] global vertex ids, edges[:, 0] < edges[:, 1]
    edge_mesh: np.ndarray         # int32[E]
    edge_owner_start: np.ndarray  # int64[E + 1], CSR into edge_owners
    edge_owners: np.ndarray       # int64[3T] triangles owning each edge

    @classmethod
    def from_meshes(cls, triangles: Sequence[np.ndarray], triangle_faces: Sequence[np.ndarray],
                    vertex_counts: Sequence[int]) -> "FrameTopology":
        """``triangles[m]`` int[M_m, 3] local vertex ids of mesh m, ``triangle_faces[m]`` int[M_m]."""
        mesh_count = len(triangles)
        vertex_offset = np.zeros(mesh_count + 1, dtype=np.int64)
        vertex_offset[1:] = np.cumsum(np.asarray(vertex_counts, dtype=np.int64))
        triangle_counts = np.array([len(t) for t in triangles], dtype=np.int64)
        triangle_offset = np.zeros(mesh_count + 1, dtype=np.int64)
        triangle_offset[1:] = np.cumsum(triangle_counts)
        triangle_mesh = np.repeat(np.arange(mesh_count, dtype=np.int32), triangle_counts)
        if mesh_count:
            all_triangles = np.concatenate([np.asarray(t, dtype=np.int64).reshape(-1, 3) for t in triangles])
            all_faces = np.concatenate([np.asarray(f, dtype=np.int32).reshape(-1) for f in triangle_faces])
        else:
            all_triangles = np.zeros((0, 3), dtype=np.int64)
            all_faces = np.zeros(0, dtype=np.int32)
        all_triangles = all_triangles + vertex_offset[:-1][triangle_mesh][:, None]

        triangle_count = len(all_triangles)
        corner_edges = all_triangles[:, [[0, 1], [1, 2], [2, 0]]].reshape(-1, 2)
        corner_edges.sort(axis=1)
        corner_owner = np.repeat(np.arange(triangle_count, dtype=np.int64), 3)
        if triangle_count:
            edges, edge_of_corner = np.unique(corner_edges, axis=0, return_inverse=True)
            edge_of_corner = edge_of_corner.reshape(-1)
        else:
            edges = np.zeros((0, 2), dtype=np.int64)
            edge_of_corner = np.zeros(0, dtype=np.int64)
        order = np.argsort(edge_of_corner, kind="stable")
        edge_owners = corner_owner[order]
        edge_owner_start = np.zeros(len(edges) + 1, dtype=np.int64)
        edge_owner_start[1:] = np.cumsum(np.bincount(edge_of_corner, minlength=len(edges)))
        edge_mesh = (np.searchsorted(vertex_offset, edges[:, 0], side="right") - 1).astype(np.int32)
        return cls(vertex_offset, triangle_offset, all_triangles, triangle_mesh, all_faces, edges,
                   edge_mesh, edge_owner_start, edge_owners)

    @property
    def mesh_count(self) -> int:
        return len(self.vertex_offset) - 1

    def edge_normals(self, vertices: np.ndarray) -> np.ndarray:
        """Unit normal of every edge in the frame ``vertices``: the sum of its owner triangles' unit normals,
        each flipped to agree with the first owner's (meshes need not be consistently oriented); the first
        owner's normal where the sum vanishes (a fold flat onto itself). float64[E, 3]."""
        corners = vertices[self.triangles]
        normals = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
        lengths = np.linalg.norm(normals, axis=1)
        normals = normals / np.where(lengths > 0.0, lengths, 1.0)[:, None]
        owner_normals = normals[self.edge_owners]
        owner_edge = np.repeat(np.arange(len(self.edges)), np.diff(self.edge_owner_start))
        first = normals[self.edge_owners[self.edge_owner_start[:-1]]] if len(self.edges) else np.zeros((0, 3))
        agree = np.where(np.einsum("ij,ij->i", owner_normals, first[owner_edge]) < 0.0, -1.0, 1.0)
        signed = owner_normals * agree[:, None]
        summed = np.stack([np.bincount(owner_edge, signed[:, axis], minlength=len(self.edges))
                           for axis in range(3)], axis=1)
        summed_length = np.linalg.norm(summed, axis=1)
        return np.where((summed_length > 1e-6)[:, None], summed / np.where(summed_length > 0.0, summed_length,
                                                                              1.0)[:, None], first)


@dataclass
class FrameIntersections:
    """Triangle pairs of one frame found properly crossing (global triangle ids, unordered, unique)."""

    triangle_a: np.ndarray
    triangle_b: np.ndarray
    counters: Dict[str, int] = field(default_factory=dict)


def _cast_all_hits(scene, origins: np.ndarray, directions: np.ndarray, advance: np.ndarray, counters):
    """Every (ray, primID) hit on the segments ``origin + s * direction``, s in [advance, 1 - advance].

    Rounds restart each active ray ``advance`` (fraction of its length) past its previous hit. Positions are
    recomputed in double from the ray's start each round so that no rounding accumulates.
    """
    ray_count = len(origins)
    start = advance.copy()
    end = 1.0 - advance
    active = np.flatnonzero(start < end)
    directions32 = directions.astype(np.float32)
    hit_rays: List[np.ndarray] = []
    hit_primitives: List[np.ndarray] = []
    rounds = 0
    while len(active) and rounds < MAX_CAST_ROUNDS:
        rounds += 1
        ray_origins = (origins[active] + start[active, None] * directions[active]).astype(np.float32)
        reach = (end[active] - start[active]).astype(np.float32)
        answer = scene.run(ray_origins, np.ascontiguousarray(directions32[active]), dists=reach, output=1)
        primitive = np.asarray(answer["primID"])
        hit = primitive >= 0
        hit_rays.append(active[hit])
        hit_primitives.append(primitive[hit].astype(np.int64))
        distance = np.asarray(answer["tfar"], dtype=np.float64)
        moved = active[hit]
        start[moved] = start[moved] + distance[hit] + advance[moved]
        active = moved[start[moved] < end[moved]]
    counters["cast_rounds"] = counters.get("cast_rounds", 0) + rounds
    counters["rays_truncated"] = counters.get("rays_truncated", 0) + int(len(active))
    counters["rays_cast"] = counters.get("rays_cast", 0) + ray_count
    if not hit_rays:
        return np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int64)
    return np.concatenate(hit_rays).astype(np.int64), np.concatenate(hit_primitives)


def intersecting_triangle_pairs(topology: FrameTopology, vertices: np.ndarray,
                                allowed_mesh_pairs: Optional[np.ndarray] = None) -> FrameIntersections:
    """Triangle pairs that properly cross in the static frame ``vertices`` (float64[V, 3], world space).

    ``allowed_mesh_pairs`` is a symmetric bool[meshes, meshes] matrix of the mesh pairs to report (the
    diagonal means self pairs); None allows every pair. Meshes with no allowed partner are left out of the
    Embree scene altogether.
    """
    from embreex import rtcore_scene
    from embreex.mesh_construction import TriangleMesh

    counters: Dict[str, int] = {}
    empty = FrameIntersections(np.zeros(0, np.int64), np.zeros(0, np.int64), counters)
    mesh_count = topology.mesh_count
    if allowed_mesh_pairs is None:
        allowed_mesh_pairs = np.ones((mesh_count, mesh_count), dtype=bool)
    allowed_mesh_pairs = np.asarray(allowed_mesh_pairs, dtype=bool)
    taking_part = allowed_mesh_pairs.any(axis=1)
    scene_triangles = np.flatnonzero(taking_part[topology.triangle_mesh])
    ray_edges = np.flatnonzero(taking_part[topology.edge_mesh])
    if len(scene_triangles) == 0 or len(ray_edges) == 0:
        return empty

    vertices = np.ascontiguousarray(vertices, dtype=np.float64)
    scene = rtcore_scene.EmbreeScene(robust=True)
    TriangleMesh(scene, vertices.astype(np.float32),
                 np.ascontiguousarray(topology.triangles[scene_triangles], dtype=np.int32))

    coordinate_scale = float(np.max(np.abs(vertices[topology.triangles[scene_triangles]])))
    ulp = float(np.finfo(np.float32).eps) * max(coordinate_scale, np.finfo(np.float64).tiny)
    noise = ADVANCE_NOISE_ULPS * ulp
    lift = LIFT_NOISE_ULPS * ulp * topology.edge_normals(vertices)[ray_edges]
    start_points = vertices[topology.edges[ray_edges, 0]] + lift
    directions = vertices[topology.edges[ray_edges, 1]] - vertices[topology.edges[ray_edges, 0]]
    lengths = np.linalg.norm(directions, axis=1)
    advance = np.where(lengths > 0.0, noise / np.where(lengths > 0.0, lengths, 1.0), 1.0)
    counters["edges_unresolvable"] = int(np.count_nonzero(advance >= 0.5))

    hit_ray, hit_primitive = _cast_all_hits(scene, start_points, directions, advance, counters)
    edge = ray_edges[hit_ray]
    triangle = scene_triangles[hit_primitive]
    counters["embree_hits"] = int(len(edge))

    # Shared-vertex exclusion: the edge hits a triangle containing one of its own end points.
    shares = np.zeros(len(edge), dtype=bool)
    for corner in range(3):
        triangle_vertex = topology.triangles[triangle, corner]
        shares |= (triangle_vertex == topology.edges[edge, 0]) | (triangle_vertex == topology.edges[edge, 1])
    keep = ~shares & allowed_mesh_pairs[topology.edge_mesh[edge], topology.triangle_mesh[triangle]]
    edge, triangle = edge[keep], triangle[keep]
    if len(edge):
        key = np.unique(edge * len(topology.triangles) + triangle)
        edge, triangle = key // len(topology.triangles), key % len(topology.triangles)
    counters["candidates"] = int(len(edge))

    corners = vertices[topology.triangles[triangle]]
    confirmed = segments_cross_triangles(vertices[topology.edges[edge, 0]], vertices[topology.edges[edge, 1]],
                                         corners[:, 0], corners[:, 1], corners[:, 2])
    counters["unconfirmed_candidates"] = int(np.count_nonzero(~confirmed))
    edge, triangle = edge[confirmed], triangle[confirmed]

    owner_counts = topology.edge_owner_start[edge + 1] - topology.edge_owner_start[edge]
    first_owner = np.repeat(topology.edge_owner_start[edge], owner_counts)
    within = np.arange(int(owner_counts.sum()), dtype=np.int64) - np.repeat(np.cumsum(owner_counts) - owner_counts,
                                                                          owner_counts)
    owner = topology.edge_owners[first_owner + within]
    other = np.repeat(triangle, owner_counts)
    low, high = np.minimum(owner, other), np.maximum(owner, other)
    if len(low):
        key = np.unique(low * len(topology.triangles) + high)
        low, high = key // len(topology.triangles), key % len(topology.triangles)
    counters["triangle_pairs"] = int(len(low))
    return FrameIntersections(low, high, counters)
