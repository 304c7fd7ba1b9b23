"""Random small scenes for property-based tests (Hypothesis): meshes with random topology (degenerate and
empty faces, indices out of range, duplicate points), animated by random samples (coincident times and
positions, huge and tiny coordinates, NaN and infinity, a points count that changes) under random
transforms, written as USD files with pxr. The same specs feed the native core directly."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import List, Optional, Sequence, Tuple

import numpy as np
from hypothesis import strategies as st

#: Coordinates that break things: zero, signed zero, tiny, subnormal, huge, float32's edge, non-finite.
SPECIAL_COORDINATES = (0.0, -0.0, 1e-30, -1e-30, 5e-324, 1e5, -1e7, 1e9, 2147483647.0, 1e15, 3.4e38, 1e39,
                       -1e300, math.nan, math.inf, -math.inf)
#: Time codes, some nearly coincident.
SPECIAL_TIMES = (0.0, 1.0, 1.0 + 1e-12, 1.0 + 1e-9, 2.0, 24.0, -5.0, 1e6, 1e12)


@dataclass(frozen=True)
class MeshSpec:
    name: str
    counts: Tuple[int, ...]
    indices: Tuple[int, ...]
    holes: Tuple[int, ...]
    samples: Tuple[Tuple[float, Tuple[Tuple[float, float, float], ...]], ...]   # (time, points) by time
    static_points: Optional[Tuple[Tuple[float, float, float], ...]]
    translate: Tuple[Tuple[float, Tuple[float, float, float]], ...]            # animated parent Xform
    scale: Optional[Tuple[float, float, float]]


@dataclass(frozen=True)
class SceneSpec:
    meshes: Tuple[MeshSpec, ...]


#: A draw is a defect (a special coordinate, an index out of range, an empty mesh...) when this many coin
#: flips all come up true, one in 32: rare enough that most scenes load and reach the core, common enough
#: that every defect is tried. Coin flips, not an integer range: Hypothesis biases integer and float draws
#: towards constants it finds in the source of the modules a process has loaded (0 among them), so a
#: defect drawn from an integer would be more or less rare depending on which tests ran before.
DEFECT_COIN_FLIPS = 5


def rarely(draw) -> bool:
    return all(draw(st.booleans()) for _ in range(DEFECT_COIN_FLIPS))


def one_in_four(draw) -> bool:
    """Two coin flips both true: as ``integers(0, 3) == 0`` would be without the bias towards 0 (see
    DEFECT_COIN_FLIPS), which held most points still and left scenes with nothing to check."""
    return draw(st.booleans()) and draw(st.booleans())


@st.composite
def coordinates(draw, allow_special: bool = True):
    if allow_special and rarely(draw):
        return draw(st.sampled_from(SPECIAL_COORDINATES))
    if draw(st.booleans()):
        return float(draw(st.integers(-2, 2)))            # a coarse grid: duplicate points, coplanar faces
    return draw(st.floats(-2, 2, allow_nan=False, width=32))


def points(count: int, allow_special: bool = True):
    point = st.tuples(coordinates(allow_special), coordinates(allow_special), coordinates(allow_special))
    return st.lists(point, min_size=count, max_size=count).map(tuple)


@st.composite
def moved(draw, previous, allow_special: bool = True):
    """The points of the next sample: the previous ones moved a little, some not at all."""
    result = []
    for point in previous:
        if one_in_four(draw):
            result.append(point)
        else:
            step = draw(st.tuples(*(st.floats(-1, 1, allow_nan=False, width=32) for _ in range(3))))
            new = tuple(c + d if math.isfinite(c) else c for c, d in zip(point, step))
            if allow_special and rarely(draw):
                axis = draw(st.integers(0, 2))
                new = tuple(draw(st.sampled_from(SPECIAL_COORDINATES)) if k == axis else c
                            for k, c in enumerate(new))
            result.append(new)
    return tuple(result)


@st.composite
def meshes(draw, name: str, allow_special: bool = True):
    count = 0 if (allow_special and rarely(draw)) else draw(st.integers(3, 9))
    faces = draw(st.lists(st.integers(0, 5) if (allow_special and rarely(draw)) else st.integers(3, 4),
                          min_size=0 if (allow_special and rarely(draw)) else 1, max_size=6))
    out_of_range = allow_special and rarely(draw)
    index = st.integers(-1, count) if out_of_range else st.integers(0, max(count - 1, 0))
    indices = tuple(draw(st.lists(index, min_size=sum(faces), max_size=sum(faces))))
    holes = tuple(draw(st.lists(st.integers(-1, len(faces)), max_size=2))) if faces and rarely(draw) else ()
    # most meshes move (two samples at least), so that most scenes reach the check; some hold one sample or none
    times = draw(st.lists(st.one_of(st.sampled_from(SPECIAL_TIMES), st.integers(1, 30).map(float)),
                          min_size=0 if one_in_four(draw) else 2, max_size=5, unique=True))
    changing = allow_special and rarely(draw)      # a points count that changes between samples
    samples = []
    for time in sorted(times):
        if not samples:
            samples.append((time, draw(points(count, allow_special))))
        elif changing and draw(st.booleans()):
            samples.append((time, draw(points(max(count + draw(st.sampled_from((-1, 1))), 0), allow_special))))
        else:
            samples.append((time, draw(moved(samples[-1][1], allow_special))))
    static = draw(points(count, allow_special)) if not samples or draw(st.booleans()) else None
    translate = ()
    if one_in_four(draw):
        steps = draw(st.lists(st.sampled_from(SPECIAL_TIMES[:6]), min_size=1, max_size=3, unique=True))
        translate = tuple((time, draw(points(1, allow_special))[0]) for time in sorted(steps))
    scale = draw(points(1, allow_special))[0] if rarely(draw) else None
    return MeshSpec(name=name, counts=tuple(faces), indices=indices, holes=holes, samples=tuple(samples),
                    static_points=static, translate=translate, scale=scale)


@st.composite
def scenes(draw, allow_special: bool = True):
    count = draw(st.integers(1, 3))
    return SceneSpec(meshes=tuple(draw(meshes(f"M{index}", allow_special)) for index in range(count)))


def write_usda(spec: SceneSpec, path) -> None:
    """The scene as a USD file: /World/X<i> Xforms (animated translate, scale) over /World/X<i>/M<i>."""
    from pxr import Gf, Usd, UsdGeom, Vt

    stage = Usd.Stage.CreateNew(str(path))
    stage.SetTimeCodesPerSecond(24)
    UsdGeom.Xform.Define(stage, "/World")
    for mesh_spec in spec.meshes:
        parent = UsdGeom.Xform.Define(stage, f"/World/X{mesh_spec.name}")
        if mesh_spec.translate:
            op = parent.AddTranslateOp()
            for time, value in mesh_spec.translate:
                op.Set(Gf.Vec3d(*value), time)
        if mesh_spec.scale is not None:
            parent.AddScaleOp().Set(Gf.Vec3f(*mesh_spec.scale))
        mesh = UsdGeom.Mesh.Define(stage, f"/World/X{mesh_spec.name}/{mesh_spec.name}")
        mesh.CreateFaceVertexCountsAttr(Vt.IntArray(list(mesh_spec.counts)))
        mesh.CreateFaceVertexIndicesAttr(Vt.IntArray(list(mesh_spec.indices)))
        if mesh_spec.holes:
            mesh.CreateHoleIndicesAttr(Vt.IntArray(list(mesh_spec.holes)))
        attribute = mesh.CreatePointsAttr()
        if mesh_spec.static_points is not None:
            attribute.Set(Vt.Vec3fArray([Gf.Vec3f(*p) for p in mesh_spec.static_points]))
        for time, values in mesh_spec.samples:
            attribute.Set(Vt.Vec3fArray([Gf.Vec3f(*p) for p in values]), time)
    stage.GetRootLayer().Save()


def core_meshes(spec: SceneSpec) -> List[Tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]]:
    """What the native core takes, straight from the spec (no USD, no checks): per mesh (times,
    points[K, N, 3], triangles (fan, indices clipped into range), triangle -> face). Meshes that the
    loader would refuse (no points, no triangles, a changing points count) are left out."""
    found = []
    for mesh in spec.meshes:
        samples = [values for _, values in mesh.samples] or ([mesh.static_points] if mesh.static_points else [])
        if not samples or len({len(values) for values in samples}) != 1 or not samples[0]:
            continue
        count = len(samples[0])
        times = np.array([time for time, _ in mesh.samples] or [0.0], dtype=np.float64)
        triangles, faces, start = [], [], 0
        for face, corners in enumerate(mesh.counts):
            ring = [min(max(i, 0), count - 1) for i in mesh.indices[start:start + corners]]
            start += corners
            for k in range(1, corners - 1):
                triangles.append((ring[0], ring[k], ring[k + 1]))
                faces.append(face)
        if not triangles:
            continue
        with np.errstate(over="ignore", invalid="ignore"):
            frames = np.array(samples, dtype=np.float32).astype(np.float64)
        found.append((times, frames, np.array(triangles, dtype=np.int32), np.array(faces, dtype=np.int32)))
    return found

