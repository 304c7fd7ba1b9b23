"""Last contacts (usdksl.checking.last_contact): the first contacts of the shot played backwards."""

import csv

import numpy as np
import pytest
from click.testing import CliRunner

from usdksl.cli.main import main
from usdksl.crosscheck.shot import _FaceNumbering, intersecting_face_pairs
from usdksl.pipeline import CheckOptions, check_shot
from usdksl.reading.loader import load_shot

from builders import QUAD_POINTS, add_mesh, new_stage

#: The core reports a time early (first) or late (last) by at most its tolerance of a sample interval.
INTERVAL_TOLERANCE = 1e-6


def _floor_and_mover(tmp_path, heights):
    """A static floor quad at y = 0 and a quad above it at ``heights`` {time: y}."""
    path = tmp_path / "shot.usda"
    stage = new_stage(path, start=min(heights), end=max(heights))
    add_mesh(stage, "/World/Floor", QUAD_POINTS + [-0.5, 0.0, -0.5])
    add_mesh(stage, "/World/Mover", None, samples={t: QUAD_POINTS + [0, y, 0] for t, y in heights.items()})
    stage.GetRootLayer().Save()
    return str(path)


def _check(path, **options):
    return check_shot(path, CheckOptions(last_contact=True, **options))


def test_a_quad_passing_down_and_back_up_first_touches_going_down_and_last_coming_up(tmp_path):
    result = _check(_floor_and_mover(tmp_path, {1.0: 1.0, 11.0: -1.0, 21.0: 1.0}))
    assert result.table.count == 1
    interval = 10.0
    assert result.table.time[0] == pytest.approx(6.0, abs=INTERVAL_TOLERANCE * interval)
    assert result.table.last_time[0] == pytest.approx(16.0, abs=INTERVAL_TOLERANCE * interval)
    assert result.table.last_time[0] >= 16.0 - 1e-12          # late, never early
    assert result.table.summary()[0]["last_contact_time"] == result.table.last_time[0]


def test_a_quad_coming_to_rest_on_the_floor_touches_until_the_end(tmp_path):
    result = _check(_floor_and_mover(tmp_path, {1.0: 1.0, 10.0: 0.0, 24.0: 0.0}))
    assert result.table.count == 1
    assert result.table.time[0] == pytest.approx(10.0, abs=INTERVAL_TOLERANCE * 9.0)
    assert result.table.last_time[0] == 24.0


def test_without_the_option_there_is_no_last_contact(tmp_path):
    result = check_shot(_floor_and_mover(tmp_path, {1.0: 1.0, 11.0: -1.0, 21.0: 1.0}))
    assert result.table.last_time is None
    assert "last_time" not in next(iter(result.files.values())).splitlines()[0]


@pytest.mark.parametrize("name", ["fold", "drape"])
def test_every_face_pair_intersecting_at_a_sample_is_in_contact_between_its_first_and_last(samples_dir, name):
    """Embree at every sample is the independent oracle: a face pair properly crossing at sample f has its
    first contact at or before f and its last at or after f."""
    path = str(samples_dir / f"{name}.usda")
    result = _check(path)
    shot = load_shot(path)
    pairs = result.plan.pairs.tolist()
    times, keys, numbering = intersecting_face_pairs(shot.meshes, shot.times, pairs)
    assert keys.size, "the sample should cross itself at some sample"
    table = result.table
    row_keys = numbering.pair_keys(table.mesh_a, table.face_a, table.mesh_b, table.face_b)
    row_of = {key: row for row, key in enumerate(row_keys.tolist())}
    rows = np.array([row_of[key] for key in keys.tolist()])            # KeyError: a crossing without a contact
    assert np.all(table.time[rows] <= times)
    assert np.all(table.last_time[rows] >= times)
    assert np.all(table.last_time >= table.time)


def test_kinetic_and_brute_force_give_the_same_last_contacts(samples_dir):
    path = str(samples_dir / "fold.usda")
    ksl, brute = _check(path), _check(path, method="brute")
    assert np.array_equal(ksl.table.pair_rows(), brute.table.pair_rows())
    assert np.array_equal(ksl.table.last_time, brute.table.last_time)


def test_command_writes_last_contact_columns(samples_dir, tmp_path):
    result = CliRunner().invoke(main, ["check", str(samples_dir / "fold.usda"), "--out", str(tmp_path),
                                       "--last-contact"])
    assert result.exit_code == 1, result.output
    with open(tmp_path / "fold.contacts.csv", newline="") as handle:
        rows = list(csv.DictReader(handle))
    assert len(rows) == 132 and {(row["prim_a"], row["prim_b"]) for row in rows} == {("/World/Strip", "/World/Strip")}
    assert list(rows[0])[-4:] == ["last_time", "last_frame", "last_seconds", "region"]
    assert all(float(row["last_time"]) >= float(row["time"]) for row in rows)
    # fold.usda starts at 1, 24 time codes and 24 frames a second: frames are the time codes
    assert all(float(row["last_frame"]) == float(row["last_time"]) for row in rows)
    assert all(float(row["last_seconds"]) == float(row["last_time"]) / 24.0 for row in rows)
    with open(tmp_path / "fold.summary.csv", newline="") as handle:
        summary = list(csv.DictReader(handle))
    assert float(summary[0]["last_contact_time"]) == max(float(row["last_time"]) for row in rows)


def test_last_contacts_are_the_same_for_any_thread_count(samples_dir):
    path = str(samples_dir / "fold.usda")
    one, two = _check(path, threads=1), _check(path, threads=2)
    assert np.array_equal(one.table.pair_rows(), two.table.pair_rows())
    assert np.array_equal(one.table.last_time, two.table.last_time)
