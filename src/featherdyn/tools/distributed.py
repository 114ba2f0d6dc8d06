"""A ``dask.distributed`` client for the commands that spread work (tools layer).

``featherdyn dataset`` and ``featherdyn verify --all`` take ``--scheduler``:
``local`` starts a ``LocalCluster`` of worker processes on this machine (one
thread each), any other value is the address of a running scheduler.
"""

from __future__ import annotations

import logging
import os
import signal
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

from ..errors import DatasetError, MissingDependencyError

__all__ = ["available_cores", "dask_client", "dask_setup", "sigint_ignored"]


def available_cores() -> int:
    """The cores this process may run on."""
    return len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1)


@contextmanager
def sigint_ignored() -> Iterator[None]:
    """Ignore Ctrl-C (SIGINT) inside the block, called from the main thread (elsewhere: do nothing).

    Processes started inside the block inherit the ignored signal; a second Ctrl-C does not break the
    shutdown of the workers into a traceback.
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)


def dask_setup(worker: Any) -> None:
    """Dask's preload hook, run in each worker process of a local cluster as it starts: ignore Ctrl-C there.

    A worker that the nanny starts again after a crash did not inherit the ignored signal
    (:func:`dask_client`); this makes it ignore it as well.
    """
    if threading.current_thread() is threading.main_thread():
        signal.signal(signal.SIGINT, signal.SIG_IGN)


@contextmanager
def dask_client(scheduler: str, workers: int | None, option: str = "--scheduler") -> Iterator[Any]:
    """A ``dask.distributed.Client``: of a new LocalCluster of ``workers`` processes for ``"local"``,
    else connected to the scheduler at address ``scheduler``; closed (and the cluster stopped) on exit.

    Ctrl-C: a terminal sends it to the whole process group, the local workers included. They ignore it
    (started while this process ignores it, they inherit ``SIG_IGN``: Python does not install its
    ``KeyboardInterrupt`` handler then; :func:`dask_setup` covers a worker started again later), so they
    print no tracebacks; this process gets it as ``KeyboardInterrupt`` and its exit from the block stops
    them. A Ctrl-C while the workers start (a second or two) is not seen: press it again.

    Raises:
        MissingDependencyError: dask.distributed is not installed.
        DatasetError: no scheduler answers at the address within 5 s.
    """
    try:
        from dask.distributed import Client, LocalCluster
    except ImportError:
        raise MissingDependencyError(f"{option} needs dask.distributed: pip install 'featherdyn[distributed]'") from None
    cluster: Any = None
    client: Any = None
    try:
        if scheduler == "local":
            with sigint_ignored():  # the worker processes start here and inherit the ignored Ctrl-C
                # silence_logs CRITICAL: a task's error reaches this process through its future (the command
                # reports it), and what Dask logs at ERROR is its shutdown's races — a worker's heartbeat to the
                # scheduler that closed first, printed as a traceback after Ctrl-C
                cluster = LocalCluster(n_workers=workers or available_cores(), threads_per_worker=1, processes=True,
                                       dashboard_address=None, silence_logs=logging.CRITICAL,
                                       preload=[__name__])
                client = Client(cluster)
        else:
            try:
                client = Client(scheduler, timeout="5s")
            except (OSError, ValueError, TypeError) as exc:  # refused, timed out, or not an address at all
                raise DatasetError(f"{option} {scheduler}: no Dask scheduler answers there ({exc}); expected local, "
                                   "sync (dataset) or a scheduler address such as tcp://host:8786") from None
        yield client
    finally:
        with sigint_ignored():  # a second Ctrl-C does not break the shutdown into a traceback
            if client is not None:
                client.close()
            if cluster is not None:
                cluster.close()
