"""usdkslValidators:NoInterpenetration in OpenUSD's validation framework: one error per contact region, sited
on its two prims, with the first contact's frame and time; none on a clean stage; an error, never a pass, for
what the check could not read."""

import json
import re

import pytest
from pxr import Gf, Sdf, Usd, UsdGeom, UsdValidation

import usdksl
from usdksl.validation.names import (DOC, INTERPENETRATION, KEYWORD, NOT_CHECKED, NOT_READ, PLUGIN_FOLDER,
                                     VALIDATOR_NAME)

from builders import box, define_mesh, new_stage, stretching_sheet
from pipeline_stage.stages import PROP_VARIANTS, THROUGH_BOX, select_in_session, write_prop_with_variants

ERROR = UsdValidation.ValidationErrorType.Error


def site_paths(error):
    return [str(site.GetPrim().GetPath()) for site in error.GetSites()]


def plug_info():
    """plugInfo.json as Plug reads it: lines starting with # are comments."""
    text = (PLUGIN_FOLDER / "plugInfo.json").read_text()
    return json.loads("\n".join(line for line in text.splitlines() if not line.lstrip().startswith("#")))


def test_register_validators_is_idempotent_and_the_registry_knows_the_validator(validator):
    assert usdksl.register_validators() is not None
    registry = UsdValidation.ValidationRegistry()
    assert registry.HasValidator(VALIDATOR_NAME)
    assert registry.GetOrLoadValidatorByName(VALIDATOR_NAME).GetMetadata().name == VALIDATOR_NAME
    metadata = validator.GetMetadata()
    assert metadata.doc == DOC and KEYWORD in metadata.GetKeywords()
    assert VALIDATOR_NAME in [m.name for m in registry.GetValidatorMetadataForKeyword(KEYWORD)]


def test_the_plugin_declares_the_validator_as_registered():
    plugins = {plugin["Name"]: plugin for plugin in plug_info()["Plugins"]}
    validators = plugins["usdkslValidators"]["Info"]["Validators"]
    assert validators["NoInterpenetration"]["doc"] == DOC and validators["keywords"] == [KEYWORD]
    assert plugins["usdksl.validation.plugin_load"]["Type"] == "python"


def test_contacts_give_one_error_per_region_on_its_two_prims_with_frame_and_time(validator, samples_dir):
    stage = Usd.Stage.Open(str(samples_dir / "drape.usda"))
    errors = validator.Validate(stage)
    result = usdksl.check_shot(str(samples_dir / "drape.usda"))
    assert len(errors) == result.regions.count == 1
    error = errors[0]
    assert error.GetType() == ERROR and error.GetName() == INTERPENETRATION
    assert error.GetIdentifier() == f"{VALIDATOR_NAME}.{INTERPENETRATION}"
    assert site_paths(error) == ["/World/Box", "/World/Cloth"]
    first = float(result.regions.first_time[0])
    assert f"from frame {result.clock.frame(first):.3f} (t={first:.3f})" in error.GetMessage()
    assert "/World/Box and /World/Cloth interpenetrate" in error.GetMessage()


def test_a_self_contact_is_sited_once_on_its_mesh(validator, samples_dir):
    stage = Usd.Stage.Open(str(samples_dir / "fold.usda"))   # held: an error's sites name prims of a live stage
    errors = validator.Validate(stage)
    assert [(e.GetName(), site_paths(e)) for e in errors] == [(INTERPENETRATION, ["/World/Strip"])]
    assert re.search(r"region 1: /World/Strip passes into itself from frame 31\.916 \(t=31\.916\)",
                     errors[0].GetMessage())


@pytest.mark.parametrize("sample", ["clean"])
def test_a_clean_stage_gives_no_error(validator, samples_dir, sample):
    assert list(validator.Validate(Usd.Stage.Open(str(samples_dir / f"{sample}.usda")))) == []


