"""USD stage -> world-space arrays the native core checks.

Every ``UsdGeom.Mesh`` of the stage becomes a :class:`MeshData`: its world-space
points at each of its time samples (the union of the ``points`` samples and of the
xformOp samples of the mesh and of its ancestors up to a ``resetXformStack``), a fan
triangulation of its authored polygons with a triangle -> face map, and a
classification (static / rigid / deforming).

Two kinds of mesh take their points from OpenUSD instead of ``points`` x transform:

* meshes skinned by UsdSkel (bound to a Skeleton under a SkelRoot): :mod:`usdksl.skinning`;
* each instance of a mesh prototype of a ``UsdGeom.PointInstancer``, named
  ``<instancer>[<index>]/<prototype>/...``: :mod:`usdksl.instancing`. Meshes below a
  PointInstancer are its prototypes and are never loaded on their own (UsdImaging and
  UsdGeomBBoxCache prune them the same way).

Empty meshes (no points, no faces, or only degenerate faces) are skipped with a warning
in :attr:`Shot.warnings`; a shot with nothing else left is an input error.

Python loops over prims and time samples only; points, faces and triangles are
handled by numpy. The points of one mesh go straight into one preallocated
``float64[K, N, 3]`` array, so loading holds little more than the result.

The input file is opened read-only and never saved.
"""

from __future__ import annotations

import fnmatch
import os
import re
from dataclasses import dataclass, field
from typing import Callable, Dict, List, Optional, Sequence, Tuple, Union

import numpy as np
from pxr import Tf, Usd, UsdGeom

from .errors import UsdkslEmptyMeshError, UsdkslInputError, UsdkslUsageError
from .triangulate import fan_triangulate

STATIC = "static"
RIGID = "rigid"
DEFORMING = "deforming"

IncludeFilter = Union[None, Callable[[str], bool], str, Sequence[str]]


@dataclass(frozen=True, eq=False)
class MeshData:
    """One mesh as the core sees it. Times are USD time codes; points are world space."""

    path: str
    times: np.ndarray          # float64[K], strictly increasing; K == 1 for static meshes
    points: np.ndarray         # float64[K, N, 3], C-contiguous, world space at each of `times`
    triangles: np.ndarray      # int32[M, 3], fan triangulation of the authored faces, holes left out
    triangle_face: np.ndarray  # int32[M], authored face index of each triangle
    face_count: int            # number of authored faces (len(faceVertexCounts))
    kind: str                  # "static" | "rigid" | "deforming"
    source: Optional[str] = None      # prim authoring points and faces when `path` is not a prim (an instance)
    instancer: Optional[str] = None   # the UsdGeom.PointInstancer of an instance mesh
    instance_index: Optional[int] = None  # the instance's index in the instancer's arrays

    @property
    def prim_path(self) -> str:
        """The USD prim that authors this mesh's points and faces (an instance's prototype mesh)."""
        return self.source or self.path

    @property
    def scene_path(self) -> str:
        """The USD prim whose scene flags (visibility, purpose, physics) apply: an instance's instancer."""
        return self.instancer or self.path

    @property
    def vertex_count(self) -> int:
        return int(self.points.shape[1])

    @property
    def triangle_count(self) -> int:
        return int(self.triangles.shape[0])

    @property
    def sample_count(self) -> int:
        return int(self.times.shape[0])


@dataclass(eq=False)
class Shot:
    """A loaded stage: its meshes, the union of their sample times and its stage metadata."""

    path: str
    meshes: List[MeshData]
    times: np.ndarray
    metadata: Dict[str, object]
    stage: Usd.Stage = field(repr=False)
    warnings: List[str] = field(default_factory=list)   # one line each: skipped meshes, rescaled layers

    def mesh(self, path: str) -> MeshData:
        for mesh in self.meshes:
            if mesh.path == path:
                return mesh
        raise KeyError(path)


# --------------------------------------------------------------------------- opening

_PXR_NAMESPACE = re.compile(r"pxrInternal_v\w*?__pxrReserved__::")


