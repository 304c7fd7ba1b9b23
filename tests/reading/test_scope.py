"""Scene scoping: which pairs get checked and why the rest is skipped."""

import numpy as np
from pxr import Sdf, UsdGeom, UsdPhysics

from usdksl.reading import scope
from usdksl.reading.loader import load_shot
from usdksl.reading.scope import (PAIR_CHECK_INTER, PAIR_CHECK_SELF, PAIR_COLLISION_GROUP, PAIR_FILTERED,
                          PAIR_INTER_DISABLED_BY_OPTION, PAIR_MESH_SKIPPED, PAIR_SELF_DISABLED_BY_ATTRIBUTE,
                          PAIR_SELF_DISABLED_BY_OPTION, PAIR_SELF_RIGID, PAIR_SELF_STATIC, PAIR_STATIC_STATIC,
                          ScopeOptions, SceneFlags, plan_pairs, plan_shot)

from builders import QUAD_POINTS, add_mesh, falling_quad_samples, fifty_mesh_scene, new_stage


def pairs_of(plan):
    return {tuple(pair) for pair in plan.pairs.tolist()}


def reasons_of(plan):
    return {(i, j): reason for i, j, reason in plan.skipped_pairs}


def test_static_rigid_deforming_rules():
    paths = ["/A_static", "/B_static", "/C_rigid", "/D_deform"]
    kinds = ["static", "static", "rigid", "deforming"]
    moving = np.array([False, False, True, True])
    # --rigid: the rigid mesh's pairs with the still ones are checked too (tests/reading covers the default)
    plan = plan_pairs(paths, kinds, moving, SceneFlags.permissive(4), ScopeOptions(rigid=True))
    assert pairs_of(plan) == {(0, 2), (0, 3), (1, 2), (1, 3), (2, 3), (3, 3)}
    skipped = reasons_of(plan)
    assert skipped[(0, 1)] == PAIR_STATIC_STATIC
    assert skipped[(0, 0)] == PAIR_SELF_STATIC
    assert skipped[(2, 2)] == PAIR_SELF_RIGID
    assert plan.possible_pairs == 10 and plan.checked_pairs == 6
    assert dict(zip(map(tuple, plan.pairs.tolist()), plan.pair_reasons))[(3, 3)] == PAIR_CHECK_SELF
    assert dict(zip(map(tuple, plan.pairs.tolist()), plan.pair_reasons))[(0, 3)] == PAIR_CHECK_INTER


def test_animated_but_never_moving_counts_as_static():
    # kind says deforming but every sample is equal: no self check, no check against statics
    plan = plan_pairs(["/A", "/B"], ["deforming", "static"], np.array([False, False]), SceneFlags.permissive(2))
    assert plan.checked_pairs == 0
    assert reasons_of(plan)[(0, 0)] == PAIR_SELF_STATIC


def test_mesh_moves_is_exact():
    points = np.zeros((3, 4, 3))
    assert not scope.mesh_moves(points)
    points[2, 1, 0] = 1e-12
    assert scope.mesh_moves(points)
    assert not scope.mesh_moves(np.zeros((1, 4, 3)))


def test_options_self_inter_off():
    paths, kinds, moving = ["/A", "/B"], ["deforming", "deforming"], np.array([True, True])
    no_self = plan_pairs(paths, kinds, moving, SceneFlags.permissive(2), ScopeOptions(self_check=False))
    assert pairs_of(no_self) == {(0, 1)}
    assert reasons_of(no_self)[(0, 0)] == PAIR_SELF_DISABLED_BY_OPTION
    no_inter = plan_pairs(paths, kinds, moving, SceneFlags.permissive(2), ScopeOptions(inter_check=False))
    assert pairs_of(no_inter) == {(0, 0), (1, 1)}
    assert reasons_of(no_inter)[(0, 1)] == PAIR_INTER_DISABLED_BY_OPTION


