"""The shots a command line names: quoted globs expanded (``usdksl check 'shots/*.usd'``), folders
replaced by the USD files in them (``usdksl check shots/``; docs/contracts.md, Outputs).

On its own so that a check of one shot reads its argument without importing the many-shot machinery
(usdksl.scale.batch) at start-up.
"""

from __future__ import annotations

import glob
import os
from typing import List, Sequence

from ..errors import UsdkslUsageError

#: Characters that make a shot argument a pattern to expand (a quoted glob the shell left alone).
GLOB_CHARACTERS = "*?["

#: The file names a folder argument stands for: its USD files, not those of its subfolders.
USD_FILE_PATTERNS = ("*.usd", "*.usda", "*.usdc", "*.usdz")


def expand_shots(arguments: Sequence[str]) -> List[str]:
    """Shot arguments with quoted globs expanded (sorted) and folders replaced by their USD files (sorted;
    :data:`USD_FILE_PATTERNS`); an argument that is a file, or a pattern that matches nothing, is kept as
    it is (it is then reported as a missing file). Raises UsdkslUsageError naming a folder that holds no
    USD file: checking nothing must not pass as clean."""
    shots: List[str] = []
    for argument in arguments:
        if os.path.isdir(argument):
            shots.extend(folder_shots(argument))
            continue
        matches = sorted(glob.glob(argument)) if any(c in argument for c in GLOB_CHARACTERS) else []
        shots.extend(matches if matches and not os.path.isfile(argument) else [argument])
    return list(dict.fromkeys(shots))


def folder_shots(folder: str) -> List[str]:
    """The USD files directly in ``folder`` (hidden files left out, as a shell glob does), sorted, each
    named as ``folder`` joined with its file name. Raises UsdkslUsageError when there is none."""
    found = sorted(path for pattern in USD_FILE_PATTERNS
                   for path in glob.glob(os.path.join(glob.escape(folder), pattern)) if os.path.isfile(path))
    if not found:
        raise UsdkslUsageError(f"no USD file in this folder (looked for {', '.join(USD_FILE_PATTERNS)}, "
                               f"not in subfolders)", file=folder)
    return found


__all__ = ["GLOB_CHARACTERS", "USD_FILE_PATTERNS", "expand_shots", "folder_shots"]