def _pxr_error_text(error: Exception) -> str:
    """The diagnostics of a Tf.ErrorException on one line, without C++ function/file noise."""
    messages = []
    for entry in re.split(r"\n\s*Error in ", str(error)):
        _, separator, message = entry.partition(" : '")
        text = message.strip().rstrip("'") if separator else entry
        text = " ".join(_PXR_NAMESPACE.sub("", text).split())
        if text:
            messages.append(text)
    return "; ".join(messages) or type(error).__name__


def open_stage(path: Union[str, os.PathLike]) -> Usd.Stage:
    """Open ``path`` read-only with all payloads loaded; one-line UsdkslInputError on failure.

    A local file is checked first (missing, a directory, unreadable: one line each). Anything that is not a
    local file but that the asset resolver resolves (a package-relative path such as
    ``shot.usdz[scene.usdc]``, or a path a studio resolver understands) is opened through Usd.Stage.Open.
    """
    file = os.fspath(path)
    if not os.path.exists(file):
        if not _resolves(file):
            raise UsdkslInputError("no such file", file=file)
    elif not os.path.isfile(file):
        raise UsdkslInputError("not a file", file=file)
    elif not os.access(file, os.R_OK):
        raise UsdkslInputError("file is not readable", file=file)
    try:
        stage = Usd.Stage.Open(file, Usd.Stage.LoadAll)
    except Tf.ErrorException as error:
        raise UsdkslInputError(f"cannot open as USD: {_pxr_error_text(error)}", file=file) from None
    if stage is None:
        raise UsdkslInputError("cannot open as USD", file=file)
    return stage


def _resolves(asset_path: str) -> bool:
    """True when the asset resolver finds ``asset_path`` (not a plain local file)."""
    from pxr import Ar

    try:
        return bool(str(Ar.GetResolver().Resolve(asset_path)))
    except Tf.ErrorException:
        return False


def stage_metadata(stage: Usd.Stage) -> Dict[str, object]:
    """Stage metadata an override layer must copy so the cache's samples keep their meaning."""
    root = stage.GetRootLayer()
    metadata: Dict[str, object] = {
        "timeCodesPerSecond": float(stage.GetTimeCodesPerSecond()),
        "framesPerSecond": float(stage.GetFramesPerSecond()),
    }
    if root.HasStartTimeCode():
        metadata["startTimeCode"] = float(stage.GetStartTimeCode())
    if root.HasEndTimeCode():
        metadata["endTimeCode"] = float(stage.GetEndTimeCode())
    metadata["upAxis"] = str(UsdGeom.GetStageUpAxis(stage))
    metadata["metersPerUnit"] = float(UsdGeom.GetStageMetersPerUnit(stage))
    if root.HasDefaultPrim():
        metadata["defaultPrim"] = str(root.defaultPrim)
    return metadata


# --------------------------------------------------------------------------- finding meshes

def _include_predicate(include: IncludeFilter) -> Callable[[str], bool]:
    if include is None:
        return lambda path: True
    if callable(include):
        return include
    patterns = [include] if isinstance(include, str) else list(include)

    def matches(path: str) -> bool:
        for pattern in patterns:
            pattern = str(pattern).rstrip("/") or "/"
            if (fnmatch.fnmatchcase(path, pattern) or path.startswith(pattern + "/")
                    or path.startswith(pattern + "[")):   # instances: <instancer>[<index>]/...
                return True
        return False

    return matches


def mesh_prims(stage: Usd.Stage, include: IncludeFilter = None) -> List[Usd.Prim]:
    """Every defined, active UsdGeom.Mesh (instance proxies included), in traversal order.

    Meshes below a UsdGeom.PointInstancer are its prototypes: they are left out here and
    loaded once per instance (:mod:`usdksl.instancing`).
    ``include``: None (all), a callable on the prim path, or fnmatch patterns; a pattern
    also selects every mesh below the prim it names.
    """
    wanted = _include_predicate(include)
    predicate = Usd.TraverseInstanceProxies(Usd.PrimDefaultPredicate)
    found = []
    prims = iter(Usd.PrimRange.Stage(stage, predicate))
    for prim in prims:
        if prim.IsA(UsdGeom.PointInstancer):
            prims.PruneChildren()
        elif prim.IsA(UsdGeom.Mesh) and wanted(str(prim.GetPath())):
            found.append(prim)
    return found


# --------------------------------------------------------------------------- time samples

