"""Meshes skinned by UsdSkel, posed through OpenUSD's own UsdSkel API at each time sample.

A mesh is skinned when UsdSkel says so: it sits under a ``SkelRoot`` and binds (``skel:skeleton``, possibly
inherited) to a ``Skeleton`` with joint influences (``primvars:skel:jointIndices`` / ``jointWeights``)
and/or blend shapes (``skel:blendShapes`` / ``skel:blendShapeTargets``) that its animation drives. A mesh
bound outside a SkelRoot, or with neither influences nor animated blend shapes, is an ordinary mesh (as for
``UsdSkel.BakeSkinning``).

Points at time t (time codes), exactly as ``UsdSkel.BakeSkinning`` computes them:

1. the authored ``points`` at t (the rest shape);
2. blend shapes: the SkelAnimation's ``blendShapeWeights`` at t, remapped to the mesh's
   ``skel:blendShapes`` order, resolved into sub-shape (inbetween) weights and applied
   (``UsdSkel.BlendShapeQuery``);
3. joints: ``SkeletonQuery.ComputeSkinningTransforms(t)`` (skeleton-space joint transforms times the inverse
   bind transforms) and ``SkinningQuery.ComputeSkinnedPoints`` (linear blend or dual-quaternion skinning as
   the mesh's ``skel:skinningMethod`` says, with ``geomBindTransform``); the result is in skeleton space;
4. world space: skinned points go through the Skeleton prim's local-to-world transform at t (the skinned
   mesh's own transform is ignored, as UsdSkel defines); a mesh with blend shapes but no joint influences
   keeps its own local-to-world transform.

The *keys* of a skinned mesh are the union of the SkelAnimation's joint-transform samples, its
blend-shape-weight samples, the mesh's ``points`` samples, the samples of the skinning properties
(joint influences, geomBindTransform) and the xformOp samples of the Skeleton and its ancestors (of the
mesh and its ancestors when no joints move it). Points are skinned at each sample time and move
linearly between them, as in a baked cache.

Between keys USD slerps joint rotations (and interpolates each xformOp of the skeleton's transform, and
resolves in-between blend shapes), so a straight line between two skinned keys is not the pose UsdSkel
gives in between. ``UsdSkel.BakeSkinning`` therefore also bakes every playback frame of the stage inside
the span of a skeleton's keys, and so does usdksl: the sample times are the keys plus the frames
(:func:`playback_frames`) from the first to the last key of the *animation* (joint transforms and the
Skeleton's world transform when joints move the mesh, blend-shape weights when blend shapes do) that are
not keys already. A mesh keyed at every frame gets nothing more; ``keys_only`` (``--skin-keys-only``) poses
at the keys only. The frames are BakeSkinning's exactly: ``startTimeCode + i * timeCodesPerSecond /
framesPerSecond`` for ``i`` from 0 to ``int((endTimeCode - startTimeCode) / step + 1)`` inclusive, which is
one frame past ``endTimeCode`` (usd-core 26.11 does so; still within the keys' span only). A stage that
authors no startTimeCode/endTimeCode has no frames for BakeSkinning (it bakes the keys only); usdksl then
poses at the keys only too and says so (:func:`sparse_key_notes`). Where the mesh's ``points`` or skinning
properties are sampled beyond the animation's keys, BakeSkinning bakes frames there too: the animation is
held there, skinning is linear in what moves, and the straight lines are its poses, so usdksl adds none.

Native instancing (``instanceable = true``, nested too: a character inside an instanceable crowd group):
each skinned mesh of an instance is its own mesh, named by its instance-proxy path
(``/World/crowd/char2/Body/Arm``), and posed as the de-instanced stage would be (``UsdSkel.BakeSkinning``
refuses instanced SkelRoots): with the joint influences and blend shapes UsdSkel resolves for the
instance-proxy mesh, the animation bound to the instance's Skeleton (``skel:animationSource`` is inherited,
so one authored on the instanceable prim or above it, outside the prototype, gives that instance an
animation of its own), and the local-to-world transform and xformOp samples of the instance's Skeleton
(the instance proxy, whose ancestors place the instance). ``UsdSkel.Cache`` resolves the animation per instance but hands back the
prototype's Skeleton prim, whose transform is the prototype's: every instance would be posed where the
prototype is.

A skinned mesh is *deforming*; one skinned with constant (per-mesh, not per-vertex) joint influences
and no blend shapes moves as one transform and is *rigid* (``UsdSkel.BakeSkinning`` bakes it into a
transform too); one that never moves is static. A mesh that UsdSkel cannot pose (a skeleton with neither
an animation nor ``restTransforms``, joint influences that do not fit the points) is an input error.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Dict, List, Optional, Sequence, Tuple

import numpy as np
from pxr import Usd, UsdGeom, UsdSkel, Vt

from ..errors import UsdkslInputError
from ..unmasked import distinct_sorted
from .meshes import (MeshData, _MatrixCache, classified_mesh, read_local_points, read_topology,
                     to_world_checked, xform_sample_times)

#: A frame closer than this to a key is that key (fraction of one frame step): ``start + i * step`` rounds
#: differently from an authored key such as 2.4, and two samples that close would pose the same shape twice.
FRAME_KEY_TOLERANCE = 1e-6
#: UsdSkel.BakeSkinning bakes no playback frames when timeCodesPerSecond or framesPerSecond is this close
#: to zero (its own GfIsClose threshold).
ZERO_RATE = 1e-6


def frame_step(stage: Usd.Stage) -> Optional[float]:
    """Time codes between two playback frames (|timeCodesPerSecond / framesPerSecond|), None when either
    rate is zero."""
    per_second, frames = stage.GetTimeCodesPerSecond(), stage.GetFramesPerSecond()
    if abs(per_second) <= ZERO_RATE or abs(frames) <= ZERO_RATE:
        return None
    return abs(per_second / frames)


def playback_frames(stage: Usd.Stage, first: float, last: float) -> np.ndarray:
    """The playback frames (time codes) in [first, last] at which ``UsdSkel.BakeSkinning`` bakes skinning:
    ``startTimeCode + i * step`` for i = 0 .. int((endTimeCode - startTimeCode) / step + 1), as its
    ``_GetStagePlaybackTimeCodesInRange`` computes them (that last i is one frame past endTimeCode). Empty
    when the stage authors no time range, a rate is zero or endTimeCode < startTimeCode."""
    step = frame_step(stage)
    if step is None or not stage.HasAuthoredTimeCodeRange():
        return np.zeros(0, dtype=np.float64)
    start, end = stage.GetStartTimeCode(), stage.GetEndTimeCode()
    if end < start or last < first:
        return np.zeros(0, dtype=np.float64)
    count = int((end - start) / step + 1)
    # a margin of one frame on each side; the exact products are then filtered as BakeSkinning's are
    low = max(0, math.floor((first - start) / step) - 1)
    high = min(count, math.ceil((last - start) / step) + 1)
    if high < low:
        return np.zeros(0, dtype=np.float64)
    frames = start + step * np.arange(low, high + 1, dtype=np.float64)
    return frames[(frames >= first) & (frames <= last)]


@dataclass(eq=False)
class SkinnedMesh:
    """One UsdGeom.Mesh that UsdSkel poses, with the queries that pose it."""

    prim: Usd.Prim
    skeleton_query: UsdSkel.SkeletonQuery
    skinning_query: UsdSkel.SkinningQuery
    uses_joints: bool                                    # joint influences and a poseable skeleton
    blend_shapes: Optional[UsdSkel.BlendShapeQuery]      # None when no animated blend shape applies
    sub_shape_offsets: Optional[list] = None
    blend_shape_point_indices: Optional[list] = None
    poseable: bool = True           # False: joint influences but a skeleton UsdSkel cannot pose (load raises)
    keys_only: bool = False         # True: posed at its keys only, never at the frames between sparse keys
    # The bound Skeleton as the stage shows it (an instance proxy under native instancing, where the
    # query's own prim is the prototype's); None: the query's prim.
    skeleton: Optional[Usd.Prim] = None

    @property
    def path(self) -> str:
        return str(self.prim.GetPath())

    @property
    def skeleton_prim(self) -> Usd.Prim:
        """The bound Skeleton where this mesh's instance has it: its transforms place the skinned points."""
        return self.skeleton if self.skeleton is not None else self.skeleton_query.GetPrim()

    def motion_prims(self) -> List[Usd.Prim]:
        """Prims whose opinions move this mesh: the mesh, its skeleton and the skeleton's animation."""
        prims = [self.prim, self.skeleton_prim]
        animation = self.skeleton_query.GetAnimQuery()
        if animation:
            prims.append(animation.GetPrim())
        return prims

    def sample_times(self) -> np.ndarray:
        """Time codes at which the mesh is posed: its keys, plus the playback frames between its animation's
        keys that are not keys unless ``keys_only`` (module docstring)."""
        animation_keys, keys = self._keys()
        if self.keys_only:
            return keys
        frames = self._frames_between(animation_keys, keys)
        return distinct_sorted(np.concatenate([keys, frames])) if frames.size else keys

    def key_times(self) -> np.ndarray:
        """Union of every sample that changes the posed points (module docstring), in time codes."""
        return self._keys()[1]

    def frames_between_keys(self) -> np.ndarray:
        """The playback frames (time codes) ``UsdSkel.BakeSkinning`` poses this mesh at from the first to the
        last key of its animation that are no key of it: empty when it is keyed at every frame or the stage
        authors no time range. ``keys_only`` does not change them (they are left out of the samples)."""
        return self._frames_between(*self._keys())

    def key_gaps_wider_than_a_frame(self) -> List[Tuple[float, float]]:
        """(key, next key) of the animation, in time codes, further apart than one playback frame (empty
        when a rate is zero)."""
        step = frame_step(self.prim.GetStage())
        keys = self._keys()[0]
        if step is None or len(keys) < 2:
            return []
        wide = np.flatnonzero(np.diff(keys) > step * (1.0 + FRAME_KEY_TOLERANCE))
        return [(float(keys[i]), float(keys[i + 1])) for i in wide]

    def _keys(self) -> Tuple[np.ndarray, np.ndarray]:
        """(the animation's keys: what USD interpolates other than linearly into the pose; all the keys),
        each sorted, in time codes. The animation is the joint transforms and the xformOps of the Skeleton and
        its ancestors when joints move the mesh, and the blend-shape weights when blend shapes do."""
        times = set(UsdGeom.Mesh(self.prim).GetPointsAttr().GetTimeSamples())
        # SkinningQuery.GetTimeSamples() throws when geomBindTransform is not authored (usd-core 26.11)
        for attribute in (self.skinning_query.GetJointIndicesPrimvar().GetAttr(),
                          self.skinning_query.GetJointWeightsPrimvar().GetAttr(),
                          self.skinning_query.GetGeomBindTransformAttr()):
            if attribute:
                times.update(attribute.GetTimeSamples())
        animated = set()
        animation = self.skeleton_query.GetAnimQuery()
        if self.uses_joints:
            if animation:
                animated.update(animation.GetJointTransformTimeSamples())
            animated.update(xform_sample_times(self.skeleton_prim))
        else:
            times.update(xform_sample_times(self.prim))
        if self.blend_shapes is not None:
            animated.update(animation.GetBlendShapeWeightTimeSamples())
        times.update(animated)
        return (np.array(sorted(animated), dtype=np.float64), np.array(sorted(times), dtype=np.float64))

    def _frames_between(self, animation_keys: np.ndarray, keys: np.ndarray) -> np.ndarray:
        if animation_keys.size < 2:
            return np.zeros(0, dtype=np.float64)
        stage = self.prim.GetStage()
        frames = playback_frames(stage, float(animation_keys[0]), float(animation_keys[-1]))
        if frames.size == 0:
            return frames
        after = np.clip(np.searchsorted(keys, frames), 1, keys.size - 1)
        nearest = np.minimum(np.abs(frames - keys[after - 1]), np.abs(keys[after] - frames))
        return frames[nearest > FRAME_KEY_TOLERANCE * frame_step(stage)]

    def load(self, times: np.ndarray, file: str, matrices: _MatrixCache) -> MeshData:
        """World-space points at ``times`` (increasing, non-empty), classified (module docstring)."""
        path = self.path
        if not self.poseable:
            raise UsdkslInputError(f"skinned by {self.skeleton_prim.GetPath()}, which has neither an animation "
                                   f"nor restTransforms: UsdSkel cannot pose it", file=file, prim=path)
        times = np.asarray(times, dtype=np.float64)
        topology = read_topology(self.prim, times, file)
        points_attr = UsdGeom.Mesh(self.prim).GetPointsAttr()
        points = np.empty((times.shape[0], topology.point_count, 3), dtype=np.float64)
        rest_constant = True
        for k, time in enumerate(times.tolist()):
            rest = read_local_points(file, path, points_attr, time, topology)
            if rest_constant and rest is not topology.first_local:
                rest_constant = np.array_equal(rest, topology.first_local)
            posed, matrix = self.posed(rest, time, file, matrices)
            to_world_checked(file, path, time, posed, matrix, points[k])
        moves_as_one = (self.uses_joints and self.skinning_query.IsRigidlyDeformed()
                        and self.blend_shapes is None and rest_constant)
        return classified_mesh(path, times, points, moves_as_one, topology)

    def posed(self, rest: np.ndarray, time: float, file: str, matrices: _MatrixCache):
        """(``rest`` points after blend shapes and skinning at ``time`` (time codes), float64[N, 3]; the
        matrix taking them to world space)."""
        path = self.path
        points = Vt.Vec3fArray.FromNumpy(np.ascontiguousarray(rest, dtype=np.float32))
        if self.blend_shapes is not None:
            animation = self.skeleton_query.GetAnimQuery()
            weights = self.skinning_query.GetBlendShapeMapper().Remap(
                animation.ComputeBlendShapeWeights(time))
            sub_weights, shape_indices, sub_indices = self.blend_shapes.ComputeSubShapeWeights(weights)
            if not self.blend_shapes.ComputeDeformedPoints(sub_weights, shape_indices, sub_indices,
                                                           self.blend_shape_point_indices,
                                                           self.sub_shape_offsets, points):
                raise UsdkslInputError("UsdSkel cannot apply the blend shapes (offsets or point indices do "
                                       "not fit the points)", file=file, prim=path, time=time)
        if not self.uses_joints:
            return np.asarray(points, dtype=np.float64), matrices.local_to_world(self.prim, time)
        transforms = self.skeleton_query.ComputeSkinningTransforms(time)
        if transforms is None or len(transforms) != len(self.skeleton_query.GetJointOrder()):
            raise UsdkslInputError(f"UsdSkel cannot compute the skinning transforms of "
                                   f"{self.skeleton_prim.GetPath()}", file=file, prim=path, time=time)
        if not self.skinning_query.ComputeSkinnedPoints(transforms, points, time):
            raise UsdkslInputError("UsdSkel cannot skin the points (joint influences do not fit the points "
                                   "or the skeleton)", file=file, prim=path, time=time)
        return np.asarray(points, dtype=np.float64), matrices.local_to_world(self.skeleton_prim, time)


