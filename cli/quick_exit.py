"""Ending the ``usdksl`` process once a command is done, without the interpreter's teardown.

When a command has said everything and published its files, Python would still tear the interpreter
down: clear every module, collect numpy's and USD's objects and run the C++ static destructors of the
USD library. That takes about 40 ms on a 2-core machine (numpy, pxr and the native core each add to
it), a few percent of a whole ``usdksl check`` of a small shot, and changes nothing anyone can see.

:func:`exit_quickly` does what a normal exit does that can be seen from outside -- the ``atexit``
handlers run (Python code that registered them still gets its say) and stdout and stderr are flushed --
and then ends the process with ``os._exit``. It falls back on the normal exit whenever skipping the
teardown could be noticed: another thread still runs (a normal exit waits for it), the exit code is not
a number (Python prints it), a profiler or tracer watches (``python -m cProfile`` writes its report
after the command returns), or flushing a stream fails (Python reports that and exits 120).
"""

from __future__ import annotations

import atexit
import os
import sys
import threading
from typing import Optional, Union


def exit_quickly(code: Optional[Union[int, str]]) -> None:
    """End the process with ``code`` (``SystemExit.code``) as a normal exit would, minus the teardown;
    returns (having done nothing) when the normal exit has to do it (module docstring)."""
    if code is not None and not isinstance(code, int):
        return
    if threading.active_count() > 1 or sys.getprofile() is not None or sys.gettrace() is not None:
        return
    atexit._run_exitfuncs()   # they run once: the normal exit finds none left if we return below
    for stream in (sys.stdout, sys.stderr, sys.__stdout__, sys.__stderr__):
        try:
            if stream is not None:
                stream.flush()
        except Exception:   # noqa: BLE001  (the normal exit reports it as Python does)
            return
    os._exit(0 if code is None else code & 0xFF)
