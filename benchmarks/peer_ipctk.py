"""The peer pipeline a user would pick instead of usdksl, computing the same answer with the IPC Toolkit.

    python benchmarks/peer_ipctk.py SHOT.usd                     # all first contacts (ipctk defaults)
    python benchmarks/peer_ipctk.py SHOT.usd --mode tight        # the tight reference
    python benchmarks/peer_ipctk.py SHOT.usd --mode sweep        # earliest contact per sample interval
    python benchmarks/peer_ipctk.py SHOT.usd --compare out/shot.contacts.csv   # usdksl's times vs tight
    python benchmarks/peer_ipctk.py SHOT.usd --compare out/shot.contacts.csv --csv tight.csv   # ... and keep it
    python benchmarks/peer_ipctk.py SHOT.usd --compare out/shot.contacts.csv --reference tight.csv  # reuse it

``all_first_contacts`` answers what ``usdksl check`` answers: the first-contact time of every contacting
authored face pair over the whole shot. Per sample interval of the shot (the union of all meshes'
samples; every vertex moves linearly in between, as USD interpolates), one ``ipctk.CollisionMesh`` of all
checked meshes goes through the ipctk broad phase (``Candidates.build`` over the interval's start and
end positions, LBVH by default); every vertex-face and edge-edge candidate is then tested with
Tight-Inclusion CCD (``ipctk.tight_inclusion.point_triangle_ccd`` / ``edge_edge_ccd``, which return the
time of impact unscaled; ``ipctk.TightInclusionCCD`` would rescale it). Hits become face pairs with
usdksl's semantics (DESIGN.md):

- a face includes its edges and vertices: a vertex touching a triangle makes every triangle around the
  vertex touch it; two edges touching make every triangle around one touch every triangle around the
  other; triangles map to their authored faces;
- primitive pairs that share a vertex are never tested; pairs inside one authored face are never
  reported; only the mesh pairs usdksl's scope planner checks are kept (``usdksl.reading.scope.plan_shot``);
- faces already touching at the first sample are reported at that time (CCD at time 0, plus edges
  piercing triangles at the first sample, tested with ``ipctk.is_edge_intersecting_triangle``);
- one row per face pair, at its earliest time.

A primitive pair that hit in one interval is not tested again in later ones: its face pairs already
have a time no later than any later hit. Python touches each ipctk candidate once to read its ids (the
bindings return candidate objects) and once to call the CCD; everything else is numpy.

Modes: ``default`` uses ipctk's own CCD defaults (tolerance 1e-6, 1e7 iterations), as a user would;
``tight`` (tolerance 1e-9, 1e8 iterations) is the independent reference for reported times.
``earliest_contact_sweep`` is what most ipctk users run: ``ipctk.compute_collision_free_stepsize`` per
interval, one earliest time per interval (not per face pair).

Times are USD time codes. Tolerances of Tight-Inclusion are distances in scene units (its codomain
tolerance), not fractions of an interval.
"""

from __future__ import annotations

import argparse
import json
import sys
from dataclasses import dataclass, field
from typing import Dict, List, Optional, Sequence, Tuple

import numpy as np

from harness import Clock

#: ipctk's own defaults for Tight-Inclusion (what a user gets without choosing).
DEFAULT_TOLERANCE = 1e-6
DEFAULT_MAX_ITERATIONS = 10_000_000
#: The tight reference: Tight-Inclusion's codomain tolerance (scene units) and iteration cap.
TIGHT_TOLERANCE = 1e-9
TIGHT_MAX_ITERATIONS = 100_000_000
#: Largest difference between a reported time and the tight reference that still agrees (time codes): the
#: exact-times acceptance threshold (benchmarks/results/exact_times.md).
AGREEMENT_TIME_CODES = 1e-3


@dataclass(frozen=True)
class PeerSettings:
    tolerance: float = DEFAULT_TOLERANCE
    max_iterations: int = DEFAULT_MAX_ITERATIONS
    thickness: float = 0.0
    broad_phase: str = "LBVH"


