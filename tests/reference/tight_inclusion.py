"""First contacts of whole triangle pairs and whole shots from ipctk's Tight-Inclusion CCD, sharing no code
with the product's narrow phase: a reference for the product's own brute force.

What it computes (docs/contracts.md, Motion, Faces, Contacts):

* every triangle pair of the checked mesh pairs, on every raw sample interval of its two meshes (the
  union of their sample times inside the checked range, with the range's ends; a vertex moves in a
  straight line between samples and holds still outside them);
* on each interval, the 15 primitive pairs of the triangle pair: the three vertices of each triangle
  against the other triangle (6 ``ipctk.tight_inclusion.point_triangle_ccd`` queries, both ways) and
  every edge of one against every edge of the other (9 ``edge_edge_ccd`` queries). Primitive pairs that
  share a vertex are never tested, and two triangles of one authored face never make a contact;
* faces that properly intersect at the start of the range (an edge piercing the inside of the other
  face, which no vertex-face or edge-edge query sees; signed volumes in numpy): the contract's
  ``initial`` contacts;
* the earliest time (time codes) of each authored face pair.

The broad phase is plain numpy (swept boxes per interval); nothing of ``usdksl`` is imported. ipctk has no
batch Tight-Inclusion call, so each primitive query is one Python call (about 50 to 100 microseconds):
the tests run this on small meshes only.

Tolerance. Tight-Inclusion's ``tolerance`` is a distance (its codomain tolerance, scene units), not a
fraction of the interval: it returns the start of the earliest parameter box whose image overlaps the
per-axis box [-(ms + err), ms + err] (``ms`` the minimum separation, ``err`` its rounding filter, about
1e-14 here) and is at most ``tolerance`` wide. So its time is never late, and at that time the pair is
within ``ms + err + tolerance`` of touching on every axis. No conservative rescaling is applied (ipctk's
``TightInclusionCCD`` class would scale the time by 0.8; the raw ``tight_inclusion`` functions do not).
The tolerance is REFERENCE_TOLERANCE (1e-12 scene units) at separation 0 and SEPARATION_TOLERANCE (a tenth)
of a positive separation. A query that reaches REFERENCE_MAX_ITERATIONS (pairs sliding in one plane, whose
roots fill a curve) answers "maybe" only.

Thickness. Tight-Inclusion's minimum separation is a per-axis box, the contract's thickness a Euclidean
distance. At a thickness ``h > 0`` the reference therefore answers twice:

* ``must``: separation ``h / sqrt(3)`` less twice its tolerance, a box inside the Euclidean ball even
  with the tolerance added: at its time every pair found is within ``h``, so the product must report it
  and, never being late, at that time or before;
* ``may``: separation ``h + MAY_MARGIN``, a box around the ball with room for the distance the product
  may move within its own tolerance: every pair the product reports must be found, and the product,
  early by at most its tolerance of the interval, no earlier than that.

At thickness 0 one query answers both (separation 0): a pair found there must be reported, at most
REFERENCE_LATE_SLACK of its interval after the reference's time (the time a pair takes to close 1e-12;
below 1e-9 of an interval on the test scenes), and every reported pair must be found.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Dict, Iterable, List, Optional, Sequence, Tuple

import numpy as np
from ipctk import tight_inclusion

#: Tight-Inclusion's codomain tolerance (scene units; the test meshes are about one unit across) at a
#: separation of 0: far above its rounding filter (about 1e-14 here), so its times are early by the time
#: a pair takes to close 1e-12.
REFERENCE_TOLERANCE = 1e-12
#: Codomain tolerance at a positive separation, as a fraction of it: a minimum-separation query refines
#: the whole surface of its separation box down to the tolerance, which at 1e-12 takes millions of
#: refinements, and still hundreds of thousands at 1 %; at a tenth each query is fast. The ``must``
#: separation is shrunk by twice the tolerance, so its answers stay inside the thickness all the same.
SEPARATION_TOLERANCE = 0.1
#: At thickness 0: how much later than the reference's time (a fraction of the raw interval) the product
#: may report a pair. Tight-Inclusion's time is early by the time the pair takes to close
#: REFERENCE_TOLERANCE, below 1e-9 of an interval on the test scenes; a tenth of the product's own
#: tolerance (1e-6 of an interval) leaves room and still catches a contact reported late.
REFERENCE_LATE_SLACK = 1e-7
#: Refinements of one Tight-Inclusion query before it gives up; a query that reaches it is counted as a
#: possible contact (``may``) and never as a certain one (``must``). Coplanar and parallel sliding pairs
#: reach any cap (their roots fill a curve, refined level by level); at 10,000 each costs about 5 ms.
REFERENCE_MAX_ITERATIONS = 10_000
#: Room (scene units) added to the thickness for the ``may`` answer: the product decides a pair to its
#: tolerance, so a pair it reports may come within the thickness plus the distance it moves within a
#: millionth of its interval (far below this on the test meshes), plus rounding.
MAY_MARGIN = 1e-7
#: Padding (scene units) of the numpy broad phase's swept boxes beyond the ``may`` separation: the
#: boxes only drop queries Tight-Inclusion could not find anyway, so it is generous.
BOX_PADDING = 1e-6
#: Largest number of triangle pairs whose boxes are compared at once (memory of the broad phase).
BOX_PAIRS_PER_CHUNK = 2_000_000

#: Features, as the contract names them, of the query that touched first; the contract's order.
VERTEX_FACE, FACE_VERTEX, EDGE_EDGE, INITIAL = 0, 1, 2, 3

#: Primitive queries of one triangle pair (a, b), in the order the feature codes rank them: vertex i of a
#: against b, vertex j of b against a, edge i of a against edge j of b (edge i runs from corner i to
#: corner i + 1).
_SLOT_FEATURE = np.array([VERTEX_FACE] * 3 + [FACE_VERTEX] * 3 + [EDGE_EDGE] * 9, np.int8)


@dataclass
class ReferenceContacts:
    """First contact per authored face pair, keyed ``(mesh_a, face_a, mesh_b, face_b)`` with the smaller
    (mesh, face) side first.

    ``must``/``may``: time codes (see the module docstring), with ``must_step``/``may_step`` the length
    (time codes) of the raw interval each lies on; ``feature``: what touched first in the ``must`` answer,
    for the key's sides in key order (vertex-face: a vertex of the key's first face); ``capped``: face
    pairs whose earliest ``may`` query reached the iteration cap; ``late_slack``: how late the product may
    be (a fraction of the interval); ``queries``: Tight-Inclusion calls made."""

    must: Dict[Tuple[int, int, int, int], float] = field(default_factory=dict)
    must_step: Dict[Tuple[int, int, int, int], float] = field(default_factory=dict)
    may: Dict[Tuple[int, int, int, int], float] = field(default_factory=dict)
    may_step: Dict[Tuple[int, int, int, int], float] = field(default_factory=dict)
    feature: Dict[Tuple[int, int, int, int], int] = field(default_factory=dict)
    capped: set = field(default_factory=set)
    late_slack: float = 0.0
    queries: int = 0


def points_at(mesh, times: np.ndarray) -> np.ndarray:
    """float64[T, N, 3]: the mesh's points at ``times`` (time codes), linear between samples and held
    outside them."""
    sample_times = np.asarray(mesh.times, np.float64)
    points = np.asarray(mesh.points, np.float64)
    if sample_times.size == 1:
        return np.broadcast_to(points[0], (len(times),) + points.shape[1:]).copy()
    segment = np.clip(np.searchsorted(sample_times, times, side="right") - 1, 0, sample_times.size - 2)
    t0, t1 = sample_times[segment], sample_times[segment + 1]
    weight = np.clip((times - t0) / (t1 - t0), 0.0, 1.0)[:, None, None]
    return (1.0 - weight) * points[segment] + weight * points[segment + 1]


def step_times(meshes: Sequence, i: int, j: int, t_begin: float, t_end: float) -> np.ndarray:
    """float64[K]: the raw sample times of mesh pair (i, j) inside [t_begin, t_end], with both ends."""
    samples = np.unique(np.concatenate([np.asarray(meshes[i].times, np.float64),
                                        np.asarray(meshes[j].times, np.float64)]))
    inside = samples[(samples > t_begin) & (samples < t_end)]
    return np.unique(np.concatenate([[t_begin], inside, [t_end]]))


def _swept_boxes(start: np.ndarray, end: np.ndarray, corners: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
    """(lo, hi) float64[M, 3]: boxes around the linear motion of the corner sets ``corners`` (int[M, C])."""
    both = np.concatenate([start[corners], end[corners]], axis=1)
    return both.min(axis=1), both.max(axis=1)


def _overlapping(lo_a, hi_a, lo_b, hi_b, reach: float) -> Tuple[np.ndarray, np.ndarray]:
    """(a, b) int64[P]: every pair of boxes within ``reach`` of each other on every axis."""
    rows_per_chunk = max(1, BOX_PAIRS_PER_CHUNK // max(1, len(lo_b)))
    found_a, found_b = [np.zeros(0, np.int64)], [np.zeros(0, np.int64)]
    for first in range(0, len(lo_a), rows_per_chunk):
        last = min(len(lo_a), first + rows_per_chunk)
        near = np.all((lo_a[first:last, None, :] <= hi_b[None, :, :] + reach) &
                      (lo_b[None, :, :] <= hi_a[first:last, None, :] + reach), axis=2)
        a, b = np.nonzero(near)
        found_a.append(a + first)
        found_b.append(b)
    return np.concatenate(found_a), np.concatenate(found_b)


def _face_keys(mesh_a, face_a: np.ndarray, mesh_b, face_b: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
    """(int64[P, 4] face pair keys with the smaller (mesh, face) side first, bool[P] sides swapped to get
    there); the meshes are indices or arrays of them."""
    side_a = np.stack(np.broadcast_arrays(np.asarray(mesh_a, np.int64), np.asarray(face_a, np.int64)), axis=1)
    side_b = np.stack(np.broadcast_arrays(np.asarray(mesh_b, np.int64), np.asarray(face_b, np.int64)), axis=1)
    swap = (side_a[:, 0] > side_b[:, 0]) | ((side_a[:, 0] == side_b[:, 0]) & (side_a[:, 1] > side_b[:, 1]))
    keys = np.concatenate([np.where(swap[:, None], side_b, side_a), np.where(swap[:, None], side_a, side_b)],
                          axis=1)
    return keys, swap


def _queries(tri_a: np.ndarray, tri_b: np.ndarray, same_mesh: bool) -> Tuple[np.ndarray, np.ndarray]:
    """The 15 primitive queries of each triangle pair, as vertex ids into the pair's joint vertex array.

    ``tri_a``/``tri_b``: int64[P, 3] corner ids. Returns (ids int64[P, 15, 4], valid bool[P, 15]): rows 0-2
    vertex i of a then the corners of b, rows 3-5 vertex j of b then the corners of a, rows 6-14 edge i of
    a then edge j of b. Within one mesh, a query whose two primitives share a vertex is not valid."""
    count = tri_a.shape[0]
    ids = np.empty((count, 15, 4), np.int64)
    for i in range(3):
        ids[:, i, 0], ids[:, i, 1:] = tri_a[:, i], tri_b
        ids[:, 3 + i, 0], ids[:, 3 + i, 1:] = tri_b[:, i], tri_a
        for j in range(3):
            slot = 6 + 3 * i + j
            ids[:, slot, 0], ids[:, slot, 1] = tri_a[:, i], tri_a[:, (i + 1) % 3]
            ids[:, slot, 2], ids[:, slot, 3] = tri_b[:, j], tri_b[:, (j + 1) % 3]
    valid = np.ones((count, 15), bool)
    if same_mesh:
        vertex_face = np.any(ids[:, :6, :1] == ids[:, :6, 1:], axis=2)
        edge_edge = np.any(ids[:, 6:, :2, None] == ids[:, 6:, None, 2:], axis=(2, 3))
        valid[:, :6] = ~vertex_face
        valid[:, 6:] = ~edge_edge
    return ids, valid


def _query_keys(ids: np.ndarray, slots: np.ndarray) -> np.ndarray:
    """int64[Q, 5]: one key per distinct primitive pair (a vertex and its face's corners as a set, two
    edges as sets, in either order), so each is asked once per interval."""
    keys = np.zeros((ids.shape[0], 5), np.int64)
    vertex_face = slots < 6
    corners = np.sort(ids[vertex_face, 1:], axis=1)
    keys[vertex_face, 1] = ids[vertex_face, 0]
    keys[vertex_face, 2:] = corners
    edges = ~vertex_face
    first = np.sort(ids[edges, :2], axis=1)
    second = np.sort(ids[edges, 2:], axis=1)
    swap = (first[:, 0] > second[:, 0]) | ((first[:, 0] == second[:, 0]) & (first[:, 1] > second[:, 1]))
    keys[edges, 0] = 1
    keys[edges, 1:3] = np.where(swap[:, None], second, first)
    keys[edges, 3:5] = np.where(swap[:, None], first, second)
    return keys


def tolerance_at(separation: float) -> float:
    """Tight-Inclusion's codomain tolerance (scene units) for a query at ``separation`` (scene units)."""
    return max(REFERENCE_TOLERANCE, SEPARATION_TOLERANCE * separation)


