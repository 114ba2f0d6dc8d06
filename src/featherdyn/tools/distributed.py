"""A ``dask.distributed`` client for the commands that spread work (tools layer).

``featherdyn dataset`` and ``featherdyn verify --all`` take ``--scheduler``:
``local`` starts a ``LocalCluster`` of worker processes on this machine (one
thread each), any other value is the address of a running scheduler.
"""

from __future__ import annotations

import logging
import os
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

from ..errors import DatasetError, MissingDependencyError

__all__ = ["available_cores", "dask_client"]


def available_cores() -> int:
    """The cores this process may run on."""
    return len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1)


@contextmanager
def dask_client(scheduler: str, workers: int | None, option: str = "--scheduler") -> Iterator[Any]:
    """A ``dask.distributed.Client``: of a new LocalCluster of ``workers`` processes for ``"local"``,
    else connected to the scheduler at address ``scheduler``; closed (and the cluster stopped) on exit.

    Raises:
        MissingDependencyError: dask.distributed is not installed.
        DatasetError: no scheduler answers at the address within 5 s.
    """
    try:
        from dask.distributed import Client, LocalCluster
    except ImportError:
        raise MissingDependencyError(f"{option} needs dask.distributed: pip install 'featherdyn[distributed]'") from None
    cluster = None
    if scheduler == "local":
        cluster = LocalCluster(n_workers=workers or available_cores(), threads_per_worker=1, processes=True,
                               dashboard_address=None, silence_logs=logging.ERROR)
        client = Client(cluster)
    else:
        try:
            client = Client(scheduler, timeout="5s")
        except (OSError, ValueError, TypeError) as exc:  # refused, timed out, or not an address at all
            raise DatasetError(f"{option} {scheduler}: no Dask scheduler answers there ({exc}); expected local, sync "
                               "(dataset) or a scheduler address such as tcp://host:8786") from None
    try:
        yield client
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
