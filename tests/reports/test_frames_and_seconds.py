"""Frames and seconds beside time codes (usdksl.clock), end to end through ``usdksl check``: frames are numbered
on the stage's own timeline as usdview, Maya and Houdini number them (a shot starting at 1001 starts at frame
1001), ``frame = time * fps / tcps`` and ``seconds = time / tcps``, whatever the stage's startTimeCode."""

import csv
import json

import pytest
from click.testing import CliRunner
from pxr import Sdf

from usdksl.cli.main import main
from usdksl.clock import StageClock, console_number

from builders import QUAD_POINTS, add_mesh, falling_quad_samples, new_stage

START, TCPS, FPS = 1001.0, 48.0, 24.0
#: The falling quad goes from y = 1 at START to y = -1 at START + 16: it reaches the floor at START + 8.
CONTACT_TIME = START + 8.0


def _shot(tmp_path, start=START, tcps=TCPS, fps=FPS, author_start=True, contact=None, fall_from=None,
          name="shot"):
    """A floor quad and a quad falling through it, reaching it at ``contact`` (time codes; default
    CONTACT_TIME): it falls from y = 1 at ``fall_from`` (default: the stage's ``start``) to y = -1 at
    twice as far past the contact, where the stage ends."""
    contact = CONTACT_TIME if contact is None else contact
    fall_from = start if fall_from is None else fall_from
    end = fall_from + 2.0 * (contact - fall_from)
    path = tmp_path / f"{name}.usda"
    stage = new_stage(path, tcps=tcps, fps=fps, start=start, end=end)
    if not author_start:
        stage.GetRootLayer().ClearStartTimeCode()
    add_mesh(stage, "/World/Floor", QUAD_POINTS + [-0.5, 0.0, -0.5])
    add_mesh(stage, "/World/Falling", None, samples=falling_quad_samples(times=(fall_from, end)))
    stage.GetRootLayer().Save()
    return path


def _rows(path):
    with open(path, newline="") as handle:
        return list(csv.DictReader(handle))


def _check(shot, out, *extra):
    result = CliRunner().invoke(main, ["check", str(shot), "--out", str(out), *map(str, extra)])
    assert result.exit_code == 1, result.output
    return result


def test_contacts_and_summary_give_frames_and_seconds_on_the_stage_timeline(tmp_path):
    shot = _shot(tmp_path)
    result = _check(shot, tmp_path / "out", "--json", tmp_path / "out" / "shot.json")
    rows = _rows(tmp_path / "out" / "shot.contacts.csv")
    assert rows and list(rows[0])[:6] == ["time", "prim_a", "face_a", "prim_b", "face_b", "kind"]
    for row in rows:
        time = float(row["time"])
        assert time == pytest.approx(CONTACT_TIME, abs=1e-6)
        assert float(row["seconds"]) == time / TCPS                     # repr round-trips exactly
        assert float(row["frame"]) == time * (FPS / TCPS)
        assert float(row["frame"]) == pytest.approx(504.5, abs=1e-6)    # t = 1009 at 48 codes/s = 504.5 frames
    summary = _rows(tmp_path / "out" / "shot.summary.csv")
    assert len(summary) == 1
    first = float(summary[0]["first_contact_time"])
    assert float(summary[0]["first_contact_frame"]) == first * (FPS / TCPS)
    assert float(summary[0]["first_contact_seconds"]) == first / TCPS
    document = json.loads((tmp_path / "out" / "shot.json").read_text())
    assert document["clock"] == {"timeCodesPerSecond": TCPS, "framesPerSecond": FPS}
    assert document["contacts"][0]["frame"] == float(rows[0]["frame"])
    assert document["contacts"][0]["seconds"] == float(rows[0]["seconds"])
    assert document["summary"][0]["first_contact_frame"] == float(summary[0]["first_contact_frame"])
    # the console says frames, rounded
    assert f"first at frame {console_number(float(rows[0]['frame']))} (t=" in result.stderr
    assert "first at frame 504.5 (t=1009)" in result.stderr


def test_a_shot_starting_at_1001_reports_the_frames_an_artist_scrubs_to(tmp_path):
    shot = _shot(tmp_path, start=1001.0, tcps=24.0, fps=24.0, contact=1031.5)
    result = _check(shot, tmp_path / "out", "-v")
    assert "first at frame 1031.5 (t=1031.5)" in result.stderr
    rows = _rows(tmp_path / "out" / "shot.contacts.csv")
    assert rows
    for row in rows:
        time = float(row["time"])
        assert time == pytest.approx(1031.5, abs=1e-9)
        assert float(row["frame"]) == time                               # equal rates: the frame is the time code
        assert float(row["frame"]) == pytest.approx(1031.5, abs=1e-9)
        assert float(row["seconds"]) == time / 24.0
        assert float(row["seconds"]) == pytest.approx(1031.5 / 24.0, abs=1e-9)
    summary = _rows(tmp_path / "out" / "shot.summary.csv")
    assert float(summary[0]["first_contact_frame"]) == float(summary[0]["first_contact_time"])