def _ask(points: np.ndarray, vertex_face: bool, separation: float) -> Tuple[bool, float, bool]:
    """One Tight-Inclusion query on float64[8, 3] (the 4 points at the interval's start, then its end):
    (hit, time of impact in [0, 1], reached the iteration cap)."""
    function = tight_inclusion.point_triangle_ccd if vertex_face else tight_inclusion.edge_edge_ccd
    tolerance = tolerance_at(separation)
    hit, toi, reached = function(*points, separation, 1.0, tolerance, REFERENCE_MAX_ITERATIONS)
    return bool(hit), float(toi), bool(hit) and reached > tolerance


def _orientation(a: np.ndarray, b: np.ndarray, c: np.ndarray, d: np.ndarray) -> np.ndarray:
    """float64[P]: the signed volume det(b - a, c - a, d - a) (positive: d above the plane a, b, c)."""
    return np.einsum("ij,ij->i", np.cross(b - a, c - a), d - a)


def _piercing(start: np.ndarray, tri_a: np.ndarray, tri_b: np.ndarray, same_mesh: bool) -> np.ndarray:
    """bool[P]: an edge of one triangle passes strictly through the inside of the other at ``start``: its
    ends strictly on both sides of the other's plane and its line strictly inside the other's three edges.
    A crossing through an edge or a corner is a touch of an edge or a vertex, which the queries at the
    interval's start find; a triangle without area has no inside; an edge sharing a vertex with the other
    triangle never counts."""
    hits = np.zeros(tri_a.shape[0], bool)
    for edge_of, face_of in ((tri_a, tri_b), (tri_b, tri_a)):
        a, b, c = (start[face_of[:, k]] for k in range(3))
        for i in range(3):
            e0, e1 = edge_of[:, i], edge_of[:, (i + 1) % 3]
            p, q = start[e0], start[e1]
            sides = _orientation(a, b, c, p) * _orientation(a, b, c, q) < 0
            around = np.stack([_orientation(p, q, a, b), _orientation(p, q, b, c), _orientation(p, q, c, a)])
            inside = np.all(around > 0, axis=0) | np.all(around < 0, axis=0)
            crossing = sides & inside
            if same_mesh:
                crossing &= ~np.any((face_of == e0[:, None]) | (face_of == e1[:, None]), axis=1)
            hits |= crossing
    return hits