def sparse_key_notes(meshes: Sequence[SkinnedMesh], time_range: Optional[Tuple[float, float]] = None
                     ) -> List[str]:
    """Information lines (for :attr:`usdksl.reading.meshes.Shot.notes`, kind
    ``usdksl.warning_kinds.SPARSE_SKIN_KEYS``) on the skinned meshes keyed more sparsely than the playback
    frames within ``time_range`` (time codes, ends excluded; None: everywhere): those posed at every frame,
    those posed at their keys only under ``keys_only``, and those posed at their keys only because the stage
    authors no time range (module docstring). One line per case, none when no mesh is keyed sparsely."""
    start, end = time_range if time_range is not None else (-math.inf, math.inf)
    at_frames: List[str] = []
    by_option: List[str] = []
    no_range: List[str] = []
    for mesh in dict.fromkeys(meshes):      # a prototype posed for many instances counts once
        frames = mesh.frames_between_keys()
        if frames.size:
            if np.any((frames > start) & (frames < end)):
                (by_option if mesh.keys_only else at_frames).append(mesh.path)
        elif not mesh.prim.GetStage().HasAuthoredTimeCodeRange():
            if any(first < end and last > start for first, last in mesh.key_gaps_wider_than_a_frame()):
                no_range.append(mesh.path)

    def meshes_named(paths: List[str]) -> str:
        count = len(paths)
        return (f"{count} skinned mesh{'es' if count > 1 else ''} keyed more sparsely than the frames "
                f"(first {paths[0]}) {'are' if count > 1 else 'is'}")

    lines = []
    if at_frames:
        lines.append(f"{meshes_named(at_frames)} posed at every frame, as UsdSkel.BakeSkinning does "
                     f"(--skin-keys-only checks on the keys only)")
    if by_option:
        lines.append(f"{meshes_named(by_option)} posed at the keys only (--skin-keys-only): straight lines between "
                     f"keys, where UsdSkel.BakeSkinning poses every frame")
    if no_range:
        lines.append(f"{meshes_named(no_range)} posed at the keys only: the stage authors no startTimeCode/"
                     f"endTimeCode, so UsdSkel.BakeSkinning has no frames to pose them at either (author the "
                     f"range to check every frame)")
    return lines