def xform_sample_times(prim: Usd.Prim) -> List[float]:
    """xformOp sample times of ``prim`` and of its ancestors, up to a resetXformStack."""
    times = set()
    current = prim
    while current and not current.IsPseudoRoot():
        xformable = UsdGeom.Xformable(current)
        if xformable:
            times.update(xformable.GetTimeSamples())
            if xformable.GetResetXformStack():
                break
        current = current.GetParent()
    return sorted(times)


def mesh_sample_times(prim: Usd.Prim) -> np.ndarray:
    """Union of the ``points`` samples and the xform chain samples of a mesh (may be empty)."""
    times = set(UsdGeom.Mesh(prim).GetPointsAttr().GetTimeSamples())
    times.update(xform_sample_times(prim))
    return np.array(sorted(times), dtype=np.float64)


def _window(times: np.ndarray, time_range: Optional[Tuple[float, float]]) -> np.ndarray:
    """Samples strictly inside the range plus both range ends (flightplans exact on it)."""
    if time_range is None or times.size == 0:
        return times
    start, end = time_range
    inside = times[(times > start) & (times < end)]
    ends = [start] if end == start else [start, end]
    return np.unique(np.concatenate([np.array(ends, dtype=np.float64), inside]))


def _topology_sample_times(mesh: UsdGeom.Mesh) -> List[float]:
    times = set(mesh.GetFaceVertexCountsAttr().GetTimeSamples())
    times.update(mesh.GetFaceVertexIndicesAttr().GetTimeSamples())
    times.update(mesh.GetHoleIndicesAttr().GetTimeSamples())
    return sorted(times)


def _array(attribute: Usd.Attribute, time: float, dtype) -> np.ndarray:
    value = attribute.Get(time)
    if value is None:
        return np.zeros(0, dtype=dtype)
    return np.asarray(value, dtype=dtype).reshape(-1)


def _points_count(attribute: Usd.Attribute, time: float) -> int:
    value = attribute.Get(time)
    return 0 if value is None else len(value)


def _topology_key(mesh: UsdGeom.Mesh, time: float):
    return (_array(mesh.GetFaceVertexCountsAttr(), time, np.int64),
            _array(mesh.GetFaceVertexIndicesAttr(), time, np.int64),
            _array(mesh.GetHoleIndicesAttr(), time, np.int64),
            _points_count(mesh.GetPointsAttr(), time))


def _same_topology(a, b) -> bool:
    return a[3] == b[3] and all(np.array_equal(x, y) for x, y in zip(a[:3], b[:3]))


def topology_segments(prim: Usd.Prim) -> List[Tuple[float, float]]:
    """Constant-topology stretches of a mesh as (first, last) sample times, in time codes.

    Topology here is faceVertexCounts, faceVertexIndices, holeIndices and the points
    count. Between two samples whose topology differs USD holds the earlier value, so a
    segment ends at its last sample and the next starts at the sample that differs; each
    segment can be loaded on its own with ``load_shot(..., time_range=segment)``. A mesh
    without any samples is one segment at the default time, reported as (0.0, 0.0).
    """
    mesh = UsdGeom.Mesh(prim)
    times = sorted(set(_topology_sample_times(mesh))
                   | set(mesh.GetPointsAttr().GetTimeSamples()))
    if not times:
        return [(0.0, 0.0)]
    segments = []
    start = previous = times[0]
    key = _topology_key(mesh, start)
    for time in times[1:]:
        current = _topology_key(mesh, time)
        if not _same_topology(key, current):
            segments.append((float(start), float(previous)))
            start, key = time, current
        previous = time
    segments.append((float(start), float(previous)))
    return segments


# --------------------------------------------------------------------------- one mesh

