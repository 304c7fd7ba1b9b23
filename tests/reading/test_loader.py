"""The loader against pxr read directly: topology, world points, time samples, classification."""

import numpy as np
import pytest
from pxr import Gf, Usd, UsdGeom

from usdksl.reading.loader import load_shot, topology_segments
from usdksl.reading.triangulate import fan_triangulate
from builders import quad_grid, write_mesh


def reference_world_points(stage, prim_path, time):
    """World points straight from pxr: points.Get(t), each transformed by Gf (tiny meshes only)."""
    prim = stage.GetPrimAtPath(prim_path)
    local = UsdGeom.Mesh(prim).GetPointsAttr().Get(time)
    matrix = UsdGeom.Xformable(prim).ComputeLocalToWorldTransform(Usd.TimeCode(time))
    return np.array([list(matrix.Transform(Gf.Vec3d(p))) for p in local], dtype=np.float64)


def polygon_area(points, loop):
    """Area of a planar polygon (vector area, shoelace in 3-D)."""
    p = points[loop]
    return 0.5 * np.linalg.norm(np.cross(p, np.roll(p, -1, axis=0)).sum(axis=0))


def triangle_areas(points, triangles):
    a, b, c = points[triangles[:, 0]], points[triangles[:, 1]], points[triangles[:, 2]]
    return 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1)


# a quad, a pentagon, a triangle and a quad, all convex and in the y = 0 plane
MIXED_POINTS = np.array([[0, 0, 0], [1, 0, 0], [1, 0, 1], [0, 0, 1],            # quad 0
                         [2, 0, 0], [3, 0, 0.5], [2.8, 0, 1.6], [2, 0, 1.8], [1.5, 0, 0.8],  # pentagon
                         [4, 0, 0], [5, 0, 0], [4.5, 0, 1],                     # triangle
                         [6, 0, 0], [7, 0, 0], [7, 0, 2], [6, 0, 2]], dtype=float)  # quad
MIXED_COUNTS = [4, 5, 3, 4]
MIXED_INDICES = [0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15]


def test_quads_and_pentagon_triangles_name_their_authored_face(build):
    path = build("mixed.usda", lambda s: write_mesh(s, "/Mixed", MIXED_COUNTS, MIXED_INDICES,
                                                     points=MIXED_POINTS))
    mesh = load_shot(path).mesh("/Mixed")
    stage = Usd.Stage.Open(path)
    pxr_mesh = UsdGeom.Mesh(stage.GetPrimAtPath("/Mixed"))
    counts = np.array(pxr_mesh.GetFaceVertexCountsAttr().Get())
    indices = np.array(pxr_mesh.GetFaceVertexIndicesAttr().Get())
    starts = np.cumsum(counts) - counts

    assert mesh.face_count == 4
    assert mesh.triangles.dtype == np.int32 and mesh.triangle_face.dtype == np.int32
    assert mesh.triangle_face.tolist() == [0, 0, 1, 1, 1, 2, 3, 3]
    points = mesh.points[0]
    areas = triangle_areas(points, mesh.triangles)
    for face in range(4):
        loop = indices[starts[face]:starts[face] + counts[face]]
        mine = mesh.triangles[mesh.triangle_face == face]
        assert set(mine.ravel()) <= set(loop.tolist())
        assert areas[mesh.triangle_face == face].sum() == pytest.approx(polygon_area(points, loop))
    assert np.all(areas > 0)


def test_holes_and_degenerate_faces_give_no_triangles_but_keep_face_numbers(build):
    points, counts, indices = quad_grid(3, 1)        # faces 0, 1, 2 along x
    counts = counts + [2, 0]                          # a 2-gon and an empty face
    indices = indices + [0, 1]

    path = build("holes.usda", lambda s: write_mesh(s, "/Grid", counts, indices, points=points,
                                                    holes=[1]))
    mesh = load_shot(path).mesh("/Grid")
    assert mesh.face_count == 5
    assert mesh.triangle_face.tolist() == [0, 0, 2, 2]
    stage = Usd.Stage.Open(path)
    authored = np.array(UsdGeom.Mesh(stage.GetPrimAtPath("/Grid")).GetFaceVertexIndicesAttr().Get())
    assert set(mesh.triangles[2:].ravel()) == set(authored[8:12].tolist())


