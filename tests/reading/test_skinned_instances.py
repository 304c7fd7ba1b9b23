"""Skinned characters under native instancing (``instanceable = true`` references): each instance is posed
with its own Skeleton, animation binding and world transform, so usdksl checks an instanced crowd exactly as
it checks the same stage de-instanced and baked by ``UsdSkel.BakeSkinning``."""

import shutil

import numpy as np
import pytest
from pxr import Gf, Usd, UsdGeom, UsdSkel, Vt

from usdksl.reading.loader import load_shot

from builders import sha256 as file_digest

#: Largest time difference between a contact on the instanced stage and on its baked copy (time codes).
TIME_AGREEMENT = 1e-4
#: Largest difference between the points usdksl poses and the baked ones (scene units; both skin in float32).
POINT_AGREEMENT = 1e-5

FRAMES = (1, 12)                                  # the animations' first and last key (time codes)
JOINTS = ["shoulder", "shoulder/elbow"]
SHOULDER = (0.6, 1.5, 0.0)                        # the shoulder joint in character space (scene units)
UPPER_ARM, FOREARM = 1.0, 1.3                     # bone lengths along +X (scene units)
ARM_HALF_WIDTH = 0.1                              # the arm is a square tube (scene units)
ARM_SECTIONS = 8
TORSO = ((-0.5, 0.0, -0.3), (0.5, 2.0, 0.3))      # the torso box's corners in character space (scene units)
CURL_OFFSET = 0.2                                 # the blend shape lifts the arm's tip by this (scene units)
REACH = (90.0, 0.0)                               # elbow degrees at the first and last frame: the arm stretches
WAVE = (90.0, 120.0)                              # the forearm stays raised
ASSET = "character.usda"

#: Where the SkelRoot sits relative to the instanceable prim: (asset type of /Character, SkelRoot inside the
#: asset, SkelRoot defined on the stage above the instances).
LAYOUTS = {
    "skel_root_is_the_instance": ("SkelRoot", None, False),
    "skel_root_inside_the_instance": ("Xform", "Body", False),
    "skel_root_above_the_instances": ("Xform", None, True),
}


def _animation(stage, path, elbow=REACH, blend_shapes=("curl",), weights=((0.0,), (0.5,))):
    """A SkelAnimation keyed at every frame: the elbow turns about Z from ``elbow[0]`` to ``elbow[1]``
    degrees; ``blend_shapes`` weigh ``weights[0]`` at the first frame and ``weights[1]`` at the last."""
    animation = UsdSkel.Animation.Define(stage, path)
    animation.CreateJointsAttr(JOINTS)
    animation.CreateTranslationsAttr(Vt.Vec3fArray([SHOULDER, (UPPER_ARM, 0.0, 0.0)]))
    animation.CreateScalesAttr(Vt.Vec3hArray([(1, 1, 1)] * len(JOINTS)))
    rotations = animation.CreateRotationsAttr()
    animation.CreateBlendShapesAttr(list(blend_shapes))
    blend_weights = animation.CreateBlendShapeWeightsAttr()
    for time in range(FRAMES[0], FRAMES[1] + 1):
        f = (time - FRAMES[0]) / (FRAMES[1] - FRAMES[0])
        degrees = elbow[0] + f * (elbow[1] - elbow[0])
        rotations.Set(Vt.QuatfArray([Gf.Quatf(1.0), Gf.Quatf(Gf.Rotation(Gf.Vec3d(0, 0, 1), degrees).GetQuat())]),
                      float(time))
        blend_weights.Set(Vt.FloatArray([a + f * (b - a) for a, b in zip(*weights)]), float(time))
    return animation


def _define_mesh(stage, path, points, faces):
    mesh = UsdGeom.Mesh.Define(stage, path)
    mesh.CreateFaceVertexCountsAttr(Vt.IntArray([len(face) for face in faces]))
    mesh.CreateFaceVertexIndicesAttr(Vt.IntArray([int(i) for face in faces for i in face]))
    mesh.CreatePointsAttr(Vt.Vec3fArray.FromNumpy(np.asarray(points, np.float32)))
    return mesh


