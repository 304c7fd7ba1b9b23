"""The LocalCluster behind ``--jobs N``: worker processes that a Ctrl-C or a SIGTERM ends within a second.

A stop (usdksl.stopping) raises in the main thread of the process that runs the cluster. What this module
adds to a plain ``LocalCluster``:

- Worker processes never see SIGINT or SIGTERM themselves. A Ctrl-C at a terminal, and many farms'
  SIGTERM, reach the whole process group; a worker interrupted while it imports USD prints tracebacks
  and its nanny errors. The cluster's threads are started with both signals blocked, and the processes
  those threads start inherit the mask, so only the main process decides. (A worker still exits at once
  when this process dies: Dask watches the parent.)
- Dask's own start-up (a fraction of a second) is never cut in half by a stop: that leaves a cluster
  that cannot be closed.
- On a stop the worker processes are killed instead of closed gracefully (a graceful close waits for
  the running task, seconds or minutes of native code), with Dask's logging silenced meanwhile: their
  results are not wanted, and nothing but the command's one line should reach the terminal.
- The scratch space of the scheduler and the workers is a folder of ours, removed afterwards (even when
  workers were killed): nothing is left in the temporary folder.
"""

from __future__ import annotations

import gc
import logging
import os
import shutil
import signal
import tempfile
from contextlib import contextmanager, suppress
from multiprocessing import resource_tracker
from typing import Iterator, Optional, Set

from ..stopping import Stopped, deferred_stops

#: Signals the cluster's threads and worker processes block (the main process handles them).
BLOCKED_IN_WORKERS = {signal.SIGINT, signal.SIGTERM}
#: Seconds given to closing the client and the cluster after the workers were killed.
ABANDON_TIMEOUT_SECONDS = 5


def default_workers() -> int:
    """Worker processes of ``--jobs`` without a count: one per core."""
    return os.cpu_count() or 1


@contextmanager
def local_cluster_client(workers: Optional[int] = None) -> Iterator[object]:
    """A distributed Client on a new LocalCluster of ``workers`` (default: one per core) single-threaded
    worker processes,
    closed on exit; on a :class:`usdksl.stopping.Stopped` the workers are killed first."""
    import dask
    from distributed import Client, LocalCluster

    scratch = tempfile.mkdtemp(prefix="usdksl-dask-")
    cluster = client = None
    children_before: Set[int] = set()
    try:
        with deferred_stops():
            # multiprocessing's resource tracker unblocks SIGINT and SIGTERM in the thread that starts it
            # (the first process spawned does): start it here, before the mask is set.
            resource_tracker.ensure_running()
            children_before = _child_pids()
            with _signals_blocked_in_new_threads(), dask.config.set({"temporary-directory": scratch}):
                # One thread per worker: the core is single-threaded and pxr is not thread-safe for writing.
                cluster = LocalCluster(n_workers=0, threads_per_worker=1, processes=True,
                                       dashboard_address=":0", silence_logs=logging.ERROR,
                                       local_directory=scratch)
            client = Client(cluster)   # before the workers: it would wait for them to start
            cluster.scale(workers or default_workers())
        yield client
    except Stopped:
        _abandon(cluster, client, children_before)
        cluster = client = None
        raise
    finally:
        try:
            if client is not None:
                client.close()
            if cluster is not None:
                cluster.close()
        finally:
            shutil.rmtree(scratch, ignore_errors=True)


@contextmanager
def _signals_blocked_in_new_threads():
    """BLOCKED_IN_WORKERS blocked in this thread while the block runs: threads started meanwhile inherit
    the mask, and so do the processes they start. Signals that arrive meanwhile wait for the block's end."""
    previous = signal.pthread_sigmask(signal.SIG_BLOCK, BLOCKED_IN_WORKERS)
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, previous)


def _child_pids() -> Set[int]:
    import psutil   # a dependency of distributed

    return {child.pid for child in psutil.Process().children()}


def _abandon(cluster, client, children_before: Set[int]) -> None:
    """Kill the worker processes (also those still starting), then close the client and the cluster,
    with logging off: the failures that follow are expected and not the user's business."""
    previous_disable = logging.root.manager.disable
    logging.disable(logging.CRITICAL)
    try:
        if cluster is not None:
            for nanny in list(cluster.workers.values()):
                with suppress(Exception):
                    nanny.close_gracefully(reason="usdksl-stopped")   # no restart of a killed worker
        for pid in _child_pids() - children_before:
            with suppress(OSError):
                os.kill(pid, signal.SIGKILL)
        if client is not None:
            with suppress(Exception):
                client.close(timeout=ABANDON_TIMEOUT_SECONDS)
        if cluster is not None:
            with suppress(Exception):
                cluster.close(timeout=ABANDON_TIMEOUT_SECONDS)
        gc.collect()   # asyncio reports never-retrieved task errors when the tasks are collected
    finally:
        logging.disable(previous_disable)
