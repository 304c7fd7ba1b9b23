"""Where ``pxr`` comes from: usd-core (``pip install "usdksl[usd]"``) or a USD build already on the path.

usdksl only needs OpenUSD's Python module. Inside Houdini's hython, mayapy or a studio's own build, ``pxr``
is already importable and is used as it is: install usdksl there without the ``usd`` extra, so that pip
does not put a second USD beside it. Without any ``pxr``, importing usdksl fails with one actionable line
(and the ``usdksl`` command prints it as its error and exits 2, like every input error).
"""

from __future__ import annotations

import os
import sys

MISSING_OPENUSD = ("usdksl needs OpenUSD's Python module 'pxr': install usd-core with "
                   "pip install \"usdksl[usd]\", or run usdksl inside a Python that already has pxr "
                   "(Houdini's hython, mayapy, a studio USD build)")

#: Exit code of the ``usdksl`` command when pxr is missing (same as other input and usage errors).
MISSING_OPENUSD_EXIT_CODE = 2


def _running_the_command() -> bool:
    name = os.path.basename(sys.argv[0]) if sys.argv and sys.argv[0] else ""
    return name in ("usdksl", "usdksl.exe", "usdksl-script.py")


#: OpenUSD's setting that reads crate (.usdc) files with pread instead of mapping them into memory.
CRATE_PREAD_VARIABLE = "USDC_USE_PREAD"


def require_openusd() -> None:
    """Import pxr.Usd or fail with one line (module docstring).

    The ``usdksl`` command (and the Dask workers it starts, which inherit its environment) reads crate files
    with pread (CRATE_PREAD_VARIABLE, unless set already): a mapped crate file's pages count in the process's
    resident memory for as long as its stage is open, half again what the loader keeps of the shot's points,
    where pread reads what is asked and lets it go. A library user's process keeps USD's own choice."""
    if _running_the_command():
        os.environ.setdefault(CRATE_PREAD_VARIABLE, "1")
    try:
        from pxr import Usd  # noqa: F401
    except ImportError as error:
        reason = " ".join(str(error).split())
        if _running_the_command():
            sys.stderr.write(f"usdksl: error: {MISSING_OPENUSD} ({reason})\n")
            raise SystemExit(MISSING_OPENUSD_EXIT_CODE) from None
        raise ImportError(f"{MISSING_OPENUSD} ({reason})") from None
