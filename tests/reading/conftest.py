"""Fixtures of the reading tests: run ``usdksl check`` and read its CSV output."""

import csv

import pytest
from click.testing import CliRunner

from usdksl.cli.main import main


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
