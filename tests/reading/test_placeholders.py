"""Empty placeholder meshes are skipped with one warning naming them; the rest of the shot is checked."""

import pytest

from usdksl.reading.loader import load_shot

from builders import EMPTY_KINDS, sha256 as file_digest, shot_with_empty_mesh
from .conftest import run_cli


@pytest.mark.parametrize("contact", [True, False], ids=["contact", "clean"])
@pytest.mark.parametrize("empty_kind", EMPTY_KINDS)
def test_empty_mesh_beside_good_ones_is_skipped_with_one_warning(tmp_path, empty_kind, contact):
    path = tmp_path / "layout.usda"
    placeholder = shot_with_empty_mesh(path, empty_kind, contact=contact)
    digest = file_digest(path)
    result = run_cli("check", path, "--out", tmp_path / "out")
    assert result.exit_code == (1 if contact else 0), result.stderr
    warnings = [line for line in result.stderr.splitlines() if placeholder in line]
    assert len(warnings) == 1, result.stderr
    assert warnings[0].startswith("usdksl: warning: ") and str(path) in warnings[0]
    assert "empty mesh" in warnings[0] and warnings[0].endswith("skipped")
    assert "usdksl: error" not in result.stderr
    assert (tmp_path / "out" / "layout.contacts.csv").is_file()
    assert placeholder not in (tmp_path / "out" / "layout.contacts.csv").read_text()
    assert file_digest(path) == digest


def test_loader_reports_the_skipped_mesh_in_shot_warnings(tmp_path):
    path = tmp_path / "layout.usda"
    placeholder = shot_with_empty_mesh(path, "no points")
    shot = load_shot(path)
    assert {mesh.path for mesh in shot.meshes} == {"/World/Sheet", "/World/Box"}
    assert len(shot.warnings) == 1 and placeholder in shot.warnings[0]


def test_info_warns_about_the_placeholder_and_lists_the_rest(tmp_path):
    path = tmp_path / "layout.usda"
    placeholder = shot_with_empty_mesh(path, "no faces")
    result = run_cli("info", path)
    assert result.exit_code == 0, result.stderr
    assert placeholder in result.stderr and placeholder not in result.stdout
    assert "/World/Box" in result.stdout