def first_contacts(meshes: Sequence, pairs: Iterable[Tuple[int, int]], thickness: float = 0.0,
                   time_range: Optional[Tuple[float, float]] = None) -> ReferenceContacts:
    """The first contact of every authored face pair of the mesh pairs ``pairs`` ((i, i) a self check).

    ``meshes`` carry times (time codes), points float64[T, N, 3], triangles int[F, 3] and triangle_face
    int[F] (the loader's MeshData or the tests' arrays). ``time_range`` defaults to the span of all the
    meshes' samples, as the product's does. ``thickness`` in scene units."""
    if time_range is None:
        time_range = (min(float(m.times[0]) for m in meshes), max(float(m.times[-1]) for m in meshes))
    t_begin, t_end = float(time_range[0]), float(time_range[1])
    if thickness > 0:
        inner = thickness / math.sqrt(3.0)
        must_separation = inner - 2.0 * tolerance_at(inner)
        may_separation = thickness + MAY_MARGIN
    else:
        must_separation = may_separation = 0.0
    answer = ReferenceContacts(late_slack=0.0 if thickness > 0 else REFERENCE_LATE_SLACK)
    for i, j in pairs:
        _pair_first_contacts(meshes, int(i), int(j), t_begin, t_end, must_separation, may_separation, answer)
    return answer


