"""The override layer shows *when*: per-face colours sampled in time, a review material bound for usdview's
preview purpose, and crate files (.usdc) when the layer is large. Every check opens the composed stage
(the written layer over the cache) with usd-core."""

import csv
import math

import numpy as np
import pytest
from click.testing import CliRunner
from pxr import Sdf, Usd, UsdGeom, UsdShade, Vt

from usdksl.cli.main import main
from usdksl.reports.override import (CLEAN_COLOR, CONTACT_COLOR, MAX_EXACT_COLOR_SAMPLES, REVIEW_MATERIAL,
                                     color_sample_times)

from builders import new_stage, quad_grid, write_mesh

START, END = 1.0, 101.0


def _sheet_over_floor(path, cells, scene_material=False):
    """A static floor quad at y = 0 and a cells x cells sheet above it, tilted so that its faces reach the
    floor at many different times while it sinks (and bends) from START to END; the faces at high x never
    reach it."""
    stage = new_stage(path, start=START, end=END)
    floor = np.array([[-1, 0, -1], [2, 0, -1], [2, 0, 2], [-1, 0, 2]], dtype=np.float64)
    write_mesh(stage, "/World/Floor", [4], [0, 1, 2, 3], points=floor)
    points, counts, indices = quad_grid(cells, cells)
    x, z = points[:, 0], points[:, 2]
    first = points + np.stack([0 * x, 0.5 + 0.5 * x + 0.01 * z, 0 * x], axis=1)
    last = points + np.stack([0 * x, -0.4 + 0.5 * x + 0.01 * z + 0.1 * x * x, 0 * x], axis=1)
    sheet = write_mesh(stage, "/World/Sheet", counts, indices, samples={START: first, END: last})
    if scene_material:
        material = UsdShade.Material.Define(stage, "/World/Looks/Cloth")
        UsdShade.MaterialBindingAPI.Apply(sheet.GetPrim()).Bind(material)
        subset = UsdGeom.Subset.Define(stage, "/World/Sheet/Hem")
        subset.CreateElementTypeAttr(UsdGeom.Tokens.face)
        subset.CreateFamilyNameAttr("materialBind")
        subset.CreateIndicesAttr(Vt.IntArray([0, 1]))
        UsdShade.MaterialBindingAPI.Apply(subset.GetPrim()).Bind(material)
    stage.GetRootLayer().Save()
    return path


def _check(shot, out, *extra):
    result = CliRunner().invoke(main, ["check", str(shot), "--out", str(out), *map(str, extra)])
    assert result.exit_code == 1, result.output
    return result


def _face_first_times(contacts_csv, prim):
    """{face: first contact} of ``prim`` over every row of contacts.csv."""
    first = {}
    with open(contacts_csv, newline="") as handle:
        for row in csv.DictReader(handle):
            for side in ("a", "b"):
                if row[f"prim_{side}"] == prim:
                    face = int(row[f"face_{side}"])
                    first[face] = min(first.get(face, math.inf), float(row["time"]))
    return first


def _colors(stage, prim, time):
    return np.asarray(UsdGeom.PrimvarsAPI(stage.GetPrimAtPath(prim)).GetPrimvar("displayColor")
                      .ComputeFlattened(time))


def test_a_face_is_grey_before_its_first_contact_and_red_from_it_on(tmp_path):
    shot = _sheet_over_floor(tmp_path / "sheet.usda", cells=8)
    _check(shot, tmp_path / "out")
    layer = tmp_path / "out" / "sheet.usdksl.usda"
    stage = Usd.Stage.Open(str(layer))
    first = _face_first_times(tmp_path / "out" / "sheet.contacts.csv", "/World/Sheet")
    assert 32 <= len(first) <= 64 and len(set(first.values())) > 16    # many faces, many different times
    for face, time in first.items():
        just_before = np.nextafter(time, -math.inf)
        assert np.allclose(_colors(stage, "/World/Sheet", just_before)[face], CLEAN_COLOR), (face, time)
        assert np.allclose(_colors(stage, "/World/Sheet", time)[face], CONTACT_COLOR), (face, time)
        assert np.allclose(_colors(stage, "/World/Sheet", END)[face], CONTACT_COLOR)
    never = sorted(set(range(64)) - set(first))
    assert never and np.allclose(_colors(stage, "/World/Sheet", END)[never], CLEAN_COLOR)
    assert np.allclose(_colors(stage, "/World/Sheet", START), CLEAN_COLOR)   # nothing touches at the start
    # the per-face first contact times ride along, NaN where a face never touches
    per_face = np.asarray(UsdGeom.PrimvarsAPI(stage.GetPrimAtPath("/World/Sheet"))
                          .GetPrimvar("usdksl:firstContactTime").Get())
    assert [per_face[face] for face in sorted(first)] == [first[face] for face in sorted(first)]
    assert np.isnan(per_face[never]).all()
    assert not (tmp_path / "out" / "sheet.usdksl.usdc").exists()