def test_scene_flags_skip_meshes_and_pairs():
    paths = ["/A", "/B", "/C", "/D", "/E"]
    kinds = ["deforming"] * 5
    moving = np.ones(5, bool)
    flags = SceneFlags.permissive(5)
    flags.collision_enabled[0] = False
    flags.guide[1] = True
    flags.self_collision[2] = False
    flags.filtered[2, 3] = True          # one-sided on purpose: the planner symmetrises
    flags.group_filtered[3, 4] = True
    plan = plan_pairs(paths, kinds, moving, flags)
    assert plan.skipped_meshes == {0: scope.MESH_COLLISION_DISABLED, 1: scope.MESH_GUIDE}
    skipped = reasons_of(plan)
    assert skipped[(0, 3)] == PAIR_MESH_SKIPPED and skipped[(1, 1)] == PAIR_MESH_SKIPPED
    assert skipped[(2, 2)] == PAIR_SELF_DISABLED_BY_ATTRIBUTE
    assert skipped[(2, 3)] == PAIR_FILTERED
    assert skipped[(3, 4)] == PAIR_COLLISION_GROUP
    assert pairs_of(plan) == {(2, 4), (3, 3), (4, 4)}
    with_guides = plan_pairs(paths, kinds, moving, flags, ScopeOptions(include_guides=True))
    assert 1 not in with_guides.skipped_meshes and (1, 1) in pairs_of(with_guides)


def test_patterns():
    paths = ["/World/Cloth", "/World/Props/Chair", "/World/Props/Table/Top", "/Other"]
    include, exclude = scope.split_patterns(["/World*", "!/World/Props/Table"], ["/World/Props/Ch*"])
    assert include == ("/World*",) and exclude == ("/World/Props/Table", "/World/Props/Ch*")
    assert scope.pattern_mask(paths, include, exclude).tolist() == [True, False, False, False]
    # a prim path also selects the meshes below it
    assert scope.pattern_mask(paths, ("/World/Props",), ()).tolist() == [False, True, True, False]
    predicate = scope.include_predicate(("/World/Props",), ())
    assert [predicate(p) for p in paths] == [False, True, True, False]
    assert predicate.rejected == ["/World/Cloth", "/Other"]


def test_fifty_meshes_two_animated_checks_only_pairs_that_can_change(tmp_path):
    path = tmp_path / "fifty.usda"
    fifty_mesh_scene(path)
    shot = load_shot(str(path))
    plan = plan_shot(shot, ScopeOptions(rigid=True))   # the mover's pairs with the statics need --rigid
    assert plan.mesh_count == 50
    assert plan.possible_pairs == 50 * 51 // 2
    cloth = [m.path for m in shot.meshes].index("/World/Anim/Cloth")
    mover = [m.path for m in shot.meshes].index("/World/Anim/Mover/Box")
    # each animated mesh against the 49 others (their shared pair once) + the cloth's self check
    assert plan.checked_pairs == 49 + 49 - 1 + 1
    checked = pairs_of(plan)
    assert (cloth, cloth) in checked and (mover, mover) not in checked
    assert all(cloth in pair or mover in pair for pair in checked)
    counts = plan.skipped_pair_counts()
    assert counts[PAIR_STATIC_STATIC] == 48 * 47 // 2
    assert counts[PAIR_SELF_STATIC] == 48 and counts[PAIR_SELF_RIGID] == 1
    assert plan.describe()[0].startswith("pairs checked: 98 of 1275 possible (50 meshes, 2 moving)")


