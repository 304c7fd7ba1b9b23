"""One mesh as arrays: its sample times, topology, world-space points and motion class.

:class:`MeshData` is what the core checks and :class:`Shot` a loaded stage of them. The functions here
read one ``UsdGeom.Mesh`` (time samples of its points and transforms, constant topology, points to world
space, the static / rigid / deforming class); :mod:`usdksl.reading.loader` finds the meshes of a stage
and loads them, and :mod:`usdksl.reading.skinning` and :mod:`usdksl.reading.instancing` build their
meshes from the same pieces.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Dict, Iterator, List, Optional, Tuple

import numpy as np
from pxr import Sdf, Usd, UsdGeom

from ..errors import UsdkslEmptyMeshError, UsdkslInputError
from ..unmasked import distinct_sorted
from .positions import samples_all_alike
from .triangulate import fan_triangulate

STATIC = "static"
RIGID = "rigid"
DEFORMING = "deforming"



@dataclass(frozen=True, eq=False)
class MeshData:
    """One mesh as the core sees it. Times are USD time codes; points are world space."""

    path: str
    times: np.ndarray          # float64[K], strictly increasing; K == 1 for static meshes
    #: float64[K, N, 3], C-contiguous, world space at each of `times`; float32 when they are the authored
    #: float points as they are (no transform moves them): the same numbers in half the memory.
    points: np.ndarray
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


#: Solid gprims that are not UsdGeom.Mesh (implicit surfaces, NURBS patches): surfaces a contact could be
#: with, which usdksl does not tessellate. Curves and points are not surfaces and are not listed.
UNMESHED_SOLIDS = ("Capsule", "Capsule_1", "Cone", "Cube", "Cylinder", "Cylinder_1", "Plane", "Sphere",
                   "NurbsPatch")


#: Gprims that hold geometry but no surface a contact is defined on (hair, particles, volumes): named in the
#: coverage account as scoped out, never warned about.
NOT_SURFACES = ("BasisCurves", "NurbsCurves", "HermiteCurves", "Points", "Volume")


def not_surface_kind(prim: Usd.Prim) -> Optional[str]:
    """The schema name (one of NOT_SURFACES) of a curves, points or volume prim, else None."""
    for name in NOT_SURFACES:
        # by its registered name: UsdVol is not imported for a check (its import costs start-up time)
        schema = Usd.SchemaRegistry.GetTypeFromSchemaTypeName(name)
        if not schema.isUnknown and prim.IsA(schema):
            return name
    return None


def unmeshed_solid_kind(prim: Usd.Prim) -> Optional[str]:
    """The schema name (one of UNMESHED_SOLIDS) of a solid gprim that is not a mesh, else None."""
    for name in UNMESHED_SOLIDS:
        schema = getattr(UsdGeom, name, None)
        if schema is not None and prim.IsA(schema):
            return name
    return None


def rendered(prim: Usd.Prim) -> bool:
    """Visible at the earliest time and not a guide: what a render (and usdksl's default scope) shows."""
    imageable = UsdGeom.Imageable(prim)
    return (imageable.ComputeVisibility(Usd.TimeCode.EarliestTime()) != UsdGeom.Tokens.invisible
            and imageable.ComputePurpose() != UsdGeom.Tokens.guide)


@dataclass(frozen=True)
class UncheckedGeometry:
    """Geometry on the stage that usdksl reads past without checking it (a nested PointInstancer's
    instances): a warning by default, an input error under ``--strict``."""

    prim: str
    reason: str
    #: Stable name of why (usdksl.warning_kinds), None when not named.
    kind: Optional[str] = None


@dataclass(eq=False)
class Shot:
    """A loaded stage: its meshes, the union of their sample times and its stage metadata."""

    path: str
    meshes: List[MeshData]
    times: np.ndarray
    metadata: Dict[str, object]
    stage: Usd.Stage = field(repr=False)
    warnings: List[str] = field(default_factory=list)   # one line each: skipped meshes, rescaled layers
    unchecked: List[UncheckedGeometry] = field(default_factory=list)   # each also has a warning line
    #: Meshes loaded still, at one sample of a neighbouring stretch, only so that every piece of a shot cut at
    #: gaps (usdksl.reading.segments) has the same meshes: no points here, never in a checked pair.
    absent: frozenset = frozenset()
    #: Information lines about how the shot was read (not warnings): e.g. meshes posed at every frame.
    notes: List[str] = field(default_factory=list)
    #: First and last sample (time codes) of the animated meshes over the whole stage, before any time range
    #: windows them; None when nothing is animated.
    sample_span: Optional[Tuple[float, float]] = None

    def mesh(self, path: str) -> MeshData:
        for mesh in self.meshes:
            if mesh.path == path:
                return mesh
        raise KeyError(path)


# --------------------------------------------------------------------------- time samples

def transform_chain(prim: Usd.Prim) -> Iterator[UsdGeom.Xformable]:
    """The xformables whose ops make up the local-to-world transform of ``prim``: ``prim`` and its
    ancestors, nearest first, up to and including the first that resets the xform stack."""
    current = prim
    while current and not current.IsPseudoRoot():
        xformable = UsdGeom.Xformable(current)
        if xformable:
            yield xformable
            if xformable.GetResetXformStack():
                return
        current = current.GetParent()


def xform_sample_times(prim: Usd.Prim) -> List[float]:
    """xformOp sample times of ``prim`` and of its ancestors, up to a resetXformStack."""
    times = set()
    for xformable in transform_chain(prim):
        authored_value(xformable.GetXformOpOrderAttr(), None)   # unreadable: USD would drop the transform
        times.update(xformable.GetTimeSamples())
    return sorted(times)


def transform_may_vary(prim: Usd.Prim) -> bool:
    """Whether the local-to-world transform of ``prim`` can differ between two times: an xformOp of the
    prim or of an ancestor (up to a resetXformStack) has more than one time sample (or value clips).
    An op with a single time sample holds that value at every time, so it moves nothing."""
    return any(xformable.TransformMightBeTimeVarying() for xformable in transform_chain(prim))


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
    return distinct_sorted(np.concatenate([np.array(ends, dtype=np.float64), inside]))


def _topology_sample_times(mesh: UsdGeom.Mesh) -> List[float]:
    times = set(mesh.GetFaceVertexCountsAttr().GetTimeSamples())
    times.update(mesh.GetFaceVertexIndicesAttr().GetTimeSamples())
    times.update(mesh.GetHoleIndicesAttr().GetTimeSamples())
    return sorted(times)


def authored_value(attribute: Usd.Attribute, time: Optional[float], file: Optional[str] = None):
    """``attribute.Get(time)`` (time None: a uniform attribute's value), or a one-line UsdkslInputError
    when the file gives it a type USD does not know (``point9f[] points``): USD then hands back an opaque
    value instead of refusing the file. The error names no file when ``file`` is None; load_shot adds it."""
    value = attribute.Get() if time is None else attribute.Get(time)
    if isinstance(value, Sdf.UnregisteredValue):
        raise UsdkslInputError(f"{attribute.GetName()} is authored with a type USD does not know, not as "
                               f"{attribute.GetTypeName()}", file=file, prim=str(attribute.GetPrim().GetPath()),
                               time=time)
    return value


def _array(attribute: Usd.Attribute, time: float, dtype) -> np.ndarray:
    value = authored_value(attribute, time)
    if value is None:
        return np.zeros(0, dtype=dtype)
    return np.asarray(value, dtype=dtype).reshape(-1)


def _points_count(attribute: Usd.Attribute, time: float) -> int:
    value = authored_value(attribute, time)
    return 0 if value is None else len(value)


def _topology_key(mesh: UsdGeom.Mesh, time: float):
    return (_array(mesh.GetFaceVertexCountsAttr(), time, np.int64),
            _array(mesh.GetFaceVertexIndicesAttr(), time, np.int64),
            _array(mesh.GetHoleIndicesAttr(), time, np.int64),
            _points_count(mesh.GetPointsAttr(), time))


def _same_topology(a, b) -> bool:
    return a[3] == b[3] and all(np.array_equal(x, y) for x, y in zip(a[:3], b[:3]))


def topology_stretches(prim: Usd.Prim) -> List[Tuple[float, float, tuple]]:
    """(first, last, topology key) of each run of consecutive ``points`` and topology samples of a mesh with one
    topology, in time order (time codes); [] for a mesh without samples. The key is (faceVertexCounts,
    faceVertexIndices, holeIndices, points count). Reads every sample."""
    mesh = UsdGeom.Mesh(prim)
    times = sorted(set(_topology_sample_times(mesh))
                   | set(mesh.GetPointsAttr().GetTimeSamples()))
    if not times:
        return []
    stretches = []
    start = previous = float(times[0])
    key = _topology_key(mesh, start)
    for time in times[1:]:
        current = _topology_key(mesh, time)
        if not _same_topology(key, current):
            stretches.append((start, previous, key))
            start, key = float(time), current
        previous = float(time)
    stretches.append((start, previous, key))
    return stretches


def topology_segments(prim: Usd.Prim) -> List[Tuple[float, float]]:
    """Constant-topology stretches of a mesh as (first, last) sample times, in time codes.

    Topology here is faceVertexCounts, faceVertexIndices, holeIndices and the points
    count. Between two samples whose topology differs USD holds the earlier value, so a
    segment ends at its last sample and the next starts at the sample that differs; each
    segment can be loaded on its own with ``load_shot(..., time_range=segment)``. A mesh
    without any samples is one segment at the default time, reported as (0.0, 0.0).
    """
    return [(first, last) for first, last, _ in topology_stretches(prim)] or [(0.0, 0.0)]


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
    """out = [local, 1] @ matrix (USD row vectors), projective matrices included. ``local`` is [N, 3] or a
    stack [K, N, 3] of samples, ``matrix`` [4, 4], or a stack [K, 4, 4] with one per sample of a stack or
    of ``out`` (numpy multiplies a stack slice by slice, and one [N, 3] local against every matrix of a stack:
    the same numbers as one by one)."""
    if local.dtype != out.dtype:
        # numpy multiplies mixed precisions element by element, several times slower than after one cast
        # (the same doubles: a float widens exactly)
        local = local.astype(out.dtype)
    with np.errstate(invalid="ignore", over="ignore"):   # non-finite input is reported by the caller
        np.matmul(local, matrix[..., :3, :3], out=out)
        out += matrix[..., None, 3, :3] if matrix.ndim == 3 else matrix[3, :3]
        if matrix.ndim == 2:
            if not np.array_equal(matrix[:, 3], (0.0, 0.0, 0.0, 1.0)):
                w = local @ matrix[:3, 3] + matrix[3, 3]
                out /= w[..., None]
            return
        for k in np.flatnonzero((matrix[:, :, 3] != (0.0, 0.0, 0.0, 1.0)).any(axis=1)):
            w = (local if local.ndim == 2 else local[k]) @ matrix[k, :3, 3] + matrix[k, 3, 3]
            out[k] /= w[..., None]


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
    value = authored_value(attribute, time, file)
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
    if samples_all_alike(points):
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


#: The local-to-world transform that leaves points as authored (USD row-vector convention).
IDENTITY_MATRIX = np.eye(4)

#: Point coordinates (samples x points x 3) read before they are moved to world space together: bounds the
#: extra memory of a block (16 MB of float32) while keeping per-sample numpy calls out of the Python loop over
#: samples (a transform that moves, as a rigid body's, contributes one matrix per sample to the block's product).
TRANSFORM_BLOCK_VALUES = 1 << 22


def _points_in_blocks(file: str, path: str, attribute: Usd.Attribute, times: np.ndarray, topology: MeshTopology,
                      animated: bool, fixed_matrix: Optional[np.ndarray], matrices: "_MatrixCache", prim: Usd.Prim,
                      out: np.ndarray) -> Optional[bool]:
    """``out[k]`` = the authored points at ``times[k]`` through the local-to-world transform at ``times[k]``
    (``fixed_matrix`` when it cannot vary, else from ``matrices``): the numbers, checks and first error of
    :func:`to_world_checked` sample after sample, the products taken over blocks of samples. Returns whether
    the authored points never change, or None (nothing done) when a sample's points come in another
    precision than the first's."""
    first = topology.first_local
    if not animated and fixed_matrix is not None:   # every sample is the first one
        to_world_checked(file, path, float(times[0]), first, fixed_matrix, out[0])
        out[1:] = out[0]
        return True
    samples_per_block = max(1, TRANSFORM_BLOCK_VALUES // max(1, first.size))
    # points that no transform moves are read straight into their place: no block, no product
    as_authored = (fixed_matrix is not None and out.dtype == first.dtype
                   and np.array_equal(fixed_matrix, IDENTITY_MATRIX))
    # held points (a rigid mesh) need no block: the one local goes against each sample's matrix
    block = (np.empty((min(samples_per_block, times.shape[0]),) + first.shape, dtype=first.dtype)
             if animated and not as_authored else None)
    local_constant = True
    for start in range(0, times.shape[0], samples_per_block):
        if as_authored:
            block = out[start:start + samples_per_block]
        stop = min(start + samples_per_block, times.shape[0])
        read, failure = stop - start, None
        if animated:
            read = 0
            for k in range(start, stop):
                try:
                    local = read_local_points(file, path, attribute, float(times[k]), topology)
                except UsdkslInputError as error:   # raised once the samples before it are checked
                    failure = error
                    break
                if local.dtype != first.dtype:
                    return None
                block[read] = local
                read += 1
        if read:
            world = out[start:start + read]
            if fixed_matrix is not None:
                matrix = fixed_matrix
                bad_matrix = 0 if start == 0 and not np.isfinite(fixed_matrix).all() else read
            else:
                matrix = np.stack([matrices.local_to_world(prim, float(t)) for t in times[start:start + read]])
                finite = np.isfinite(matrix).all(axis=(1, 2))
                bad_matrix = read if finite.all() else int(np.argmin(finite))
            if bad_matrix == 0:
                raise UsdkslInputError("local-to-world transform is not finite", file=file, prim=path,
                                       time=float(times[start]))
            if not as_authored:
                _to_world(block[:read] if animated else first, matrix, world)
            finite = np.isfinite(world).all(axis=(1, 2))
            bad = read if finite.all() else int(np.argmin(finite))
            if bad < bad_matrix:
                check_finite_points(file, path, float(times[start + bad]), world[bad])
            if bad_matrix < read:
                raise UsdkslInputError("local-to-world transform is not finite", file=file, prim=path,
                                       time=float(times[start + bad_matrix]))
            # sample by sample, so that deforming points stop comparing at their first change
            local_constant = local_constant and (not animated or all(
                np.array_equal(block[i], first) for i in range(read)))
        if failure is not None:
            raise failure
    return local_constant


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

    points_animated = points_attr.GetNumTimeSamples() > 1
    # a transform that cannot vary is the same matrix at every sample: computed once, applied in blocks
    fixed_matrix = None if transform_may_vary(prim) else matrices.local_to_world(prim, topology.first_time)

    # authored float points already in world space are kept as they are: the same numbers in half the memory
    in_place = (fixed_matrix is not None and np.array_equal(fixed_matrix, IDENTITY_MATRIX)
                and topology.first_local.dtype == np.float32)
    points = np.empty((times.shape[0], topology.point_count, 3), dtype=np.float32 if in_place else np.float64)
    local_constant = _points_in_blocks(file, path, points_attr, times, topology, points_animated, fixed_matrix,
                                       matrices, prim, points)
    if local_constant is not None:
        return classified_mesh(path, times, points, local_constant, topology)
    if points.dtype != np.float64:   # a sample in double: the points cannot stay float
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


