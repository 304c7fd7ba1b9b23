"""The override layer's customLayerData says what produced it: the usdksl version, the settings and the shot's hash."""

import hashlib
import json

from click.testing import CliRunner
from pxr import Sdf, Usd

from usdksl.cli.main import main
from usdksl.reports.override import PROVENANCE_KEY

from builders import add_mesh, falling_quad_samples, new_stage


def _run(*args):
    return CliRunner().invoke(main, [str(arg) for arg in args])


def _shot(tmp_path):
    """A quad falling through a still one: contacts, so the layer authors results too."""
    path = tmp_path / "shot.usda"
    stage = new_stage(path)
    add_mesh(stage, "/World/Cloth", None, samples=falling_quad_samples())
    add_mesh(stage, "/World/Floor", falling_quad_samples()[1.0] - [0, 1.0, 0])
    stage.GetRootLayer().Save()
    return path


def test_the_layer_names_settings_and_shot_hash(tmp_path):
    shot = _shot(tmp_path)
    result = _run("check", shot, "--out", tmp_path / "out", "--prims", "/World/*", "--time-range", 1, 24)
    assert result.exit_code == 1, result.output
    layer = Sdf.Layer.FindOrOpen(str(tmp_path / "out" / "shot.usdksl.usda"))
    data = layer.customLayerData[PROVENANCE_KEY]
    from usdksl.version import package_version
    assert data["version"] == package_version() != ""   # the version the build recorded
    assert data["shotSha256"] == hashlib.sha256(shot.read_bytes()).hexdigest()
    settings = data["settings"]
    assert settings["method"] == "ksl" and settings["self"] is True
    assert list(settings["prims"]) == ["/World/*"] and list(settings["time_range"]) == [1.0, 24.0]
    # the farm chunk's manifest names the same hash
    manifest = json.loads((tmp_path / "out" / "shot.usdksl-run.json").read_text())
    assert manifest["shot_sha256"] == data["shotSha256"]
    # usdview reads it through the stage as well
    stage = Usd.Stage.Open(str(tmp_path / "out" / "shot.usdksl.usda"))
    assert stage.GetRootLayer().customLayerData[PROVENANCE_KEY]["shotSha256"] == data["shotSha256"]


def test_a_setting_that_is_none_is_left_out(tmp_path):
    shot = _shot(tmp_path)
    assert _run("check", shot, "--out", tmp_path / "out").exit_code == 1
    settings = Sdf.Layer.FindOrOpen(str(tmp_path / "out" / "shot.usdksl.usda")).customLayerData[
        PROVENANCE_KEY]["settings"]
    assert "time_range" not in settings and list(settings["prims"]) == []


def test_two_runs_write_byte_identical_layers(tmp_path):
    shot = _shot(tmp_path)
    for out in ("a", "b"):
        assert _run("check", shot, "--out", tmp_path / out).exit_code == 1
    first = (tmp_path / "a" / "shot.usdksl.usda").read_bytes()
    assert first == (tmp_path / "b" / "shot.usdksl.usda").read_bytes()
    assert b"shotSha256" in first


def test_the_hash_read_beside_the_check_is_the_file_hash_and_a_missing_file_fails_when_asked(tmp_path):
    """A check hashes its shot on a thread of its own while it loads it (usdksl.reports.shot_hash)."""
    import pytest

    from usdksl.reports import shot_hash

    big = tmp_path / "blocks.bin"
    big.write_bytes(bytes(range(256)) * (3 * shot_hash._HASH_BLOCK_BYTES // 256 + 7))   # several blocks and a rest
    assert shot_hash.file_sha256_in_background(big).result() == hashlib.sha256(big.read_bytes()).hexdigest()
    missing = shot_hash.file_sha256_in_background(tmp_path / "missing.usda")
    with pytest.raises(FileNotFoundError):
        missing.result()
