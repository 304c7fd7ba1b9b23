"""check_stage checks the stage it is given, as it is composed in memory: the answer follows the session
layer, the variant selections and the population mask of that stage, not its file, which is never opened
again nor changed."""

import hashlib

import pytest
from pxr import Gf, Sdf, Usd, UsdGeom

import usdksl
from usdksl import CheckOptions, UsdkslInputError, check_shot, check_stage
from usdksl.pipeline.files import OutputTargets
from usdksl.pipeline.messages import INFO, WARNING

from builders import box, define_mesh, new_stage, stretching_sheet
from .stages import CLEAR_BOX, PROP_VARIANTS, THROUGH_BOX, select_in_session

#: Where the session layer lifts clean.usda's static box: its top (half size 0.5) into the waving sheet at y 1.2.
LIFT_INTO_SHEET = Gf.Vec3d(0.0, 0.7, 0.0)


def sha256(path):
    return hashlib.sha256(path.read_bytes()).hexdigest()


def mesh_pairs(result):
    """{(prim_a, prim_b)} of the mesh pairs with contacts."""
    return {(row["prim_a"], row["prim_b"]) for row in result.table.summary()}


def test_a_session_layer_edit_makes_contacts_the_file_does_not_have(sample_copy):
    path = sample_copy("clean")
    before = sha256(path)
    stage = Usd.Stage.Open(str(path))
    with Usd.EditContext(stage, stage.GetSessionLayer()):
        UsdGeom.Xformable(stage.GetPrimAtPath("/World/Box")).AddTranslateOp().Set(LIFT_INTO_SHEET)

    on_stage = check_stage(stage)
    from_file = check_shot(str(path))
    assert from_file.exit_code == 0 and from_file.table.count == 0
    assert on_stage.exit_code == 1
    assert mesh_pairs(on_stage) == {("/World/Box", "/World/Sheet")}
    # the stage is read, not written: its file, its root layer and its session layer are as they were
    assert sha256(path) == before and not stage.GetRootLayer().dirty
    session_box = stage.GetSessionLayer().GetPrimAtPath("/World/Box")
    assert list(session_box.attributes.keys()) == ["xformOp:translate", "xformOpOrder"]
    assert any(m.level == INFO and "session layer" in m.text for m in on_stage.messages)


def test_the_reports_go_beside_the_root_layer_file_and_are_named_after_it(sample_copy):
    path = sample_copy("fold")
    result = check_stage(Usd.Stage.Open(str(path)))
    assert result.exit_code == 1 and result.table.count == check_shot(str(path)).table.count
    names = {target.name: data for target, data in result.files.items()}
    assert {target.parent for target in result.files} == {path.parent}
    assert "fold.contacts.csv" in names and names["fold.usdksl.usda"].startswith("#usda")
    assert "@./fold.usda@" in names["fold.usdksl.usda"]   # the override layer sublayers the file


def test_a_variant_switched_on_the_stage_changes_which_mesh_is_checked(prop_with_variants):
    stage = Usd.Stage.Open(str(prop_with_variants))
    clear = check_stage(stage)
    assert clear.exit_code == 0 and CLEAR_BOX in clear.table.paths and THROUGH_BOX not in clear.table.paths

    select_in_session(stage, "/World/Prop", PROP_VARIANTS, "through")
    through = check_stage(stage)
    assert through.exit_code == 1
    assert THROUGH_BOX in through.table.paths and CLEAR_BOX not in through.table.paths
    assert mesh_pairs(through) == {("/World/Cloth", THROUGH_BOX)}
    assert check_shot(str(prop_with_variants)).table.count == 0   # the file still selects "clear"


def test_a_population_mask_leaves_a_mesh_out(sample_copy):
    path = sample_copy("drape")
    whole = check_stage(Usd.Stage.Open(str(path)))
    assert mesh_pairs(whole) == {("/World/Box", "/World/Cloth")}

    masked = check_stage(Usd.Stage.OpenMasked(str(path), Usd.StagePopulationMask(["/World/Cloth"])))
    assert "/World/Box" not in masked.table.paths and masked.table.count == 0
    assert any(m.level == INFO and "population mask holds /World/Cloth" in m.text for m in masked.messages)


def cloth_with_body_reference(tmp_path, arc="reference"):
    """A shot whose cloth falls onto a body brought in by a reference (or payload) to body.usda."""
    body_path = tmp_path / "body.usda"
    body = new_stage(body_path)
    points, counts, indices = box(1.0)
    define_mesh(body, "/World/Body", points, counts, indices)
    body.GetRootLayer().Save()
    shot_path = tmp_path / "shot.usda"
    shot = new_stage(shot_path)
    stretching_sheet(shot, "/World/Cloth")
    arcs = shot.DefinePrim("/World/Body")
    (arcs.GetPayloads().AddPayload if arc == "payload" else arcs.GetReferences().AddReference)(
        "./body.usda", "/World/Body")
    shot.GetRootLayer().Save()
    return shot_path, body_path


