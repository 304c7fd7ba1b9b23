"""One progress bar over a whole batch: a piece per shot, or per time window of a shot split into windows.

``usdksl check S1 S2 ...`` (and ``--jobs``/``--scheduler``) draws a single tqdm bar on stderr counting the
pieces of work done: a shot checked whole is one piece, a long shot split into N time windows on Dask
(usdksl.scale.windows) is N pieces, one as each window's task ends. The bar starts at one piece per shot
and grows when a shot is split. Like the one-shot bar (usdksl.pipeline.progress) it is drawn only on a
terminal, never in CI (``CI`` set) or in a pipe, and never with ``-q``.
"""

from __future__ import annotations

import sys
from typing import Optional, TextIO

from ..pipeline.progress import progress_enabled

#: What the bar counts.
PIECE_UNIT = "piece"


class BatchProgress:
    """The batch's bar. ``shots``: the pieces known at the start (one per shot). Disabled: counts only."""

    def __init__(self, shots: int, enabled: Optional[bool] = None, stream: Optional[TextIO] = None):
        from tqdm import tqdm

        self.stream = sys.stderr if stream is None else stream
        self.enabled = progress_enabled(self.stream) if enabled is None else enabled
        # pieces end seconds apart: draw every one (tqdm would skip updates within its minimum interval)
        self._bar = tqdm(total=shots, unit=PIECE_UNIT, file=self.stream, disable=not self.enabled, leave=False,
                         desc="shots and windows", mininterval=0, miniters=1)
        self.total = shots
        self.done = 0

    def split(self, windows: int) -> None:
        """One shot became ``windows`` pieces (its time windows)."""
        self.total += windows - 1
        self._bar.total = self.total
        self._bar.refresh()

    def advance(self, pieces: int = 1) -> None:
        """``pieces`` more pieces are done."""
        self.done += pieces
        self._bar.update(pieces)

    def write(self, line: str) -> None:
        """Print ``line`` on the bar's stream above the bar (the bar is redrawn below it)."""
        self._bar.write(line, file=self.stream)

    def close(self) -> None:
        """Erase the bar (the total line follows on a clean line)."""
        self._bar.close()
