"""A simulation blow-up in a shipped sample: named, checked anyway, the rest of the answer unchanged."""

import csv
import shutil
from pathlib import Path

import pytest
from click.testing import CliRunner
from pxr import Usd, UsdGeom, Vt

from usdksl.cli.main import main

SAMPLES = Path(__file__).resolve().parents[2] / "samples"
CLOTH = "/World/Cloth"
BLOWN_VERTEX = 220
BLOWN_TIME = 13.0


def run(*args):
    return CliRunner().invoke(main, ["check", *map(str, args)], catch_exceptions=False)


def blown_copy(tmp_path, height):
    """drape.usda with one cloth vertex moved to y = height at one time sample (the original is untouched)."""
    path = tmp_path / f"drape_blown_{height:g}.usda"
    shutil.copyfile(SAMPLES / "drape.usda", path)
    stage = Usd.Stage.Open(str(path))
    points = UsdGeom.Mesh(stage.GetPrimAtPath(CLOTH)).GetPointsAttr()
    value = list(points.Get(BLOWN_TIME))
    value[BLOWN_VERTEX] = (value[BLOWN_VERTEX][0], height, value[BLOWN_VERTEX][2])
    points.Set(Vt.Vec3fArray(value), BLOWN_TIME)
    stage.GetRootLayer().Save()
    return path


def blown_faces():
    stage = Usd.Stage.Open(str(SAMPLES / "drape.usda"))
    mesh = UsdGeom.Mesh(stage.GetPrimAtPath(CLOTH))
    counts = list(mesh.GetFaceVertexCountsAttr().Get())
    indices = list(mesh.GetFaceVertexIndicesAttr().Get())
    faces, start = set(), 0
    for face, count in enumerate(counts):
        if BLOWN_VERTEX in indices[start:start + count]:
            faces.add(face)
        start += count
    return faces


def rows_away(contacts_csv, faces):
    with open(contacts_csv, newline="") as handle:
        rows = list(csv.DictReader(handle))
    return {(r["prim_a"], r["face_a"], r["prim_b"], r["face_b"]): r["time"] for r in rows
            if not ((r["prim_a"] == CLOTH and int(r["face_a"]) in faces)
                    or (r["prim_b"] == CLOTH and int(r["face_b"]) in faces))}


@pytest.mark.parametrize("height", [1e3, 1e5, 1e7, 1e9])
def test_one_blown_vertex_is_named_and_changes_no_contact_away_from_it(tmp_path, height):
    reference_dir, blown_dir = tmp_path / "reference", tmp_path / "blown"
    reference = run(SAMPLES / "drape.usda", "--out", reference_dir)
    shot = blown_copy(tmp_path, height)
    blown = run(shot, "--out", blown_dir)
    assert reference.exit_code == blown.exit_code == 1
    warnings = [line for line in blown.stderr.splitlines() if "blows up" in line]
    assert len(warnings) == 1, blown.stderr
    assert CLOTH in warnings[0] and f"vertex {BLOWN_VERTEX} " in warnings[0]
    assert "between time 12 and 14" in warnings[0]
    assert "blows up" not in reference.stderr
    faces = blown_faces()
    away = rows_away(blown_dir / f"{shot.stem}.contacts.csv", faces)
    assert away == rows_away(reference_dir / "drape.contacts.csv", faces)
    assert away, "the sample's own contacts must be there"


def test_strict_refuses_a_blown_cache_with_one_line_and_writes_nothing(tmp_path):
    shot = blown_copy(tmp_path, 1e7)
    out = tmp_path / "out"
    result = run(shot, "--out", out, "--strict")
    assert result.exit_code == 2
    errors = [line for line in result.stderr.splitlines() if line.startswith("usdksl: error:")]
    assert len(errors) == 1 and CLOTH in errors[0] and f"vertex {BLOWN_VERTEX}" in errors[0]
    assert not out.exists() or not any(out.iterdir())
