"""The progress bar of one check: a fraction that never goes down however the core's threads report, the time
elapsed and left (from an injected clock), at most REDRAWS_PER_SECOND redraws a second, nothing off a terminal."""

import io
import re

import pytest

from usdksl.pipeline import progress as progress_module
from usdksl.pipeline.progress import (ETA_MIN_FRACTION, REDRAW_INTERVAL_SECONDS, REDRAWS_PER_SECOND, Progress,
                                      duration_text, remaining_seconds)

PERCENT = re.compile(r"\] +(\d+)%")


class FakeTty(io.StringIO):
    def isatty(self):
        return True


def ticking(step=1.0, start=0.0):
    """A clock that moves ``step`` seconds at every reading: every call of a bar is a redraw."""
    readings = iter(range(10 ** 6))
    return lambda: start + step * next(readings)


def drawn_lines(stream):
    """Each line the bar drew, in order (blanks of an erase left out)."""
    return [line.rstrip() for line in stream.getvalue().split("\r") if line.strip()]


def test_a_time_that_steps_back_never_shows_a_smaller_percentage():
    # windows on threads report their covered time summed: it steps back when a cut window is clamped
    reported = [0.0, 6.0, 3.0, 12.0, 12.0, 9.0, 30.0, 24.0, 29.0, 47.0, 40.0, 48.0, 45.0]
    stream = FakeTty()
    bar = Progress(0.0, 48.0, stream=stream, enabled=True, clock=ticking())
    for count, reached in enumerate(reported):
        bar(reached, count)
    percents = [int(PERCENT.search(line).group(1)) for line in drawn_lines(stream)]
    assert len(percents) == len(reported)                    # one draw per call: the clock moves a second each
    assert percents == sorted(percents)                      # never smaller than before
    assert percents[2] == percents[1] == 12 and percents[-1] == 100
    assert bar.time_reached == 48.0


def test_the_contact_count_is_the_cores_latest():
    # confirming on raw samples starts the count again: a maximum would show candidates that were dropped
    stream = FakeTty()
    bar = Progress(0.0, 10.0, stream=stream, enabled=True, clock=ticking())
    bar(10.0, 2109)
    bar(10.0, 895)
    assert drawn_lines(stream)[-1].endswith("contacts: 895") and bar.contacts == 895


@pytest.mark.parametrize("seconds, text", [(0, "0:00"), (7.4, "0:07"), (59.6, "1:00"), (754, "12:34"),
                                           (3723, "1:02:03"), (-3, "0:00")])
def test_durations_read_as_a_clock(seconds, text):
    assert duration_text(seconds) == text


def test_eta_after_known_elapsed_times():
    readings = iter([100.0, 102.0, 110.0, 200.0, 300.0])
    stream = FakeTty()
    bar = Progress(0.0, 200.0, stream=stream, enabled=True, clock=lambda: next(readings))
    bar(0.0, 0)        # first report: the clock starts here, not when the bar was made
    bar(1.0, 0)        # 2 s in, 0.5% done: too little to say
    bar(50.0, 3)       # 10 s in, 25% done: 10 * 0.75 / 0.25 = 30 s left
    bar(100.0, 5)      # 100 s in, 50% done: 100 s left
    bar(200.0, 5)      # done: nothing left
    lines = drawn_lines(stream)
    assert "0:00 elapsed  ETA --" in lines[0]
    assert "0:02 elapsed  ETA --" in lines[1]
    assert "0:10 elapsed  ETA 0:30" in lines[2] and " 25%" in lines[2]
    assert "1:40 elapsed  ETA 1:40" in lines[3] and " 50%" in lines[3]
    assert "3:20 elapsed  ETA 0:00" in lines[4] and "100%" in lines[4]


def test_eta_counts_from_where_the_bar_first_stood():
    # a shot whose first piece has nothing to check reports first halfway: the rate is that of what moved since
    readings = iter([0.0, 10.0])
    stream = FakeTty()
    bar = Progress(0.0, 100.0, stream=stream, enabled=True, clock=lambda: next(readings))
    bar(50.0, 0)
    bar(75.0, 0)       # 25% in 10 s: 25% left takes 10 s (not 10 * 0.25 / 0.75)
    assert "0:10 elapsed  ETA 0:10" in drawn_lines(stream)[-1]


