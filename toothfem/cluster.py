"""The Dask cluster of the long runs (``toothfem sweep``, ``toothfem tolerance``)."""
from __future__ import annotations

import contextlib
import os

from .errors import ToothfemError


def dask_client(scheduler, n_workers):
    """A context manager giving a ``distributed.Client``.

    Parameters
    ----------
    scheduler : None, str or distributed.Client
        None: a LocalCluster of ``n_workers`` single-threaded processes (default one per
        CPU), closed on exit; a scheduler address; or a Client the caller owns.
    n_workers : int or None
        Workers of the local cluster.

    Returns
    -------
    contextlib.AbstractContextManager
    """
    from distributed import Client, LocalCluster

    @contextlib.contextmanager
    def owned():
        if scheduler is None:
            with LocalCluster(n_workers=n_workers or os.cpu_count() or 1,
                              threads_per_worker=1, processes=True,
                              dashboard_address=":0") as cluster, Client(cluster) as client:
                yield client
        elif isinstance(scheduler, Client):
            yield scheduler
        else:
            try:
                client = Client(scheduler)
            except (OSError, ValueError, TimeoutError) as exc:
                raise ToothfemError(f"scheduler = {scheduler!r}: no Dask scheduler there "
                                    f"({exc}); valid: an address such as "
                                    "tcp://host:8786") from None
            with client:
                yield client
    return owned()
