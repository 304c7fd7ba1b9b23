"""Layers: a rate mismatch that makes USD rescale times is warned about; resolvable asset paths open."""

import pytest
from pxr import UsdUtils

from usdksl.reading.loader import load_shot
from usdksl.reading.layer_rates import rescaled_layers

from builders import falling_instancer, sha256 as file_digest, wrapper_around_cache
from .conftest import contact_rows, run_cli


@pytest.mark.parametrize("reference", [False, True], ids=["sublayer", "reference"])
def test_wrapper_without_a_rate_rescales_the_cache_with_a_warning(tmp_path, reference):
    wrapper, cache = wrapper_around_cache(tmp_path, cache_rate=30.0, wrapper_rate=None, reference=reference)
    shot = load_shot(wrapper)
    assert shot.mesh("/World/Box").times.tolist() == [8.0, 16.0]          # USD's rule: 10, 20 x 24/30
    assert len(shot.warnings) == 1
    warning = shot.warnings[0]
    assert str(cache) in warning and "30" in warning and "24" in warning and "0.8" in warning
    result = run_cli("check", wrapper, "--out", tmp_path / "out")
    assert result.exit_code == 1, result.stderr
    lines = [line for line in result.stderr.splitlines() if "timeCodesPerSecond" in line]
    assert lines == [f"usdksl: warning: {warning}"]
    # the cache's own contacts, at its times in the wrapper's time codes (24/30 of them)
    alone = run_cli("check", cache, "--out", tmp_path / "alone")
    assert alone.exit_code == 1, alone.stderr
    rescaled = contact_rows(tmp_path / "out" / "shot.contacts.csv")
    own = contact_rows(tmp_path / "alone" / "cache.contacts.csv")
    assert set(rescaled) == set(own) and own
    assert all(rescaled[pair] == pytest.approx(0.8 * own[pair], rel=1e-12) for pair in own), (rescaled, own)


def test_matching_rates_and_the_cache_alone_give_no_warning(tmp_path):
    wrapper, cache = wrapper_around_cache(tmp_path, cache_rate=30.0, wrapper_rate=30.0)
    assert load_shot(wrapper).warnings == [] and load_shot(cache).warnings == []
    assert load_shot(wrapper).mesh("/World/Box").times.tolist() == [10.0, 20.0]
    assert rescaled_layers(load_shot(cache).stage, []) == {}


def test_package_relative_path_opens_and_missing_ones_fail_in_one_line(tmp_path):
    scene = tmp_path / "scene.usda"
    falling_instancer(scene)
    package = tmp_path / "props.usdz"
    assert UsdUtils.CreateNewUsdzPackage(str(scene), str(package))
    digest = file_digest(package)
    inner = f"{package}[scene.usda]"
    result = run_cli("check", inner, "--out", tmp_path / "out")
    assert result.exit_code == 1, result.stderr
    unpacked = run_cli("check", scene, "--out", tmp_path / "unpacked")
    assert unpacked.exit_code == 1, unpacked.stderr
    assert ((tmp_path / "out" / "props.scene.contacts.csv").read_bytes()
            == (tmp_path / "unpacked" / "scene.contacts.csv").read_bytes())
    assert (tmp_path / "out" / "props.scene.usdksl.usda").is_file()
    assert file_digest(package) == digest
    for missing in (f"{package}[nope.usda]", str(tmp_path / "nope.usda")):
        failed = run_cli("check", missing, "--out", tmp_path / "out2")
        assert failed.exit_code == 2
        assert failed.stderr.strip().splitlines() == [f"usdksl: error: {missing}: no such file"]