def _pair_first_contacts(meshes, i: int, j: int, t_begin: float, t_end: float, must_separation: float,
                         may_separation: float, answer: ReferenceContacts) -> None:
    """Fold the first contacts of mesh pair (i, j) over [t_begin, t_end] (time codes) into ``answer``,
    interval by interval in time order."""
    same_mesh = i == j
    times = step_times(meshes, i, j, t_begin, t_end)
    if times.size == 1:  # a range of one instant: the pair held still over it
        times = np.array([t_begin, t_begin])
    tri_a = np.asarray(meshes[i].triangles, np.int64)
    face_a = np.asarray(meshes[i].triangle_face, np.int64)
    face_b = np.asarray(meshes[j].triangle_face, np.int64)
    offset = 0 if same_mesh else np.asarray(meshes[i].points).shape[1]
    tri_b = np.asarray(meshes[j].triangles, np.int64) + offset
    positions = points_at(meshes[i], times)
    if not same_mesh:
        positions = np.concatenate([positions, points_at(meshes[j], times)], axis=1)
    reach = may_separation + BOX_PADDING
    done = np.zeros((0, 4), np.int64)  # face pairs with a ``must`` time: later intervals cannot be earlier
    for k in range(times.size - 1):
        start, end = positions[k], positions[k + 1]
        a, b = _overlapping(*_swept_boxes(start, end, tri_a), *_swept_boxes(start, end, tri_b), reach)
        if same_mesh:
            keep = (a < b) & (face_a[a] != face_b[b])
            a, b = a[keep], b[keep]
        keys, swapped = _face_keys(i, face_a[a], j, face_b[b])
        if done.size and a.size:
            fresh = ~_rows_in(keys, done)
            a, b, keys, swapped = a[fresh], b[fresh], keys[fresh], swapped[fresh]
        if not a.size:
            continue
        found = _interval_first_contacts(start, end, tri_a[a], tri_b[b], same_mesh, must_separation,
                                         may_separation, initial=k == 0, answer=answer)
        must_toi, may_toi, feature, capped = found
        must_time, may_time = (_time_of(toi, times[k], times[k + 1]) for toi in (must_toi, may_toi))
        _keep_earliest(answer, keys, must_time, may_time, feature, swapped, capped, times[k + 1] - times[k])
        reached = np.isfinite(must_time)
        if reached.any():
            done = np.unique(np.concatenate([done, keys[reached]]), axis=0)


