"""UsdGeom.PointInstancer instances as meshes of their own.

Every instance of every mesh prototype is one mesh, named ``<instancer path>[<index>]<prototype-relative
mesh path>``: instance 3 of the prototype ``/World/scatter/Prototypes/box`` whose mesh is
``.../box/geo`` is ``/World/scatter[3]/box/geo`` (a prototype that is itself the mesh: ``/World/scatter[3]/box``).
These names are not USD prim paths; reports carry them as they are, and the override layer writes
per-instance results on the instancer (:mod:`usdksl.reports.override`). ``--prims /World/scatter`` selects every
instance of that instancer.

World points of instance i of prototype mesh m at time t (time codes):

    points_m(t) x [transforms from m up to, not including, its prototype root](t)
                x ComputeInstanceTransformsAtTime(t, baseTime=t, IncludeProtoXform)[i]
                x local-to-world of the instancer(t)

so the prototype root's own transform, scales, orientations and positions apply as UsdGeom defines, and
the transforms of prims between the instancer and a prototype root are ignored (as UsdImaging does).
A prototype mesh that UsdSkel skins (a SkelRoot inside the prototype, :mod:`usdksl.reading.skinning`)
is posed first: its skinned points at t go through the skeleton's local-to-world transform and back
through the inverse of the prototype root's, in place of ``points_m(t) x [transforms ... root]``, and
its skinning samples are sample times too.

Sample times: the union of the samples of the instancer's per-instance attributes (positions, orientations,
scales, velocities, angular velocities, accelerations, protoIndices, ids, invisibleIds), the xformOp
samples of the instancer and its ancestors, and the ``points`` and xformOp samples of the prototype mesh
up to its prototype root. Points are evaluated at each sample and move linearly between them.

Velocities: when ``velocities`` or ``angularVelocities`` are authored, USD does not interpolate between
samples but moves each instance from the sample at or before t by velocity x (t - sample) / timeCodesPerSecond
(and accelerations, angular velocities). At every sample time usdksl asks USD for exactly that, so where the
velocities agree with the sampled positions the straight line between samples is USD's motion. Where they
do not (USD's instance leaves the straight line by more than :data:`VELOCITY_DEVIATION_TOLERANCE` of its
size, checked at each interval's middle and just before its end), a warning names the instancer, the
distance and the interval: usdksl checks the straight line between the sampled transforms. With velocities
authored, the stage's start and end time codes are samples too, since USD extrapolates beyond the last one.

Masking and identity: ``inactiveIds`` instances are skipped; an instance in ``invisibleIds`` is skipped only
when it is invisible at every sample of the checked range (one visible moment keeps it, checked over the
whole range). ``protoIndices`` or ``ids`` that change at an index, or an instance count that changes,
within the checked range are an input error (the instance at that index would jump to another object);
check the stretches in between with ``--time-range``. A PointInstancer inside a prototype (nested
instancing) is not expanded: a warning says its instances are not checked.

Meshes below a PointInstancer are never loaded on their own (see :func:`usdksl.reading.loader.mesh_prims`).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Callable, Dict, List, Optional, Tuple

import numpy as np
from pxr import Usd, UsdGeom

from ..errors import UsdkslInputError
from ..warning_kinds import NESTED_INSTANCER
from .meshes import (MeshData, MeshTopology, UncheckedGeometry, _MatrixCache, check_finite_points, classified_mesh,
                     rendered, unmeshed_solid_kind,
                     read_local_points, read_topology, xform_sample_times)

if TYPE_CHECKING:
    from .skinning import SkinnedMesh

#: Per-instance attributes whose time samples move or change instances.
INSTANCE_ATTRIBUTES = ("positions", "orientations", "orientationsf", "scales", "velocities",
                       "angularVelocities", "accelerations", "protoIndices", "ids", "invisibleIds")
#: Attributes that make USD extrapolate from the sample at or before t instead of interpolating.
VELOCITY_ATTRIBUTES = ("velocities", "angularVelocities")
#: Largest distance, as a fraction of an instance's bounding-box diagonal, by which USD's
#: velocity-extrapolated instance may leave the straight line between two samples without a warning.
VELOCITY_DEVIATION_TOLERANCE = 1e-5

_PROTOTYPE_PREDICATE = Usd.TraverseInstanceProxies(Usd.PrimIsActive & Usd.PrimIsLoaded & ~Usd.PrimIsAbstract)


def instance_mesh_path(instancer_path: str, index: int, relative_path: str) -> str:
    """``/World/scatter`` + 3 + ``/box/geo`` -> ``/World/scatter[3]/box/geo``."""
    return f"{instancer_path}[{index}]{relative_path}"


@dataclass(eq=False)
class PrototypeMesh:
    prim: Usd.Prim
    root: Usd.Prim          # the prototype root the instancer targets
    prototype_index: int
    relative_path: str      # '/<root name>/<path below the root>'


@dataclass(eq=False)
class Instancer:
    """One PointInstancer: its prototype meshes and, per time, its instance transforms."""

    prim: Usd.Prim
    file: str
    warnings: List[str]
    unchecked: List[UncheckedGeometry] = field(default_factory=list)
    prototype_meshes: List[PrototypeMesh] = field(default_factory=list)
    _transforms: Dict[Tuple[float, float], np.ndarray] = field(default_factory=dict)
    _warned_velocity: bool = False

    @property
    def path(self) -> str:
        return str(self.prim.GetPath())

    @property
    def schema(self) -> UsdGeom.PointInstancer:
        return UsdGeom.PointInstancer(self.prim)

    def uses_velocities(self) -> bool:
        return any(self.prim.GetAttribute(name).HasAuthoredValue() for name in VELOCITY_ATTRIBUTES
                   if self.prim.GetAttribute(name))

    def sample_times(self) -> set:
        times = set()
        for name in INSTANCE_ATTRIBUTES:
            attribute = self.prim.GetAttribute(name)
            if attribute:
                times.update(attribute.GetTimeSamples())
        times.update(xform_sample_times(self.prim))
        stage = self.prim.GetStage()
        if self.uses_velocities() and times and stage.HasAuthoredTimeCodeRange():
            times.update((stage.GetStartTimeCode(), stage.GetEndTimeCode()))
        return times

    def transforms(self, time: float, base_time: Optional[float] = None) -> np.ndarray:
        """float64[instances, 4, 4]: ComputeInstanceTransformsAtTime(time, base_time), prototype root
        transform included, no mask applied."""
        base_time = time if base_time is None else base_time
        key = (time, base_time)
        cached = self._transforms.get(key)
        if cached is None:
            result = self.schema.ComputeInstanceTransformsAtTime(
                Usd.TimeCode(time), Usd.TimeCode(base_time), UsdGeom.PointInstancer.IncludeProtoXform,
                UsdGeom.PointInstancer.IgnoreMask)
            cached = np.array(result, dtype=np.float64).reshape(-1, 4, 4)
            count = len(self.schema.GetProtoIndicesAttr().Get(base_time) or [])
            if cached.shape[0] != count:
                raise UsdkslInputError(
                    f"UsdGeom cannot compute the {count} instance transforms (positions, orientations or "
                    f"scales do not match protoIndices)", file=self.file, prim=self.path, time=base_time)
            if not np.isfinite(cached).all():
                raise UsdkslInputError("an instance transform is not finite", file=self.file,
                                       prim=self.path, time=time)
            self._transforms[key] = cached
        return cached

    def kept_instances(self, times: np.ndarray, prototype_index: int) -> np.ndarray:
        """Indices of the instances of ``prototype_index`` that are active and visible at some time of
        ``times``; input error when prototypes, ids or the instance count change within ``times``."""
        schema = self.schema
        first = float(times[0])
        indices = np.asarray(schema.GetProtoIndicesAttr().Get(first) or [], dtype=np.int64)
        ids_attribute = schema.GetIdsAttr()
        ids = ids_attribute.Get(first) if ids_attribute.HasAuthoredValue() else None
        visible = np.zeros(indices.size, bool)
        for time in times.tolist():
            current = np.asarray(schema.GetProtoIndicesAttr().Get(time) or [], dtype=np.int64)
            if current.size != indices.size:
                raise UsdkslInputError(
                    f"instance count changes from {indices.size} (time {first:g}) to {current.size}; check "
                    f"the stretches between changes with --time-range", file=self.file, prim=self.path,
                    time=time)
            if not np.array_equal(current, indices):
                index = int(np.argmax(current != indices))
                raise UsdkslInputError(
                    f"protoIndices change: instance {index} switches from prototype {int(indices[index])} to "
                    f"{int(current[index])}; check the stretches between changes with --time-range",
                    file=self.file, prim=self.path, time=time)
            if ids is not None and not np.array_equal(np.asarray(ids_attribute.Get(time)), np.asarray(ids)):
                raise UsdkslInputError(
                    "ids change: an index holds another instance from here on; check the stretches between "
                    "changes with --time-range", file=self.file, prim=self.path, time=time)
            mask = np.asarray(schema.ComputeMaskAtTime(Usd.TimeCode(time)), bool)
            visible |= mask if mask.size == visible.size else True   # no mask (or a malformed one): visible
        return np.flatnonzero(visible & (indices == prototype_index))

    def start_load(self, warnings: List[str]) -> None:
        """Say what loading finds (velocities off the straight line) in ``warnings``, once per load: the
        sources found on a stage are loaded once per piece of a shot cut at gaps (usdksl.pipeline.loading)."""
        self.warnings = warnings
        self._warned_velocity = False

    def warn_velocity_deviation(self, distance: float, start: float, end: float) -> None:
        if self._warned_velocity:
            return
        self._warned_velocity = True
        self.warnings.append(
            f"{self.file}: {self.path}: velocities move instances up to {distance:.3g} away from the straight "
            f"line between the samples at time {start:g} and {end:g} (USD extrapolates from each sample); "
            f"usdksl checks the straight line between sampled transforms")


@dataclass(eq=False)
class InstancedMesh:
    """The instances of one prototype mesh of one PointInstancer, loaded as one MeshData each."""

    instancer: Instancer
    mesh: PrototypeMesh
    wanted: Callable[[str], bool]
    skinned: Optional["SkinnedMesh"] = None     # UsdSkel poses the prototype mesh

    @property
    def path(self) -> str:
        return str(self.mesh.prim.GetPath())

    def motion_prims(self) -> List[Usd.Prim]:
        prims = [self.instancer.prim, self.mesh.root, self.mesh.prim]
        return prims + (self.skinned.motion_prims() if self.skinned is not None else [])

    def sample_times(self) -> np.ndarray:
        times = self.instancer.sample_times()
        times.update(UsdGeom.Mesh(self.mesh.prim).GetPointsAttr().GetTimeSamples())
        if self.skinned is not None:
            times.update(self.skinned.sample_times().tolist())
        probe = self.mesh.prim
        while probe and probe != self.mesh.root.GetParent():
            xformable = UsdGeom.Xformable(probe)
            if xformable:
                times.update(xformable.GetTimeSamples())
            probe = probe.GetParent()
        return np.array(sorted(times), dtype=np.float64)

    def load(self, times: np.ndarray, file: str, matrices: _MatrixCache) -> List[MeshData]:
        times = np.asarray(times, dtype=np.float64)
        # selection first: an instancer that --prims/--exclude leaves out is not read, nor rejected
        indices = np.asarray(self.instancer.schema.GetProtoIndicesAttr().Get(float(times[0])) or [], np.int64)
        candidates = np.flatnonzero(indices == self.mesh.prototype_index)
        selected = {int(i): name for i, name in (
            (i, instance_mesh_path(self.instancer.path, i, self.mesh.relative_path)) for i in candidates.tolist())
            if self.wanted(name)}
        if not selected:
            return []
        kept = self.instancer.kept_instances(times, self.mesh.prototype_index)
        kept = kept[np.isin(kept, list(selected))]
        names = [selected[i] for i in kept.tolist()]
        if kept.size == 0:
            return []
        topology = read_topology(self.mesh.prim, times, file)
        if self.skinned is not None and not self.skinned.poseable:
            self.skinned.load(times, file, matrices)        # raises the skinned mesh's own input error
        points = np.empty((kept.size, times.size, topology.point_count, 3), dtype=np.float64)
        local_constant = True
        first_local = None
        for k, time in enumerate(times.tolist()):
            local, relative = self._prototype_points(time, topology, file, matrices)
            if first_local is None:
                first_local = local
            elif local_constant and local is not first_local:
                local_constant = np.array_equal(local, first_local)
            points[:, k] = self._world(local, relative, time, time, matrices)[kept]
            if not np.isfinite(points[:, k]).all():
                row = int(np.argmax(~np.isfinite(points[:, k]).all(axis=(1, 2))))
                check_finite_points(file, names[row], time, points[row, k])
        if self.instancer.uses_velocities():
            self._check_velocities(times, topology, kept, points, matrices, file)
        return [classified_mesh(name, times, points[row], local_constant, topology, source=self.path,
                                instancer=self.instancer.path, instance_index=int(index))
                for row, (name, index) in enumerate(zip(names, kept.tolist()))]

    def _prototype_points(self, time: float, topology: MeshTopology, file: str, matrices: _MatrixCache):
        """(points of the prototype mesh at ``time``, float64[N, 3]; the matrix taking them into the frame
        of the prototype root's children). A skinned prototype mesh is posed by UsdSkel, in the skeleton's
        space, and taken from there through the skeleton's and the root's local-to-world transforms, so
        instances carry the skinned pose exactly as ``UsdSkel.BakeSkinning`` would bake it."""
        points_attr = UsdGeom.Mesh(self.mesh.prim).GetPointsAttr()
        local = read_local_points(file, self.path, points_attr, time, topology)
        if self.skinned is not None:
            posed, to_world = self.skinned.posed(local, time, file, matrices)
            return posed, to_world @ np.linalg.inv(matrices.local_to_world(self.mesh.root, time))
        cache = matrices.xform_cache(time)
        relative = np.eye(4)
        probe = self.mesh.prim
        while probe != self.mesh.root:
            matrix, resets = cache.GetLocalTransformation(probe)
            relative = relative @ np.array(matrix, dtype=np.float64)
            if resets:
                break
            probe = probe.GetParent()
        return local, relative

    def _world(self, local: np.ndarray, relative: np.ndarray, time: float, base_time: float,
               matrices: _MatrixCache) -> np.ndarray:
        """float64[instances, N, 3]: prototype-mesh points of every instance in world space (``relative``
        takes ``local`` into the frame of the prototype root's children)."""
        instance = self.instancer.transforms(time, base_time)
        full = relative[None] @ instance @ matrices.local_to_world(self.instancer.prim, time)[None]
        with np.errstate(invalid="ignore", over="ignore"):   # non-finite results are reported by the caller
            world = np.einsum("nj,ijk->ink", local, full[:, :3, :3]) + full[:, None, 3, :3]
            if not np.allclose(full[:, :, 3], (0.0, 0.0, 0.0, 1.0), rtol=0.0, atol=0.0):
                w = np.einsum("nj,ij->in", local, full[:, :3, 3]) + full[:, None, 3, 3]
                world /= w[..., None]
        return world

    def _check_velocities(self, times, topology: MeshTopology, kept, points, matrices, file) -> None:
        """Warn when USD's velocity-driven instances leave the straight line between two samples."""
        size = np.linalg.norm(np.ptp(points, axis=2), axis=-1).max(axis=1)   # per instance diagonal
        size = np.maximum(size, np.finfo(np.float64).tiny)
        for k in range(times.size - 1):
            start, end = float(times[k]), float(times[k + 1])
            middle = 0.5 * (start + end)
            straight_middle = 0.5 * (points[:, k] + points[:, k + 1])
            for time, straight in ((middle, straight_middle), (end, points[:, k + 1])):
                local, relative = self._prototype_points(time, topology, file, matrices)
                usd = self._world(local, relative, time, start, matrices)[kept]
                distance = np.linalg.norm(usd - straight, axis=-1).max(axis=1)
                worst = int(np.argmax(distance / size))
                if distance[worst] > VELOCITY_DEVIATION_TOLERANCE * size[worst]:
                    self.instancer.warn_velocity_deviation(float(distance[worst]), start, end)
                    return


def _prototype_meshes(instancer: Instancer, wanted: Callable[[str], bool],
                      unmeshed: List[Tuple[str, str]]) -> List[PrototypeMesh]:
    """The mesh prims of every prototype; (kind, path) of solid non-meshes in prototypes that have
    selected instances on a rendered instancer are appended to ``unmeshed``."""
    stage = instancer.prim.GetStage()
    meshes = []
    proto_indices = np.asarray(instancer.schema.GetProtoIndicesAttr().Get(Usd.TimeCode.EarliestTime()) or [],
                               dtype=np.int64) if rendered(instancer.prim) else np.zeros(0, np.int64)
    for index, target in enumerate(instancer.schema.GetPrototypesRel().GetForwardedTargets()):
        root = stage.GetPrimAtPath(target)
        if not root:
            instancer.warnings.append(f"{instancer.file}: {instancer.path}: prototype {index} ({target}) is not "
                                      f"on the stage; its instances have no geometry to check")
            continue
        prims = iter(Usd.PrimRange(root, _PROTOTYPE_PREDICATE))
        for prim in prims:
            if prim.IsA(UsdGeom.PointInstancer):
                reason = (f"a PointInstancer inside prototype {index} of {instancer.path}: nested instancing is "
                          f"not supported; its instances are not checked")
                instancer.warnings.append(f"{instancer.file}: {prim.GetPath()}: {reason}")
                instancer.unchecked.append(UncheckedGeometry(prim=str(prim.GetPath()), reason=reason,
                                                             kind=NESTED_INSTANCER))
                prims.PruneChildren()
                continue
            below = str(prim.GetPath().MakeRelativePath(root.GetPath()))
            relative = "/" + root.GetName() + ("" if below == "." else "/" + below)
            if unmeshed_solid_kind(prim) and rendered(prim) and any(
                    wanted(instance_mesh_path(instancer.path, i, relative))
                    for i in np.flatnonzero(proto_indices == index).tolist()):
                unmeshed.append((unmeshed_solid_kind(prim), str(prim.GetPath())))
            elif prim.IsA(UsdGeom.Mesh):
                meshes.append(PrototypeMesh(prim=prim, root=root, prototype_index=index, relative_path=relative))
    return meshes


def find_instanced_meshes(stage: Usd.Stage, wanted: Callable[[str], bool], file: str,
                          warnings: List[str], skinned: Optional[Dict[str, "SkinnedMesh"]] = None,
                          unchecked: Optional[List[UncheckedGeometry]] = None,
                          unmeshed: Optional[List[Tuple[str, str]]] = None) -> List[InstancedMesh]:
    """One InstancedMesh per (PointInstancer, prototype mesh), in traversal order. PointInstancers below
    another PointInstancer are prototypes of it (nested instancing, see the module docstring).
    ``skinned``: {mesh path: SkinnedMesh} of :func:`usdksl.reading.skinning.find_skinned_meshes`; prototype
    meshes found there are posed by UsdSkel. Geometry read past without a check is appended to
    ``unchecked`` (and to ``warnings``); solid non-mesh prims in prototypes with instances to ``unmeshed``
    as (kind, path)."""
    skinned = skinned or {}
    unchecked = unchecked if unchecked is not None else []
    unmeshed = unmeshed if unmeshed is not None else []
    predicate = Usd.TraverseInstanceProxies(Usd.PrimDefaultPredicate)
    found = []
    prims = iter(Usd.PrimRange.Stage(stage, predicate))
    for prim in prims:
        if not prim.IsA(UsdGeom.PointInstancer):
            continue
        prims.PruneChildren()
        instancer = Instancer(prim=prim, file=file, warnings=warnings, unchecked=unchecked)
        instancer.prototype_meshes = _prototype_meshes(instancer, wanted, unmeshed)
        found.extend(InstancedMesh(instancer=instancer, mesh=mesh, wanted=wanted,
                                   skinned=skinned.get(str(mesh.prim.GetPath())))
                     for mesh in instancer.prototype_meshes)
    return found