def test_fan_triangulation_matches_a_per_face_reference():
    rng = np.random.default_rng(3)
    counts = rng.integers(0, 9, size=200)
    indices = rng.integers(0, 50, size=counts.sum())
    holes = rng.choice(200, size=15, replace=False)
    triangles, triangle_face = fan_triangulate(counts, indices, holes)
    expected, expected_face, start = [], [], 0
    for face, count in enumerate(counts):
        loop = indices[start:start + count]
        start += count
        if face in set(holes.tolist()):
            continue
        for k in range(1, count - 1):
            expected.append([loop[0], loop[k], loop[k + 1]])
            expected_face.append(face)
    assert triangles.tolist() == expected
    assert triangle_face.tolist() == expected_face


def test_animated_parent_xform_gives_world_points_of_pxr_at_every_time(build):
    points, counts, indices = quad_grid(2, 2)

    def fill(stage):
        root = UsdGeom.Xform.Define(stage, "/Root")
        translate = root.AddTranslateOp()
        for time, value in {0.0: (0, 0, 0), 1.0: (1, 2, 0), 3.0: (1, 2, 5)}.items():
            translate.Set(Gf.Vec3d(*value), time)
        rotate = root.AddRotateYOp()
        rotate.Set(0.0, 0.0)
        rotate.Set(90.0, 2.0)
        child = UsdGeom.Xform.Define(stage, "/Root/Child")
        child.AddScaleOp().Set(Gf.Vec3f(2, 1, 0.5))
        write_mesh(stage, "/Root/Child/Mesh", counts, indices, points=points)

    path = build("parent.usda", fill)
    shot = load_shot(path)
    mesh = shot.mesh("/Root/Child/Mesh")
    assert mesh.times.tolist() == [0.0, 1.0, 2.0, 3.0]
    assert mesh.kind == "rigid"
    assert mesh.points.flags["C_CONTIGUOUS"] and mesh.points.dtype == np.float64
    stage = Usd.Stage.Open(path)
    for k, time in enumerate(mesh.times):
        np.testing.assert_allclose(mesh.points[k], reference_world_points(stage, mesh.path, time),
                                   atol=1e-12)


def test_reset_xform_stack_ignores_ancestor_animation(build):
    points, counts, indices = quad_grid(1, 1)

    def fill(stage):
        root = UsdGeom.Xform.Define(stage, "/Root")
        root.AddTranslateOp().Set(Gf.Vec3d(5, 0, 0), 0.0)
        root.GetPrim().GetAttribute("xformOp:translate").Set(Gf.Vec3d(9, 0, 0), 10.0)
        mesh = write_mesh(stage, "/Root/Mesh", counts, indices, points=points)
        mesh.SetResetXformStack(True)
        translate = mesh.AddTranslateOp()
        translate.Set(Gf.Vec3d(0, 1, 0), 2.0)
        translate.Set(Gf.Vec3d(0, 3, 0), 5.0)

    path = build("reset.usda", fill)
    mesh = load_shot(path).mesh("/Root/Mesh")
    assert mesh.times.tolist() == [2.0, 5.0]
    stage = Usd.Stage.Open(path)
    for k, time in enumerate(mesh.times):
        np.testing.assert_allclose(mesh.points[k], reference_world_points(stage, mesh.path, time))
    assert mesh.points[0, :, 0].max() == pytest.approx(1.0)   # no +5 from /Root


def test_static_mesh_has_one_sample_in_world_space(build):
    points, counts, indices = quad_grid(2, 2)

    def fill(stage):
        root = UsdGeom.Xform.Define(stage, "/Root")
        root.AddTranslateOp().Set(Gf.Vec3d(0, 4, 0))
        write_mesh(stage, "/Root/Floor", counts, indices, points=points)
        same = {float(t): points for t in range(3)}           # samples, all identical
        write_mesh(stage, "/Root/Still", counts, indices, samples=same)

    path = build("static.usda", fill)
    shot = load_shot(path)
    stage = Usd.Stage.Open(path)
    for name in ("/Root/Floor", "/Root/Still"):
        mesh = shot.mesh(name)
        assert mesh.kind == "static"
        assert mesh.points.shape == (1, 9, 3) and mesh.times.shape == (1,)
        np.testing.assert_allclose(mesh.points[0], reference_world_points(stage, name, mesh.times[0]))
    assert shot.mesh("/Root/Still").times.tolist() == [0.0]