def test_an_asset_that_does_not_resolve_on_the_stage_is_an_input_error(tmp_path):
    shot_path, body_path = cloth_with_body_reference(tmp_path)
    body_path.unlink()
    stage = Usd.Stage.Open(str(shot_path))
    with pytest.raises(UsdkslInputError) as refused:
        check_stage(stage)
    assert refused.value.prim == "/World/Body"
    assert "reference @./body.usda@</World/Body> does not resolve" in str(refused.value)
    allowed = check_stage(stage, CheckOptions(allow_missing_assets=True))
    assert [entry.prim for entry in allowed.coverage.with_status("not checked")] == ["/World/Body"]


def test_a_payload_the_stage_has_not_loaded_counts_as_missing_until_it_is_loaded(tmp_path):
    shot_path, _ = cloth_with_body_reference(tmp_path, arc="payload")
    stage = Usd.Stage.Open(str(shot_path), Usd.Stage.LoadNone)
    with pytest.raises(UsdkslInputError) as refused:
        check_stage(stage)
    assert refused.value.prim == "/World/Body" and "payload @./body.usda@" in str(refused.value)
    assert "is not loaded on the stage" in str(refused.value)
    allowed = check_stage(stage, CheckOptions(allow_missing_assets=True))
    assert [(entry.prim, entry.kind) for entry in allowed.coverage.with_status("not checked")] == [
        ("/World/Body", "usdksl:UnresolvedAsset")]
    stage.Load("/World/Body")
    loaded = check_stage(stage)
    assert mesh_pairs(loaded) == {("/World/Body", "/World/Cloth")}


def in_memory_fold(samples_dir):
    stage = Usd.Stage.CreateInMemory("fold_in_memory.usda")
    stage.GetRootLayer().TransferContent(Sdf.Layer.FindOrOpen(str(samples_dir / "fold.usda")))
    return stage


def test_an_in_memory_stage_reports_into_the_targets_without_an_override_layer(tmp_path, samples_dir):
    stage = in_memory_fold(samples_dir)
    options = CheckOptions(time_range=(1.0, 36.0))   # a time range adds the manifest, which names the shot hash
    result = check_stage(stage, options, targets=OutputTargets(out_dir=tmp_path), name="fold_take2")
    files = {target.name: data for target, data in result.files.items()}
    assert {target.parent for target in result.files} == {tmp_path}
    assert result.shot == "fold_take2" and result.exit_code == 1
    assert files["fold_take2.contacts.csv"].startswith("time,prim_a")
    # no override layer (it would have no file to sublayer), and none of an earlier check left beside the reports
    assert files["fold_take2.usdksl.usda"] is None and files["fold_take2.usdksl.usdc"] is None
    warnings = [m.text for m in result.messages if m.level == WARNING]
    assert any("in memory" in text and "no override layer" in text for text in warnings)
    text_sha = hashlib.sha256(stage.GetRootLayer().ExportToString().encode("utf-8")).hexdigest()
    manifest = files["fold_take2.usdksl-run.json"]
    assert f'"shot_sha256": "{text_sha}"' in manifest
    # nothing names the temporary copy that was hashed
    assert not [m.text for m in result.messages if "usdksl-stage-" in m.text]


def test_an_in_memory_stage_without_targets_reports_into_the_working_directory(tmp_path, samples_dir, monkeypatch):
    monkeypatch.chdir(tmp_path)
    result = check_stage(in_memory_fold(samples_dir))
    assert result.shot == "fold_in_memory.usda"
    assert tmp_path / "fold_in_memory.contacts.csv" in result.files
    assert usdksl.write_files(result.files)   # written all together, the stale override layer entries removed
    assert sorted(p.name for p in tmp_path.iterdir()) == [
        "fold_in_memory.contacts.csv", "fold_in_memory.regions.csv", "fold_in_memory.summary.csv"]


def test_an_input_error_on_an_in_memory_stage_names_the_stage_not_a_temporary_file(tmp_path):
    stage = Usd.Stage.CreateInMemory("empty_take.usda")
    UsdGeom.Xform.Define(stage, "/World")
    with pytest.raises(UsdkslInputError) as refused:
        check_stage(stage)
    assert refused.value.file == "empty_take.usda" and "usdksl-stage-" not in str(refused.value)


def test_unsaved_edits_of_the_root_layer_are_checked_and_named(sample_copy):
    path = sample_copy("clean")
    stage = Usd.Stage.Open(str(path))
    UsdGeom.Xformable(stage.GetPrimAtPath("/World/Box")).AddTranslateOp().Set(LIFT_INTO_SHEET)
    result = check_stage(stage)
    assert mesh_pairs(result) == {("/World/Box", "/World/Sheet")}
    assert any(m.level == WARNING and "unsaved edits" in m.text for m in result.messages)


def test_anything_but_a_stage_is_a_usage_error(sample_copy):
    with pytest.raises(usdksl.UsdkslUsageError):
        check_stage(str(sample_copy("fold")))
