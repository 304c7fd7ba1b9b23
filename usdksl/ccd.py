"""Narrow-phase continuous collision queries, batched (numpy in, numpy out).

Every query is one primitive pair moving linearly over one step, given as
float64 rows ``(Q, 8, 3)`` in the order of the public CCD datasets:
vertex-face ``v_t0, f0_t0, f1_t0, f2_t0, v_t1, f0_t1, f1_t1, f2_t1``;
edge-edge ``ea0_t0, ea1_t0, eb0_t0, eb1_t0, ea0_t1, ea1_t1, eb0_t1, eb1_t1``.
Times of impact are fractions of the step in [0, 1] and never later than the
true first contact; a query that reaches the iteration cap is *undecided* and
counts as a contact.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from . import _native
from .ccd_defaults import DEFAULT_MAX_ITERATIONS, DEFAULT_THICKNESS, DEFAULT_TOLERANCE

__all__ = [
    "DEFAULT_TOLERANCE",
    "DEFAULT_MAX_ITERATIONS",
    "DEFAULT_THICKNESS",
    "CCDAnswers",
    "vertex_face",
    "edge_edge",
    "vertex_face_detailed",
    "edge_edge_detailed",
    "triangle_pair",
    "triangles_intersect_static",
    "triangle_pair_intersect_static",
    "orient3d",
    "read_query_csv",
]


@dataclass(frozen=True)
class CCDAnswers:
    """Answers of a batch of primitive queries."""

    hit: np.ndarray  # bool[Q]; True for undecided queries too
    toi: np.ndarray  # float64[Q], fraction of the step; 1.0 where no hit
    reached_tolerance: np.ndarray  # float64[Q], width of the final time interval
    undecided: np.ndarray  # bool[Q], the iteration cap stopped the search
    iterations: np.ndarray  # int64[Q], parameter boxes examined (what max_iterations caps)


def _queries(queries) -> np.ndarray:
    array = np.ascontiguousarray(queries, dtype=np.float64)
    if array.ndim != 3 or array.shape[1:] != (8, 3):
        raise ValueError(f"queries must have shape (Q, 8, 3), got {array.shape}")
    return array


def _check_settings(tolerance, thickness):
    if not tolerance > 0.0:
        raise ValueError("tolerance must be > 0")
    if not thickness >= 0.0:
        raise ValueError("thickness must be >= 0")


def vertex_face_detailed(queries, tolerance=DEFAULT_TOLERANCE, thickness=DEFAULT_THICKNESS,
                         max_iterations=DEFAULT_MAX_ITERATIONS) -> CCDAnswers:
    """Vertex-face CCD with undecided flags, reached tolerances and iteration counts."""
    _check_settings(tolerance, thickness)
    return CCDAnswers(*_native.vertex_face_ccd_batch(_queries(queries), float(tolerance),
                                                     float(thickness), int(max_iterations)))


def edge_edge_detailed(queries, tolerance=DEFAULT_TOLERANCE, thickness=DEFAULT_THICKNESS,
                       max_iterations=DEFAULT_MAX_ITERATIONS) -> CCDAnswers:
    """Edge-edge CCD with undecided flags, reached tolerances and iteration counts."""
    _check_settings(tolerance, thickness)
    return CCDAnswers(*_native.edge_edge_ccd_batch(_queries(queries), float(tolerance),
                                                   float(thickness), int(max_iterations)))


def vertex_face(queries, tolerance=DEFAULT_TOLERANCE, thickness=DEFAULT_THICKNESS,
                max_iterations=DEFAULT_MAX_ITERATIONS):
    """Vertex-face CCD over (Q, 8, 3) queries -> (hit bool[Q], toi float64[Q])."""
    answers = vertex_face_detailed(queries, tolerance, thickness, max_iterations)
    return answers.hit, answers.toi


def edge_edge(queries, tolerance=DEFAULT_TOLERANCE, thickness=DEFAULT_THICKNESS,
              max_iterations=DEFAULT_MAX_ITERATIONS):
    """Edge-edge CCD over (Q, 8, 3) queries -> (hit bool[Q], toi float64[Q])."""
    answers = edge_edge_detailed(queries, tolerance, thickness, max_iterations)
    return answers.hit, answers.toi


def _triangles(array, name) -> np.ndarray:
    array = np.ascontiguousarray(array, dtype=np.float64)
    if array.ndim == 2:
        array = array[None]
    if array.ndim != 3 or array.shape[1:] != (3, 3):
        raise ValueError(f"{name} must have shape (Q, 3, 3), got {array.shape}")
    return array


def _ids(array, count, name) -> np.ndarray:
    if array is None:
        return np.full((count, 3), -1, dtype=np.int32) + np.arange(3, dtype=np.int32)
    array = np.ascontiguousarray(array, dtype=np.int32)
    if array.ndim == 1:
        array = np.broadcast_to(array, (count, 3)).copy()
    if array.shape != (count, 3):
        raise ValueError(f"{name} must have shape (Q, 3), got {array.shape}")
    return array


def triangle_pair(a_t0, a_t1, b_t0, b_t1, ids_a=None, ids_b=None, same_mesh=False,
                  tolerance=DEFAULT_TOLERANCE, thickness=DEFAULT_THICKNESS, max_iterations=DEFAULT_MAX_ITERATIONS,
                  reuse=True):
    """Earliest contact of Q moving triangle pairs (6 vertex-face + 9 edge-edge each).

    Returns (hit bool[Q], toi float64[Q], feature int8[Q], undecided bool[Q],
    primitive_queries int32[Q]); feature codes as in :mod:`usdksl.contacts.table`
    (0 vertex of A on B, 1 vertex of B on A, 2 edge-edge). With ``reuse``, a vertex-face
    query repeated within the batch with the same inputs is answered from a memo, as
    ``usdksl check`` does: the answers are the same bit for bit either way.
    """
    _check_settings(tolerance, thickness)
    a_t0, a_t1 = _triangles(a_t0, "a_t0"), _triangles(a_t1, "a_t1")
    b_t0, b_t1 = _triangles(b_t0, "b_t0"), _triangles(b_t1, "b_t1")
    count = a_t0.shape[0]
    return _native.triangle_pair_ccd_batch(a_t0, a_t1, b_t0, b_t1, _ids(ids_a, count, "ids_a"),
                                           _ids(ids_b, count, "ids_b"), bool(same_mesh),
                                           float(tolerance), float(thickness), int(max_iterations),
                                           bool(reuse))[:5]


def triangles_intersect_static(a, b, thickness=DEFAULT_THICKNESS) -> np.ndarray:
    """Closed triangles a[q], b[q] touch or intersect (within thickness) -> bool[Q]."""
    if not thickness >= 0.0:
        raise ValueError("thickness must be >= 0")
    a, b = _triangles(a, "a"), _triangles(b, "b")
    return _native.triangles_intersect_static_batch(a, b, float(thickness))


def triangle_pair_intersect_static(ids_a, a, ids_b, b, same_mesh=True, thickness=DEFAULT_THICKNESS) -> np.ndarray:
    """Static triangle-pair test over primitives sharing no vertex id -> bool[Q]."""
    if not thickness >= 0.0:
        raise ValueError("thickness must be >= 0")
    a, b = _triangles(a, "a"), _triangles(b, "b")
    count = a.shape[0]
    return _native.triangle_pair_intersect_static_batch(_ids(ids_a, count, "ids_a"), a,
                                                        _ids(ids_b, count, "ids_b"), b,
                                                        bool(same_mesh), float(thickness))


def orient3d(points) -> np.ndarray:
    """Exact sign of det[a-d, b-d, c-d] for (Q, 4, 3) points -> int8[Q]."""
    points = np.ascontiguousarray(points, dtype=np.float64)
    if points.ndim != 3 or points.shape[1:] != (4, 3):
        raise ValueError(f"points must have shape (Q, 4, 3), got {points.shape}")
    return _native.orient3d_batch(points)


# Integers with at most this many digits fit in int64.
_INT64_SAFE_DIGITS = 18
_EXACT_DOUBLE_INTEGER = 2**53


def _rationals_to_double(numerators: np.ndarray, denominators: np.ndarray) -> np.ndarray:
    """Correctly rounded float64 of numerator/denominator given as decimal strings."""
    numerators = np.char.strip(numerators)
    denominators = np.char.strip(denominators)
    short = (np.char.str_len(np.char.lstrip(numerators, "-")) <= _INT64_SAFE_DIGITS) & (
        np.char.str_len(np.char.lstrip(denominators, "-")) <= _INT64_SAFE_DIGITS)
    result = np.empty(numerators.shape, dtype=np.float64)
    num = np.where(short, numerators, "0").astype(np.int64)
    den = np.where(short, denominators, "1").astype(np.int64)
    den_is_power_of_two = (den > 0) & ((den & (den - 1)) == 0)
    # One IEEE division of two exactly representable doubles is correctly rounded.
    fast = short & (np.abs(num) <= _EXACT_DOUBLE_INTEGER) & (
        (np.abs(den) <= _EXACT_DOUBLE_INTEGER) | den_is_power_of_two)
    result[fast] = num[fast].astype(np.float64) / den[fast].astype(np.float64)
    slow = ~fast
    if slow.any():
        # Python int / int true division is correctly rounded for any size.
        big_num = np.array([int(s) for s in numerators[slow]], dtype=object)
        big_den = np.array([int(s) for s in denominators[slow]], dtype=object)
        result[slow] = (big_num / big_den).astype(np.float64)
    return result


def _truth_path(csv_path: Path) -> Path:
    # scalable-ccd layout: <scene>/queries/<s>vf.csv -> <scene>/mma_bool/<s>vf_mma_bool.json
    return csv_path.parent.parent / "mma_bool" / f"{csv_path.stem}_mma_bool.json"


def read_query_csv(path):
    """Reads a rational query CSV -> (queries float64[Q, 8, 3], truth bool[Q]).

    Sample-queries files carry the truth in a seventh column; scalable-ccd
    files have six columns and the truth in ``../mma_bool/<stem>_mma_bool.json``.
    """
    path = Path(path)
    table = np.loadtxt(path, delimiter=",", dtype=str, ndmin=2)
    if table.shape[0] % 8 != 0:
        raise ValueError(f"{path}: {table.shape[0]} rows is not a multiple of 8")
    coordinates = _rationals_to_double(table[:, 0:6:2], table[:, 1:6:2])
    queries = coordinates.reshape(-1, 8, 3)
    if table.shape[1] >= 7:
        truth = table[::8, 6].astype(np.int64) != 0
    else:
        truth_file = _truth_path(path)
        truth = np.asarray(json.loads(truth_file.read_text()), dtype=bool)
    if truth.shape[0] != queries.shape[0]:
        raise ValueError(f"{path}: {queries.shape[0]} queries but {truth.shape[0]} truth values")
    return queries, truth