def _skeleton_is_poseable(skeleton_query: UsdSkel.SkeletonQuery) -> bool:
    """True when UsdSkel can compute skinning transforms: a mappable animation or authored restTransforms
    (the condition UsdSkel.BakeSkinning uses)."""
    animation = skeleton_query.GetAnimQuery()
    if animation and not skeleton_query.GetMapper().IsNull():
        return True
    skeleton = skeleton_query.GetSkeleton()
    return bool(skeleton) and skeleton.GetRestTransformsAttr().HasAuthoredValue()


def _animated_blend_shapes(skeleton_query: UsdSkel.SkeletonQuery, skinning_query: UsdSkel.SkinningQuery,
                           prim: Usd.Prim):
    """(BlendShapeQuery, sub-shape offsets, point indices) when animated blend shapes deform ``prim``."""
    animation = skeleton_query.GetAnimQuery()
    if not (skinning_query.HasBlendShapes() and animation):
        return None
    weights = UsdSkel.Animation(animation.GetPrim()).GetBlendShapeWeightsAttr()
    if not (weights and weights.HasAuthoredValue()):
        return None
    query = UsdSkel.BlendShapeQuery(UsdSkel.BindingAPI(prim))
    offsets = query.ComputeSubShapePointOffsets()
    if not any(len(shape) for shape in offsets):
        return None
    return query, offsets, query.ComputeBlendShapePointIndices()


