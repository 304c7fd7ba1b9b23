"""Progress of a check on a terminal: shot time covered and contacts so far; silent in CI and in pipes.

The bar is drawn on stderr only when stderr is a TTY and the environment variable ``CI`` is unset (or
empty), redrawn at most every :data:`REDRAW_INTERVAL_SECONDS`. The final summary line is not the bar's
business: ``usdksl check`` always prints it.
"""

from __future__ import annotations

import os
import sys
import time
from typing import Optional, TextIO

REDRAW_INTERVAL_SECONDS = 0.1
BAR_WIDTH = 30


def progress_enabled(stream: Optional[TextIO] = None, environ=None) -> bool:
    stream = sys.stderr if stream is None else stream
    environ = os.environ if environ is None else environ
    if environ.get("CI"):
        return False
    isatty = getattr(stream, "isatty", None)
    return bool(isatty and isatty())


class Progress:
    """Callable ``(time_reached, contacts_so_far)`` for ``find_contacts(progress=...)``.

    ``start``/``end`` are the checked range in time codes; ``label`` is shown before the bar. When
    disabled every call is a no-op.
    """

    def __init__(self, start: float, end: float, stream: Optional[TextIO] = None,
                 enabled: Optional[bool] = None, clock=time.monotonic, label: str = ""):
        self.label = label
        self.stream = sys.stderr if stream is None else stream
        self.enabled = progress_enabled(self.stream) if enabled is None else enabled
        self.start = float(start)
        self.end = float(end)
        self._clock = clock
        self._last_draw = -float("inf")
        self._drawn = False
        self.time_reached = self.start
        self.contacts = 0

    def fraction(self, time_reached: float) -> float:
        span = self.end - self.start
        if span <= 0:
            return 1.0
        return min(max((float(time_reached) - self.start) / span, 0.0), 1.0)

    def line(self) -> str:
        fraction = self.fraction(self.time_reached)
        filled = int(round(fraction * BAR_WIDTH))
        return (f"\r{self.label + ' ' if self.label else ''}[{'#' * filled}{'.' * (BAR_WIDTH - filled)}] t={self.time_reached:g} of "
                f"{self.start:g}..{self.end:g}  contacts: {self.contacts}")

    def __call__(self, time_reached: float, contacts_so_far: int) -> None:
        self.time_reached = max(self.time_reached, float(time_reached))
        self.contacts = int(contacts_so_far)
        if not self.enabled:
            return
        now = self._clock()
        if now - self._last_draw < REDRAW_INTERVAL_SECONDS and self.fraction(self.time_reached) < 1.0:
            return
        self._last_draw = now
        self.stream.write(self.line())
        self.stream.flush()
        self._drawn = True

    def close(self) -> None:
        """Erase the bar so the summary line starts on a clean line."""
        if self.enabled and self._drawn:
            self.stream.write("\r" + " " * len(self.line()) + "\r")
            self.stream.flush()
            self._drawn = False