def test_subframe_and_non_uniform_samples_are_kept_exactly(build):
    points, counts, indices = quad_grid(2, 1)
    times = [0.0, 0.5, 1.25, 4.0]
    samples = {t: points + [0, 0.3 * t * t, 0] + np.outer(np.arange(6), [0, 0, 0.01 * t])
               for t in times}
    path = build("subframe.usda", lambda s: write_mesh(s, "/Cloth", counts, indices, samples=samples))
    mesh = load_shot(path).mesh("/Cloth")
    assert mesh.times.tolist() == times
    assert mesh.kind == "deforming"
    stage = Usd.Stage.Open(path)
    for k, time in enumerate(times):
        np.testing.assert_allclose(mesh.points[k], reference_world_points(stage, "/Cloth", time))
        np.testing.assert_allclose(mesh.points[k], samples[time].astype(np.float32), atol=0)


def test_meshes_keep_their_own_times_and_the_shot_takes_the_union(build):
    points, counts, indices = quad_grid(1, 1)

    def fill(stage):
        write_mesh(stage, "/A", counts, indices, samples={t: points + [t, 0, 0] for t in (0.0, 1.0, 2.0)})
        write_mesh(stage, "/B", counts, indices, samples={t: points + [0, t, 0] for t in (0.5, 3.0)})
        parent = UsdGeom.Xform.Define(stage, "/P")
        op = parent.AddTranslateOp()
        op.Set(Gf.Vec3d(0, 0, 0), 1.5)
        op.Set(Gf.Vec3d(0, 0, 1), 2.5)
        # points sampled at 0 and 2, parent at 1.5 and 2.5: union, points interpolated at 1.5
        write_mesh(stage, "/P/C", counts, indices, samples={t: points * (1 + t) for t in (0.0, 2.0)})

    path = build("times.usda", fill)
    shot = load_shot(path)
    assert shot.mesh("/A").times.tolist() == [0.0, 1.0, 2.0]
    assert shot.mesh("/B").times.tolist() == [0.5, 3.0]
    c = shot.mesh("/P/C")
    assert c.times.tolist() == [0.0, 1.5, 2.0, 2.5]
    assert shot.times.tolist() == [0.0, 0.5, 1.0, 1.5, 2.0, 2.5, 3.0]
    stage = Usd.Stage.Open(path)
    for mesh in shot.meshes:
        for k, time in enumerate(mesh.times):
            np.testing.assert_allclose(mesh.points[k],
                                       reference_world_points(stage, mesh.path, time), atol=1e-6)
    np.testing.assert_allclose(c.points[1], points * 2.5, atol=1e-6)   # linear interpolation


def test_rigid_and_deforming_classification(build):
    points, counts, indices = quad_grid(2, 2)

    def fill(stage):
        mover = UsdGeom.Xform.Define(stage, "/Mover")
        rotate = mover.AddRotateXOp()
        rotate.Set(0.0, 1.0)
        rotate.Set(45.0, 2.0)
        write_mesh(stage, "/Mover/Rigid", counts, indices, points=points)
        # points move by a translation: still "deforming" (points change, not the transform)
        write_mesh(stage, "/Baked", counts, indices, samples={t: points + [0, t, 0] for t in (1.0, 2.0)})
        wave = {t: points + np.outer(np.sin(np.arange(9) + t), [0, 0.1, 0]) for t in (1.0, 2.0, 3.0)}
        write_mesh(stage, "/Mover/Wave", counts, indices, samples=wave)
        # a transform that is sampled but never changes: static
        still = UsdGeom.Xform.Define(stage, "/Still")
        op = still.AddTranslateOp()
        op.Set(Gf.Vec3d(1, 1, 1), 1.0)
        op.Set(Gf.Vec3d(1, 1, 1), 3.0)
        write_mesh(stage, "/Still/Mesh", counts, indices, points=points)

    shot = load_shot(build("kinds.usda", fill))
    assert shot.mesh("/Mover/Rigid").kind == "rigid"
    assert shot.mesh("/Mover/Rigid").times.tolist() == [1.0, 2.0]
    assert shot.mesh("/Baked").kind == "deforming"
    assert shot.mesh("/Mover/Wave").kind == "deforming"
    assert shot.mesh("/Mover/Wave").times.tolist() == [1.0, 2.0, 3.0]
    assert shot.mesh("/Still/Mesh").kind == "static"


