"""The <stem>.usdksl.usda override layer: sublayer, metadata, per-mesh and per-face results."""

import math
import os

import numpy as np
from pxr import Sdf, Usd, UsdGeom, Vt

from usdksl.reading.loader import load_shot
from usdksl.reports.override import CLEAN_COLOR, CONTACT_COLOR, REVIEW_MATERIAL, REVIEW_SCOPE, build_override_layer, face_first_contact_times, relative_sublayer_path
from usdksl.contacts.table import ContactTable

from builders import STRIP_COUNTS, STRIP_INDICES, STRIP_POINTS, add_mesh, new_stage, sha256
from .test_reports import contacts


def _shot(tmp_path, tcps=30.0, fps=None, indexed_colors=False):
    path = tmp_path / "cache" / "shot.usda"
    path.parent.mkdir()
    stage = new_stage(path, tcps=tcps, fps=fps, start=10.0, end=20.0, up="Z", meters=0.01)
    samples = {10.0: STRIP_POINTS, 15.0: STRIP_POINTS + [0, 0.5, 0], 20.0: STRIP_POINTS + [0, 1.0, 0]}
    add_mesh(stage, "/World/Strip", None, STRIP_COUNTS, STRIP_INDICES, samples=samples)
    box = add_mesh(stage, "/World/Box", STRIP_POINTS + [0, 0.7, 0], STRIP_COUNTS, STRIP_INDICES)
    if indexed_colors:
        primvar = UsdGeom.PrimvarsAPI(box).CreatePrimvar("displayColor", Sdf.ValueTypeNames.Color3fArray,
                                                         UsdGeom.Tokens.constant)
        primvar.Set(Vt.Vec3fArray([(0, 0, 1)]))
        primvar.SetIndices(Vt.IntArray([0, 0]))
    stage.GetRootLayer().Save()
    return path


def _write_layer(tmp_path, shot_path, rows, out_dir=None):
    shot = load_shot(str(shot_path))
    paths = [m.path for m in shot.meshes]
    table = ContactTable.from_face_contacts(contacts(rows), paths)
    out_dir = out_dir or (tmp_path / "results")
    out_dir.mkdir(exist_ok=True)
    layer_path = out_dir / "shot.usdksl.usda"
    layer_path.write_text(build_override_layer(shot, range(len(paths)), table, layer_path))
    return shot, layer_path


def test_samples_read_back_unchanged_through_the_layer_at_30_tcps(tmp_path):
    shot_path = _shot(tmp_path, tcps=30.0)
    before = sha256(shot_path)
    shot, layer_path = _write_layer(tmp_path, shot_path, [])
    assert sha256(shot_path) == before
    original = Usd.Stage.Open(str(shot_path))
    layered = Usd.Stage.Open(str(layer_path))
    for mesh_path in ("/World/Strip", "/World/Box"):
        a = UsdGeom.Mesh(original.GetPrimAtPath(mesh_path)).GetPointsAttr()
        b = UsdGeom.Mesh(layered.GetPrimAtPath(mesh_path)).GetPointsAttr()
        assert b.GetTimeSamples() == a.GetTimeSamples()
        for t in a.GetTimeSamples() or [Usd.TimeCode.Default()]:
            assert np.array_equal(np.asarray(b.Get(t)), np.asarray(a.Get(t)))
    assert layered.GetTimeCodesPerSecond() == 30.0
    assert layered.GetStartTimeCode() == 10.0 and layered.GetEndTimeCode() == 20.0
    assert UsdGeom.GetStageUpAxis(layered) == "Z" and UsdGeom.GetStageMetersPerUnit(layered) == 0.01
    assert layered.GetDefaultPrim().GetPath() == "/World"
    # the sublayer is relative so the pair of folders can move
    assert Sdf.Layer.FindOrOpen(str(layer_path)).subLayerPaths[0] == "../cache/shot.usda"


