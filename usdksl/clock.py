"""A shot's clock: USD time codes as frames and seconds (docs/contracts.md, Frames and seconds).

Every time usdksl computes is a USD time code. People read frames and seconds, counted from the stage's
``startTimeCode``:

* ``seconds = (time - startTimeCode) / timeCodesPerSecond``
* ``frame = seconds * framesPerSecond``, fractional (frame 0 is the stage's start)

A stage that does not author ``startTimeCode`` starts at 0; ``timeCodesPerSecond`` and
``framesPerSecond`` are what USD answers for the stage (24 each when neither is authored, and
``framesPerSecond`` stands in for an unauthored ``timeCodesPerSecond``).

Files carry these numbers with ``repr(float)`` (exact, byte-identical run to run); the console rounds
them to :data:`CONSOLE_DECIMALS` decimals.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Mapping

import numpy as np

#: USD's fallback for timeCodesPerSecond and framesPerSecond.
USD_FALLBACK_RATE = 24.0
#: Decimals of frames and seconds on the console (a thousandth of a frame: finer than any display step).
CONSOLE_DECIMALS = 3


@dataclass(frozen=True)
class StageClock:
    """Converts time codes to frames and seconds since the stage's start. Rates are per second."""

    start_time_code: float = 0.0
    time_codes_per_second: float = USD_FALLBACK_RATE
    frames_per_second: float = USD_FALLBACK_RATE

    @classmethod
    def from_metadata(cls, metadata: Mapping[str, object]) -> "StageClock":
        """The clock of a loaded shot (``usdksl.reading.loader.Shot.metadata``)."""
        return cls(start_time_code=float(metadata.get("startTimeCode", 0.0)),
                   time_codes_per_second=float(metadata.get("timeCodesPerSecond", USD_FALLBACK_RATE)),
                   frames_per_second=float(metadata.get("framesPerSecond", USD_FALLBACK_RATE)))

    def seconds(self, time_codes):
        """Seconds since the stage's start (float or float64 array, like ``time_codes``)."""
        return (np.asarray(time_codes, dtype=np.float64) - self.start_time_code) / self.time_codes_per_second

    def frames(self, time_codes):
        """Fractional frames since the stage's start (frame 0 = startTimeCode)."""
        return self.seconds(time_codes) * self.frames_per_second

    def frame(self, time_code: float) -> float:
        return float(self.frames(time_code))

    def describe(self, time_code: float) -> str:
        """How the console says a time: ``frame 12.5 (t=1013.5)``, rounded to CONSOLE_DECIMALS."""
        return f"frame {console_number(self.frame(time_code))} (t={console_number(time_code)})"


def console_number(value: float) -> str:
    """``value`` rounded to CONSOLE_DECIMALS decimals, trailing zeros dropped (12.5, 30, -0.25)."""
    text = f"{float(value):.{CONSOLE_DECIMALS}f}".rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text


__all__ = ["CONSOLE_DECIMALS", "StageClock", "USD_FALLBACK_RATE", "console_number"]