def test_physics_schemas_on_a_stage(tmp_path):
    path = tmp_path / "physics.usda"
    stage = new_stage(path)
    names = ["A", "B", "C", "D", "E", "F", "G"]
    for k, name in enumerate(names):
        add_mesh(stage, f"/World/{name}", None, samples=falling_quad_samples(offset=(2.0 * k, 0, 0)))
    a = stage.GetPrimAtPath("/World/A")
    UsdPhysics.CollisionAPI.Apply(a).CreateCollisionEnabledAttr(False)
    b = stage.GetPrimAtPath("/World/B")
    UsdPhysics.FilteredPairsAPI.Apply(b).CreateFilteredPairsRel().AddTarget("/World/C")
    group_d = UsdPhysics.CollisionGroup.Define(stage, "/World/GroupD")
    group_d.GetCollidersCollectionAPI().GetIncludesRel().AddTarget("/World/D")
    group_e = UsdPhysics.CollisionGroup.Define(stage, "/World/GroupE")
    group_e.GetCollidersCollectionAPI().GetIncludesRel().AddTarget("/World/E")
    group_d.CreateFilteredGroupsRel().AddTarget("/World/GroupE")
    UsdGeom.Imageable(stage.GetPrimAtPath("/World/F")).CreatePurposeAttr(UsdGeom.Tokens.guide)
    stage.GetPrimAtPath("/World/G").CreateAttribute("usdksl:selfCollision", Sdf.ValueTypeNames.Bool).Set(False)
    stage.GetRootLayer().Save()

    shot = load_shot(str(path))
    plan = plan_shot(shot)
    index = {m.path: i for i, m in enumerate(shot.meshes)}
    skipped = {(plan.paths[i], plan.paths[j]): r for i, j, r in plan.skipped_pairs}
    assert plan.skipped_meshes[index["/World/A"]] == scope.MESH_COLLISION_DISABLED
    assert plan.skipped_meshes[index["/World/F"]] == scope.MESH_GUIDE
    pair = lambda x, y: tuple(sorted((x, y), key=index.get))  # noqa: E731
    assert skipped[pair("/World/B", "/World/C")] == PAIR_FILTERED
    assert skipped[pair("/World/D", "/World/E")] == PAIR_COLLISION_GROUP
    assert skipped[("/World/G", "/World/G")] == PAIR_SELF_DISABLED_BY_ATTRIBUTE
    checked = {(plan.paths[i], plan.paths[j]) for i, j in plan.pairs.tolist()}
    assert pair("/World/B", "/World/D") in checked and ("/World/B", "/World/B") in checked
    assert pair("/World/C", "/World/E") in checked


def test_group_membership_conservative_with_several_groups(tmp_path):
    path = tmp_path / "groups.usda"
    stage = new_stage(path)
    for k, name in enumerate(["A", "B"]):
        add_mesh(stage, f"/World/{name}", None, samples=falling_quad_samples(offset=(2.0 * k, 0, 0)))
    g1 = UsdPhysics.CollisionGroup.Define(stage, "/World/G1")
    g2 = UsdPhysics.CollisionGroup.Define(stage, "/World/G2")
    g3 = UsdPhysics.CollisionGroup.Define(stage, "/World/G3")
    g1.GetCollidersCollectionAPI().GetIncludesRel().AddTarget("/World/A")
    g2.GetCollidersCollectionAPI().GetIncludesRel().AddTarget("/World/B")
    g3.GetCollidersCollectionAPI().GetIncludesRel().AddTarget("/World/B")
    g1.CreateFilteredGroupsRel().AddTarget("/World/G2")   # G1-G3 still collide: keep the pair
    stage.GetRootLayer().Save()
    flags = scope.read_scene_flags(Usd_open(path), ["/World/A", "/World/B"], (1.0, 24.0))
    assert not flags.group_filtered.any()
    g1.CreateFilteredGroupsRel().AddTarget("/World/G3")
    stage.GetRootLayer().Save()
    flags = scope.read_scene_flags(Usd_open(path), ["/World/A", "/World/B"], (1.0, 24.0))
    assert flags.group_filtered[0, 1] and flags.group_filtered[1, 0]


def Usd_open(path):
    from pxr import Usd

    return Usd.Stage.Open(str(path))