def _check_topology(file: str, path: str, time: float, counts: np.ndarray, indices: np.ndarray,
                    point_count: int) -> None:
    if point_count == 0:
        raise UsdkslEmptyMeshError("empty mesh: no points", file=file, prim=path, time=time)
    if counts.size == 0:
        raise UsdkslEmptyMeshError("empty mesh: no faces", file=file, prim=path, time=time)
    if counts.min() < 0:
        face = int(np.argmax(counts < 0))
        raise UsdkslInputError(f"faceVertexCounts[{face}] is negative ({int(counts[face])})",
                               file=file, prim=path, time=time)
    total = int(counts.sum())
    if total != indices.size:
        raise UsdkslInputError(
            f"faceVertexCounts add up to {total} corners but faceVertexIndices has {indices.size}",
            file=file, prim=path, time=time)
    bad = (indices < 0) | (indices >= point_count)
    if bad.any():
        corner = int(np.argmax(bad))
        face = int(np.searchsorted(np.cumsum(counts), corner, side="right"))
        raise UsdkslInputError(
            f"face {face} uses point index {int(indices[corner])}, out of range of the "
            f"{point_count} points", file=file, prim=path, time=time)


def _check_constant_topology(file: str, path: str, mesh: UsdGeom.Mesh, times: np.ndarray,
                             first_key) -> None:
    start, end = times[0], times[-1]
    for time in _topology_sample_times(mesh):
        if time <= start or time > end:
            continue
        if not _same_topology(first_key, _topology_key(mesh, time)):
            segments = ", ".join(f"[{a:g}, {b:g}]" for a, b in topology_segments(mesh.GetPrim()))
            raise UsdkslInputError(
                f"topology (faceVertexCounts/faceVertexIndices/holeIndices) changes here; "
                f"constant-topology segments: {segments}", file=file, prim=path, time=float(time))


class _MatrixCache:
    """One XformCache per time code, shared by all meshes so ancestors are computed once."""

    def __init__(self):
        self._caches: Dict[float, UsdGeom.XformCache] = {}

    def xform_cache(self, time: float) -> UsdGeom.XformCache:
        cache = self._caches.get(time)
        if cache is None:
            cache = self._caches[time] = UsdGeom.XformCache(Usd.TimeCode(time))
        return cache

    def local_to_world(self, prim: Usd.Prim, time: float) -> np.ndarray:
        return np.array(self.xform_cache(time).GetLocalToWorldTransform(prim), dtype=np.float64)


def _to_world(local: np.ndarray, matrix: np.ndarray, out: np.ndarray) -> None:
    """out = [local, 1] @ matrix (USD row vectors), projective matrices included."""
    with np.errstate(invalid="ignore", over="ignore"):   # non-finite input is reported by the caller
        np.matmul(local, matrix[:3, :3], out=out)
        out += matrix[3, :3]
        if not np.array_equal(matrix[:, 3], (0.0, 0.0, 0.0, 1.0)):
            w = local @ matrix[:3, 3] + matrix[3, 3]
            out /= w[:, None]


def to_world_checked(file: str, path: str, time: float, local: np.ndarray, matrix: np.ndarray,
                     out: np.ndarray) -> None:
    """``out`` = ``local`` points through the row-vector ``matrix``; one-line error when not finite."""
    if not np.isfinite(matrix).all():
        raise UsdkslInputError("local-to-world transform is not finite", file=file, prim=path, time=time)
    _to_world(local, matrix, out)
    check_finite_points(file, path, time, out)


def check_finite_points(file: str, path: str, time: float, points: np.ndarray) -> None:
    if not np.isfinite(points).all():
        bad = int(np.argmax(~np.isfinite(points).all(axis=1)))
        raise UsdkslInputError(f"point {bad} is NaN or infinite", file=file, prim=path, time=time)


def _read_points(file: str, path: str, attribute: Usd.Attribute, time: float) -> np.ndarray:
    value = attribute.Get(time)
    if value is None:
        raise UsdkslEmptyMeshError("empty mesh: points have no value", file=file, prim=path, time=time)
    return np.asarray(value).reshape(-1, 3)   # point3f as authored; a double type keeps its precision


@dataclass(frozen=True, eq=False)
class MeshTopology:
    """The checked, triangulated faces of one mesh over a stretch of constant topology."""

    triangles: np.ndarray       # int32[M, 3]
    triangle_face: np.ndarray   # int32[M]
    face_count: int
    point_count: int
    first_time: float
    first_local: np.ndarray     # the authored points at first_time, shape [point_count, 3]


