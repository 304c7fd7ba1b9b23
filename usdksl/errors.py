"""Errors a user sees as one line: what went wrong, in which file, prim and time."""

from __future__ import annotations

from typing import Optional

from .exit_codes import INPUT_ERROR


class UsdkslInputError(Exception):
    """Bad input (unreadable file, NaN points, changing topology, ...): exit code 2.

    ``str(error)`` is the one line the command prints: ``file: prim @ time: message``
    with the prim and time parts left out when they do not apply.
    """

    exit_code = INPUT_ERROR

    def __init__(self, message: str, file: Optional[str] = None, prim: Optional[str] = None,
                 time: Optional[float] = None):
        self.message = message
        self.file = file
        self.prim = prim
        self.time = time
        super().__init__(self.one_line())

    def one_line(self) -> str:
        where = []
        if self.file:
            where.append(str(self.file))
        if self.prim:
            where.append(str(self.prim))
        if self.time is not None:
            where.append(f"time {self.time:g}")
        prefix = ": ".join(where)
        text = " ".join(self.message.split())
        return f"{prefix}: {text}" if prefix else text


class UsdkslUsageError(UsdkslInputError):
    """Wrong arguments (bad option value, unwritable output directory): exit code 2."""


class UsdkslGapError(UsdkslInputError):
    """A mesh that cannot be followed across some of its samples (an empty or blocked ``points`` sample between
    samples with points): the shot is checked in pieces around the gap (usdksl.reading.segments)."""


class UsdkslEmptyMeshError(UsdkslInputError):
    """A mesh without points, without faces, or whose faces are all degenerate: the loader skips it with a
    warning (placeholders are common in layouts) instead of failing the shot."""

    @property
    def degenerate(self) -> bool:
        """Points and faces are there, but every face is a hole or has fewer than 3 vertices."""
        return "degenerate" in self.message or "fewer than 3" in self.message
