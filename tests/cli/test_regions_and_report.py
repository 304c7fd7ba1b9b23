"""What ``usdksl check`` writes about regions, and ``--report FILE.html`` from the command line: regions.csv's
columns, the region column of contacts.csv, the JSON's regions, the page of one shot and of several (a shot that
could not be checked on it with its error), the console line linking the page, and exit 2 before any check when
the report's libraries are missing."""

import csv
import json
import re
from pathlib import Path

from click.testing import CliRunner

from usdksl.cli.main import main
from usdksl.regions.csv_file import REGION_COLUMNS

REQUIRED_REGION_COLUMNS = ("region,prim_a,prim_b,kind,first_time,last_time,first_frame,last_frame,face_pairs,"
                           "max_depth,max_depth_time,center_x,center_y,center_z").split(",")


def _run(*args):
    return CliRunner().invoke(main, ["check", *map(str, args)])


def _rows(path: Path):
    with open(path, newline="") as handle:
        return list(csv.DictReader(handle))


def test_regions_csv_json_and_contacts_name_the_same_regions(samples_dir, tmp_path):
    result = _run(samples_dir / "pass_through.usda", "--out", tmp_path, "--json", tmp_path / "shot.json")
    assert result.exit_code == 1, result.output
    header = (tmp_path / "pass_through.regions.csv").read_text().splitlines()[0].split(",")
    assert header[:len(REQUIRED_REGION_COLUMNS)] == REQUIRED_REGION_COLUMNS == list(REGION_COLUMNS)
    regions = _rows(tmp_path / "pass_through.regions.csv")
    contacts = _rows(tmp_path / "pass_through.contacts.csv")
    assert regions and [int(row["region"]) for row in regions] == list(range(1, len(regions) + 1))
    # every contact names a region, and each region counts its own contacts
    per_region = {}
    for row in contacts:
        per_region[int(row["region"])] = per_region.get(int(row["region"]), 0) + 1
    assert per_region == {int(row["region"]): int(row["face_pairs"]) for row in regions}
    for row in regions:
        assert float(row["first_time"]) <= float(row["last_time"]) and float(row["max_depth"]) > 0
        assert row["depth_measure"] == "penetration"       # a mesh through a closed box
    document = json.loads((tmp_path / "shot.json").read_text())
    assert [region["region"] for region in document["regions"]] == [int(row["region"]) for row in regions]
    assert [contact["region"] for contact in document["contacts"]] == [int(row["region"]) for row in contacts]
    for region in document["regions"]:       # the faces of each side, as the contacts name them
        rows = [row for row in contacts if int(row["region"]) == region["region"]]
        assert region["face_ids_a"] == sorted({int(row["face_a"]) for row in rows})
        assert region["face_ids_b"] == sorted({int(row["face_b"]) for row in rows})
        assert (region["faces_a"], region["faces_b"]) == (len(region["face_ids_a"]), len(region["face_ids_b"]))
    assert f"{len(regions)} problem" in result.stderr.splitlines()[-1]


def test_a_clean_shot_writes_a_header_only_regions_csv(samples_dir, tmp_path):
    result = _run(samples_dir / "clean.usda", "--out", tmp_path)
    assert result.exit_code == 0, result.output
    assert (tmp_path / "clean.regions.csv").read_text().splitlines()[0].split(",")[:14] == REQUIRED_REGION_COLUMNS
    assert _rows(tmp_path / "clean.regions.csv") == []


def test_report_of_one_shot_is_linked_from_the_console(samples_dir, tmp_path):
    page = tmp_path / "report" / "run.html"
    result = _run(samples_dir / "drape.usda", "--out", tmp_path / "out", "--report", page)
    assert result.exit_code == 1, result.output
    text = page.read_text()
    assert "drape.usda" in text and "<script" not in text
    assert len(re.findall(r'<figure class="region"', text)) == len(_rows(tmp_path / "out" / "drape.regions.csv"))
    assert f"usdksl: report: {page.resolve().as_uri()}" in result.stderr.splitlines()


def test_report_of_several_shots_shows_each_and_a_failed_one(samples_dir, tmp_path):
    missing = tmp_path / "missing.usda"
    page = tmp_path / "run.html"
    result = _run(samples_dir / "fold.usda", missing, samples_dir / "clean.usda", "--out", tmp_path / "out",
                  "--report", page)
    assert result.exit_code == 2, result.output
    text = page.read_text()
    positions = [text.find(name) for name in ("fold.usda", "missing.usda", "clean.usda")]
    assert -1 not in positions and positions == sorted(positions)      # in the order given
    assert "no such file" in text
    assert result.stderr.splitlines()[-1] == f"usdksl: report: {page.resolve().as_uri()}"


def test_report_without_its_libraries_is_refused_before_any_check(samples_dir, tmp_path, monkeypatch):
    import usdksl.reports.pictures as pictures
    from usdksl.errors import UsdkslUsageError

    def missing():
        raise UsdkslUsageError(pictures.INSTALL_HINT)

    monkeypatch.setattr(pictures, "require_pyvista", missing)
    result = _run(samples_dir / "fold.usda", "--out", tmp_path / "out", "--report", tmp_path / "run.html")
    assert result.exit_code == 2
    assert "pip install 'usdksl[report]'" in result.stderr
    assert not (tmp_path / "out").exists() and not (tmp_path / "run.html").exists()