def test_time_range_keeps_inner_samples_plus_exact_ends(build):
    points, counts, indices = quad_grid(1, 1)
    samples = {float(t): points + [0, t * t, 0] for t in range(11)}
    path = build("range.usda", lambda s: write_mesh(s, "/Cloth", counts, indices, samples=samples))
    stage = Usd.Stage.Open(path)

    mesh = load_shot(path, time_range=(2.5, 7)).mesh("/Cloth")
    assert mesh.times.tolist() == [2.5, 3.0, 4.0, 5.0, 6.0, 7.0]
    np.testing.assert_allclose(mesh.points[0], reference_world_points(stage, "/Cloth", 2.5))
    np.testing.assert_allclose(mesh.points[0, 0, 1], (4 + 9) / 2)   # USD's linear interpolation

    mesh = load_shot(path, time_range=(3.2, 3.7)).mesh("/Cloth")
    assert mesh.times.tolist() == [3.2, 3.7]

    # before the first sample the value is held: nothing moves in the range
    mesh = load_shot(path, time_range=(-5, -1)).mesh("/Cloth")
    assert mesh.kind == "static" and mesh.times.tolist() == [-5.0]
    np.testing.assert_allclose(mesh.points[0], samples[0.0])


def test_include_selects_meshes_by_pattern_or_subtree(build):
    points, counts, indices = quad_grid(1, 1)

    def fill(stage):
        for name in ("/World/Cloth", "/World/Props/Box", "/World/Props/Ball"):
            write_mesh(stage, name, counts, indices, points=points)

    path = build("include.usda", fill)
    assert [m.path for m in load_shot(path, include=["/World/Props"]).meshes] == [
        "/World/Props/Box", "/World/Props/Ball"]
    assert [m.path for m in load_shot(path, include="/World/C*").meshes] == ["/World/Cloth"]


def test_topology_segments_split_where_topology_changes(build):
    points, counts, indices = quad_grid(2, 1)
    triangle_counts = [3, 3, 3, 3]
    triangle_indices = [0, 1, 4, 0, 4, 3, 1, 2, 5, 1, 5, 4]

    def fill(stage):
        write_mesh(stage, "/Remesh", counts, indices,
                   samples={float(t): points + [0, t, 0] for t in range(6)},
                   topology_samples={0.0: (counts, indices), 3.0: (triangle_counts, triangle_indices)})

    path = build("segments.usda", fill)
    stage = Usd.Stage.Open(path)
    assert topology_segments(stage.GetPrimAtPath("/Remesh")) == [(0.0, 2.0), (3.0, 5.0)]
    before = load_shot(path, time_range=(0.0, 2.0)).mesh("/Remesh")
    after = load_shot(path, time_range=(3.0, 5.0)).mesh("/Remesh")
    assert before.face_count == 2 and before.triangle_face.tolist() == [0, 0, 1, 1]
    assert after.face_count == 4 and after.triangle_face.tolist() == [0, 1, 2, 3]


def test_stage_metadata_is_reported(build):
    points, counts, indices = quad_grid(1, 1)

    def fill(stage):
        stage.SetTimeCodesPerSecond(30)
        stage.SetFramesPerSecond(30)
        stage.SetStartTimeCode(10)
        stage.SetEndTimeCode(20)
        UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.z)
        UsdGeom.SetStageMetersPerUnit(stage, 1.0)
        world = UsdGeom.Xform.Define(stage, "/World")
        stage.SetDefaultPrim(world.GetPrim())
        write_mesh(stage, "/World/Mesh", counts, indices, samples={10.0: points, 20.0: points * 2})

    shot = load_shot(build("meta.usda", fill))
    assert shot.metadata == {"timeCodesPerSecond": 30.0, "framesPerSecond": 30.0,
                             "startTimeCode": 10.0, "endTimeCode": 20.0, "upAxis": "Z",
                             "metersPerUnit": 1.0, "defaultPrim": "World"}
    assert shot.mesh("/World/Mesh").times.tolist() == [10.0, 20.0]


