"""Assets that do not resolve: a stage composed without them is never a silent pass. Without
--allow-missing-assets it is one error line naming the asset and the prim that asked for it (exit 2, nothing
written); with it, what composes is checked and each asset is named as not checked (exit 2 under --strict).
pxr's own warnings about them are not printed."""

import pytest
from pxr import Sdf, Usd, UsdGeom

from usdksl.errors import UsdkslInputError
from usdksl.pipeline.memory_budget import scan_shot
from usdksl.reading.composition import CLIP, PAYLOAD, REFERENCE, SUBLAYER, refusal, unresolved_assets
from usdksl.reading.loader import load_shot, open_stage, shot_sample_times
from usdksl.warning_kinds import UNRESOLVED_ASSET

from builders import bare_stage
from .conftest import BODY_ARCS, run_cli

REFUSED = "nothing checked (--allow-missing-assets checks what composes)"
NOT_CHECKED = "what it brings in is not checked"
#: What pxr prints about a missing asset when left to itself.
PXR_WARNINGS = ("Could not open asset", "Could not load sublayer", "Unable to open clip layer")


def rename(path, name):
    path.rename(path.with_name(name))


def written(out):
    return sorted(p.name for p in out.iterdir()) if out.exists() else []


def assert_no_pxr_warning(capfd):
    err = capfd.readouterr().err   # pxr writes to file descriptor 2, past click's and pytest's sys.stderr
    assert not [text for text in PXR_WARNINGS if text in err], err


@pytest.mark.parametrize("strict", [(), ("--strict",)], ids=["default", "strict"])
def test_renamed_body_file_is_an_input_error_naming_asset_and_prim(tmp_path, cloth_and_body, capfd, strict):
    shot, body = cloth_and_body("reference")
    rename(body, "body_v2.usda")
    out = tmp_path / "out"
    result = run_cli("check", shot, "--out", out, *strict)
    assert result.exit_code == 2, result.stderr
    assert result.stderr.strip().splitlines() == [
        f"usdksl: error: {shot}: /World/Body: reference @./body.usda@ does not resolve; {REFUSED}"]
    assert written(out) == []
    assert_no_pxr_warning(capfd)


def test_allow_missing_assets_checks_what_composes_and_names_the_asset(cloth_and_body, check, capfd):
    shot, body = cloth_and_body("reference")
    rename(body, "body_v2.usda")
    result, contacts, summary = check(shot, "--allow-missing-assets")
    assert result.exit_code == 0, result.stderr   # the cloth alone has no contact
    assert contacts == {} and summary == {}
    warning = f"usdksl: warning: {shot}: /World/Body: reference @./body.usda@ does not resolve: {NOT_CHECKED}"
    assert result.stderr.splitlines().count(warning) == 1
    assert_no_pxr_warning(capfd)


def test_allow_missing_assets_under_strict_is_still_exit_2(tmp_path, cloth_and_body):
    shot, body = cloth_and_body("reference")
    rename(body, "body_v2.usda")
    out = tmp_path / "out"
    result = run_cli("check", shot, "--out", out, "--allow-missing-assets", "--strict")
    assert result.exit_code == 2, result.stderr
    assert result.stderr.strip().splitlines()[-1] == (
        f"usdksl: error: {shot}: /World/Body: reference @./body.usda@ does not resolve: {NOT_CHECKED} (--strict)")
    assert written(out) == []


@pytest.mark.parametrize("arc, renamed, requester, what", [
    ("payload", "body.usda", "/World/Body", "payload @./body.usda@"),
    ("sublayer", "body.usda", None, "sublayer @./body.usda@"),
    ("clip", "body.usda", "/World/Body", "value clip @./body.usda@"),
    ("clip", "body_manifest.usda", "/World/Body", "value clip manifest @./body_manifest.usda@"),
], ids=["payload", "sublayer", "clip", "clip-manifest"])
def test_missing_payload_sublayer_and_clip_are_input_errors(tmp_path, cloth_and_body, capfd, arc, renamed,
                                                            requester, what):
    shot, _ = cloth_and_body(arc)
    rename(tmp_path / renamed, "renamed.usda")
    # a sublayer is asked for by a layer: here the shot's root layer, which the line names once
    asker = f"{requester}: " if requester else ""
    out = tmp_path / "out"
    result = run_cli("check", shot, "--out", out)
    assert result.exit_code == 2, result.stderr
    assert result.stderr.strip().splitlines() == [
        f"usdksl: error: {shot}: {asker}{what} does not resolve; {REFUSED}"]
    assert written(out) == []
    assert_no_pxr_warning(capfd)
    allowed = run_cli("check", shot, "--out", out, "--allow-missing-assets")
    assert allowed.exit_code == 0, allowed.stderr
    assert f"usdksl: warning: {shot}: {asker}{what} does not resolve: {NOT_CHECKED}" in allowed.stderr


@pytest.mark.parametrize("arc", BODY_ARCS)
def test_stage_with_every_asset_present_is_checked_as_before(cloth_and_body, check, arc):
    shot, _ = cloth_and_body(arc)
    assert unresolved_assets(open_stage(shot)) == []
    result, contacts, summary = check(shot)
    assert result.exit_code == 1, result.stderr
    assert list(summary) == [("/World/Body", "/World/Cloth")]
    first, pairs = summary[("/World/Body", "/World/Cloth")]
    assert pairs == 16 and first == pytest.approx(9.625, abs=1e-6)
    assert "resolve" not in result.stderr


