"""Shots on Dask: a LocalCluster of worker processes (``--jobs N``) or a running scheduler (``--scheduler``).

Each shot is one task, ``usdksl.scale.batch.run_job``, returning a picklable ShotOutcome; the client
collects outcomes as they finish and writes the files itself (workers never write). When there are fewer
shots than worker slots, a long shot is instead a task per time window and a task merging them
(usdksl.scale.windows), whose outcome is the same. A task whose worker dies is run again by Dask on
another worker (the scheduler's ``allowed-failures``; a window result lost with its worker is computed
again); a task that raises is retried :data:`TASK_RETRIES` times. Every run of a task computes the same
result and only one outcome per shot reaches the client, so a retry can neither lose nor duplicate a
contact.

Workers do not oversubscribe the cores: unless ``--threads`` is given, the core of each task runs with
``cores // workers`` threads on a LocalCluster (at least 1) and with 1 thread on a running scheduler,
whose worker slots are taken to be sized to its machines' cores already.
"""

from __future__ import annotations

import time
from contextlib import contextmanager
from dataclasses import replace
from typing import Iterator, Optional, Sequence

from ..checking.collision import default_threads
from ..errors import UsdkslUsageError
from ..pipeline.options import CheckOptions
from ..stopping import Stopped
from .batch import ShotJob, ShotOutcome, run_job
from .batch_progress import BatchProgress
from .local_cluster import default_workers, local_cluster_client
from .windows import check_window, merge_windows, shot_windows, windows_per_shot

#: Extra runs of a task that raised (a worker that dies does not count: Dask reschedules its tasks).
TASK_RETRIES = 2
#: Seconds to wait for a --scheduler address to answer.
CONNECT_TIMEOUT_SECONDS = 30
#: The one line (exit 2) of --jobs and --scheduler where Dask is not installed: the base install leaves it out.
INSTALL_HINT = "--jobs and --scheduler need Dask: pip install 'usdksl[dask]'"


def require_dask() -> None:
    """Raise UsdkslUsageError (exit 2) when dask.distributed cannot be imported."""
    try:
        import distributed  # noqa: F401
    except ImportError:
        raise UsdkslUsageError(INSTALL_HINT) from None


@contextmanager
def dask_client(workers: Optional[int] = None, scheduler: Optional[str] = None):
    """A distributed Client: on a new LocalCluster of ``workers`` single-threaded processes
    (usdksl.scale.local_cluster), or on the scheduler at ``scheduler`` (tcp://host:port). The cluster is
    closed on exit."""
    require_dask()
    from distributed import Client

    if scheduler:
        try:
            client = Client(scheduler, timeout=CONNECT_TIMEOUT_SECONDS)
        except (OSError, TimeoutError) as error:
            raise UsdkslUsageError(f"cannot reach the Dask scheduler at {scheduler}: {error}") from None
        with client:
            yield client
        return
    with local_cluster_client(workers) as client:
        yield client


def worker_options(options: CheckOptions, local_workers: Optional[int]) -> CheckOptions:
    """``options`` as each Dask task runs them: the user's ``threads``, or (None) ``cores // workers``
    threads for ``local_workers`` processes of this machine, or 1 on a running scheduler (None)."""
    if options.threads is not None:
        return options
    threads = max(1, default_threads() // local_workers) if local_workers else 1
    return replace(options, threads=threads)


def worker_slots(client) -> int:
    """Tasks the cluster runs at once: the threads of its workers (at least 1)."""
    return max(1, sum(info.get("nthreads", 1) for info in client.scheduler_info()["workers"].values()))


def run_on_dask(jobs: Sequence[ShotJob], options: CheckOptions, workers: Optional[int] = None,
                scheduler: Optional[str] = None, progress: Optional[BatchProgress] = None) -> Iterator[ShotOutcome]:
    """Outcomes of ``jobs`` as their tasks finish (runner for :func:`usdksl.scale.batch.run_batch`);
    ``progress`` advances a piece per shot checked whole and per time window."""
    if not jobs:
        return
    require_dask()
    from distributed import as_completed

    with dask_client(workers, scheduler) as client:
        local_workers = None if scheduler else (workers or default_workers())
        options = worker_options(options, local_workers)
        count = windows_per_shot(len(jobs), local_workers or worker_slots(client))
        shot_futures, window_futures = [], []
        submitted = {}
        for index, job in enumerate(jobs):
            windows = shot_windows(job, options, count)
            if windows:
                parts = [client.submit(check_window, job, options, window, pure=False, retries=TASK_RETRIES,
                                       key=f"usdksl-window-{index}-{number}-{job.name}")
                         for number, window in enumerate(windows)]
                window_futures.extend(parts)
                future = client.submit(merge_windows, job, options, *parts, pure=False, retries=TASK_RETRIES,
                                       key=f"usdksl-merge-{index}-{job.name}")
                if progress is not None:
                    progress.split(len(windows))
            else:
                future = client.submit(run_job, job, options, key=f"usdksl-check-{index}-{job.name}", pure=False,
                                       retries=TASK_RETRIES)
            shot_futures.append(future)
            submitted[future.key] = (time.monotonic(), bool(windows))
        try:
            for future in as_completed(shot_futures + window_futures):
                if future.key not in submitted:          # a window: one piece more
                    if progress is not None:
                        progress.advance()
                    continue
                outcome = future.result()
                started, split = submitted[future.key]
                if not split:
                    if progress is not None:
                        progress.advance()
                elif outcome.result is not None:
                    outcome.result.seconds = time.monotonic() - started   # wall time of the shot, windows included
                yield outcome
        except Stopped:
            # On a scheduler of its own the tasks go on running until they end; their results are
            # not wanted (a local cluster's workers are killed by local_cluster_client).
            if scheduler:
                client.cancel(shot_futures + window_futures)
            raise