def test_the_review_material_shows_with_scene_materials_on(tmp_path):
    shot = _sheet_over_floor(tmp_path / "sheet.usda", cells=8, scene_material=True)
    _check(shot, tmp_path / "out")
    stage = Usd.Stage.Open(str(tmp_path / "out" / "sheet.usdksl.usda"))
    for prim_path in ("/World/Sheet", "/World/Sheet/Hem", "/World/Floor"):
        binding = UsdShade.MaterialBindingAPI(stage.GetPrimAtPath(prim_path))
        material, _ = binding.ComputeBoundMaterial(UsdShade.Tokens.preview)
        assert material and material.GetPath() == REVIEW_MATERIAL, prim_path
    # full-quality renders keep the scene's material
    full, _ = UsdShade.MaterialBindingAPI(stage.GetPrimAtPath("/World/Sheet")).ComputeBoundMaterial(
        UsdShade.Tokens.full)
    assert full.GetPath() == "/World/Looks/Cloth"
    # the review surface's diffuse colour reads the displayColor primvar
    surface = UsdShade.Material(stage.GetPrimAtPath(REVIEW_MATERIAL)).ComputeSurfaceSource()[0]
    assert surface.GetIdAttr().Get() == "UsdPreviewSurface"
    source = surface.GetInput("diffuseColor").GetConnectedSources()[0][0].source
    reader = UsdShade.Shader(source.GetPrim())
    assert reader.GetIdAttr().Get() == "UsdPrimvarReader_float3"
    assert reader.GetInput("varname").Get() == "displayColor"


def test_a_large_layer_is_a_crate_file_with_samples_on_whole_time_codes(tmp_path):
    shot = _sheet_over_floor(tmp_path / "sheet.usda", cells=64)
    out = tmp_path / "out"
    out.mkdir()
    (out / "sheet.usdksl.usda").write_text("#usda 1.0\n")             # stale, from an earlier small run
    _check(shot, out)
    layer = out / "sheet.usdksl.usdc"
    assert layer.read_bytes()[:8] == b"PXR-USDC"
    assert not (out / "sheet.usdksl.usda").exists()
    again = tmp_path / "again"
    _check(shot, again)
    assert (again / "sheet.usdksl.usdc").read_bytes() == layer.read_bytes()    # deterministic bytes
    stage = Usd.Stage.Open(str(layer))
    assert stage.GetTimeCodesPerSecond() == 24.0 and stage.GetStartTimeCode() == START
    first = _face_first_times(out / "sheet.contacts.csv", "/World/Sheet")
    assert len(set(first.values())) > MAX_EXACT_COLOR_SAMPLES
    indices = stage.GetPrimAtPath("/World/Sheet").GetAttribute("primvars:displayColor:indices")
    samples = indices.GetTimeSamples()
    assert samples[0] == START and all(float(t).is_integer() for t in samples)
    for face, time in list(first.items())[::97]:
        assert np.allclose(_colors(stage, "/World/Sheet", math.ceil(time))[face], CONTACT_COLOR), (face, time)
        if math.floor(time) < time:
            assert np.allclose(_colors(stage, "/World/Sheet", math.floor(time))[face], CLEAN_COLOR), (face, time)


def test_colour_samples_start_at_the_range_and_follow_the_first_contacts():
    times = np.array([np.nan, 3.5, 3.5, 7.25, 1.0])
    assert color_sample_times(times, 1.0) == [1.0, 3.5, 7.25]
    many = np.linspace(2.01, 9.99, MAX_EXACT_COLOR_SAMPLES + 1)
    assert color_sample_times(many, 1.0) == [1.0] + [float(t) for t in range(3, 11)]