def _arm_tube():
    """(points, faces): a closed square tube along +X from the shoulder to the forearm's tip."""
    xs = np.linspace(SHOULDER[0], SHOULDER[0] + UPPER_ARM + FOREARM, ARM_SECTIONS + 1)
    h = ARM_HALF_WIDTH
    ring = [(-h, -h), (h, -h), (h, h), (-h, h)]
    points = np.array([[x, SHOULDER[1] + dy, SHOULDER[2] + dz] for x in xs for dy, dz in ring])
    faces = [[4 * s + k, 4 * s + (k + 1) % 4, 4 * s + 4 + (k + 1) % 4, 4 * s + 4 + k]
             for s in range(ARM_SECTIONS) for k in range(4)]
    last = 4 * ARM_SECTIONS
    faces += [[3, 2, 1, 0], [last, last + 1, last + 2, last + 3]]
    return points, faces


def _character(path, root_type="SkelRoot", root_child=None, animation_on="skeleton"):
    """A character asset, default prim /Character: a Skeleton (shoulder, elbow), its SkelAnimation (the arm
    stretches), a skinned arm tube (each vertex blends the two joints, a ``curl`` blend shape lifts the tip)
    and a torso box bound rigidly to the shoulder. ``root_type``: the type of /Character; ``root_child``: the
    SkelRoot is /Character/<root_child> instead; ``animation_on``: the prim that binds the animation
    ("skeleton", the SkelRoot "root", or None)."""
    stage = Usd.Stage.CreateNew(str(path))
    UsdGeom.SetStageUpAxis(stage, "Y")
    character = stage.DefinePrim("/Character", root_type)
    stage.SetDefaultPrim(character)
    root = stage.DefinePrim(f"/Character/{root_child}", "SkelRoot") if root_child else character
    base = str(root.GetPath())
    skeleton = UsdSkel.Skeleton.Define(stage, f"{base}/Skel")
    skeleton.CreateJointsAttr(JOINTS)
    shoulder = Gf.Matrix4d(1).SetTranslate(Gf.Vec3d(*SHOULDER))
    elbow = Gf.Matrix4d(1).SetTranslate(Gf.Vec3d(UPPER_ARM, 0.0, 0.0))
    skeleton.CreateBindTransformsAttr(Vt.Matrix4dArray([shoulder, elbow * shoulder]))
    skeleton.CreateRestTransformsAttr(Vt.Matrix4dArray([shoulder, elbow]))
    animation = _animation(stage, f"{base}/Anim")
    binder = {"skeleton": skeleton.GetPrim(), "root": root, None: None}[animation_on]
    if binder is not None:
        UsdSkel.BindingAPI.Apply(binder).CreateAnimationSourceRel().SetTargets([animation.GetPath()])
    UsdSkel.BindingAPI.Apply(root).CreateSkeletonRel().SetTargets([skeleton.GetPath()])

    points, faces = _arm_tube()
    arm = _define_mesh(stage, f"{base}/Arm", points, faces)
    binding = UsdSkel.BindingAPI.Apply(arm.GetPrim())
    elbow_weight = np.clip((points[:, 0] - SHOULDER[0] - 0.7 * UPPER_ARM) / (0.6 * UPPER_ARM), 0.0, 1.0)
    binding.CreateJointIndicesPrimvar(False, 2).Set(Vt.IntArray([0, 1] * len(points)))
    binding.CreateJointWeightsPrimvar(False, 2).Set(
        Vt.FloatArray([float(w) for w in np.stack([1.0 - elbow_weight, elbow_weight], axis=1).ravel()]))
    binding.CreateGeomBindTransformAttr(Gf.Matrix4d(1))
    tip = np.flatnonzero(points[:, 0] > SHOULDER[0] + UPPER_ARM + 0.7 * FOREARM)
    curl = UsdSkel.BlendShape.Define(stage, f"{base}/Arm/curl")
    curl.CreateOffsetsAttr(Vt.Vec3fArray([(0.0, CURL_OFFSET, 0.0)] * tip.size))
    curl.CreatePointIndicesAttr(Vt.IntArray([int(i) for i in tip]))
    binding.CreateBlendShapesAttr(["curl"])
    binding.CreateBlendShapeTargetsRel().SetTargets([curl.GetPath()])

    (x0, y0, z0), (x1, y1, z1) = TORSO
    corners = np.array([[x, y, z] for x in (x0, x1) for y in (y0, y1) for z in (z0, z1)])
    torso = _define_mesh(stage, f"{base}/Torso", corners, [[0, 1, 3, 2], [4, 6, 7, 5], [0, 4, 5, 1],
                                                          [2, 3, 7, 6], [0, 2, 6, 4], [1, 5, 7, 3]])
    rigid = UsdSkel.BindingAPI.Apply(torso.GetPrim())
    rigid.CreateJointIndicesPrimvar(True, 1).Set(Vt.IntArray([0]))
    rigid.CreateJointWeightsPrimvar(True, 1).Set(Vt.FloatArray([1.0]))
    stage.GetRootLayer().Save()
    return "/" + root_child if root_child else ""


