"""The narrow phase's default settings, as the native core defines them.

On their own so that ``usdksl check`` reads them without importing the batch query API of
:mod:`usdksl.ccd` (which re-exports them) at start-up.
"""

from __future__ import annotations

from . import _native

# The defaults are the native core's (native/include/usdksl/constants.hpp), read through the binding so
# they are written once.
#: Width (fraction of the step) of the time interval at which refinement stops.
DEFAULT_TOLERANCE: float = _native.DEFAULT_CCD_TOLERANCE
#: Cap on sub-box refinements of one query; reaching it makes it undecided.
DEFAULT_MAX_ITERATIONS: int = _native.DEFAULT_CCD_MAX_ITERATIONS
#: Minimum separation (scene units): a contact is a distance <= thickness.
DEFAULT_THICKNESS: float = _native.DEFAULT_THICKNESS

__all__ = ["DEFAULT_MAX_ITERATIONS", "DEFAULT_THICKNESS", "DEFAULT_TOLERANCE"]
