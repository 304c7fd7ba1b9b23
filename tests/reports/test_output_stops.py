"""A stop (Ctrl-C, SIGTERM, --timeout) while files are published: all of them or none, and no temporary
file left; signals delivered at the exact step by the step itself."""

import os
import signal

import pytest

from usdksl.reports import output
from usdksl.stopping import Interrupted, Terminated, deferred_stops, stop_on_signals

FILES = ("a.contacts.csv", "a.summary.csv", "a.usdksl.usda")


def targets(folder):
    return {folder / name: f"{name}\n" * 1000 for name in FILES}


def signal_on_call(monkeypatch, module, name, signum, call=1, after=False):
    """Make ``module.name`` send ``signum`` to this process on its ``call``-th call, before its work (or
    ``after`` it)."""
    original = getattr(module, name)
    count = []

    def wrapper(*args, **kwargs):
        count.append(1)
        if len(count) == call and not after:
            os.kill(os.getpid(), signum)
        result = original(*args, **kwargs)
        if len(count) == call and after:
            os.kill(os.getpid(), signum)
        return result

    monkeypatch.setattr(module, name, wrapper)


def test_a_stop_while_the_files_are_written_leaves_no_file_and_no_temporary(tmp_path, monkeypatch):
    out = tmp_path / "out" / "deeper"
    signal_on_call(monkeypatch, output.os, "fsync", signal.SIGINT, call=2)
    with pytest.raises(Interrupted):
        with stop_on_signals():
            output.write_files(targets(out))
    assert not (tmp_path / "out").exists(), "folders it created are removed again"


def test_a_stop_during_the_renames_waits_until_every_file_is_in_place(tmp_path, monkeypatch):
    signal_on_call(monkeypatch, output.os, "replace", signal.SIGTERM, call=1)
    with pytest.raises(Terminated):
        with stop_on_signals():
            output.write_files(targets(tmp_path))
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(FILES)
    assert (tmp_path / FILES[2]).read_text() == f"{FILES[2]}\n" * 1000


def test_a_stop_while_a_temporary_file_is_created_removes_it(tmp_path, monkeypatch):
    signal_on_call(monkeypatch, output.tempfile, "mkstemp", signal.SIGINT, call=2, after=True)
    with pytest.raises(Interrupted):
        with stop_on_signals():
            output.write_files(targets(tmp_path))
    assert list(tmp_path.iterdir()) == []


def test_the_writable_folder_probe_is_never_left_behind(tmp_path, monkeypatch):
    signal_on_call(monkeypatch, output.tempfile, "mkstemp", signal.SIGINT, call=1, after=True)
    with pytest.raises(Interrupted):
        with stop_on_signals():
            output.check_writable_directory(tmp_path)
    assert list(tmp_path.iterdir()) == []


@pytest.fixture
def default_ctrl_c():
    """Python's own SIGINT handler for the test: a shell starts background jobs with SIGINT ignored, and
    an ignored signal is never held back (nor raised) outside a run."""
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, previous)


def test_outside_a_run_a_held_back_ctrl_c_is_a_keyboard_interrupt_after_the_block(tmp_path, default_ctrl_c):
    done = []
    with pytest.raises(KeyboardInterrupt):
        with deferred_stops():
            os.kill(os.getpid(), signal.SIGINT)
            done.append("the block ran to its end")
    assert done == ["the block ran to its end"]
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler


def test_a_dropped_stop_is_forgotten_and_a_second_signal_after_a_stop_waits_for_the_block():
    with stop_on_signals():
        with deferred_stops(drop=True):
            os.kill(os.getpid(), signal.SIGINT)
        # nothing raised: the run had its answer
    with pytest.raises(Interrupted):
        with stop_on_signals():
            with deferred_stops():
                os.kill(os.getpid(), signal.SIGINT)
                os.kill(os.getpid(), signal.SIGTERM)   # held too; the first stop wins