def test_loader_lists_each_unresolved_asset_as_unchecked(cloth_and_body):
    shot, body = cloth_and_body("reference")
    rename(body, "body_v2.usda")
    with pytest.raises(UsdkslInputError) as refused:
        load_shot(shot)
    assert (refused.value.file, refused.value.prim) == (str(shot), "/World/Body")
    loaded = load_shot(shot, allow_missing_assets=True)
    assert [mesh.path for mesh in loaded.meshes] == ["/World/Cloth"]
    assert [(item.prim, item.kind) for item in loaded.unchecked] == [("/World/Body", UNRESOLVED_ASSET)]
    assert loaded.unchecked[0].reason == f"reference @./body.usda@ does not resolve: {NOT_CHECKED}"
    assert loaded.warnings == [f"{shot}: /World/Body: {loaded.unchecked[0].reason}"]


def test_time_sample_and_memory_scans_read_what_composes(cloth_and_body, capfd):
    shot, body = cloth_and_body("reference")
    rename(body, "body_v2.usda")
    assert [times.tolist() for times in shot_sample_times(shot)] == [[1.0, 24.0]]   # the cloth
    size = scan_shot(str(shot))
    assert (size.meshes, size.vertex_samples) == (1, 2 * 49)
    assert_no_pxr_warning(capfd)


def test_nothing_left_with_allow_missing_assets_names_the_asset(tmp_path):
    stage = bare_stage(tmp_path / "shot.usda")
    stage.DefinePrim("/World/Body").GetReferences().AddReference("./body.usda")
    stage.GetRootLayer().Save()
    with pytest.raises(UsdkslInputError) as refused:
        load_shot(tmp_path / "shot.usda", allow_missing_assets=True)
    assert "no UsdGeom.Mesh prims" in refused.value.message
    assert "@./body.usda@ (reference of /World/Body)" in refused.value.message


def test_sublayers_at_any_depth_and_of_referenced_layers_are_named_with_their_layer(tmp_path):
    inner = Sdf.Layer.CreateNew(str(tmp_path / "anim.usda"))
    inner.subLayerPaths.append("./anim_v3.usda")   # missing, two sublayers deep
    inner.Save()
    outer = Sdf.Layer.CreateNew(str(tmp_path / "layout.usda"))
    outer.subLayerPaths.append("./anim.usda")
    outer.Save()
    character = Usd.Stage.CreateNew(str(tmp_path / "char.usda"))
    character.SetDefaultPrim(UsdGeom.Xform.Define(character, "/Char").GetPrim())
    character.GetRootLayer().subLayerPaths.append("./char_fx.usda")   # missing, in a referenced layer
    character.GetRootLayer().Save()
    stage = bare_stage(tmp_path / "shot.usda")
    stage.GetRootLayer().subLayerPaths.append("./layout.usda")
    stage.DefinePrim("/World/Char").GetReferences().AddReference("./char.usda")
    stage.GetRootLayer().Save()
    found = unresolved_assets(Usd.Stage.Open(str(tmp_path / "shot.usda")))
    assert sorted((item.kind, item.asset_path, item.requester) for item in found) == [
        (SUBLAYER, "./anim_v3.usda", str(tmp_path / "anim.usda")),
        (SUBLAYER, "./char_fx.usda", str(tmp_path / "char.usda"))]


def test_every_kind_is_listed_once_and_the_error_counts_the_rest(tmp_path):
    (tmp_path / "props.usda").write_text('#usda 1.0\n(\n    defaultPrim = "Props"\n)\n\ndef Xform "Props"\n{\n}\n')
    stage = bare_stage(tmp_path / "shot.usda")
    stage.DefinePrim("/World/A").GetReferences().AddReference("./a.usda")
    stage.DefinePrim("/World/B").GetPayloads().AddPayload("./b.usda")
    stage.DefinePrim("/World/C").GetReferences().AddReference("./props.usda", "/Crate")   # no such prim
    clips = Usd.ClipsAPI(stage.DefinePrim("/World/D"))
    clips.SetClipAssetPaths([Sdf.AssetPath("./props.usda"), Sdf.AssetPath("./d.2.usda")])
    clips.SetClipPrimPath("/Props")
    stage.GetRootLayer().subLayerPaths.append("./e.usda")
    stage.GetRootLayer().Save()
    found = unresolved_assets(Usd.Stage.Open(str(tmp_path / "shot.usda")))
    assert [(item.kind, item.describe(), item.requester) for item in found] == [
        (REFERENCE, "reference @./a.usda@ does not resolve", "/World/A"),
        (PAYLOAD, "payload @./b.usda@ does not resolve", "/World/B"),
        (REFERENCE, "reference @./props.usda@</Crate> does not resolve: its asset has no prim </Crate>",
         "/World/C"),
        (SUBLAYER, "sublayer @./e.usda@ does not resolve", str(tmp_path / "shot.usda")),
        (CLIP, "value clip @./d.2.usda@ does not resolve", "/World/D")]
    assert refusal(found) == f"reference @./a.usda@ does not resolve, and 4 more unresolved assets; {REFUSED}"


def test_info_and_crosscheck_refuse_a_missing_asset_unless_allowed(tmp_path, cloth_and_body):
    shot, body = cloth_and_body("reference")
    rename(body, "body_v2.usda")
    for command in (["info", shot], ["crosscheck", shot, "--out", tmp_path / "out"]):
        refused = run_cli(*command)
        assert refused.exit_code == 2 and "reference @./body.usda@ does not resolve" in refused.stderr
        allowed = run_cli(*command, "--allow-missing-assets")
        assert allowed.exit_code == 0, allowed.stderr
        assert f"{shot}: /World/Body: reference @./body.usda@ does not resolve" in allowed.stderr
    assert "/World/Cloth" in run_cli("info", shot, "--allow-missing-assets").stdout
