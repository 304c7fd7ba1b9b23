"""The shots a command line names: quoted globs expanded (``usdksl check 'shots/*.usd'``).

On its own so that a check of one shot reads its argument without importing the many-shot machinery
(usdksl.scale.batch) at start-up.
"""

from __future__ import annotations

import glob
import os
from typing import List, Sequence

#: Characters that make a shot argument a pattern to expand (a quoted glob the shell left alone).
GLOB_CHARACTERS = "*?["


def expand_shots(arguments: Sequence[str]) -> List[str]:
    """Shot arguments with quoted globs expanded (sorted); an argument that is a file, or a pattern that
    matches nothing, is kept as it is (it is then reported as a missing file)."""
    shots: List[str] = []
    for argument in arguments:
        matches = sorted(glob.glob(argument)) if any(c in argument for c in GLOB_CHARACTERS) else []
        shots.extend(matches if matches and not os.path.isfile(argument) else [argument])
    return list(dict.fromkeys(shots))


__all__ = ["GLOB_CHARACTERS", "expand_shots"]