def _new_stage(path):
    stage = Usd.Stage.CreateNew(str(path))
    stage.SetTimeCodesPerSecond(24.0)
    stage.SetStartTimeCode(FRAMES[0])
    stage.SetEndTimeCode(FRAMES[1])
    UsdGeom.SetStageUpAxis(stage, "Y")
    stage.SetDefaultPrim(UsdGeom.Xform.Define(stage, "/World").GetPrim())
    return stage


def _place(stage, path, reference, placement, prim_path=None):
    """An instanceable prim at ``path`` referencing ``reference`` (default prim, or ``prim_path``), translated
    by ``placement``: a position, or {time: position}."""
    prim = stage.DefinePrim(path)
    if prim_path:
        prim.GetReferences().AddReference(reference, prim_path)
    else:
        prim.GetReferences().AddReference(reference)
    prim.SetInstanceable(True)
    translate = UsdGeom.Xformable(prim).AddTranslateOp(opSuffix="place")
    for time, position in (placement.items() if isinstance(placement, dict) else [(None, placement)]):
        translate.Set(Gf.Vec3d(*position), Usd.TimeCode.Default() if time is None else float(time))
    return prim


#: char1 stands still and stretches its arm into char2's torso, char2 slides towards it, char3 stands far off.
CROWD = {"char1": (0.0, 0.0, 0.0), "char2": {1.0: (3.7, 0.0, 0.0), 12.0: (3.1, 0.0, 0.0)},
         "char3": (0.0, 0.0, 6.0)}


def instanced_crowd(directory, layout="skel_root_is_the_instance", placements=None, animation_on="skeleton"):
    """/World/crowd/<name>: one instanceable reference to the character asset per ``placements`` entry (default
    :data:`CROWD`). Returns (stage path, {name: mesh path prefix}, e.g. /World/crowd/char2/Body)."""
    root_type, root_child, root_above = LAYOUTS[layout]
    inner = _character(directory / ASSET, root_type, root_child, animation_on)
    path = directory / "crowd.usda"
    stage = _new_stage(path)
    stage.DefinePrim("/World/crowd", "SkelRoot" if root_above else "Xform")
    names = {}
    for name, placement in (placements or CROWD).items():
        _place(stage, f"/World/crowd/{name}", ASSET, placement)
        names[name] = f"/World/crowd/{name}{inner}"
    stage.GetRootLayer().Save()
    return path, names


def deinstanced_baked_copy(source, target):
    """The reference: a copy of ``source`` with every prim's instanceable set to false (nested instances
    included), then ``UsdSkel.BakeSkinning`` (which refuses instanced SkelRoots). ``source`` is not written."""
    shutil.copyfile(source, target)
    stage = Usd.Stage.Open(str(target))
    while True:       # de-instancing an outer instance shows the instanceable prims inside it
        instanceable = [prim for prim in stage.TraverseAll() if prim.IsInstanceable()]
        if not instanceable:
            break
        for prim in instanceable:
            prim.SetInstanceable(False)
    assert not stage.GetPrototypes()
    if not UsdSkel.BakeSkinning(stage.Traverse()):
        raise RuntimeError(f"UsdSkel.BakeSkinning failed on {target}")
    stage.GetRootLayer().Save()
    return target