def test_remaining_seconds_waits_for_the_named_fraction():
    assert remaining_seconds(5.0, ETA_MIN_FRACTION * 0.99) is None
    assert remaining_seconds(5.0, 0.5 + ETA_MIN_FRACTION * 0.5, first_fraction=0.5) is None
    assert remaining_seconds(5.0, 0.5) == pytest.approx(5.0)
    assert remaining_seconds(5.0, 1.0) == 0.0


def test_redraws_at_most_the_named_number_of_times_a_second():
    # two seconds of calls every hundredth of a second (REDRAWS_PER_SECOND a second at most: 10 a second)
    calls = 200
    step = 2.0 / calls
    stream = FakeTty()
    bar = Progress(0.0, 100.0, stream=stream, enabled=True, clock=ticking(step))
    for k in range(calls):
        bar(min(k, 100), k)      # the end is reached half way: at 100% the bar keeps to the rate too
    draws = stream.getvalue().count("\r")
    assert draws <= 2.0 * REDRAWS_PER_SECOND + 1
    assert draws > 2 * REDRAWS_PER_SECOND // 2          # and it does redraw as the clock moves
    assert REDRAW_INTERVAL_SECONDS == pytest.approx(1.0 / REDRAWS_PER_SECOND)


def test_nothing_is_written_when_disabled():
    def no_clock():
        raise AssertionError("a bar that is not drawn reads no clock")

    quiet = FakeTty()
    bar = Progress(0.0, 48.0, stream=quiet, enabled=False, clock=no_clock)
    for reached in (10.0, 5.0, 48.0):
        bar(reached, 2)
    bar.close()
    assert quiet.getvalue() == ""
    assert bar.time_reached == 48.0 and bar.contacts == 2     # it still keeps count for its owner


def test_off_a_terminal_or_in_ci_the_bar_is_not_drawn(monkeypatch):
    monkeypatch.setenv("CI", "true")
    assert not Progress(0.0, 1.0, stream=FakeTty()).enabled
    monkeypatch.delenv("CI")
    assert Progress(0.0, 1.0, stream=FakeTty()).enabled
    pipe = io.StringIO()
    bar = Progress(0.0, 1.0, stream=pipe, clock=ticking())
    bar(0.5, 1)
    bar.close()
    assert not bar.enabled and pipe.getvalue() == ""


def test_a_shorter_line_covers_the_longer_one_and_close_erases_all(monkeypatch):
    stream = FakeTty()
    bar = Progress(0.0, 100.0, stream=stream, enabled=True, clock=ticking(), label="last contacts, reversed time")
    bar(0.0, 123456)
    bar(60.0, 7)          # fewer digits of contacts: blanks cover the rest of the longer line
    writes = stream.getvalue().split("\r")[1:]
    assert len(writes[1]) >= len(writes[0].rstrip())
    assert writes[1].startswith("last contacts, reversed time [")
    bar.close()
    assert stream.getvalue().endswith("\r" + " " * len(writes[0]) + "\r")


def test_the_line_is_cut_to_the_terminal_width(monkeypatch):
    monkeypatch.setattr(progress_module, "_terminal_columns", lambda stream: 40)
    stream = FakeTty()
    bar = Progress(0.0, 100.0, stream=stream, enabled=True, clock=ticking())
    bar(25.0, 3)
    (drawn,) = stream.getvalue().split("\r")[1:]
    assert len(drawn) == 39 and drawn.startswith("[" + "#" * 8)   # one column short of wrapping


def test_the_reversed_run_shows_its_range_without_a_negative_zero():
    stream = FakeTty()
    bar = Progress(-150.0, -0.0, stream=stream, enabled=True, clock=ticking(), label="last contacts, reversed time")
    bar(-75.0, 1)
    assert "t=-75 of -150..0  contacts: 1" in drawn_lines(stream)[-1]
