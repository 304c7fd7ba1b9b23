"""Imports without the cyclic garbage collector.

Importing numpy, USD and usdksl creates a few hundred thousand objects, nearly none of them garbage; each
allocation burst runs the collector, which then walks all of them again and again (about 10 ms of a
plain ``usdksl check``, for nothing to collect). The command's heavy imports run inside
:func:`collector_paused`; the collector is back on, as it was, when the check itself runs, and the
objects the imports made are moved out of its sight (``gc.freeze``: modules, classes and functions live
as long as the process anyway), so that its first pass after them does not walk them all either.
"""

from __future__ import annotations

import gc
from contextlib import contextmanager
from typing import Iterator


@contextmanager
def collector_paused() -> Iterator[None]:
    """Turn the cyclic garbage collector off for the block (imports), then freeze what exists and turn it
    back on if it was on."""
    was_enabled = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        gc.freeze()
        if was_enabled:
            gc.enable()