MODES = {"default": PeerSettings(), "tight": PeerSettings(TIGHT_TOLERANCE, TIGHT_MAX_ITERATIONS)}


@dataclass
class PeerContacts:
    """First contact per authored face pair (time codes), sorted by time; mesh indices into ``paths``.
    Self rows: mesh_a == mesh_b, face_a < face_b; inter rows: mesh_a < mesh_b."""

    paths: List[str]
    time: np.ndarray
    mesh_a: np.ndarray
    face_a: np.ndarray
    mesh_b: np.ndarray
    face_b: np.ndarray
    counters: Dict[str, int] = field(default_factory=dict)

    def __len__(self) -> int:
        return int(self.time.shape[0])

    def keys(self) -> np.ndarray:
        """One string per face pair, order-free: the same as ``csv_pair_keys`` builds from a contacts CSV."""
        paths = np.asarray(self.paths, dtype=object)
        return pair_keys(paths[self.mesh_a].astype(str), self.face_a, paths[self.mesh_b].astype(str), self.face_b)


# --------------------------------------------------------------------------- the combined mesh

@dataclass
class CombinedMesh:
    """All checked meshes in one vertex and triangle numbering (what ipctk sees), with adjacency."""

    paths: List[str]
    times: np.ndarray                 # float64[K], union of the meshes' sample times
    positions: np.ndarray             # float64[K, V, 3]
    triangles: np.ndarray             # int32[F, 3], combined vertex ids
    edges: np.ndarray                 # int32[E, 2]
    vertex_mesh: np.ndarray           # int64[V]
    triangle_mesh: np.ndarray         # int64[F]
    triangle_face: np.ndarray         # int64[F], authored face within its mesh
    edge_mesh: np.ndarray             # int64[E]
    vertex_triangles: Tuple[np.ndarray, np.ndarray]   # CSR (offsets[V + 1], triangle ids)
    edge_triangles: Tuple[np.ndarray, np.ndarray]     # CSR (offsets[E + 1], triangle ids)
    allowed: np.ndarray               # bool[M, M], symmetric: mesh pair checked (diagonal: self)
    dynamic_vertices: int             # vertices [0, dynamic) belong to meshes that move


def _csr(keys: np.ndarray, values: np.ndarray, count: int) -> Tuple[np.ndarray, np.ndarray]:
    order = np.argsort(keys, kind="stable")
    offsets = np.zeros(count + 1, np.int64)
    np.cumsum(np.bincount(keys, minlength=count), out=offsets[1:])
    return offsets, values[order]


def _mesh_points_at(mesh, times: np.ndarray) -> np.ndarray:
    """float64[T, N, 3]: a mesh's points linearly interpolated at ``times`` (held outside its samples)."""
    points = np.asarray(mesh.points, np.float64)
    if len(mesh.times) == 1:
        return np.broadcast_to(points[0], (len(times),) + points.shape[1:]).copy()
    segment = np.clip(np.searchsorted(mesh.times, times, side="right") - 1, 0, len(mesh.times) - 2)
    t0, t1 = mesh.times[segment], mesh.times[segment + 1]
    weight = np.clip((times - t0) / (t1 - t0), 0.0, 1.0)[:, None, None]
    return (1.0 - weight) * points[segment] + weight * points[segment + 1]