def test_an_unresolved_reference_is_an_error_not_a_pass(validator, tmp_path):
    path = tmp_path / "broken.usda"
    stage = new_stage(path)
    stretching_sheet(stage, "/World/Cloth")
    stage.DefinePrim("/World/Body").GetReferences().AddReference("./body_v2.usda")
    stage.GetRootLayer().Save()
    stage = Usd.Stage.Open(str(path))
    errors = validator.Validate(stage)
    assert [(e.GetType(), e.GetName(), site_paths(e)) for e in errors] == [(ERROR, NOT_READ, ["/World/Body"])]
    assert "reference @./body_v2.usda@ does not resolve" in errors[0].GetMessage()


def test_geometry_the_check_cannot_read_is_an_error(validator, tmp_path):
    path = tmp_path / "sphere.usda"
    stage = new_stage(path)
    stretching_sheet(stage, "/World/Cloth")
    UsdGeom.Sphere.Define(stage, "/World/Ball")
    points, counts, indices = box(1.0)
    define_mesh(stage, "/World/Box", points + [0.0, 3.0, 0.0], counts, indices)
    stage.GetRootLayer().Save()
    stage = Usd.Stage.Open(str(path))
    errors = validator.Validate(stage)
    assert [(e.GetType(), e.GetName(), site_paths(e)) for e in errors] == [(ERROR, NOT_CHECKED, ["/World/Ball"])]
    assert "usdksl:UnmeshedSolid" in errors[0].GetMessage()


def test_the_context_time_range_bounds_the_check(validator, samples_dir):
    stage = Usd.Stage.Open(str(samples_dir / "fold.usda"))   # contacts from time 31.9 on
    context = UsdValidation.ValidationContext([validator])
    before = context.Validate(stage, UsdValidation.ValidationTimeRange(Gf.Interval(1.0, 20.0)))
    over = context.Validate(stage, UsdValidation.ValidationTimeRange(Gf.Interval(20.0, 36.0)))
    whole = context.Validate(stage)
    assert list(before) == []
    assert [e.GetName() for e in over] == [e.GetName() for e in whole] == [INTERPENETRATION]
    default_only = context.Validate(stage, UsdValidation.ValidationTimeRange(Usd.TimeCode.Default()))
    assert list(default_only) == []   # no motion at the default time: nothing over time to check


def test_a_variant_switched_in_the_session_layer_is_validated(validator, tmp_path):
    stage = Usd.Stage.Open(str(write_prop_with_variants(tmp_path / "prop.usda")))
    assert list(validator.Validate(stage)) == []
    select_in_session(stage, "/World/Prop", PROP_VARIANTS, "through")   # as usdchecker explores variants
    errors = validator.Validate(stage)
    assert [site_paths(e) for e in errors] == [["/World/Cloth", THROUGH_BOX]]


def test_an_in_memory_stage_is_validated(validator, samples_dir):
    stage = Usd.Stage.CreateInMemory()
    stage.GetRootLayer().TransferContent(Sdf.Layer.FindOrOpen(str(samples_dir / "fold.usda")))
    assert [site_paths(e) for e in validator.Validate(stage)] == [["/World/Strip"]]


def test_an_instance_is_sited_on_its_instancer_and_a_layer_on_the_stage():
    from usdksl.validation.validation_errors import _site_path

    assert _site_path("/World/scatter[3]/box/geo") == Sdf.Path("/World/scatter")
    assert _site_path("/World/crowd/char2/Body/Arm") == Sdf.Path("/World/crowd/char2/Body/Arm")
    assert _site_path("/tmp/shot/layers/cloth.usda") is None and _site_path("anon:0x1:tmp.usda") is None


def test_a_check_that_fails_unexpectedly_is_an_error_and_the_run_goes_on(validator, samples_dir, monkeypatch):
    def broken(*_, **__):
        raise RuntimeError("disk on fire")

    monkeypatch.setattr("usdksl.validation.task.check_stage", broken)
    stage = Usd.Stage.Open(str(samples_dir / "clean.usda"))
    errors = validator.Validate(stage)
    assert [(e.GetType(), e.GetName(), site_paths(e)) for e in errors] == [(ERROR, NOT_READ, ["/"])]
    assert errors[0].GetMessage() == "usdksl could not check the stage: RuntimeError: disk on fire"
