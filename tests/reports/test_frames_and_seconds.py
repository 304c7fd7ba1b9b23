"""Frames and seconds beside time codes (usdksl.clock), end to end through ``usdksl check``, on stages whose
time codes are not frames: a start at 1001, 48 time codes a second played at 24 frames a second."""

import csv
import json

import pytest
from click.testing import CliRunner

from usdksl.cli.main import main
from usdksl.clock import StageClock, console_number

from builders import QUAD_POINTS, add_mesh, falling_quad_samples, new_stage

START, TCPS, FPS = 1001.0, 48.0, 24.0
#: The falling quad goes from y = 1 at START to y = -1 at START + 16: it reaches the floor at START + 8.
CONTACT_TIME = START + 8.0


def _shot(tmp_path, start=START, tcps=TCPS, fps=FPS, author_start=True):
    path = tmp_path / "shot.usda"
    stage = new_stage(path, tcps=tcps, fps=fps, start=start, end=start + 16.0)
    if not author_start:
        stage.GetRootLayer().ClearStartTimeCode()
    add_mesh(stage, "/World/Floor", QUAD_POINTS + [-0.5, 0.0, -0.5])
    add_mesh(stage, "/World/Falling", None, samples=falling_quad_samples(times=(START, START + 16.0)))
    stage.GetRootLayer().Save()
    return path


def _rows(path):
    with open(path, newline="") as handle:
        return list(csv.DictReader(handle))


def test_contacts_and_summary_give_frames_and_seconds_since_the_stage_start(tmp_path):
    shot = _shot(tmp_path)
    result = CliRunner().invoke(main, ["check", str(shot), "--out", str(tmp_path / "out"), "--json",
                                       str(tmp_path / "out" / "shot.json")])
    assert result.exit_code == 1, result.output
    rows = _rows(tmp_path / "out" / "shot.contacts.csv")
    assert rows and list(rows[0])[:6] == ["time", "prim_a", "face_a", "prim_b", "face_b", "kind"]
    for row in rows:
        time = float(row["time"])
        assert time == pytest.approx(CONTACT_TIME, abs=1e-6)
        assert float(row["seconds"]) == (time - START) / TCPS           # repr round-trips exactly
        assert float(row["frame"]) == (time - START) / TCPS * FPS
        assert float(row["frame"]) == pytest.approx(4.0, abs=1e-6)      # 8 time codes = 1/6 s = 4 frames
    summary = _rows(tmp_path / "out" / "shot.summary.csv")
    assert len(summary) == 1
    first = float(summary[0]["first_contact_time"])
    assert float(summary[0]["first_contact_frame"]) == (first - START) / TCPS * FPS
    assert float(summary[0]["first_contact_seconds"]) == (first - START) / TCPS
    document = json.loads((tmp_path / "out" / "shot.json").read_text())
    assert document["clock"] == {"startTimeCode": START, "timeCodesPerSecond": TCPS, "framesPerSecond": FPS}
    assert document["contacts"][0]["frame"] == float(rows[0]["frame"])
    # the console says frames, rounded
    assert f"first at frame {console_number(float(rows[0]['frame']))} (t=" in result.stderr


def test_a_stage_without_start_counts_frames_from_time_code_zero(tmp_path):
    shot = _shot(tmp_path, author_start=False)
    result = CliRunner().invoke(main, ["check", str(shot), "--out", str(tmp_path / "out")])
    assert result.exit_code == 1, result.output
    row = _rows(tmp_path / "out" / "shot.contacts.csv")[0]
    assert float(row["frame"]) == float(row["time"]) / TCPS * FPS
    assert float(row["frame"]) == pytest.approx(CONTACT_TIME / 2, abs=1e-6)


def test_console_numbers_are_rounded_to_a_thousandth():
    assert console_number(29.998876546636872) == "29.999"
    assert console_number(12.0) == "12"
    assert console_number(-0.0001) == "0"
    assert StageClock(10.0, 30.0, 60.0).describe(11.5) == "frame 3 (t=11.5)"