def combine(meshes: Sequence, pairs: np.ndarray, moving: Sequence[bool],
            time_range: Optional[Tuple[float, float]] = None) -> CombinedMesh:
    """One CollisionMesh's worth of arrays from loader meshes and the checked mesh pairs.

    Only meshes that take part in a checked pair are included; moving meshes come first so that
    ``ipctk.make_static_obstacle_filter`` can drop still-against-still vertex pairs."""
    pairs = np.asarray(pairs, np.int64).reshape(-1, 2)
    used = sorted(set(pairs.reshape(-1).tolist()))
    order = [i for i in used if moving[i]] + [i for i in used if not moving[i]]
    local = {mesh_index: position for position, mesh_index in enumerate(order)}
    allowed = np.zeros((len(order), len(order)), bool)
    for i, j in pairs.tolist():
        allowed[local[i], local[j]] = allowed[local[j], local[i]] = True
    chosen = [meshes[i] for i in order]
    all_times = np.unique(np.concatenate([np.asarray(m.times, np.float64) for m in chosen])) if chosen \
        else np.zeros(1)
    if time_range is not None:
        inside = all_times[(all_times > time_range[0]) & (all_times < time_range[1])]
        all_times = np.unique(np.concatenate([[time_range[0]], inside, [time_range[1]]]))
    vertex_counts = np.array([m.points.shape[1] for m in chosen], np.int64)
    vertex_offsets = np.concatenate([[0], np.cumsum(vertex_counts)])
    positions = (np.concatenate([_mesh_points_at(m, all_times) for m in chosen], axis=1) if chosen
                 else np.zeros((len(all_times), 0, 3)))
    triangles = (np.concatenate([np.asarray(m.triangles, np.int64) + vertex_offsets[k] for k, m in enumerate(chosen)])
                 if chosen else np.zeros((0, 3), np.int64))
    triangle_mesh = (np.concatenate([np.full(len(m.triangles), k, np.int64) for k, m in enumerate(chosen)])
                     if chosen else np.zeros(0, np.int64))
    triangle_face = (np.concatenate([np.asarray(m.triangle_face, np.int64) for m in chosen]) if chosen
                     else np.zeros(0, np.int64))
    vertex_mesh = np.repeat(np.arange(len(chosen), dtype=np.int64), vertex_counts)
    triangle_count = len(triangles)
    corner_edges = np.sort(np.concatenate([triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]]), axis=1)
    edges, edge_of_corner = np.unique(corner_edges, axis=0, return_inverse=True)
    edge_of_corner = edge_of_corner.reshape(-1)
    corner_triangle = np.tile(np.arange(triangle_count, dtype=np.int64), 3)
    vertex_triangles = _csr(triangles.reshape(-1), np.repeat(np.arange(triangle_count, dtype=np.int64), 3),
                            len(vertex_mesh))
    edge_triangles = _csr(edge_of_corner, corner_triangle, len(edges))
    dynamic = int(sum(vertex_counts[k] for k, i in enumerate(order) if moving[i]))
    return CombinedMesh(paths=[meshes[i].path for i in order], times=all_times, positions=positions,
                        triangles=triangles.astype(np.int32), edges=edges.astype(np.int32),
                        vertex_mesh=vertex_mesh, triangle_mesh=triangle_mesh, triangle_face=triangle_face,
                        edge_mesh=vertex_mesh[edges[:, 0]] if len(edges) else np.zeros(0, np.int64),
                        vertex_triangles=vertex_triangles, edge_triangles=edge_triangles, allowed=allowed,
                        dynamic_vertices=dynamic)


def load_combined(shot_path: str) -> CombinedMesh:
    """Load a shot and plan its pairs the way ``usdksl check`` does (defaults), through the public API."""
    import usdksl
    from usdksl.reading.scope import ScopeOptions, plan_shot

    shot = usdksl.load_shot(shot_path)
    plan = plan_shot(shot, ScopeOptions())
    return combine(shot.meshes, plan.pairs, plan.moving)


def _ipctk_mesh(combined: CombinedMesh):
    import ipctk

    mesh = ipctk.CollisionMesh(np.asfortranarray(combined.positions[0]), np.asfortranarray(combined.edges),
                               np.asfortranarray(combined.triangles))
    if combined.dynamic_vertices < len(combined.vertex_mesh):
        mesh.can_collide = ipctk.make_static_obstacle_filter(combined.dynamic_vertices)
    return mesh


def _broad_phase(name: str):
    import ipctk

    return getattr(ipctk, name)()


# --------------------------------------------------------------------------- primitive hits -> face pairs

