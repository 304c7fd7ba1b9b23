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

The sample times of a skinned mesh are the union of the SkelAnimation's joint-transform samples, its
blend-shape-weight samples, the mesh's ``points`` samples, the samples of the skinning properties
(joint influences, geomBindTransform) and the xformOp samples of the Skeleton and its ancestors (of the
mesh and its ancestors when no joints move it). Points are skinned at each of these samples and move
linearly between them: joint rotations that USD would slerp between two samples are followed by the
straight line between the two skinned poses, as in a baked cache.

A skinned mesh is *deforming*; one skinned with constant (per-mesh, not per-vertex) joint influences
and no blend shapes moves as one transform and is *rigid* (``UsdSkel.BakeSkinning`` bakes it into a
transform too); one that never moves is static. A mesh that UsdSkel cannot pose (a skeleton with neither
an animation nor ``restTransforms``, joint influences that do not fit the points) is an input error.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Dict, List, Optional

import numpy as np
from pxr import Usd, UsdGeom, UsdSkel, Vt

from ..errors import UsdkslInputError
from .meshes import (MeshData, _MatrixCache, classified_mesh, read_local_points, read_topology,
                     to_world_checked, xform_sample_times)


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

    @property
    def path(self) -> str:
        return str(self.prim.GetPath())

    @property
    def skeleton_prim(self) -> Usd.Prim:
        return self.skeleton_query.GetPrim()

    def motion_prims(self) -> List[Usd.Prim]:
        """Prims whose opinions move this mesh: the mesh, its skeleton and the skeleton's animation."""
        prims = [self.prim, self.skeleton_prim]
        animation = self.skeleton_query.GetAnimQuery()
        if animation:
            prims.append(animation.GetPrim())
        return prims

    def sample_times(self) -> np.ndarray:
        """Union of every sample that changes the posed points (module docstring), in time codes."""
        times = set(UsdGeom.Mesh(self.prim).GetPointsAttr().GetTimeSamples())
        # SkinningQuery.GetTimeSamples() throws when geomBindTransform is not authored (usd-core 26.11)
        for attribute in (self.skinning_query.GetJointIndicesPrimvar().GetAttr(),
                          self.skinning_query.GetJointWeightsPrimvar().GetAttr(),
                          self.skinning_query.GetGeomBindTransformAttr()):
            if attribute:
                times.update(attribute.GetTimeSamples())
        animation = self.skeleton_query.GetAnimQuery()
        if self.uses_joints:
            if animation:
                times.update(animation.GetJointTransformTimeSamples())
            times.update(xform_sample_times(self.skeleton_prim))
        else:
            times.update(xform_sample_times(self.prim))
        if self.blend_shapes is not None:
            times.update(animation.GetBlendShapeWeightTimeSamples())
        return np.array(sorted(times), dtype=np.float64)

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
            posed, matrix = self._posed(rest, time, file, matrices)
            to_world_checked(file, path, time, posed, matrix, points[k])
        moves_as_one = (self.uses_joints and self.skinning_query.IsRigidlyDeformed()
                        and self.blend_shapes is None and rest_constant)
        return classified_mesh(path, times, points, moves_as_one, topology)

    def _posed(self, rest: np.ndarray, time: float, file: str, matrices: _MatrixCache):
        """(points after blend shapes and skinning, float64[N, 3]; matrix taking them to world space)."""
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


def find_skinned_meshes(stage: Usd.Stage) -> Dict[str, SkinnedMesh]:
    """{mesh prim path: SkinnedMesh} for every UsdGeom.Mesh UsdSkel poses (module docstring)."""
    predicate = Usd.TraverseInstanceProxies(Usd.PrimDefaultPredicate)
    cache = UsdSkel.Cache()
    found: Dict[str, SkinnedMesh] = {}
    for prim in Usd.PrimRange.Stage(stage, predicate):
        if not prim.IsA(UsdSkel.Root):
            continue
        root = UsdSkel.Root(prim)
        cache.Populate(root, predicate)
        for binding in cache.ComputeSkelBindings(root, predicate):
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
                                          poseable=not uses_joints or _skeleton_is_poseable(skeleton_query))
    return found