def _interval_first_contacts(start: np.ndarray, end: np.ndarray, tri_a: np.ndarray, tri_b: np.ndarray,
                             same_mesh: bool, must_separation: float, may_separation: float, initial: bool,
                             answer: ReferenceContacts):
    """The earliest hit of each triangle pair (tri_a[p], tri_b[p]) on one interval: (must toi, may toi,
    must feature, may hit capped) per pair, times of impact in [0, 1] (inf: none). ``initial``: the
    interval starts the checked range, where faces already crossing count as touching at its start."""
    count = tri_a.shape[0]
    must_toi = np.full(count, np.inf)
    may_toi = np.full(count, np.inf)
    feature = np.full(count, -1, np.int8)
    capped = np.zeros(count, bool)
    if initial:
        pierced = _piercing(start, tri_a, tri_b, same_mesh)
        must_toi[pierced] = may_toi[pierced] = 0.0
        feature[pierced] = INITIAL
    ids, valid = _queries(tri_a, tri_b, same_mesh)
    valid &= _primitive_boxes_near(start, end, ids, may_separation + BOX_PADDING)
    pair_index, slot = np.nonzero(valid)
    if not pair_index.size:
        return must_toi, may_toi, feature, capped
    query_ids = ids[pair_index, slot]
    unique, inverse = np.unique(_query_keys(query_ids, slot), axis=0, return_inverse=True)
    inverse = inverse.reshape(-1)
    asked = np.zeros(unique.shape[0], np.int64)
    asked[inverse] = np.arange(inverse.size)
    unique_must = np.full(unique.shape[0], np.inf)
    unique_may = np.full(unique.shape[0], np.inf)
    unique_capped = np.zeros(unique.shape[0], bool)
    for q, row in enumerate(asked):
        corners = query_ids[row]
        points = np.concatenate([start[corners], end[corners]])
        vertex_face = bool(slot[row] < 6)
        hit, toi, cap = _ask(points, vertex_face, may_separation)
        answer.queries += 1
        if not hit:
            continue
        unique_may[q], unique_capped[q] = toi, cap
        if must_separation != may_separation:
            hit, toi, cap = _ask(points, vertex_face, must_separation)
            answer.queries += 1
        if hit and not cap:
            unique_must[q] = toi
    query_must, query_may = unique_must[inverse], unique_may[inverse]
    # The earliest query of each triangle pair, ties to the lowest feature (the contract's order).
    order = np.lexsort((_SLOT_FEATURE[slot], query_must, pair_index))
    first = np.ones(order.size, bool)
    first[1:] = pair_index[order[1:]] != pair_index[order[:-1]]
    chosen = order[first]
    earlier = query_must[chosen] < must_toi[pair_index[chosen]]
    must_toi[pair_index[chosen[earlier]]] = query_must[chosen[earlier]]
    feature[pair_index[chosen[earlier]]] = _SLOT_FEATURE[slot[chosen[earlier]]]
    np.minimum.at(may_toi, pair_index, query_may)
    capped_toi = np.full(count, np.inf)
    np.minimum.at(capped_toi, pair_index, np.where(unique_capped[inverse], query_may, np.inf))
    capped = capped_toi <= may_toi
    return must_toi, may_toi, feature, capped


