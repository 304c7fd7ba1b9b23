"""A shot's clock: USD time codes as frames and seconds (docs/contracts.md, Frames and seconds).

Every time usdksl computes is a USD time code. People read frames and seconds, numbered as usdview, Maya
and Houdini number them: on the stage's own timeline, not counted from its ``startTimeCode``:

* ``frame = time * (framesPerSecond / timeCodesPerSecond)``, fractional (time code 1001 at 24/24 is
  frame 1001; time code 48 at 48 time codes and 24 frames a second is frame 24)
* ``seconds = time / timeCodesPerSecond``, so ``frame = seconds * framesPerSecond``

``timeCodesPerSecond`` and ``framesPerSecond`` are what USD answers for the stage (24 each when neither is
authored, and ``framesPerSecond`` stands in for an unauthored ``timeCodesPerSecond``). The stage's
``startTimeCode`` moves no frame.

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
    """Converts time codes to frames and seconds on the stage's timeline. Rates are per second."""

    time_codes_per_second: float = USD_FALLBACK_RATE
    frames_per_second: float = USD_FALLBACK_RATE

    @classmethod
    def from_metadata(cls, metadata: Mapping[str, object]) -> "StageClock":
        """The clock of a loaded shot (``usdksl.reading.loader.Shot.metadata``)."""
        return cls(time_codes_per_second=float(metadata.get("timeCodesPerSecond", USD_FALLBACK_RATE)),
                   frames_per_second=float(metadata.get("framesPerSecond", USD_FALLBACK_RATE)))

    @property
    def frames_per_time_code(self) -> float:
        """Frames per time code: exactly 1 when the two rates agree, so frames then equal time codes."""
        return self.frames_per_second / self.time_codes_per_second

    def seconds(self, time_codes):
        """Seconds since time code 0 (float or float64 array, like ``time_codes``)."""
        return np.asarray(time_codes, dtype=np.float64) / self.time_codes_per_second

    def frames(self, time_codes):
        """Fractional frames on the stage's timeline (float or float64 array, like ``time_codes``)."""
        # One multiplication by the rate ratio, not (time / tcps) * fps: with equal rates the ratio is
        # exactly 1 and a frame is its time code bit for bit.
        return np.asarray(time_codes, dtype=np.float64) * self.frames_per_time_code

    def frame(self, time_code: float) -> float:
        """The frame of one time code."""
        return float(self.frames(time_code))

    def describe(self, time_code: float) -> str:
        """How the console says a time: ``frame 1012.5 (t=2025)`` (48 time codes, 24 frames a second),
        rounded to CONSOLE_DECIMALS."""
        return f"frame {console_number(self.frame(time_code))} (t={console_number(time_code)})"


def console_number(value: float) -> str:
    """``value`` rounded to CONSOLE_DECIMALS decimals, trailing zeros dropped (12.5, 30, -0.25)."""
    text = f"{float(value):.{CONSOLE_DECIMALS}f}".rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text


__all__ = ["CONSOLE_DECIMALS", "StageClock", "USD_FALLBACK_RATE", "console_number"]
