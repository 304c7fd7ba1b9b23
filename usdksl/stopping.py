"""Stopping a run early: Ctrl-C (SIGINT), a farm pre-empting a task (SIGTERM) and ``--timeout``.

Inside :func:`stop_on_signals` each of them raises a :class:`Stopped` exception in the main thread, which
unwinds the run like any other exception: files not yet published are never published (the all-or-nothing
writer drops its temporary files), a Dask cluster is closed, and the caller prints :meth:`Stopped.line` and
exits with :attr:`Stopped.exit_code` (130 for SIGINT, 143 for SIGTERM, as a shell reports a process killed
by them; 2 for a timeout, like every run that could not be done).

The native core runs with the GIL released; it calls back into Python periodically (``find_contacts``
always passes a callback, which checks for pending signals first), and that is where the exception is
raised and then unwinds through the core. How often the core calls back is the core's business
(docs/contracts.md, Stopping).

Some steps must not be cut in half: creating a temporary file and remembering it (so that it is removed
again), renaming a set of finished files into place. They run inside :func:`deferred_stops`, which holds a
stop back until the step is done and then raises it. A second signal while a run is already stopping ends
the process at once (``os._exit``) unless it arrives inside such a step.

Signals can only be handled in the main thread: anywhere else both context managers do nothing.
"""

from __future__ import annotations

import math
import os
import signal
import threading
from contextlib import contextmanager
from typing import Dict, Iterator, List, Optional

from .exit_codes import INPUT_ERROR, INTERRUPTED, TERMINATED

#: Signals a run stops on, in the order they are handled.
STOP_SIGNALS = (signal.SIGINT, signal.SIGTERM)
#: The signal ``--timeout`` is delivered by (a one-shot real-time interval timer).
TIMEOUT_SIGNAL = signal.SIGALRM


class Stopped(BaseException):
    """A run was asked to stop. A BaseException, so crash handlers (``except Exception``) let it pass."""

    exit_code = INPUT_ERROR
    #: Printed before the reason: a timeout is an error (exit 2), an interruption is not.
    level = ""

    def line(self, done: str = "nothing written", shot: Optional[str] = None) -> str:
        """The one line the command prints, e.g. ``usdksl: interrupted (SIGINT); nothing written``."""
        return f"usdksl: {self.level}{shot + ': ' if shot else ''}{self.reason()}; {done}"

    def reason(self) -> str:
        raise NotImplementedError


class Interrupted(Stopped):
    """SIGINT (Ctrl-C). Not a KeyboardInterrupt: click would turn that into "Aborted!" and exit 1."""

    exit_code = INTERRUPTED

    def reason(self) -> str:
        return "interrupted (SIGINT)"


class Terminated(Stopped):
    """SIGTERM: a farm pre-empting the task, a ``kill``."""

    exit_code = TERMINATED

    def reason(self) -> str:
        return "terminated (SIGTERM)"


class TimedOut(Stopped):
    """``--timeout SECONDS`` ran out."""

    exit_code = INPUT_ERROR
    level = "error: "

    def __init__(self, seconds: float):
        super().__init__(seconds)
        self.seconds = float(seconds)

    def reason(self) -> str:
        return f"timed out after {self.seconds:g} s (--timeout)"


_EXCEPTION_OF_SIGNAL = {signal.SIGINT: Interrupted, signal.SIGTERM: Terminated}


class _StopState:
    """What the handlers of the current :func:`stop_on_signals` block share."""

    def __init__(self, timeout: Optional[float]):
        self.timeout = timeout
        self.stopping = False
        self.deferring = 0
        self.pending: List[int] = []


_state: Optional[_StopState] = None


def _in_main_thread() -> bool:
    return threading.current_thread() is threading.main_thread()


def _raise_for(signum: int, state: _StopState) -> None:
    if signum == TIMEOUT_SIGNAL:
        raise TimedOut(state.timeout or 0.0)
    raise _EXCEPTION_OF_SIGNAL[signum]()


def _handler(signum: int, frame) -> None:
    state = _state
    if state is None:   # a stray delivery after the block ended
        return
    if state.deferring:
        if signum not in state.pending:
            state.pending.append(signum)
        return
    if state.stopping:
        # Already unwinding: the user (or the farm) insists; nothing is being published right now.
        os._exit(_EXCEPTION_OF_SIGNAL.get(signum, TimedOut).exit_code)
    state.stopping = True
    _raise_for(signum, state)


@contextmanager
def stop_on_signals(timeout: Optional[float] = None) -> Iterator[None]:
    """Turn SIGINT, SIGTERM and, after ``timeout`` seconds (None: never), the clock into :class:`Stopped`
    exceptions raised in the main thread, for the duration of the block. The previous handlers (and any
    interval timer) are restored on exit. Outside the main thread the block runs unguarded."""
    global _state
    if timeout is not None and not (timeout > 0 and math.isfinite(timeout)):
        raise ValueError(f"timeout must be a positive number of seconds, got {timeout!r}")
    if not _in_main_thread():
        yield
        return
    previous_state = _state
    state = _StopState(timeout)
    watched = STOP_SIGNALS + ((TIMEOUT_SIGNAL,) if timeout is not None else ())
    previous: Dict[int, object] = {}
    _state = state
    try:
        for signum in watched:
            previous[signum] = signal.signal(signum, _handler)
        if timeout is not None:
            signal.setitimer(signal.ITIMER_REAL, timeout)
        yield
    finally:
        if timeout is not None:
            signal.setitimer(signal.ITIMER_REAL, 0)
        for signum, handler in previous.items():
            signal.signal(signum, handler)
        _state = previous_state


@contextmanager
def deferred_stops(drop: bool = False) -> Iterator[None]:
    """Hold a stop back while the block runs (keep it short) and raise it when the block is done.

    Inside :func:`stop_on_signals` the pending stop is raised as its :class:`Stopped` exception, or
    forgotten with ``drop`` (for the last step of a run that has its answer and ends right after, so
    that what it prints stays true). Outside, SIGINT and SIGTERM are held back the same way and then
    handed to the handlers that were in place (so a Python user's Ctrl-C still raises KeyboardInterrupt,
    and a default SIGTERM still ends the process), just after the block."""
    if not _in_main_thread():
        yield
        return
    state = _state
    if state is not None:
        state.deferring += 1
        try:
            yield
        finally:
            state.deferring -= 1
            if drop:
                state.pending.clear()
            if not state.deferring and state.pending and not state.stopping:
                # Raised from finally on purpose: a stop wins over an error the block may be raising.
                signum = state.pending.pop(0)
                state.stopping = True
                _raise_for(signum, state)
        return
    with _held_back_outside_a_run():
        yield


@contextmanager
def _held_back_outside_a_run() -> Iterator[None]:
    pending: List[int] = []
    previous: Dict[int, object] = {}

    def record(signum, frame):
        pending.append(signum)

    try:
        for signum in STOP_SIGNALS:
            handler = signal.getsignal(signum)
            if handler is signal.SIG_IGN or handler is None:
                continue
            previous[signum] = signal.signal(signum, record)
        yield
    finally:
        for signum, handler in previous.items():
            signal.signal(signum, handler)
    for signum in dict.fromkeys(pending):
        _deliver(signum, previous[signum])


def _deliver(signum: int, handler) -> None:
    if callable(handler):
        handler(signum, None)
    elif handler == signal.SIG_DFL:
        os.kill(os.getpid(), signum)