def _time_of(toi: np.ndarray, start: float, end: float) -> np.ndarray:
    """Time codes of the times of impact ``toi`` (fractions of the interval [start, end]; inf: none)."""
    time = np.full(toi.shape, np.inf)
    hit = np.isfinite(toi)
    time[hit] = start + toi[hit] * (end - start)
    return time


def _primitive_boxes_near(start: np.ndarray, end: np.ndarray, ids: np.ndarray, reach: float) -> np.ndarray:
    """bool[P, 15]: the swept boxes of a query's two primitives come within ``reach`` on every axis."""
    lo, hi = np.minimum(start, end), np.maximum(start, end)
    near = np.empty(ids.shape[:2], bool)
    for slots, split in ((slice(0, 6), 1), (slice(6, 15), 2)):
        first, second = ids[:, slots, :split], ids[:, slots, split:]
        near[:, slots] = np.all((lo[first].min(axis=2) <= hi[second].max(axis=2) + reach) &
                                (lo[second].min(axis=2) <= hi[first].max(axis=2) + reach), axis=2)
    return near


def _rows_in(rows: np.ndarray, table: np.ndarray) -> np.ndarray:
    """bool[R]: each row of ``rows`` (int64[R, 4]) is a row of ``table``."""
    joined = np.concatenate([table, rows])
    _, inverse = np.unique(joined, axis=0, return_inverse=True)
    inverse = inverse.reshape(-1)
    return np.isin(inverse[table.shape[0]:], inverse[:table.shape[0]])


