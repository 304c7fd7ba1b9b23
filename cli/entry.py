"""The ``usdksl`` console script: Ctrl-C and SIGTERM handled from the first instant.

Python needs a second or two to load numpy and USD, and USD's module loader swallows an exception raised
while it imports (a Ctrl-C then goes unnoticed and the run goes on). So the stop handlers
(usdksl.stopping) are installed before anything heavy is imported, a stop during the imports is held
back until they are done, and any stop outside a command's own handling ends in one line and exit code
130 / 143 (docs/contracts.md, Stopping). The imports run with the cyclic garbage collector paused
(cli/import_pause.py), and a finished command ends the process without the interpreter's teardown
(cli/quick_exit.py).
"""

import os
import sys

from usdksl.stopping import Stopped, deferred_stops, stop_on_signals

from .import_pause import collector_paused
from .quick_exit import exit_quickly

#: numpy's OpenBLAS starts one thread per core when numpy is imported (about 40 ms here) and keeps them
#: spinning after each matrix product; the check's only products are small transforms, and its native core
#: runs its own threads on those cores. Set before anything imports numpy; a user's own setting wins.
BLAS_THREADS_VARIABLES = ("OPENBLAS_NUM_THREADS",)

#: numpy asks Linux for transparent huge pages on every large array; where the kernel compacts memory for
#: such a request when it faults (defrag "madvise", the usual default), filling the loader's copy of a shot's
#: points stalls: on the 10x-densified Newton tablecloth (110 MB of points) the check spent 0.3 s more in
#: the kernel and took 1.99 s instead of 1.86 s (median of 6). The native core asks for huge pages for its
#: own large tables itself. Set before anything imports numpy; a user's own setting wins.
NUMPY_ENVIRONMENT_DEFAULTS = {"NUMPY_MADVISE_HUGEPAGE": "0"}


def main() -> None:
    try:
        _run()
    except SystemExit as done:
        exit_quickly(done.code)
        raise


def _run() -> None:
    for variable in BLAS_THREADS_VARIABLES:
        os.environ.setdefault(variable, "1")
    for variable, value in NUMPY_ENVIRONMENT_DEFAULTS.items():
        os.environ.setdefault(variable, value)
    try:
        with stop_on_signals():
            with deferred_stops(), collector_paused():
                from usdksl._openusd import require_openusd

                require_openusd()   # without pxr: one line, exit 2
                from .main import main as command_line
            command_line.pause_collector_on_import = True
            command_line()
    except Stopped as stop:
        print(stop.line(), file=sys.stderr)
        sys.exit(stop.exit_code)
