"""The ``usdksl`` console script: Ctrl-C and SIGTERM handled from the first instant.

Python needs a second or two to load numpy and USD, and USD's module loader swallows an exception raised
while it imports (a Ctrl-C then goes unnoticed and the run goes on). So the stop handlers
(usdksl.stopping) are installed before anything heavy is imported, a stop during the imports is held
back until they are done, and any stop outside a command's own handling ends in one line and exit code
130 / 143 (docs/contracts.md, Stopping).
"""

import sys

from ..stopping import Stopped, deferred_stops, stop_on_signals


def main() -> None:
    try:
        with stop_on_signals():
            with deferred_stops():
                from .._openusd import require_openusd

                require_openusd()   # without pxr: one line, exit 2
                from .main import main as command_line
            command_line()
    except Stopped as stop:
        print(stop.line(), file=sys.stderr)
        sys.exit(stop.exit_code)
