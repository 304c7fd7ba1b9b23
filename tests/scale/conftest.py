"""Dask processes for the scale tests: a real ``dask scheduler`` and ``dask worker`` processes on loopback."""

import shutil
import socket
import subprocess
import sys
from pathlib import Path

import pytest

#: Seconds a Dask process may take to come up, and a whole check on Dask to finish.
STARTUP_SECONDS = 60
RUN_SECONDS = 300
POLL_SECONDS = 0.01


def executable(name):
    found = shutil.which(name, path=str(Path(sys.executable).parent))
    assert found, f"{name} is installed beside {sys.executable}"
    return found


def _free_port():
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


@pytest.fixture
def dask_cluster(tmp_path):
    """A real `dask scheduler` and two `dask worker` processes (no nanny: a killed worker stays dead) on
    loopback, working in a folder of their own. Yields (address, {worker name: Popen}, client)."""
    from distributed import Client

    address = f"tcp://127.0.0.1:{_free_port()}"
    workdir = tmp_path / "dask"
    workdir.mkdir()
    dask = executable("dask")
    processes = [subprocess.Popen([dask, "scheduler", "--host", "127.0.0.1", "--port", address.rsplit(":", 1)[1],
                                   "--no-dashboard"], cwd=workdir, stdout=subprocess.DEVNULL,
                                  stderr=subprocess.DEVNULL)]
    workers = {}
    client = None
    try:
        for name in ("w1", "w2"):
            workers[name] = subprocess.Popen([dask, "worker", address, "--nthreads", "1", "--no-nanny", "--name",
                                              name, "--no-dashboard", "--death-timeout", str(STARTUP_SECONDS)],
                                             cwd=workdir, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            processes.append(workers[name])
        client = Client(address, timeout=STARTUP_SECONDS)
        client.wait_for_workers(2, timeout=STARTUP_SECONDS)
        yield address, workers, client
    finally:
        if client is not None:
            client.close()
        for process in reversed(processes):
            process.kill()
            process.wait(timeout=STARTUP_SECONDS)


def processing_worker(client, workers, key_prefix):
    """The name of a worker of ``workers`` now running a task whose key starts with ``key_prefix``, or None."""
    names = {address: info["name"] for address, info in client.scheduler_info()["workers"].items()}
    for worker, keys in client.processing().items():
        if any(str(key).startswith(key_prefix) for key in keys) and names.get(worker) in workers:
            return names[worker]
    return None