def assert_points_equal_baked(path, tmp_path):
    """Every mesh of ``path`` loads with the names, sample times, kinds and points (at every sample) of its
    de-instanced baked copy. Returns (the loaded shot, the baked copy's path)."""
    digest = file_digest(path)
    baked = deinstanced_baked_copy(path, tmp_path / f"{path.stem}_baked.usda")
    assert file_digest(path) == digest
    shot, reference = load_shot(path), load_shot(baked)
    assert [mesh.path for mesh in shot.meshes] == [mesh.path for mesh in reference.meshes]
    for mesh in shot.meshes:
        other = reference.mesh(mesh.path)
        assert mesh.times.tolist() == other.times.tolist(), mesh.path
        assert mesh.kind == other.kind, mesh.path
        assert np.allclose(mesh.points, other.points, rtol=0, atol=POINT_AGREEMENT), (
            mesh.path, float(np.abs(mesh.points - other.points).max()))
    return shot, baked


def assert_check_equals_baked(check, path, baked, touching):
    """``usdksl check`` finds the face pairs of the baked copy, at times within TIME_AGREEMENT, and only
    between the mesh pairs ``touching``."""
    result, contacts, summary = check(path)
    baked_result, baked_contacts, baked_summary = check(baked)
    assert result.exit_code == baked_result.exit_code == 1, result.stderr + baked_result.stderr
    assert set(summary) == set(baked_summary) == {tuple(sorted(pair)) for pair in touching}
    assert set(contacts) == set(baked_contacts)
    assert max(abs(contacts[key] - baked_contacts[key]) for key in contacts) <= TIME_AGREEMENT


def _character_space(shot, mesh_path, offset):
    """The points of ``mesh_path`` at its last sample, moved back by the instance's ``offset``."""
    return shot.mesh(mesh_path).points[-1] - np.asarray(offset)


@pytest.mark.parametrize("layout", sorted(LAYOUTS))
def test_each_instance_is_posed_where_it_stands(tmp_path, layout):
    path, names = instanced_crowd(tmp_path, layout)
    shot, _ = assert_points_equal_baked(path, tmp_path)
    # the same pose in three places: every instance has the arm of char3, moved by its own placement
    reach = _character_space(shot, f"{names['char3']}/Arm", CROWD["char3"])
    np.testing.assert_allclose(_character_space(shot, f"{names['char1']}/Arm", CROWD["char1"]), reach,
                               rtol=0, atol=POINT_AGREEMENT)
    np.testing.assert_allclose(_character_space(shot, f"{names['char2']}/Arm", CROWD["char2"][12.0]), reach,
                               rtol=0, atol=POINT_AGREEMENT)
    assert shot.mesh(f"{names['char2']}/Torso").kind == "rigid"      # it slides with its instance
    assert shot.mesh(f"{names['char1']}/Torso").kind == "static"


def test_crowd_contacts_equal_those_of_the_deinstanced_bake(tmp_path, check):
    """char1's arm reaches char2's torso late in the shot; posed where the prototype is, the three characters
    would overlap from the first frame and that contact would be missed."""
    path, names = instanced_crowd(tmp_path, "skel_root_inside_the_instance")
    _, baked = assert_points_equal_baked(path, tmp_path)
    assert_check_equals_baked(check, path, baked, [(f"{names['char1']}/Arm", f"{names['char2']}/Torso")])


