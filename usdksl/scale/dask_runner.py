"""Shots on Dask: a LocalCluster of worker processes (``--jobs N``) or a running scheduler (``--scheduler``).

Each shot is one task, ``usdksl.scale.batch.run_job``, returning a picklable ShotOutcome; the client
collects outcomes as they finish and writes the files itself (workers never write). A task whose worker
dies is run again by Dask on another worker (the scheduler's ``allowed-failures``); a task that raises is
retried :data:`TASK_RETRIES` times. Every run of a task computes the same outcome and only one outcome per
shot reaches the client, so a retry can neither lose nor duplicate a contact.
"""

from __future__ import annotations

from contextlib import contextmanager
from typing import Iterator, Optional, Sequence

from ..checking.pipeline import CheckOptions
from ..errors import UsdkslUsageError
from ..stopping import Stopped
from .batch import ShotJob, ShotOutcome, run_job
from .local_cluster import local_cluster_client

#: Extra runs of a task that raised (a worker that dies does not count: Dask reschedules its tasks).
TASK_RETRIES = 2
#: Seconds to wait for a --scheduler address to answer.
CONNECT_TIMEOUT_SECONDS = 30


@contextmanager
def dask_client(workers: Optional[int] = None, scheduler: Optional[str] = None):
    """A distributed Client: on a new LocalCluster of ``workers`` single-threaded processes
    (usdksl.scale.local_cluster), or on the scheduler at ``scheduler`` (tcp://host:port). The cluster is
    closed on exit."""
    try:
        from distributed import Client
    except ImportError:   # pragma: no cover  (a dependency of the package)
        raise UsdkslUsageError("--jobs and --scheduler need dask[distributed]") from None
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


def run_on_dask(jobs: Sequence[ShotJob], options: CheckOptions, workers: Optional[int] = None,
                scheduler: Optional[str] = None) -> Iterator[ShotOutcome]:
    """Outcomes of ``jobs`` as their tasks finish (runner for :func:`usdksl.scale.batch.run_batch`)."""
    if not jobs:
        return
    from distributed import as_completed

    with dask_client(workers, scheduler) as client:
        futures = [client.submit(run_job, job, options, key=f"usdksl-check-{index}-{job.name}", pure=False,
                                 retries=TASK_RETRIES)
                   for index, job in enumerate(jobs)]
        try:
            for future in as_completed(futures):
                yield future.result()
        except Stopped:
            # On a scheduler of its own the tasks go on running until they end; their results are
            # not wanted (a local cluster's workers are killed by local_cluster_client).
            if scheduler:
                client.cancel(futures)
            raise