def test_fps_only_cache_keeps_its_timing(tmp_path):
    shot_path = tmp_path / "fps.usda"
    stage = Usd.Stage.CreateNew(str(shot_path))
    stage.SetFramesPerSecond(30.0)   # no timeCodesPerSecond authored: USD derives 30 from it
    add_mesh(stage, "/Strip", None, STRIP_COUNTS, STRIP_INDICES,
             samples={10.0: STRIP_POINTS, 20.0: STRIP_POINTS + [0, 1, 0]})
    stage.GetRootLayer().Save()
    shot = load_shot(str(shot_path))
    layer_path = tmp_path / "fps.usdksl.usda"
    layer_path.write_text(build_override_layer(shot, [0], ContactTable.empty(["/Strip"]), layer_path))
    layered = Usd.Stage.Open(str(layer_path))   # keep the stage alive while its prims are used
    attribute = UsdGeom.Mesh(layered.GetPrimAtPath("/Strip")).GetPointsAttr()
    assert attribute.GetTimeSamples() == [10.0, 20.0]


def test_per_mesh_and_per_face_results(tmp_path):
    shot_path = _shot(tmp_path)
    # mesh indices follow the loader's order; look them up by path
    paths = [m.path for m in load_shot(str(shot_path)).meshes]
    strip, box = paths.index("/World/Strip"), paths.index("/World/Box")
    rows = [(14.0, strip, 1, box, 0, 2), (16.0, strip, 1, box, 1, 2), (17.0, strip, 0, strip, 1, 3)]
    shot, layer_path = _write_layer(tmp_path, shot_path, rows)
    stage = Usd.Stage.Open(str(layer_path))
    strip_prim, box_prim = stage.GetPrimAtPath("/World/Strip"), stage.GetPrimAtPath("/World/Box")
    assert strip_prim.GetAttribute("usdksl:firstContactTime").Get() == 14.0
    assert strip_prim.GetAttribute("usdksl:contactFaceCount").Get() == 2
    assert [str(p) for p in strip_prim.GetRelationship("usdksl:contactsWith").GetTargets()] == \
        ["/World/Box", "/World/Strip"]
    assert [str(p) for p in box_prim.GetRelationship("usdksl:contactsWith").GetTargets()] == ["/World/Strip"]
    primvars = UsdGeom.PrimvarsAPI(strip_prim)
    per_face = primvars.GetPrimvar("usdksl:firstContactTime")
    assert per_face.GetInterpolation() == UsdGeom.Tokens.uniform
    assert list(per_face.Get()) == [17.0, 14.0]           # face 0 only touches itself at 17
    box_times = list(UsdGeom.PrimvarsAPI(box_prim).GetPrimvar("usdksl:firstContactTime").Get())
    assert box_times == [14.0, 16.0]
    colors = UsdGeom.PrimvarsAPI(strip_prim).GetPrimvar("displayColor")
    assert colors.GetInterpolation() == UsdGeom.Tokens.uniform
    assert len(colors.ComputeFlattened()) == 2


def test_clean_mesh_has_no_first_contact_time_and_nan_faces(tmp_path):
    shot_path = _shot(tmp_path)
    _, layer_path = _write_layer(tmp_path, shot_path, [])
    layered = Usd.Stage.Open(str(layer_path))
    prim = layered.GetPrimAtPath("/World/Box")
    assert not prim.GetAttribute("usdksl:firstContactTime").HasAuthoredValue()
    assert prim.GetAttribute("usdksl:contactFaceCount").Get() == 0
    assert prim.GetRelationship("usdksl:contactsWith").GetTargets() == []
    values = UsdGeom.PrimvarsAPI(prim).GetPrimvar("usdksl:firstContactTime").Get()
    assert len(values) == 2 and all(math.isnan(v) for v in values)
    # only overs on the cache's prims: the layer defines nothing but its review material
    layer = Sdf.Layer.FindOrOpen(str(layer_path))
    specs = []
    layer.Traverse("/", lambda path: specs.append(layer.GetPrimAtPath(path)) if path.IsPrimPath() else None)
    cache_specs = [spec for spec in specs if not spec.path.HasPrefix(REVIEW_SCOPE)]
    assert cache_specs and all(spec.specifier == Sdf.SpecifierOver for spec in cache_specs)
    assert layered.GetPrimAtPath(REVIEW_MATERIAL).GetTypeName() == "Material"


