"""Fixtures of the reading tests: new stages, and ``usdksl check`` with its CSV output read back."""

import csv

import pytest
from click.testing import CliRunner

from builders import bare_stage
from usdksl.cli.main import main


@pytest.fixture
def build(tmp_path):
    """build(name, fill) -> path: a new stage, fill(stage) authors it, then it is saved."""
    def make(name, fill):
        path = tmp_path / name
        stage = bare_stage(path)
        fill(stage)
        stage.GetRootLayer().Save()
        return str(path)
    return make


def run_cli(*args):
    """CliRunner result of ``usdksl *args`` (stderr kept apart)."""
    return CliRunner().invoke(main, [str(arg) for arg in args])


def contact_rows(csv_path):
    """{(prim_a, face_a, prim_b, face_b): time} of a contacts.csv."""
    with open(csv_path, newline="") as stream:
        return {(row["prim_a"], int(row["face_a"]), row["prim_b"], int(row["face_b"])): float(row["time"])
                for row in csv.DictReader(stream)}


def summary_rows(csv_path):
    """{(prim_a, prim_b): (first_contact_time, face_pairs)} of a summary.csv."""
    with open(csv_path, newline="") as stream:
        return {(row["prim_a"], row["prim_b"]): (float(row["first_contact_time"]), int(row["face_pairs"]))
                for row in csv.DictReader(stream)}


@pytest.fixture
def check(tmp_path):
    """check(shot, *options) -> (result, contacts {pair: time}, summary {mesh pair: (time, count)})."""
    def run(shot, *options):
        out = tmp_path / "out"
        result = run_cli("check", shot, "--out", out, *options)
        stem = shot.stem if hasattr(shot, "stem") else str(shot).rsplit("/", 1)[-1].rsplit(".", 1)[0]
        contacts = out / f"{stem}.contacts.csv"
        summary = out / f"{stem}.summary.csv"
        return (result, contact_rows(contacts) if contacts.exists() else None,
                summary_rows(summary) if summary.exists() else None)
    return run