def read_topology(prim: Usd.Prim, times: np.ndarray, file: str = "", path: Optional[str] = None) -> MeshTopology:
    """Faces of ``prim`` (a UsdGeom.Mesh) checked for the whole of ``times`` (increasing, non-empty).

    Raises UsdkslEmptyMeshError for a mesh without points, faces or non-degenerate faces, and
    UsdkslInputError for bad indices or topology that changes within ``times``. ``path``: the name
    errors use (default: the prim path).
    """
    mesh = UsdGeom.Mesh(prim)
    path = path or str(prim.GetPath())
    first_time = float(times[0])
    first_local = _read_points(file, path, mesh.GetPointsAttr(), first_time)
    point_count = first_local.shape[0]
    first_key = _topology_key(mesh, first_time)
    counts, indices, holes = first_key[:3]
    _check_topology(file, path, first_time, counts, indices, point_count)
    triangles, triangle_face = fan_triangulate(counts, indices, holes)
    if triangles.shape[0] == 0:
        raise UsdkslEmptyMeshError("empty mesh: every face is a hole or has fewer than 3 vertices",
                                   file=file, prim=path, time=first_time)
    _check_constant_topology(file, path, mesh, times, first_key)
    return MeshTopology(triangles=triangles, triangle_face=triangle_face, face_count=int(counts.size),
                        point_count=point_count, first_time=first_time, first_local=first_local)


def read_local_points(file: str, path: str, attribute: Usd.Attribute, time: float,
                      topology: MeshTopology) -> np.ndarray:
    """The authored ``points`` at ``time``; one-line error when their count differs from the topology's."""
    if time == topology.first_time:
        return topology.first_local
    local = _read_points(file, path, attribute, time)
    if local.shape[0] != topology.point_count:
        raise UsdkslInputError(
            f"points count changes from {topology.point_count} (time {topology.first_time:g}) to "
            f"{local.shape[0]}", file=file, prim=path, time=time)
    return local


def classified_mesh(path: str, times: np.ndarray, points: np.ndarray, local_constant: bool,
                    topology: MeshTopology, **identity) -> MeshData:
    """MeshData with its kind: static when no world point ever changes (collapsed to the first sample),
    rigid when only the transform moves it (``local_constant``), deforming otherwise."""
    if bool(np.all(points == points[:1])):
        kind = STATIC
        points = np.ascontiguousarray(points[:1])  # frees the other samples
        times = times[:1].copy()
    elif local_constant:
        kind = RIGID
    else:
        kind = DEFORMING
    return MeshData(path=path, times=times, points=points, triangles=topology.triangles,
                    triangle_face=topology.triangle_face, face_count=topology.face_count, kind=kind,
                    **identity)


def load_mesh(prim: Usd.Prim, times: np.ndarray, file: str = "",
              matrices: Optional[_MatrixCache] = None) -> MeshData:
    """World-space MeshData of one mesh evaluated at ``times`` (non-empty, increasing).

    The mesh is collapsed to its first sample when nothing moves (static).
    """
    mesh = UsdGeom.Mesh(prim)
    path = str(prim.GetPath())
    matrices = matrices or _MatrixCache()
    points_attr = mesh.GetPointsAttr()
    times = np.asarray(times, dtype=np.float64)
    topology = read_topology(prim, times, file)

    xform_animated = bool(xform_sample_times(prim))
    points_animated = points_attr.GetNumTimeSamples() > 1
    fixed_matrix = None if xform_animated else matrices.local_to_world(prim, topology.first_time)

    points = np.empty((times.shape[0], topology.point_count, 3), dtype=np.float64)
    local_constant = True
    for k, time in enumerate(times):
        time = float(time)
        local = (read_local_points(file, path, points_attr, time, topology) if points_animated
                 else topology.first_local)
        matrix = fixed_matrix if fixed_matrix is not None else matrices.local_to_world(prim, time)
        to_world_checked(file, path, time, local, matrix, points[k])
        if local_constant and local is not topology.first_local:
            local_constant = np.array_equal(local, topology.first_local)
    return classified_mesh(path, times, points, local_constant, topology)


# --------------------------------------------------------------------------- whole shot

