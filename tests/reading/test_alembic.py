"""Alembic on a USD build without its plugin (usdAbc; the usd-core wheel has none): a shot that is an ``.abc``
file is one error line naming it, saying the build cannot read Alembic and how to convert it (exit 2, nothing
written); a reference, payload or sublayer to an ``.abc`` asset says the same in its unresolved-asset line.
Where the plugin is there, an ``.abc`` shot is opened and checked as any USD layer."""

import shutil
from pathlib import Path

import pytest
from pxr import Sdf, Usd, UsdGeom

from usdksl.errors import UsdkslInputError
from usdksl.reading import composition, file_formats
from usdksl.reading.file_formats import missing_format_note, reads_format, require_file_format

from builders import box, define_mesh, snapshot, stretching_sheet
from .conftest import run_cli

#: The build these tests run on reads no Alembic (the usd-core wheel); a build with usdAbc skips them.
needs_no_alembic_plugin = pytest.mark.skipif(reads_format("shot.abc"),
                                             reason="this USD build has an Alembic file format plugin")
#: What pxr writes in Alembic's place: the first bytes of an Ogawa file, then nothing a reader can use.
NOT_READABLE_HERE = b"\xff\xffOgawa\x00\x01"


def alembic_shot(folder: Path, name="shot.abc") -> Path:
    path = folder / name
    path.write_bytes(NOT_READABLE_HERE)
    return path


def output_files(out: Path):
    return sorted(p.name for p in out.iterdir()) if out.exists() else []


@needs_no_alembic_plugin
def test_the_error_names_the_file_says_alembic_and_how_to_convert(tmp_path):
    shot = alembic_shot(tmp_path)
    with pytest.raises(UsdkslInputError) as raised:
        require_file_format(shot)
    line = raised.value.one_line()
    assert raised.value.file == str(shot) and raised.value.exit_code == 2
    assert line.startswith(f"{shot}: this USD build cannot read Alembic (it has no usdAbc file format plugin")
    assert f"(usdcat {shot} -o {tmp_path / 'shot.usdc'})" in line
    assert "\n" not in line


@needs_no_alembic_plugin
def test_any_case_and_paths_a_shell_must_quote(tmp_path):
    folder = tmp_path / "cloth caches"
    folder.mkdir()
    shot = alembic_shot(folder, "Shot.ABC")
    with pytest.raises(UsdkslInputError, match="cannot read Alembic") as raised:
        require_file_format(shot)
    assert f"(usdcat '{shot}' -o '{folder / 'Shot.usdc'}')" in str(raised.value)


def test_usd_files_pass(tmp_path):
    for name in ("shot.usda", "shot.usdc", "shot.usd", "props.usdz[scene.usdc]", "no_extension"):
        assert require_file_format(tmp_path / name) is None
        assert missing_format_note(name) == ""


@needs_no_alembic_plugin
def test_check_of_an_alembic_shot_is_one_line_exit_2_and_writes_nothing(tmp_path, capfd):
    shot = alembic_shot(tmp_path)
    out = tmp_path / "out"
    before = snapshot(tmp_path)
    result = run_cli("check", shot, "--out", out)
    assert result.exit_code == 2, result.stderr
    (line,) = result.stderr.strip().splitlines()
    assert line.startswith(f"usdksl: error: {shot}: this USD build cannot read Alembic")
    assert f"usdcat {shot} -o {tmp_path / 'shot.usdc'}" in line
    assert "Cannot determine file format" not in capfd.readouterr().err     # pxr's words are not printed
    assert output_files(out) == [] and snapshot(tmp_path) == before