def test_indexed_display_color_of_the_input_is_replaced(tmp_path):
    shot_path = _shot(tmp_path, indexed_colors=True)
    paths = [m.path for m in load_shot(str(shot_path)).meshes]
    strip, box = paths.index("/World/Strip"), paths.index("/World/Box")
    _, layer_path = _write_layer(tmp_path, shot_path, [(14.0, strip, 1, box, 1, 2)])
    layered = Usd.Stage.Open(str(layer_path))
    primvar = UsdGeom.PrimvarsAPI(layered.GetPrimAtPath("/World/Box")).GetPrimvar("displayColor")
    assert primvar.GetInterpolation() == UsdGeom.Tokens.uniform
    # our indices replace the input's: face 1 touches (from 14 on), face 0 never does
    for time, face_1 in ((Usd.TimeCode.Default(), CONTACT_COLOR), (13.0, CLEAN_COLOR), (14.0, CONTACT_COLOR)):
        flattened = np.asarray(primvar.ComputeFlattened(time))
        assert flattened.shape == (2, 3)
        assert np.allclose(flattened[0], CLEAN_COLOR) and np.allclose(flattened[1], face_1), time


def test_face_first_contact_times_takes_the_minimum_over_both_sides():
    table = ContactTable.from_face_contacts(contacts([(5.0, 0, 2, 1, 0, 2), (3.0, 1, 1, 0, 2, 2),
                                                      (4.0, 0, 0, 0, 2, 2)]), ["/a", "/b"])
    times = face_first_contact_times(table, 0, 4)
    assert times[0] == 4.0 and times[2] == 3.0
    assert math.isnan(times[1]) and math.isnan(times[3])


def test_relative_sublayer_path(tmp_path):
    assert relative_sublayer_path(tmp_path / "a" / "s.usd", tmp_path / "a") == "./s.usd"
    assert relative_sublayer_path(tmp_path / "a" / "s.usd", tmp_path / "b" / "c") == "../../a/s.usd"
    assert not os.path.isabs(relative_sublayer_path("/x/y/s.usd", "/x/z"))


def test_meshes_inside_instances_get_their_results(tmp_path):
    path = tmp_path / "instanced.usda"
    stage = new_stage(path)
    add_mesh(stage, "/Prototypes/Prop/Geo", STRIP_POINTS, STRIP_COUNTS, STRIP_INDICES)
    for name, x in (("A", 0.0), ("B", 5.0)):
        instance = UsdGeom.Xform.Define(stage, f"/World/{name}")
        instance.AddTranslateOp().Set((x, 0.0, 0.0))
        instance.GetPrim().GetReferences().AddInternalReference("/Prototypes/Prop")
        instance.GetPrim().SetInstanceable(True)
    stage.GetPrimAtPath("/Prototypes").SetSpecifier(Sdf.SpecifierClass)
    stage.GetRootLayer().Save()
    shot = load_shot(str(path))
    paths = [m.path for m in shot.meshes]
    assert "/World/A/Geo" in paths
    a = paths.index("/World/A/Geo")
    table = ContactTable.from_face_contacts(contacts([(3.0, a, 1, a, 0, 2)]), paths)
    layer_path = tmp_path / "instanced.usdksl.usda"
    layer_path.write_text(build_override_layer(shot, range(len(paths)), table, layer_path))
    layered = Usd.Stage.Open(str(layer_path))
    times = UsdGeom.PrimvarsAPI(layered.GetPrimAtPath("/World/A/Geo")).GetPrimvar("usdksl:firstContactTime").Get()
    assert list(times) == [3.0, 3.0]
    assert layered.GetPrimAtPath("/World/A/Geo").GetAttribute("usdksl:contactFaceCount").Get() == 2
    original = Usd.Stage.Open(str(path))
    assert original.GetPrimAtPath("/World/A").IsInstance()            # the input keeps its instancing
    points = UsdGeom.Mesh(layered.GetPrimAtPath("/World/B/Geo")).GetPointsAttr().Get()
    assert np.array_equal(np.asarray(points), np.asarray(
        UsdGeom.Mesh(original.GetPrimAtPath("/World/B/Geo")).GetPointsAttr().Get()))
