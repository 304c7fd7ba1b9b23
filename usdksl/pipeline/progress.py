"""Progress of a check on a terminal: how much of the shot's time is covered, time elapsed and left; silent in CI
and in pipes.

The core calls back ``(time_reached, contacts_so_far)``. Checked in time windows on several threads, it reports
the time all windows have covered, summed and added to the range's start (native/src/collision/check.cpp,
``WindowProgress``); that sum steps back when a window that ran past the point where it was cut is clamped to
its new end. The bar shows the furthest time reported so far, so its fraction never goes down. Once the time
is covered the core confirms its candidates on the raw samples and reports the range's end with the contacts
confirmed so far, which start again from 0: the count shown is the core's latest, not a maximum, which would
show candidates that the confirmation drops.

Elapsed time counts from the core's first report, not from when the bar is made: the bar of the backwards run
of ``--last-contact`` is made with the forward one and waits for the whole forward run. The estimate of the
time left assumes the rest goes at the rate so far: ``elapsed * (1 - f) / (f - f0)``, where ``f0`` is the
fraction at the first report (a shot whose first piece had nothing to check starts past 0). Before the bar has
moved :data:`ETA_MIN_FRACTION` it shows ``ETA --``: the first steps (building the separation lists) say little
of the rest. It does not foresee the confirmation after the last time step, which is short next to the time
pass on every cache measured.

The bar is drawn on stderr only when stderr is a TTY and the environment variable ``CI`` is unset (or empty),
at most :data:`REDRAWS_PER_SECOND` times a second, cut to the terminal's width. The final summary line is not
the bar's business: ``usdksl check`` always prints it.
"""

from __future__ import annotations

import math
import os
import sys
import time
from typing import Optional, TextIO

#: Redraws of the bar per second of wall time, at most (each one takes the GIL from the core's threads).
REDRAWS_PER_SECOND = 10
#: Seconds of wall time between two redraws, at least.
REDRAW_INTERVAL_SECONDS = 1.0 / REDRAWS_PER_SECOND
#: Characters of the bar between its brackets.
BAR_WIDTH = 30
#: Fraction of the checked span (0..1) the bar must have moved since the first report before it estimates the
#: time left.
ETA_MIN_FRACTION = 0.01
#: What the bar shows for the time left before it estimates it.
ETA_UNKNOWN = "--"


def progress_enabled(stream: Optional[TextIO] = None, environ=None) -> bool:
    stream = sys.stderr if stream is None else stream
    environ = os.environ if environ is None else environ
    if environ.get("CI"):
        return False
    isatty = getattr(stream, "isatty", None)
    return bool(isatty and isatty())


def duration_text(seconds: float) -> str:
    """``0:07``, ``12:34``, ``1:02:03``: whole seconds of wall time as a clock shows them."""
    total = max(int(round(seconds)), 0)
    hours, rest = divmod(total, 3600)
    minutes, secs = divmod(rest, 60)
    return f"{hours}:{minutes:02d}:{secs:02d}" if hours else f"{minutes}:{secs:02d}"


def remaining_seconds(elapsed: float, fraction: float, first_fraction: float = 0.0) -> Optional[float]:
    """Seconds left if the rest goes as fast as ``fraction - first_fraction`` went in ``elapsed`` seconds; None
    until the bar has moved ETA_MIN_FRACTION."""
    moved = fraction - first_fraction
    if moved < ETA_MIN_FRACTION:
        return None
    return elapsed * (1.0 - fraction) / moved