def test_visibility_over_the_range(tmp_path):
    path = tmp_path / "vis.usda"
    stage = new_stage(path)
    add_mesh(stage, "/World/Hidden", None, samples=falling_quad_samples())
    add_mesh(stage, "/World/Blink", None, samples=falling_quad_samples(offset=(3, 0, 0)))
    group = UsdGeom.Xform.Define(stage, "/World/Group")
    add_mesh(stage, "/World/Group/Child", None, samples=falling_quad_samples(offset=(6, 0, 0)))
    UsdGeom.Imageable(stage.GetPrimAtPath("/World/Hidden")).CreateVisibilityAttr(UsdGeom.Tokens.invisible)
    blink = UsdGeom.Imageable(stage.GetPrimAtPath("/World/Blink")).CreateVisibilityAttr()
    blink.Set(UsdGeom.Tokens.invisible, 1.0)
    blink.Set(UsdGeom.Tokens.inherited, 12.0)
    group.CreateVisibilityAttr(UsdGeom.Tokens.invisible)   # inherited by the child
    stage.GetRootLayer().Save()

    reopened = Usd_open(path)
    paths = ["/World/Hidden", "/World/Blink", "/World/Group/Child"]
    whole = scope.read_scene_flags(reopened, paths, (1.0, 24.0))
    assert whole.invisible.tolist() == [True, False, True]       # Blink is visible from 12 on: checked
    early = scope.read_scene_flags(reopened, paths, (1.0, 11.0))
    assert early.invisible.tolist() == [True, True, True]        # Blink invisible over all of [1, 11]
    plan = plan_pairs(paths, ["deforming"] * 3, np.ones(3, bool), whole)
    assert set(plan.skipped_meshes) == {0, 2}
    assert set(plan_pairs(paths, ["deforming"] * 3, np.ones(3, bool), whole,
                          ScopeOptions(include_invisible=True)).skipped_meshes) == set()


#: Where usdksl:selfCollision is authored (prim below /World: value) and whether the mesh at the end of each
#: hierarchy is then checked against itself: the value of the mesh or of its nearest ancestor that authors
#: one wins (docs/contracts.md, What is checked), however far up the others are.
SELF_COLLISION_HIERARCHIES = {
    "On/Cloth": ({"On": True, "On/Cloth": False}, False),
    "Off/Cloth": ({"Off": False, "Off/Cloth": True}, True),
    "OnAbove/Cloth": ({"OnAbove": True}, True),
    "OffAbove/Cloth": ({"OffAbove": False}, False),
    "Far/Near/Between/Cloth": ({"Far": False, "Far/Near": True}, True),
    "FarOn/NearOff/Between/Cloth": ({"FarOn": True, "FarOn/NearOff": False}, False),
    "Top/Middle/Bottom/Cloth": ({"Top": True, "Top/Middle": False, "Top/Middle/Bottom": True}, True),
    "Plain/Cloth": ({}, True),
}


def test_the_nearest_authored_self_collision_wins(tmp_path):
    path = tmp_path / "self_collision.usda"
    stage = new_stage(path)
    for k, (mesh, (authored, _)) in enumerate(sorted(SELF_COLLISION_HIERARCHIES.items())):
        parts = mesh.split("/")
        for depth in range(1, len(parts)):
            UsdGeom.Xform.Define(stage, "/World/" + "/".join(parts[:depth]))
        add_mesh(stage, f"/World/{mesh}", None, samples=falling_quad_samples(offset=(3.0 * k, 0, 0)))
        for prim, value in authored.items():
            stage.GetPrimAtPath(f"/World/{prim}").CreateAttribute(
                "usdksl:selfCollision", Sdf.ValueTypeNames.Bool).Set(value)
    stage.GetRootLayer().Save()

    plan = plan_shot(load_shot(str(path)))
    checked_self = {plan.paths[i] for i, j in plan.pairs.tolist() if i == j}
    disabled = {plan.paths[i] for i, j, reason in plan.skipped_pairs
                if i == j and reason == PAIR_SELF_DISABLED_BY_ATTRIBUTE}
    expected = {f"/World/{mesh}" for mesh, (_, checked) in SELF_COLLISION_HIERARCHIES.items() if checked}
    assert checked_self == expected
    assert disabled == {f"/World/{mesh}" for mesh in SELF_COLLISION_HIERARCHIES} - expected