def test_instanced_meshes_load_once_per_instance_in_world_space(build):
    points, counts, indices = quad_grid(1, 1)

    def fill(stage):
        write_mesh(stage, "/Proto/Mesh", counts, indices, points=points)
        for k in range(2):
            instance = UsdGeom.Xform.Define(stage, f"/Instance{k}")
            instance.AddTranslateOp().Set(Gf.Vec3d(5.0 * k, 0, 0))
            instance.GetPrim().GetReferences().AddInternalReference("/Proto")
            instance.GetPrim().SetInstanceable(True)

    path = build("instances.usda", fill)
    shot = load_shot(path)
    assert [m.path for m in shot.meshes] == ["/Proto/Mesh", "/Instance0/Mesh", "/Instance1/Mesh"]
    stage = Usd.Stage.Open(path)
    for mesh in shot.meshes:
        expected = reference_world_points(stage, mesh.path, Usd.TimeCode.Default())
        np.testing.assert_allclose(mesh.points[0], expected)
    assert shot.mesh("/Instance1/Mesh").points[0, :, 0].min() == 5.0


def test_include_that_matches_nothing_is_an_input_error(build):
    from usdksl.errors import UsdkslInputError

    points, counts, indices = quad_grid(1, 1)
    path = build("none.usda", lambda s: write_mesh(s, "/World/Cloth", counts, indices, points=points))
    with pytest.raises(UsdkslInputError, match="no UsdGeom.Mesh prims match"):
        load_shot(path, include=["/Elsewhere"])


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
@pytest.mark.parametrize("projective", [False, True])
def test_a_stack_of_samples_goes_to_world_space_with_the_same_numbers_as_one_by_one(dtype, projective):
    """The loader moves the samples of a mesh under a still transform together (usdksl.reading.meshes):
    every bit equals the sample-by-sample product."""
    from usdksl.reading.meshes import _to_world

    rng = np.random.default_rng(3)
    local = (rng.normal(size=(7, 50, 3)) * 10.0 ** rng.integers(-3, 4, size=(7, 50, 1))).astype(dtype)
    matrix = rng.normal(size=(4, 4))
    matrix[:, 3] = rng.normal(size=4) if projective else (0.0, 0.0, 0.0, 1.0)
    stacked = np.empty(local.shape, np.float64)
    _to_world(local, matrix, stacked)
    one_by_one = np.empty(local.shape, np.float64)
    for k in range(local.shape[0]):
        _to_world(local[k], matrix, one_by_one[k])
    assert stacked.tobytes() == one_by_one.tobytes()


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
@pytest.mark.parametrize("projective", [False, True])
def test_one_local_under_a_stack_of_matrices_goes_to_world_space_with_the_same_numbers_as_one_by_one(dtype,
                                                                                                projective):
    """A rigid mesh (points held, transform moving) is moved to world space once against every sample's matrix
    (usdksl.reading.meshes): every bit equals the sample-by-sample product, projective samples among them."""
    from usdksl.reading.meshes import _to_world

    rng = np.random.default_rng(5)
    local = (rng.normal(size=(50, 3)) * 10.0 ** rng.integers(-3, 4, size=(50, 1))).astype(dtype)
    matrices = rng.normal(size=(7, 4, 4))
    matrices[:, :, 3] = (0.0, 0.0, 0.0, 1.0)
    if projective:
        matrices[[1, 4], :, 3] = rng.normal(size=(2, 4))
    stacked = np.empty((7,) + local.shape, np.float64)
    _to_world(local, matrices, stacked)
    one_by_one = np.empty(stacked.shape, np.float64)
    for k in range(matrices.shape[0]):
        _to_world(local, matrices[k], one_by_one[k])
    assert stacked.tobytes() == one_by_one.tobytes()