def test_nested_instancing(tmp_path, check):
    """Instanceable characters inside an instanceable crowd group, the group referenced twice: each of the four
    characters is posed where it stands, and each group has its own reaching contact."""
    _, names = instanced_crowd(tmp_path, placements={"char1": CROWD["char1"], "char2": CROWD["char2"]})
    path = tmp_path / "groups.usda"
    stage = _new_stage(path)
    for group, offset in (("groupA", (0.0, 0.0, 0.0)), ("groupB", (0.5, 0.0, 5.0))):
        _place(stage, f"/World/{group}", "crowd.usda", offset, prim_path="/World/crowd")
    stage.GetRootLayer().Save()
    assert len(Usd.Stage.Open(str(path)).GetPrototypes()) == 2      # the group's and the character's

    shot, baked = assert_points_equal_baked(path, tmp_path)
    assert len(shot.meshes) == 8
    moved = shot.mesh("/World/groupB/char2/Arm").points - [0.5, 0.0, 5.0]
    np.testing.assert_allclose(moved, shot.mesh("/World/groupA/char2/Arm").points, rtol=0, atol=POINT_AGREEMENT)
    assert_check_equals_baked(check, path, baked, [(f"/World/{group}/char1/Arm", f"/World/{group}/char2/Torso")
                                                   for group in ("groupA", "groupB")])


@pytest.mark.parametrize("animation_on", ["root", None])
def test_animation_bound_per_instance(tmp_path, check, animation_on):
    """``skel:animationSource`` authored on the instanceable prim, outside the prototype, is inherited by the
    instance's Skeleton (UsdSkel's way of instancing a bind state): char1 plays the asset's stretch (or, when
    the asset binds none, its own copy of it), char2 waves with a blend-shape order of its own and never
    touches anyone."""
    path, names = instanced_crowd(tmp_path, placements={"char1": CROWD["char1"], "char2": CROWD["char2"]},
                                  animation_on=animation_on)
    stage = Usd.Stage.Open(str(path))
    _animation(stage, "/World/Anims/Wave", WAVE, blend_shapes=("other", "curl"), weights=((0.3, 1.0), (0.0, 0.2)))
    UsdSkel.BindingAPI.Apply(stage.GetPrimAtPath("/World/crowd/char2")).CreateAnimationSourceRel().SetTargets(
        ["/World/Anims/Wave"])
    if animation_on is None:
        _animation(stage, "/World/Anims/Reach", REACH)
        UsdSkel.BindingAPI.Apply(stage.GetPrimAtPath("/World/crowd/char1")).CreateAnimationSourceRel().SetTargets(
            ["/World/Anims/Reach"])
    stage.GetRootLayer().Save()

    shot, baked = assert_points_equal_baked(path, tmp_path)
    reach = _character_space(shot, f"{names['char1']}/Arm", CROWD["char1"])
    wave = _character_space(shot, f"{names['char2']}/Arm", CROWD["char2"][12.0])
    assert reach[:, 1].max() < SHOULDER[1] + 0.5 < wave[:, 1].max()     # stretched vs raised forearm
    assert_check_equals_baked(check, path, baked, [(f"{names['char1']}/Arm", f"{names['char2']}/Torso")])


def test_point_instancer_with_an_instanceable_skinned_prototype(tmp_path):
    """A PointInstancer whose prototype is an instanceable reference to the character, itself translated:
    each instance carries the pose through the prototype's own transform."""
    _character(tmp_path / ASSET)
    path = tmp_path / "scatter.usda"
    stage = _new_stage(path)
    instancer = UsdGeom.PointInstancer.Define(stage, "/World/scatter")
    UsdGeom.Xform.Define(stage, "/World/scatter/Prototypes")
    prototype = _place(stage, "/World/scatter/Prototypes/Character", ASSET, (0.0, 0.5, 0.0))
    instancer.CreatePrototypesRel().SetTargets([prototype.GetPath()])
    instancer.CreateProtoIndicesAttr(Vt.IntArray([0, 0]))
    instancer.CreatePositionsAttr(Vt.Vec3fArray([(0.0, 0.0, 0.0), (3.0, 0.0, 1.0)]))
    stage.GetRootLayer().Save()

    shot, _ = assert_points_equal_baked(path, tmp_path)
    assert shot.mesh("/World/scatter[1]/Character/Arm").kind == "deforming"
    torso = shot.mesh("/World/scatter[1]/Character/Torso").points
    np.testing.assert_allclose(torso.min(axis=(0, 1)), np.add(TORSO[0], (3.0, 0.5, 1.0)), rtol=0,
                               atol=POINT_AGREEMENT)
