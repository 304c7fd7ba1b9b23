"""Small helpers the sample scripts share: stages with the usual metadata, grids, meshes."""

from __future__ import annotations

import os
from typing import Dict, Iterable, Optional, Tuple

import numpy as np
from pxr import Gf, Usd, UsdGeom, Vt

TIME_CODES_PER_SECOND = 24.0
METERS_PER_UNIT = 1.0


def new_stage(path: str, start: float, end: float, default_prim: str = "World") -> Usd.Stage:
    """A fresh stage at ``path`` (overwritten) with time codes, Y up, metres and a default prim."""
    if os.path.exists(path):
        os.remove(path)
    stage = Usd.Stage.CreateNew(path)
    stage.SetTimeCodesPerSecond(TIME_CODES_PER_SECOND)
    stage.SetFramesPerSecond(TIME_CODES_PER_SECOND)
    stage.SetStartTimeCode(start)
    stage.SetEndTimeCode(end)
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.y)
    UsdGeom.SetStageMetersPerUnit(stage, METERS_PER_UNIT)
    root = UsdGeom.Xform.Define(stage, "/" + default_prim)
    stage.SetDefaultPrim(root.GetPrim())
    return stage


def grid(columns: int, rows: int, width: float, depth: float) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A quad grid in the XZ plane centred on the origin.

    Returns (points float64[(columns+1)*(rows+1), 3], faceVertexCounts, faceVertexIndices);
    point (i, j) (column i, row j) is at index j * (columns + 1) + i.
    """
    xs = np.linspace(-width / 2, width / 2, columns + 1)
    zs = np.linspace(-depth / 2, depth / 2, rows + 1)
    x, z = np.meshgrid(xs, zs)
    points = np.stack([x.ravel(), np.zeros(x.size), z.ravel()], axis=1)
    i, j = np.meshgrid(np.arange(columns), np.arange(rows))
    corner = (j * (columns + 1) + i).ravel()
    indices = np.stack([corner, corner + columns + 1, corner + columns + 2, corner + 1], axis=1)
    counts = np.full(corner.size, 4, dtype=np.int32)
    return points, counts, indices.ravel().astype(np.int32)


def box(center: Iterable[float], half: Iterable[float]) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
    """An axis-aligned box as 8 points and 6 outward-facing quads."""
    c = np.asarray(center, dtype=np.float64)
    h = np.asarray(half, dtype=np.float64)
    signs = np.array([[-1, -1, -1], [1, -1, -1], [1, 1, -1], [-1, 1, -1],
                      [-1, -1, 1], [1, -1, 1], [1, 1, 1], [-1, 1, 1]], dtype=np.float64)
    points = c + signs * h
    indices = np.array([0, 3, 2, 1, 4, 5, 6, 7, 0, 1, 5, 4, 2, 3, 7, 6, 1, 2, 6, 5, 0, 4, 7, 3],
                       dtype=np.int32)
    return points, np.full(6, 4, dtype=np.int32), indices


def define_mesh(stage: Usd.Stage, path: str, counts: np.ndarray, indices: np.ndarray,
                points: Optional[np.ndarray] = None,
                samples: Optional[Dict[float, np.ndarray]] = None,
                color: Optional[Tuple[float, float, float]] = None) -> UsdGeom.Mesh:
    """A mesh with constant topology and either static ``points`` or time-sampled ``samples``."""
    mesh = UsdGeom.Mesh.Define(stage, path)
    mesh.CreateFaceVertexCountsAttr(Vt.IntArray.FromNumpy(np.asarray(counts, dtype=np.int32)))
    mesh.CreateFaceVertexIndicesAttr(Vt.IntArray.FromNumpy(np.asarray(indices, dtype=np.int32)))
    mesh.CreateSubdivisionSchemeAttr(UsdGeom.Tokens.none)
    points_attr = mesh.CreatePointsAttr()
    if points is not None:
        points_attr.Set(Vt.Vec3fArray.FromNumpy(np.asarray(points, dtype=np.float32)))
    for time, value in sorted((samples or {}).items()):
        points_attr.Set(Vt.Vec3fArray.FromNumpy(np.asarray(value, dtype=np.float32)), time)
    if points is not None and not samples:
        low, high = np.min(points, axis=0), np.max(points, axis=0)
        mesh.CreateExtentAttr(Vt.Vec3fArray([Gf.Vec3f(*map(float, low)),
                                             Gf.Vec3f(*map(float, high))]))
    if color is not None:
        mesh.CreateDisplayColorAttr(Vt.Vec3fArray([Gf.Vec3f(*color)]))
    return mesh


def smoothstep(x: np.ndarray) -> np.ndarray:
    x = np.clip(x, 0.0, 1.0)
    return x * x * (3.0 - 2.0 * x)


def save(stage: Usd.Stage) -> None:
    stage.GetRootLayer().Save()


def layer_comment(stage: Usd.Stage, text: str) -> None:
    stage.GetRootLayer().documentation = text