def test_transforms_held_by_single_samples_move_every_sample_as_pxr_says(build):
    """xformOps with one time sample each (a cache's one-sample scale, as Newton writes it) hold their value
    at every time: the loader computes that transform once, and every sample's world points are still
    bit for bit the authored points through pxr's local-to-world matrix at that sample."""
    from usdksl.reading.meshes import _to_world, transform_may_vary

    points, counts, indices = quad_grid(3, 2)
    samples = {float(t): points + np.outer(np.sin(np.arange(len(points)) + t), [0.0, 0.1, 0.0]) for t in range(1, 6)}

    def fill(stage):
        root = UsdGeom.Xform.Define(stage, "/Root")
        root.AddScaleOp().Set(Gf.Vec3f(2.0, 0.5, 1.5), 0.0)
        root.AddRotateYOp().Set(30.0, 7.0)
        child = UsdGeom.Xform.Define(stage, "/Root/Child")
        child.AddTranslateOp().Set(Gf.Vec3d(1.0, -2.0, 0.25), 3.0)
        write_mesh(stage, "/Root/Child/Cloth", counts, indices, samples=samples)
        write_mesh(stage, "/Root/Child/Still", counts, indices, points=points)
        mover = UsdGeom.Xform.Define(stage, "/Root/Mover")
        move = mover.AddTranslateOp()
        move.Set(Gf.Vec3d(0.0, 0.0, 0.0), 1.0)
        move.Set(Gf.Vec3d(0.0, 1.0, 0.0), 4.0)
        write_mesh(stage, "/Root/Mover/Held", counts, indices, points=points).SetResetXformStack(True)
        write_mesh(stage, "/Root/Mover/Carried", counts, indices, points=points)

    path = build("held.usda", fill)
    stage = Usd.Stage.Open(path)
    assert not transform_may_vary(stage.GetPrimAtPath("/Root/Child/Cloth"))
    assert not transform_may_vary(stage.GetPrimAtPath("/Root/Mover/Held"))   # resetXformStack
    assert transform_may_vary(stage.GetPrimAtPath("/Root/Mover/Carried"))
    shot = load_shot(path)
    cloth = shot.mesh("/Root/Child/Cloth")
    assert cloth.kind == "deforming"
    assert cloth.times.tolist() == [0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 7.0]
    prim = stage.GetPrimAtPath(cloth.path)
    for k, time in enumerate(cloth.times):
        local = np.asarray(UsdGeom.Mesh(prim).GetPointsAttr().Get(time))
        matrix = np.array(UsdGeom.XformCache(Usd.TimeCode(time)).GetLocalToWorldTransform(prim))
        expected = np.empty(local.shape, np.float64)
        _to_world(local, matrix, expected)
        assert cloth.points[k].tobytes() == expected.tobytes()
        np.testing.assert_allclose(cloth.points[k], reference_world_points(stage, cloth.path, time), atol=1e-12)
    still = shot.mesh("/Root/Child/Still")
    assert still.kind == "static" and still.points.shape == (1, len(points), 3)
    np.testing.assert_allclose(still.points[0], reference_world_points(stage, still.path, still.times[0]),
                               atol=1e-12)
    assert shot.mesh("/Root/Mover/Held").kind == "static"
    assert shot.mesh("/Root/Mover/Carried").kind == "rigid"


def test_authored_float_points_in_world_space_are_kept_as_they_are_in_half_the_memory(build):
    """Points no transform moves are the authored floats: kept as float32 (the same numbers, read by the
    core and the regions as the same doubles); a transform gives float64."""
    points, counts, indices = quad_grid(3, 3)
    rng = np.random.default_rng(4)
    samples = {float(t): points + rng.normal(0, 0.1, points.shape) for t in range(6)}

    def fill(stage):
        write_mesh(stage, "/InPlace", counts, indices, samples=samples)
        moved = UsdGeom.Xform.Define(stage, "/Moved")
        moved.AddTranslateOp().Set(Gf.Vec3d(0.1, 0, 0))
        write_mesh(stage, "/Moved/Mesh", counts, indices, samples=samples)

    shot = load_shot(build("precision.usda", fill))
    in_place, moved = (shot.mesh(path) for path in ("/InPlace", "/Moved/Mesh"))
    assert in_place.points.dtype == np.float32 and in_place.points.flags["C_CONTIGUOUS"]
    assert moved.points.dtype == np.float64
    for k, time in enumerate(sorted(samples)):
        authored = np.asarray(samples[time], np.float32)
        assert in_place.points[k].tobytes() == authored.tobytes()
        assert np.array_equal(moved.points[k], authored.astype(np.float64) + [0.1, 0, 0])
    assert in_place.points.nbytes * 2 == moved.points.nbytes


def test_samples_alike_are_compared_block_by_block_to_the_last_sample(monkeypatch):
    from usdksl.reading import positions

    monkeypatch.setattr(positions, "SAMPLE_BLOCK_VALUES", 7 * 3 * 2)   # two samples of 7 points per block
    still = np.repeat(np.random.default_rng(1).normal(size=(1, 7, 3)), 9, axis=0).astype(np.float32)
    assert positions.samples_all_alike(still) and positions.samples_all_alike(still[:1])
    for sample in (1, 2, 8):
        moved = still.copy()
        moved[sample, 6, 2] = np.nextafter(moved[sample, 6, 2], np.float32(np.inf))
        assert not positions.samples_all_alike(moved), sample
