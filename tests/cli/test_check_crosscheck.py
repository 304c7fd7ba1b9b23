"""`usdksl check --crosscheck`: Embree at every sample against the contacts just found."""

import dataclasses

import numpy as np
from click.testing import CliRunner

from usdksl import exit_codes
from usdksl.pipeline import check as pipeline
from usdksl.cli.main import main


def _run(args):
    return CliRunner().invoke(main, args, catch_exceptions=False)


def test_crosscheck_flag_writes_csv_and_agrees_on_fold(samples_dir, tmp_path):
    result = _run(["check", str(samples_dir / "fold.usda"), "--out", str(tmp_path), "--crosscheck"])
    assert result.exit_code == 1, result.output
    rows = (tmp_path / "fold.crosscheck.csv").read_text().splitlines()
    assert rows[0] == "time,prim_a,face_a,prim_b,face_b"
    assert len(rows) > 1, "the fold intersects itself at its last samples"
    # Every intersecting pair Embree saw has a first contact at or before its frame.
    contacts = {}
    for line in (tmp_path / "fold.contacts.csv").read_text().splitlines()[1:]:
        time, prim_a, face_a, prim_b, face_b = line.split(",")[:5]
        contacts[(prim_a, face_a, prim_b, face_b)] = float(time)
    for line in rows[1:]:
        time, *key = line.split(",")
        assert contacts[tuple(key)] <= float(time)
    assert "consistent" in result.output


def test_crosscheck_flag_exits_3_when_a_contact_is_missing(samples_dir, tmp_path, monkeypatch):
    first = _run(["check", str(samples_dir / "drape.usda"), "--out", str(tmp_path / "a"), "--crosscheck"])
    assert first.exit_code == 1, first.output
    seen = (tmp_path / "a" / "drape.crosscheck.csv").read_text().splitlines()[1]
    _, prim_a, face_a, prim_b, face_b = seen.split(",")
    original = pipeline.check_segment

    def drop_that_contact(*args, **kwargs):
        table = original(*args, **kwargs)
        paths = np.asarray(table.paths)
        keep = ~((paths[table.mesh_a] == prim_a) & (table.face_a == int(face_a)) &
                 (paths[table.mesh_b] == prim_b) & (table.face_b == int(face_b)))
        assert not keep.all(), "the pair Embree sees must be among the contacts"
        fields = {f.name: getattr(table, f.name) for f in dataclasses.fields(table)}
        for name, value in fields.items():
            if isinstance(value, np.ndarray) and value.shape[:1] == keep.shape:
                fields[name] = value[keep]
        return type(table)(**fields)

    monkeypatch.setattr(pipeline, "check_segment", drop_that_contact)
    result = _run(["check", str(samples_dir / "drape.usda"), "--out", str(tmp_path / "b"), "--crosscheck"])
    assert result.exit_code == exit_codes.CROSSCHECK_DISAGREES == 3, result.output
    assert f"{prim_a}" in result.output and "error" in result.output


def test_without_flag_no_crosscheck_file(samples_dir, tmp_path):
    result = _run(["check", str(samples_dir / "clean.usda"), "--out", str(tmp_path)])
    assert result.exit_code == 0, result.output
    assert not (tmp_path / "clean.crosscheck.csv").exists()