def find_skinned_meshes(stage: Usd.Stage, keys_only: bool = False) -> Dict[str, SkinnedMesh]:
    """{mesh prim path: SkinnedMesh} for every UsdGeom.Mesh UsdSkel poses (module docstring); ``keys_only``:
    each is posed at its keys only (``--skin-keys-only``)."""
    predicate = Usd.TraverseInstanceProxies(Usd.PrimDefaultPredicate)
    cache = UsdSkel.Cache()
    found: Dict[str, SkinnedMesh] = {}
    for prim in Usd.PrimRange.Stage(stage, predicate):
        if not prim.IsA(UsdSkel.Root):
            continue
        root = UsdSkel.Root(prim)
        cache.Populate(root, predicate)
        for binding in cache.ComputeSkelBindings(root, predicate):
            # Under native instancing the binding names the instance's own Skeleton (an instance proxy) and
            # its query carries the animation bound to that instance, but the query's prim is the prototype's.
            skeleton = binding.GetSkeleton().GetPrim()
            skeleton_query = cache.GetSkelQuery(binding.GetSkeleton())
            if not skeleton_query:
                continue
            for skinning_query in binding.GetSkinningTargets():
                mesh_prim = skinning_query.GetPrim()
                path = str(mesh_prim.GetPath())
                if path in found or not mesh_prim.IsA(UsdGeom.Mesh):
                    continue
                uses_joints = skinning_query.HasJointInfluences()
                blend = _animated_blend_shapes(skeleton_query, skinning_query, mesh_prim)
                if not uses_joints and blend is None:
                    continue
                query, offsets, indices = blend if blend is not None else (None, None, None)
                found[path] = SkinnedMesh(prim=mesh_prim, skeleton_query=skeleton_query,
                                          skinning_query=skinning_query, uses_joints=uses_joints,
                                          blend_shapes=query, sub_shape_offsets=offsets,
                                          blend_shape_point_indices=indices,
                                          poseable=not uses_joints or _skeleton_is_poseable(skeleton_query),
                                          keys_only=keys_only, skeleton=skeleton)
    return found