def test_with_the_plugin_an_alembic_shot_is_opened_and_checked(tmp_path, monkeypatch, samples_dir):
    """The plugin simulated: the format lookup finds one, and the stage open reads the shot's USD twin in its
    place (a stand-in for usdAbc). The check goes on as for any layer: contacts found, files written."""
    shot = alembic_shot(tmp_path)
    shutil.copy(samples_dir / "fold.usda", tmp_path / "shot.usda")
    monkeypatch.setattr(file_formats, "reads_format", lambda path: True)
    opened = []
    open_usd = composition.open_stage_trapping_asset_warnings

    def open_through_the_plugin(file):
        opened.append(file)
        return open_usd(str(Path(file).with_suffix(".usda")))

    monkeypatch.setattr(composition, "open_stage_trapping_asset_warnings", open_through_the_plugin)
    assert require_file_format(shot) is None and missing_format_note("./body.abc") == ""
    out = tmp_path / "out"
    result = run_cli("check", shot, "--out", out)
    assert result.exit_code == 1, result.stderr    # the fold touches itself
    assert str(shot) in opened
    assert "shot.contacts.csv" in output_files(out)


def alembic_body(tmp_path, arc):
    """shot.usda: a deforming cloth /World/Cloth, a still box /World/Rock and, brought in by ``arc`` (reference,
    payload or sublayer), a body that is an Alembic file ./body.abc."""
    alembic_shot(tmp_path, "body.abc")
    path = tmp_path / "shot.usda"
    stage = Usd.Stage.CreateNew(str(path))
    stage.SetTimeCodesPerSecond(24)
    stage.SetStartTimeCode(1)
    stage.SetEndTimeCode(24)
    stage.SetDefaultPrim(UsdGeom.Xform.Define(stage, "/World").GetPrim())
    stretching_sheet(stage, "/World/Cloth")
    points, counts, indices = box(0.5)
    define_mesh(stage, "/World/Rock", points, counts, indices)
    stage.GetRootLayer().Save()
    del stage   # the arcs are authored on the layer alone: no stage composes them here, none warns
    layer = Sdf.Layer.FindOrOpen(str(path))
    if arc == "sublayer":
        layer.subLayerPaths.append("./body.abc")
    else:
        body = Sdf.CreatePrimInLayer(layer, "/World/Body")
        body.specifier = Sdf.SpecifierDef
        arcs = body.referenceList if arc == "reference" else body.payloadList
        arcs.Prepend(Sdf.Reference("./body.abc") if arc == "reference" else Sdf.Payload("./body.abc"))
    layer.Save()
    return path


@needs_no_alembic_plugin
@pytest.mark.parametrize("arc", ["reference", "payload", "sublayer"])
def test_an_alembic_asset_is_named_as_alembic_with_how_to_convert(tmp_path, arc):
    shot = alembic_body(tmp_path, arc)
    asker = "" if arc == "sublayer" else "/World/Body: "   # the shot's own sublayer: the file is named once
    out = tmp_path / "out"
    result = run_cli("check", shot, "--out", out)
    assert result.exit_code == 2, result.stderr
    (line,) = result.stderr.strip().splitlines()
    assert line.startswith(f"usdksl: error: {shot}: {asker}{arc} @./body.abc@ resolves but does not open: "
                           f"it is Alembic and this USD build has no usdAbc file format plugin")
    assert "(usdcat ./body.abc -o ./body.usdc)" in line
    assert line.endswith("nothing checked (--allow-missing-assets checks what composes)")
    assert output_files(out) == []

    allowed = run_cli("check", shot, "--out", out, "--allow-missing-assets")
    warnings = [w for w in allowed.stderr.splitlines() if "@./body.abc@" in w]
    assert len(warnings) == 1 and "it is Alembic" in warnings[0] and "usdcat ./body.abc" in warnings[0]


@needs_no_alembic_plugin
def test_a_missing_alembic_asset_is_missing_not_unreadable(tmp_path):
    shot = alembic_body(tmp_path, "reference")
    (tmp_path / "body.abc").unlink()
    result = run_cli("check", shot, "--out", tmp_path / "out")
    assert result.exit_code == 2
    assert "reference @./body.abc@ does not resolve;" in result.stderr and "Alembic" not in result.stderr