def _expand(csr: Tuple[np.ndarray, np.ndarray], ids: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
    """(row of ids, triangle) for every triangle around each id (CSR lookup, vectorised)."""
    offsets, values = csr
    counts = offsets[ids + 1] - offsets[ids]
    rows = np.repeat(np.arange(len(ids)), counts)
    starts = np.repeat(offsets[ids], counts)
    within = np.arange(counts.sum()) - np.repeat(np.cumsum(counts) - counts, counts)
    return rows, values[starts + within]


def _triangle_pairs_to_faces(combined: CombinedMesh, tri_a: np.ndarray, tri_b: np.ndarray, times: np.ndarray):
    """Face-pair rows (time, mesh_a, face_a, mesh_b, face_b), normalised; pairs inside one face dropped."""
    mesh_a, mesh_b = combined.triangle_mesh[tri_a], combined.triangle_mesh[tri_b]
    face_a, face_b = combined.triangle_face[tri_a], combined.triangle_face[tri_b]
    swap = (mesh_a > mesh_b) | ((mesh_a == mesh_b) & (face_a > face_b))
    mesh_a, mesh_b = np.where(swap, mesh_b, mesh_a), np.where(swap, mesh_a, mesh_b)
    face_a, face_b = np.where(swap, face_b, face_a), np.where(swap, face_a, face_b)
    keep = ~((mesh_a == mesh_b) & (face_a == face_b))
    return times[keep], mesh_a[keep], face_a[keep], mesh_b[keep], face_b[keep]


def vertex_face_hits_to_faces(combined: CombinedMesh, vertices: np.ndarray, triangles: np.ndarray,
                              times: np.ndarray):
    """A vertex touching a triangle: every triangle around the vertex touches that triangle."""
    rows, around = _expand(combined.vertex_triangles, np.asarray(vertices, np.int64))
    return _triangle_pairs_to_faces(combined, around, np.asarray(triangles, np.int64)[rows], times[rows])


def edge_edge_hits_to_faces(combined: CombinedMesh, edges_a: np.ndarray, edges_b: np.ndarray, times: np.ndarray):
    """Two edges touching: every triangle around one touches every triangle around the other."""
    rows_a, around_a = _expand(combined.edge_triangles, np.asarray(edges_a, np.int64))
    edges_b = np.asarray(edges_b, np.int64)[rows_a]
    rows_b, around_b = _expand(combined.edge_triangles, edges_b)
    return _triangle_pairs_to_faces(combined, around_a[rows_b], around_b, times[rows_a][rows_b])


def earliest_per_face_pair(paths: List[str], rows: Sequence[Tuple[np.ndarray, ...]],
                           counters: Dict[str, int]) -> PeerContacts:
    """Keep the earliest row of every face pair; sort by (time, mesh_a, face_a, mesh_b, face_b)."""
    if rows:
        time_, mesh_a, face_a, mesh_b, face_b = (np.concatenate(column) for column in zip(*rows))
    else:
        time_ = np.zeros(0)
        mesh_a = face_a = mesh_b = face_b = np.zeros(0, np.int64)
    order = np.lexsort((time_, face_b, mesh_b, face_a, mesh_a))
    keys = np.stack([mesh_a, face_a, mesh_b, face_b])[:, order]
    head = np.ones(order.shape[0], bool)
    head[1:] = np.any(keys[:, 1:] != keys[:, :-1], axis=0)
    chosen = order[head]
    time_, mesh_a, face_a, mesh_b, face_b = (a[chosen] for a in (time_, mesh_a, face_a, mesh_b, face_b))
    final = np.lexsort((face_b, mesh_b, face_a, mesh_a, time_))
    return PeerContacts(paths=list(paths), time=time_[final], mesh_a=mesh_a[final], face_a=face_a[final],
                        mesh_b=mesh_b[final], face_b=face_b[final], counters=dict(counters))


# --------------------------------------------------------------------------- the pipeline

def _candidate_ids(candidates) -> Tuple[np.ndarray, np.ndarray]:
    fv = candidates.fv_candidates
    ee = candidates.ee_candidates
    fv_ids = (np.fromiter((x for c in fv for x in (c.vertex_id, c.face_id)), np.int64, 2 * len(fv)).reshape(-1, 2)
              if len(fv) else np.zeros((0, 2), np.int64))
    ee_ids = (np.fromiter((x for c in ee for x in (c.edge0_id, c.edge1_id)), np.int64, 2 * len(ee)).reshape(-1, 2)
              if len(ee) else np.zeros((0, 2), np.int64))
    return fv_ids, ee_ids


def _keep_vertex_face(combined: CombinedMesh, ids: np.ndarray) -> np.ndarray:
    vertex, triangle = ids[:, 0], ids[:, 1]
    corners = combined.triangles[triangle]
    shares = np.any(corners == vertex[:, None], axis=1)
    return ~shares & combined.allowed[combined.vertex_mesh[vertex], combined.triangle_mesh[triangle]]


def _keep_edge_edge(combined: CombinedMesh, ids: np.ndarray) -> np.ndarray:
    a, b = combined.edges[ids[:, 0]], combined.edges[ids[:, 1]]
    shares = (a[:, :1] == b).any(axis=1) | (a[:, 1:] == b).any(axis=1)
    return ~shares & combined.allowed[combined.edge_mesh[ids[:, 0]], combined.edge_mesh[ids[:, 1]]]


def _first_sample_piercings(combined: CombinedMesh, settings: PeerSettings, counters: Dict[str, int]):
    """Edges piercing triangles at the first sample (faces intersecting without a touching vertex or edge)."""
    import ipctk

    broad_phase = _broad_phase(settings.broad_phase)
    positions = np.asfortranarray(combined.positions[0])
    broad_phase.build(positions, np.asfortranarray(combined.edges), np.asfortranarray(combined.triangles),
                      settings.thickness)
    found = broad_phase.detect_edge_face_candidates()
    if not found:
        return None
    ids = np.fromiter((x for c in found for x in (c.edge_id, c.face_id)), np.int64, 2 * len(found)).reshape(-1, 2)
    edge_vertices, corners = combined.edges[ids[:, 0]], combined.triangles[ids[:, 1]]
    shares = (corners[:, :, None] == edge_vertices[:, None, :]).any(axis=(1, 2))
    keep = ~shares & combined.allowed[combined.edge_mesh[ids[:, 0]], combined.triangle_mesh[ids[:, 1]]]
    ids = ids[keep]
    counters["first_sample_edge_face_tests"] += len(ids)
    e0, e1 = positions[combined.edges[ids[:, 0], 0]], positions[combined.edges[ids[:, 0], 1]]
    t = positions[combined.triangles[ids[:, 1]]]
    hit = np.fromiter((ipctk.is_edge_intersecting_triangle(e0[i], e1[i], t[i, 0], t[i, 1], t[i, 2])
                       for i in range(len(ids))), bool, len(ids))
    if not hit.any():
        return None
    ids = ids[hit]
    rows, around = _expand(combined.edge_triangles, ids[:, 0])
    times = np.full(len(rows), combined.times[0])
    return _triangle_pairs_to_faces(combined, around, ids[rows, 1], times)


def all_first_contacts(combined: CombinedMesh, settings: PeerSettings = PeerSettings(),
                       progress=None) -> PeerContacts:
    """Every contacting face pair and its first-contact time over the whole shot (see the module docstring)."""
    import ipctk
    from ipctk import tight_inclusion

    counters = {"intervals": max(len(combined.times) - 1, 0), "vertex_face_candidates": 0,
                "edge_edge_candidates": 0, "ccd_queries": 0, "ccd_hits": 0, "first_sample_edge_face_tests": 0}
    rows: List[Tuple[np.ndarray, ...]] = []
    if len(combined.triangles) == 0:
        return earliest_per_face_pair(combined.paths, rows, counters)
    mesh = _ipctk_mesh(combined)
    broad_phase = _broad_phase(settings.broad_phase)
    piercings = _first_sample_piercings(combined, settings, counters)
    if piercings is not None:
        rows.append(piercings)
    edge_count = len(combined.edges)
    hit_vf = np.zeros(0, np.int64)      # primitive pairs already hit: later hits cannot be earlier
    hit_ee = np.zeros(0, np.int64)
    tolerance, iterations, thickness = settings.tolerance, settings.max_iterations, settings.thickness
    candidates = ipctk.Candidates()
    for k in range(len(combined.times) - 1):
        v0 = np.asfortranarray(combined.positions[k])
        v1 = np.asfortranarray(combined.positions[k + 1])
        if not np.any(v0[:combined.dynamic_vertices] != v1[:combined.dynamic_vertices]) and k > 0:
            continue     # nothing moves in this interval: any contact here already showed at its start
        candidates.build(mesh, v0, v1, thickness, broad_phase)
        fv_ids, ee_ids = _candidate_ids(candidates)
        counters["vertex_face_candidates"] += len(fv_ids)
        counters["edge_edge_candidates"] += len(ee_ids)
        fv_ids = fv_ids[_keep_vertex_face(combined, fv_ids)] if len(fv_ids) else fv_ids
        ee_ids = ee_ids[_keep_edge_edge(combined, ee_ids)] if len(ee_ids) else ee_ids
        fv_keys = fv_ids[:, 0] * len(combined.triangles) + fv_ids[:, 1]
        ee_keys = np.minimum(ee_ids[:, 0], ee_ids[:, 1]) * edge_count + np.maximum(ee_ids[:, 0], ee_ids[:, 1])
        fresh_fv, fresh_ee = ~np.isin(fv_keys, hit_vf), ~np.isin(ee_keys, hit_ee)
        fv_ids, fv_keys = fv_ids[fresh_fv], fv_keys[fresh_fv]
        ee_ids, ee_keys = ee_ids[fresh_ee], ee_keys[fresh_ee]
        t0, t1 = combined.times[k], combined.times[k + 1]

        if len(fv_ids):
            p = np.stack([v0[fv_ids[:, 0]]] + [v0[combined.triangles[fv_ids[:, 1], c]] for c in range(3)]
                         + [v1[fv_ids[:, 0]]] + [v1[combined.triangles[fv_ids[:, 1], c]] for c in range(3)], axis=1)
            result = [tight_inclusion.point_triangle_ccd(*q, thickness, 1.0, tolerance, iterations) for q in p]
            hit = np.fromiter((r[0] for r in result), bool, len(result))
            toi = np.fromiter((r[1] for r in result), np.float64, len(result))
            counters["ccd_queries"] += len(result)
            if hit.any():
                counters["ccd_hits"] += int(hit.sum())
                hit_vf = np.union1d(hit_vf, fv_keys[hit])
                rows.append(vertex_face_hits_to_faces(combined, fv_ids[hit, 0], fv_ids[hit, 1],
                                                      t0 + toi[hit] * (t1 - t0)))
        if len(ee_ids):
            ea, eb = combined.edges[ee_ids[:, 0]], combined.edges[ee_ids[:, 1]]
            p = np.stack([v0[ea[:, 0]], v0[ea[:, 1]], v0[eb[:, 0]], v0[eb[:, 1]],
                          v1[ea[:, 0]], v1[ea[:, 1]], v1[eb[:, 0]], v1[eb[:, 1]]], axis=1)
            result = [tight_inclusion.edge_edge_ccd(*q, thickness, 1.0, tolerance, iterations) for q in p]
            hit = np.fromiter((r[0] for r in result), bool, len(result))
            toi = np.fromiter((r[1] for r in result), np.float64, len(result))
            counters["ccd_queries"] += len(result)
            if hit.any():
                counters["ccd_hits"] += int(hit.sum())
                hit_ee = np.union1d(hit_ee, ee_keys[hit])
                rows.append(edge_edge_hits_to_faces(combined, ee_ids[hit, 0], ee_ids[hit, 1],
                                                    t0 + toi[hit] * (t1 - t0)))
        if progress is not None:
            progress(k + 1, len(combined.times) - 1)
    return earliest_per_face_pair(combined.paths, rows, counters)


def earliest_contact_sweep(combined: CombinedMesh, settings: PeerSettings = PeerSettings()):
    """ipctk as most of its users run it: ``compute_collision_free_stepsize`` per sample interval with an
    unscaled Tight-Inclusion CCD. Returns (interval index, earliest contact time) of every interval whose
    collision-free step is below 1, and counters. One time per interval, no face pairs."""
    import ipctk

    mesh = _ipctk_mesh(combined)
    broad_phase = _broad_phase(settings.broad_phase)
    ccd = ipctk.TightInclusionCCD(settings.tolerance, settings.max_iterations, 1.0)
    starts, times = [], []
    for k in range(len(combined.times) - 1):
        step = ipctk.compute_collision_free_stepsize(mesh, np.asfortranarray(combined.positions[k]),
                                                     np.asfortranarray(combined.positions[k + 1]),
                                                     settings.thickness, broad_phase, ccd)
        if step < 1.0:
            starts.append(k)
            times.append(combined.times[k] + step * (combined.times[k + 1] - combined.times[k]))
    return (np.asarray(starts, np.int64), np.asarray(times, np.float64),
            {"intervals": max(len(combined.times) - 1, 0), "intervals_with_contact": len(starts)})


# --------------------------------------------------------------------------- comparing usdksl's answer

def pair_keys(prim_a, face_a, prim_b, face_b) -> np.ndarray:
    """Order-free string key per face pair: the smaller (prim, face) first."""
    if len(np.asarray(face_a)) == 0:
        return np.zeros(0, str)     # numpy's zfill cannot size an empty array
    side_a = np.char.add(np.char.add(np.asarray(prim_a, str), "#"), np.char.zfill(np.asarray(face_a).astype(str), 10))
    side_b = np.char.add(np.char.add(np.asarray(prim_b, str), "#"), np.char.zfill(np.asarray(face_b).astype(str), 10))
    low, high = np.where(side_a <= side_b, side_a, side_b), np.where(side_a <= side_b, side_b, side_a)
    return np.char.add(np.char.add(low, "|"), high)


def read_contacts_csv(path: str) -> Tuple[np.ndarray, np.ndarray]:
    """(keys, times) of a usdksl ``<stem>.contacts.csv`` (columns time,prim_a,face_a,prim_b,face_b,kind,...)."""
    with open(path) as handle:
        header = handle.readline().strip().split(",")
    expected = ["time", "prim_a", "face_a", "prim_b", "face_b", "kind"]
    if header[:6] != expected:
        raise ValueError(f"{path}: expected columns {','.join(expected)}, got {','.join(header)}")
    table = np.loadtxt(path, dtype=str, delimiter=",", skiprows=1, usecols=range(5), ndmin=2, comments=None)
    if table.size == 0:
        return np.zeros(0, str), np.zeros(0)
    return pair_keys(table[:, 1], table[:, 2], table[:, 3], table[:, 4]), table[:, 0].astype(np.float64)


def compare_times(reported_keys: np.ndarray, reported_times: np.ndarray, reference_keys: np.ndarray,
                  reference_times: np.ndarray, agreement: float = AGREEMENT_TIME_CODES) -> Dict:
    """Reported first contacts against a reference (face-pair keys from ``pair_keys``, times in time codes):
    the exact-times acceptance numbers. ``error = reported - reference``: negative is early, positive late."""
    common, at_reported, at_reference = np.intersect1d(reported_keys, reference_keys, return_indices=True)
    error = np.asarray(reported_times, np.float64)[at_reported] - np.asarray(reference_times, np.float64)[at_reference]
    within = np.abs(error) <= agreement
    unconfirmed = np.setdiff1d(reported_keys, reference_keys)
    missing = np.setdiff1d(reference_keys, reported_keys)
    return {
        "reported_pairs": int(len(reported_keys)),
        "reference_pairs": int(len(reference_keys)),
        "common_pairs": int(len(common)),
        "agreement_time_codes": agreement,
        "within_agreement": int(within.sum()),
        "within_agreement_fraction": float(within.mean()) if len(common) else float("nan"),
        "largest_early_error": float(max(0.0, -error.min())) if len(error) else 0.0,
        "largest_late_error": float(max(0.0, error.max())) if len(error) else 0.0,
        "reported_without_reference_touch": int(len(unconfirmed)),
        "reference_pairs_missing_from_report": int(len(missing)),
        "examples_without_reference_touch": unconfirmed[:5].tolist(),
        "examples_missing_from_report": missing[:5].tolist(),
    }


def compare_csv_to_tight_reference(shot_path: str, contacts_csv: str, reference: Optional[PeerContacts] = None,
                                   thickness: float = 0.0) -> Tuple[Dict, PeerContacts]:
    """usdksl's contacts CSV of ``shot_path`` against the tight reference (computed unless given)."""
    if reference is None:
        reference = all_first_contacts(load_combined(shot_path), PeerSettings(TIGHT_TOLERANCE, TIGHT_MAX_ITERATIONS,
                                                                             thickness))
    keys, times = read_contacts_csv(contacts_csv)
    return compare_times(keys, times, reference.keys(), reference.time), reference


def contacts_csv_text(contacts: PeerContacts) -> str:
    """The peer's answer in usdksl's contacts CSV columns (for diffing with ``usdksl check`` output)."""
    paths = np.asarray(contacts.paths, dtype=object)
    lines = ["time,prim_a,face_a,prim_b,face_b,kind"]
    for t, a, fa, b, fb in zip(contacts.time.tolist(), paths[contacts.mesh_a].tolist(), contacts.face_a.tolist(),
                               paths[contacts.mesh_b].tolist(), contacts.face_b.tolist()):
        lines.append(f"{t!r},{a},{fa},{b},{fb},{'self' if a == b else 'inter'}")
    return "\n".join(lines) + "\n"


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("shot")
    parser.add_argument("--mode", choices=sorted(MODES) + ["sweep"], default="default")
    parser.add_argument("--thickness", type=float, default=0.0)
    parser.add_argument("--csv", default=None, help="write the face pairs (with --compare: the tight reference's) as a contacts CSV")
    parser.add_argument("--compare", default=None, metavar="CONTACTS_CSV",
                        help="compare a usdksl contacts CSV of SHOT against the tight reference (prints JSON)")
    parser.add_argument("--reference", default=None, metavar="REFERENCE_CSV",
                        help="with --compare: the tight reference written earlier by --csv, instead of computing it")
    args = parser.parse_args(argv)
    clock = Clock()
    if args.compare and args.reference:
        report = compare_times(*read_contacts_csv(args.compare), *read_contacts_csv(args.reference))
        report["reference"] = args.reference
        print(json.dumps(report, indent=2))
        return 0
    if args.compare:
        report, reference = compare_csv_to_tight_reference(args.shot, args.compare, thickness=args.thickness)
        report["reference_seconds"] = round(clock.wall_s(), 2)
        if args.csv:
            with open(args.csv, "w") as handle:
                handle.write(contacts_csv_text(reference))
        print(json.dumps(report, indent=2))
        return 0
    combined = load_combined(args.shot)
    if args.mode == "sweep":
        starts, times, counters = earliest_contact_sweep(combined, PeerSettings(thickness=args.thickness))
        print(f"{len(starts)} of {counters['intervals']} intervals with contact; first at "
              f"{times[0] if len(times) else float('nan'):g}; {clock.wall_s():.1f} s")
        return 0
    settings = MODES[args.mode]
    settings = PeerSettings(settings.tolerance, settings.max_iterations, args.thickness, settings.broad_phase)
    contacts = all_first_contacts(combined, settings)
    if args.csv:
        with open(args.csv, "w") as handle:
            handle.write(contacts_csv_text(contacts))
    print(f"{len(contacts)} face pairs; counters {contacts.counters}; {clock.wall_s():.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