def _check_time_range(file: str, time_range) -> Optional[Tuple[float, float]]:
    if time_range is None:
        return None
    try:
        start, end = (float(value) for value in time_range)
    except (TypeError, ValueError):
        raise UsdkslUsageError(f"time range must be two numbers, got {time_range!r}",
                               file=file) from None
    if not (np.isfinite(start) and np.isfinite(end)) or start > end:
        raise UsdkslUsageError(f"time range [{start:g}, {end:g}] is empty or not finite",
                               file=file)
    return (start, end)


def load_shot(path: Union[str, os.PathLike], time_range: Optional[Tuple[float, float]] = None,
              include: IncludeFilter = None) -> Shot:
    """Load every mesh of a USD shot in world space (see module docstring).

    ``time_range=(a, b)``: each animated mesh keeps its samples inside (a, b) plus its
    values evaluated exactly at a and b. ``include``: see :func:`mesh_prims`.
    Raises :class:`usdksl.errors.UsdkslInputError` with a one-line message on bad input.
    """
    from . import instancing, layer_rates, skinning   # they build on this module

    file = os.fspath(path)
    time_range = _check_time_range(file, time_range)
    stage = open_stage(file)
    metadata = stage_metadata(stage)
    warnings: List[str] = []
    try:
        prims = mesh_prims(stage, include)
        skinned = skinning.find_skinned_meshes(stage)
        sources = [skinned.get(str(prim.GetPath())) or _AuthoredMesh(prim) for prim in prims]
        sources += instancing.find_instanced_meshes(stage, _include_predicate(include), file, warnings)
    except Tf.ErrorException as error:
        raise UsdkslInputError(f"cannot read the stage: {_pxr_error_text(error)}", file=file) from None
    if not sources:
        what = "no UsdGeom.Mesh prims" if include is None else "no UsdGeom.Mesh prims match the selection"
        raise UsdkslInputError(f"{what} on the stage", file=file)

    try:
        per_mesh_times = [_window(source.sample_times(), time_range) for source in sources]
    except Tf.ErrorException as error:
        raise UsdkslInputError(f"cannot read time samples: {_pxr_error_text(error)}",
                               file=file) from None
    animated = [times for times in per_mesh_times if times.size]
    if animated:
        reference_time = float(min(times[0] for times in animated))
    elif time_range is not None:
        reference_time = time_range[0]
    else:
        reference_time = float(metadata.get("startTimeCode", 0.0))

    matrices = _MatrixCache()
    meshes = []
    empty: List[UsdkslEmptyMeshError] = []
    for source, times in zip(sources, per_mesh_times):
        if times.size == 0:
            times = np.array([reference_time], dtype=np.float64)
        try:
            loaded = source.load(times, file, matrices)
        except UsdkslEmptyMeshError as error:
            empty.append(error)
            warnings.append(f"{error}; skipped")
            continue
        except Tf.ErrorException as error:
            raise UsdkslInputError(f"cannot read mesh: {_pxr_error_text(error)}", file=file,
                                   prim=source.path) from None
        meshes.extend(loaded if isinstance(loaded, list) else [loaded])
    if not meshes and empty:
        first = empty[0]
        others = f" and {len(empty) - 1} more empty meshes" if len(empty) > 1 else ""
        raise UsdkslInputError(f"{first.message}{others}; nothing else to check", file=file,
                               prim=first.prim, time=first.time)
    if not meshes:
        raise UsdkslInputError("nothing to check: no mesh and no visible PointInstancer instance",
                               file=file)
    warnings.extend(layer_rates.rescaled_layer_warnings(
        stage, [prim for source in sources for prim in source.motion_prims()], file))
    shot_times = np.unique(np.concatenate([mesh.times for mesh in meshes]))
    return Shot(path=file, meshes=meshes, times=shot_times, metadata=metadata, stage=stage,
                warnings=warnings)


class _AuthoredMesh:
    """A mesh whose world points are its authored points through its transforms (no UsdSkel, no instancer)."""

    def __init__(self, prim: Usd.Prim):
        self.prim = prim
        self.path = str(prim.GetPath())

    def sample_times(self) -> np.ndarray:
        return mesh_sample_times(self.prim)

    def motion_prims(self) -> List[Usd.Prim]:
        return [self.prim]

    def load(self, times: np.ndarray, file: str, matrices: _MatrixCache) -> MeshData:
        return load_mesh(self.prim, times, file, matrices)
