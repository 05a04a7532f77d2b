"""The Dask cluster of the long runs (``toothfem sweep``, ``toothfem tolerance``)."""
from __future__ import annotations

import contextlib
import os

from .errors import ToothfemError


#: The Dask setting the local cluster's workers leave unset (dask_client).
UNSET_TRIM = "distributed.nanny.pre-spawn-environ.MALLOC_TRIM_THRESHOLD_"


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
    import dask
    from distributed import Client, LocalCluster

    @contextlib.contextmanager
    def owned():
        if scheduler is None:
            # Dask sets MALLOC_TRIM_THRESHOLD_ in its workers to hand memory back eagerly;
            # setting it stops glibc from raising its mmap threshold, so every array of a
            # MB or more is mapped and zeroed afresh: the contact solves' dense tables ran
            # 3x slower in a worker than in a process (a sine ring 3.4 s against 1.1 s).
            # The workers keep glibc's own (dynamic) thresholds.
            with dask.config.set({UNSET_TRIM: None}), \
                    LocalCluster(n_workers=n_workers or os.cpu_count() or 1,
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
