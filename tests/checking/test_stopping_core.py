"""The native core calls back often enough to be stopped, and an exception raised in the callback (where
Python's signal handlers run while the core holds no GIL) unwinds through every method cleanly."""

import os
import signal
import threading
import time

import pytest

from usdksl.checking.collision import METHODS, find_contacts
from usdksl.stopping import Terminated, TimedOut, stop_on_signals

from builders import folding_sheet, sheets_passing

#: The core's promise (native/src: baselines.cpp, separation_list.cpp, raw_sample_confirmation.cpp):
#: at least one progress call per this many narrow-phase tests.
PROGRESS_EVERY_TESTS = 256
#: Seconds from a signal to the core's return that a stop may take.
STOP_SECONDS = 1.0


def scene(size):
    """Two sheets passing through each other and a sheet folding through itself."""
    lower, upper = sheets_passing(n=size, samples=9)
    return [lower, upper, folding_sheet(n=4 * size, samples=9)], [(0, 1), (2, 2), (0, 2), (1, 2)]


def size_for(method):
    return 8 if method == "brute" else 16   # brute force is quadratic


class Boom(Exception):
    pass


@pytest.mark.parametrize("method", METHODS)
def test_progress_comes_at_least_every_few_hundred_narrow_phase_tests(method):
    meshes, pairs = scene(size_for(method))
    calls = []
    result = find_contacts(meshes, pairs, method=method, progress=lambda t, n: calls.append(t))
    tests = result.counters["narrow_phase_tests"]
    assert tests > 20 * PROGRESS_EVERY_TESTS, "the scene must make the core work"
    assert len(calls) >= tests // PROGRESS_EVERY_TESTS, (len(calls), tests)


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("raise_at_call", [1, 5])
def test_an_exception_in_the_callback_unwinds_the_core_and_leaves_it_usable(method, raise_at_call):
    meshes, pairs = scene(size_for(method))
    calls = []

    def progress(t, contacts):
        calls.append(t)
        if len(calls) == raise_at_call:
            raise Boom(f"stop at call {raise_at_call}")

    with pytest.raises(Boom, match=f"stop at call {raise_at_call}"):
        find_contacts(meshes, pairs, method=method, progress=progress)
    assert len(calls) == raise_at_call, "the core must not call back after the exception"
    again = find_contacts(meshes, pairs, method=method)
    fresh = find_contacts(meshes, pairs, method=method, progress=lambda t, n: None)
    assert len(again) == len(fresh) > 0
    assert (again.time == fresh.time).all() and (again.tri_a == fresh.tri_a).all()


@pytest.mark.parametrize("method", ["ksl", "brute"])
def test_a_timeout_stops_the_core_without_a_progress_object(method):
    meshes, pairs = scene(128 if method == "ksl" else 16)   # seconds of work on any machine
    started = time.monotonic()
    with pytest.raises(TimedOut):
        with stop_on_signals(timeout=0.3):
            find_contacts(meshes, pairs, method=method)
    assert time.monotonic() - started < 0.3 + STOP_SECONDS


def test_sigterm_stops_the_core_and_the_handlers_are_restored():
    meshes, pairs = scene(16)
    before = signal.getsignal(signal.SIGTERM)
    timer = threading.Timer(0.3, os.kill, (os.getpid(), signal.SIGTERM))
    started = time.monotonic()
    with pytest.raises(Terminated):
        with stop_on_signals():
            timer.start()
            find_contacts(meshes, pairs, method="brute")
    assert time.monotonic() - started < 0.3 + STOP_SECONDS
    assert signal.getsignal(signal.SIGTERM) is before