def test_48_time_codes_a_second_at_24_fps_halves_the_time_codes(tmp_path):
    shot = _shot(tmp_path, start=0.0, tcps=48.0, fps=24.0, contact=48.0)
    result = _check(shot, tmp_path / "out")
    assert "first at frame 24 (t=48)" in result.stderr
    row = _rows(tmp_path / "out" / "shot.contacts.csv")[0]
    assert float(row["time"]) == pytest.approx(48.0, abs=1e-9)
    assert float(row["frame"]) == float(row["time"]) * 0.5
    assert float(row["frame"]) == pytest.approx(24.0, abs=1e-9)
    assert float(row["seconds"]) == pytest.approx(1.0, abs=1e-12)


def test_the_start_time_code_moves_no_frame(tmp_path):
    # One animation (falling from t = 10, touching at t = 17.25) on stages that start at 10, at 0 and
    # nowhere: the frames are the time codes (24/24) in all three, never the time since the start.
    outputs = {}
    for name, start, authored in (("at10", 10.0, True), ("at0", 0.0, True), ("unset", 10.0, False)):
        shot = _shot(tmp_path, start=start, tcps=24.0, fps=24.0, contact=17.25, fall_from=10.0,
                     author_start=authored, name=name)
        result = _check(shot, tmp_path / name)
        assert "first at frame 17.25 (t=17.25)" in result.stderr, result.stderr
        rows = _rows(tmp_path / name / f"{name}.contacts.csv")
        assert rows and all(float(row["frame"]) == float(row["time"]) for row in rows)
        assert all(float(row["seconds"]) == float(row["time"]) / 24.0 for row in rows)
        outputs[name] = [(row["time"], row["frame"], row["seconds"]) for row in rows]
    assert outputs["at10"] == outputs["at0"] == outputs["unset"]


def test_the_clock_converts_time_codes_without_the_start():
    shot_1001 = StageClock.from_metadata({"startTimeCode": 1001.0, "timeCodesPerSecond": 24.0,
                                          "framesPerSecond": 24.0})
    assert shot_1001.frame(1031.5) == 1031.5
    assert float(shot_1001.seconds(1031.5)) == 1031.5 / 24.0
    assert shot_1001.describe(1031.5) == "frame 1031.5 (t=1031.5)"
    doubled = StageClock.from_metadata({"startTimeCode": 7.0, "timeCodesPerSecond": 48.0, "framesPerSecond": 24.0})
    assert doubled.frame(48.0) == 24.0 and float(doubled.seconds(48.0)) == 1.0
    assert doubled.frames([0.0, 48.0, 1001.0]).tolist() == [0.0, 24.0, 500.5]
    assert StageClock.from_metadata({}).frame(30.0) == 30.0       # 24 and 24 when nothing is said


def test_frames_per_second_stands_in_for_an_unauthored_time_code_rate(tmp_path):
    shot = _shot(tmp_path, start=1001.0, tcps=30.0, fps=30.0, contact=1016.0)
    layer = Sdf.Layer.FindOrOpen(str(shot))
    layer.ClearTimeCodesPerSecond()
    layer.Save()
    result = _check(shot, tmp_path / "out")
    assert "first at frame 1016 (t=1016)" in result.stderr
    row = _rows(tmp_path / "out" / "shot.contacts.csv")[0]
    assert float(row["frame"]) == float(row["time"])
    assert float(row["seconds"]) == float(row["time"]) / 30.0


def test_equal_rates_give_the_time_code_bit_for_bit():
    # time / rate * rate is off by an ulp for some times; frames must equal time codes exactly then.
    # (1900.9273926518706 / 24 * 24 is one of them.)
    times = [1900.9273926518706, 811.3979373379394, 250.38593927054697, 1939.774553984539, 1031.5, 0.1 + 0.2]
    for rate in (24.0, 25.0, 30.0, 23.976):
        clock = StageClock(time_codes_per_second=rate, frames_per_second=rate)
        assert clock.frames(times).tolist() == times
        assert [clock.frame(time) for time in times] == times


def test_console_numbers_are_rounded_to_a_thousandth():
    assert console_number(29.998876546636872) == "29.999"
    assert console_number(12.0) == "12"
    assert console_number(-0.0001) == "0"
    assert StageClock(30.0, 60.0).describe(11.5) == "frame 23 (t=11.5)"