class Progress:
    """Callable ``(time_reached, contacts_so_far)`` for ``find_contacts(progress=...)``.

    ``start``/``end`` are the checked range in time codes; ``label`` is shown before the bar; ``clock`` gives
    wall seconds (monotonic) and is read once per call of a drawn bar. When disabled a call only records the
    time and count, and draws nothing.
    """

    def __init__(self, start: float, end: float, stream: Optional[TextIO] = None,
                 enabled: Optional[bool] = None, clock=time.monotonic, label: str = ""):
        self.label = label
        self.stream = sys.stderr if stream is None else stream
        self.enabled = progress_enabled(self.stream) if enabled is None else enabled
        self.start = float(start)
        self.end = float(end)
        self._clock = clock
        self._last_draw = -math.inf
        self._width = 0                 # characters of the line on the terminal, 0 when none is
        self._first_report: Optional[float] = None   # clock at the core's first report
        self._first_fraction = 0.0
        self._now: Optional[float] = None
        self.time_reached = self.start
        self.contacts = 0

    @property
    def _drawn(self) -> bool:
        return self._width > 0

    def fraction(self, time_reached: float) -> float:
        span = self.end - self.start
        if span <= 0:
            return 1.0
        return min(max((float(time_reached) - self.start) / span, 0.0), 1.0)

    def elapsed(self) -> float:
        """Wall seconds from the first report to the latest (0 before any report of a drawn bar)."""
        if self._first_report is None or self._now is None:
            return 0.0
        return self._now - self._first_report

    def eta_text(self) -> str:
        """``ETA 0:12``, or ``ETA --`` before the bar estimates it."""
        left = remaining_seconds(self.elapsed(), self.fraction(self.time_reached), self._first_fraction)
        return f"ETA {ETA_UNKNOWN if left is None else duration_text(left)}"

    def line(self) -> str:
        """The bar as drawn (without the carriage return): label, bar, percent, elapsed, ETA, time, contacts."""
        fraction = self.fraction(self.time_reached)
        filled = int(round(fraction * BAR_WIDTH))
        percent = math.floor(fraction * 100.0)   # 100% only once the end is reached
        label = self.label + " " if self.label else ""
        reached = f"t={_number(self.time_reached)} of {_number(self.start)}..{_number(self.end)}"
        return (f"{label}[{'#' * filled}{'.' * (BAR_WIDTH - filled)}] {percent:3d}%  "
                f"{duration_text(self.elapsed())} elapsed  {self.eta_text()}  {reached}  contacts: {self.contacts}")

    def __call__(self, time_reached: float, contacts_so_far: int) -> None:
        self.time_reached = max(self.time_reached, float(time_reached))
        self.contacts = int(contacts_so_far)
        if not self.enabled:
            return
        now = self._clock()
        if self._first_report is None:
            self._first_report = now
            self._first_fraction = self.fraction(self.time_reached)
        self._now = now
        if now - self._last_draw < REDRAW_INTERVAL_SECONDS:
            return
        self._last_draw = now
        self._draw(self.line())

    def _draw(self, text: str) -> None:
        columns = _terminal_columns(self.stream)
        if columns is not None:
            text = text[:max(columns - 1, 0)]   # a line as wide as the terminal wraps, and \r redraws only its tail
        # blanks over what is left of a longer line drawn before
        self.stream.write("\r" + text.ljust(self._width))
        self.stream.flush()
        self._width = max(self._width, len(text))

    def close(self) -> None:
        """Erase the bar so the summary line starts on a clean line."""
        if self.enabled and self._drawn:
            self.stream.write("\r" + " " * self._width + "\r")
            self.stream.flush()
            self._width = 0


def _number(time_code: float) -> str:
    """``12``, ``12.5``, ``0`` for -0 (the reversed run's end when the shot starts at 0)."""
    return f"{time_code + 0.0:g}"


def _terminal_columns(stream: TextIO) -> Optional[int]:
    """Columns of the terminal ``stream`` writes to; None when it is not one (or does not say)."""
    try:
        return os.get_terminal_size(stream.fileno()).columns or None
    except (AttributeError, OSError, ValueError):
        return None


__all__ = ["BAR_WIDTH", "ETA_MIN_FRACTION", "ETA_UNKNOWN", "REDRAWS_PER_SECOND", "REDRAW_INTERVAL_SECONDS",
           "Progress", "duration_text", "progress_enabled", "remaining_seconds"]