def _keep_earliest(answer: ReferenceContacts, keys: np.ndarray, must_time: np.ndarray, may_time: np.ndarray,
                   feature: np.ndarray, swapped: np.ndarray, capped: np.ndarray, duration: float) -> None:
    """Fold one interval's triangle pairs (times in time codes) into the face pairs' earliest times."""
    swap_feature = {VERTEX_FACE: FACE_VERTEX, FACE_VERTEX: VERTEX_FACE}
    for row in np.flatnonzero(np.isfinite(may_time)):
        key = tuple(int(x) for x in keys[row])
        if may_time[row] < answer.may.get(key, np.inf):
            answer.may[key] = float(may_time[row])
            answer.may_step[key] = float(duration)
            if capped[row]:
                answer.capped.add(key)
            else:
                answer.capped.discard(key)
        if must_time[row] < answer.must.get(key, np.inf):
            answer.must[key] = float(must_time[row])
            answer.must_step[key] = float(duration)
            code = int(feature[row])
            answer.feature[key] = swap_feature.get(code, code) if swapped[row] else code


def product_face_pairs(result, meshes: Sequence) -> Dict[Tuple[int, int, int, int], Tuple[float, int]]:
    """The product's answer (a ``find_contacts`` result) keyed as :class:`ReferenceContacts`: (time, feature)
    per face pair."""
    table = result.face_contacts(meshes)
    keys, swap = _face_keys(table.mesh_a, table.face_a, table.mesh_b, table.face_b)
    flip = {VERTEX_FACE: FACE_VERTEX, FACE_VERTEX: VERTEX_FACE}
    answer = {}
    for key, t, code, swapped in zip(keys.tolist(), np.asarray(table.time).tolist(),
                                     np.asarray(table.feature).tolist(), swap.tolist()):
        answer[tuple(key)] = (float(t), flip.get(code, code) if swapped else int(code))
    return answer


def disagreements(reference: ReferenceContacts, product: Dict[Tuple[int, int, int, int], Tuple[float, int]],
                  product_tolerance: float) -> List[str]:
    """What the product's face pairs (from :func:`product_face_pairs`) get wrong against the reference;
    empty when they agree within the tolerances of the module docstring. ``product_tolerance`` is the
    product's narrow-phase tolerance (a fraction of a raw interval)."""
    problems = []
    for key, t in sorted(reference.must.items()):
        if key not in product:
            problems.append(f"missed {key}: the reference finds it at {t!r}")
        elif product[key][0] > t + reference.late_slack * reference.must_step[key] + _time_rounding(t):
            problems.append(f"late {key}: {product[key][0]!r}, the reference finds it at {t!r}")
    for key, (t, _) in sorted(product.items()):
        if key not in reference.may:
            problems.append(f"extra {key} at {t!r}: the reference never finds it within the thickness")
        elif t < reference.may[key] - product_tolerance * reference.may_step[key] - _time_rounding(t):
            problems.append(f"early {key}: {t!r}, the reference's earliest is {reference.may[key]!r}")
    return problems


def assert_agrees(reference: ReferenceContacts, result, meshes: Sequence, product_tolerance: float,
                  label: str = "") -> None:
    """Fail with the first disagreements when a ``find_contacts`` result disagrees with the reference."""
    problems = disagreements(reference, product_face_pairs(result, meshes), product_tolerance)
    assert not problems, f"{label}{len(problems)} disagreements with ipctk: " + "; ".join(problems[:5])


def _time_rounding(t: float) -> float:
    """Time codes: a few units in the last place of ``t``, the rounding of t_k + toi * (t_k+1 - t_k)."""
    return 8.0 * math.ulp(max(abs(t), 1.0))
