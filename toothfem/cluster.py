"""The Dask cluster of the long runs (``toothfem sweep``, ``toothfem tolerance``).

A run never waits on the cluster without a bound (issue 27):

- reaching a scheduler (connection and handshake) takes at most 25 s: an
  address where nothing answers, or something that accepts and never replies, ends there
  (Dask's own ``timeout`` does not bound the handshake: measured, it waited for ever);
- a cluster without a worker (none at the start, or the last one lost) is waited on for
  NO_WORKER_TIMEOUT_S, then the run stops;
- a scheduler that stops answering mid-run stops the run at once (its futures are
  cancelled; Dask reconnects for a few seconds first).

The first is refused as bad input (ToothfemError), the others end in :class:`ClusterError`;
each is one line, and the finished points are kept by the caller
(:func:`toothfem.output.resumable_dir`). Work of a lost worker is resubmitted by the
scheduler itself (Dask's ``allowed-failures``, default 3 tries) while another worker is
there.
"""
from __future__ import annotations

import contextlib
import logging
import os
import signal
import threading
import time

from .errors import IncompleteRun, ToothfemError


#: The Dask setting the local cluster's workers leave unset (dask_client).
UNSET_TRIM = "distributed.nanny.pre-spawn-environ.MALLOC_TRIM_THRESHOLD_"
#: Seconds to reach a scheduler, handshake included.
CONNECT_TIMEOUT_S = 20.0
#: The connecting thread is waited on this times CONNECT_TIMEOUT_S, so that Dask's own
#: errors (refused, unknown host) arrive with their words before ours.
CONNECT_GRACE = 1.25
#: Seconds a run waits while the cluster has no worker before it stops (a local worker
#: that dies is restarted by its nanny in a few seconds).
NO_WORKER_TIMEOUT_S = 30.0
#: Seconds between two looks at the cluster while waiting for results.
POLL_S = 1.0


class ClusterError(IncompleteRun):
    """The cluster cannot finish the run: no scheduler, no worker, or the scheduler lost."""


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

    Raises
    ------
    ToothfemError
        (On entry) when no scheduler answers at ``scheduler`` within CONNECT_TIMEOUT_S.
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
            with _dask_logs_quiet(), dask.config.set({UNSET_TRIM: None}), \
                    LocalCluster(n_workers=n_workers or os.cpu_count() or 1,
                                 threads_per_worker=1, processes=True,
                                 dashboard_address=":0", preload=[__name__]) as cluster, \
                    Client(cluster) as client:
                yield client
        elif isinstance(scheduler, Client):
            yield scheduler
        else:
            with _dask_logs_quiet(), _connect(Client, scheduler) as client:
                _a_worker(client)
                yield client
    return owned()


#: Dask's loggers are held at this level while a toothfem run owns the client: their
#: warnings and errors on shutdown, a Ctrl-C or a lost scheduler (a cancelled task, a
#: closed connection with its traceback) repeat what the run's one line says
#: (TOOTHFEM_DEBUG=1 keeps them).
DASK_LOG_LEVEL = logging.CRITICAL


@contextlib.contextmanager
def _dask_logs_quiet():
    if os.environ.get("TOOTHFEM_DEBUG"):
        yield
        return
    before = _set_dask_levels(DASK_LOG_LEVEL)
    try:
        yield
    finally:
        for logger, level in before:
            logger.setLevel(level)


#: The loggers held quiet: Dask's own, and tornado's, whose event loop logs the errors of
#: distributed's callbacks (on a Ctrl-C, distributed 2026.11's ``sync.cancel`` logged a
#: NameError traceback through ``tornado.application`` after the run's one line).
QUIET_LOGGERS = ("distributed", "tornado")


def _set_dask_levels(level) -> list:
    """Set every logger of QUIET_LOGGERS and below (Dask's configuration gives some their
    own level) to ``level``; returns [(logger, its level before)]."""
    loggers = [logging.getLogger(n) for n in list(logging.root.manager.loggerDict)
               if n in QUIET_LOGGERS or n.startswith(tuple(q + "." for q in QUIET_LOGGERS))]
    before = [(lg, lg.level) for lg in loggers]
    for lg in loggers:
        lg.setLevel(level)
    return before


def dask_setup(worker) -> None:
    """Dask's preload hook, run in each worker of the local cluster as it starts: the
    worker ignores SIGINT and logs as the run does (DASK_LOG_LEVEL). A Ctrl-C at the
    terminal reaches the whole process group; the command stops and closes its cluster,
    and a worker that also raised printed its own traceback (issue 27).

    Parameters
    ----------
    worker : distributed.Worker
        The worker starting (unused).
    """
    if threading.current_thread() is threading.main_thread():
        signal.signal(signal.SIGINT, signal.SIG_IGN)
    if not os.environ.get("TOOTHFEM_DEBUG"):
        _set_dask_levels(DASK_LOG_LEVEL)


def _connect(Client, address):
    """``Client(address)`` within CONNECT_TIMEOUT_S: made in a daemon thread, which is
    abandoned (and ends with the process) when the handshake never completes."""
    box = {}

    def connect():
        try:
            box["client"] = Client(address, timeout=CONNECT_TIMEOUT_S)
        except Exception as exc:        # noqa: BLE001 -- reported below, in one line
            box["error"] = exc

    thread = threading.Thread(target=connect, name="toothfem-connect", daemon=True)
    thread.start()
    thread.join(CONNECT_TIMEOUT_S * CONNECT_GRACE)      # (a silent address: abandoned)
    if "client" in box:
        return box["client"]
    waited = CONNECT_TIMEOUT_S * CONNECT_GRACE
    why = (f"no answer within {waited:.0f} s" if thread.is_alive() else
           f"{type(box['error']).__name__}: {box['error']}".splitlines()[0])
    raise ToothfemError(f"scheduler = {address!r}: no Dask scheduler there ({why}); valid: "
                       "the address of a running scheduler, such as tcp://host:8786")


def _a_worker(client) -> None:
    """Wait up to NO_WORKER_TIMEOUT_S for the scheduler to have a worker (a scheduler
    without one is found before any work is prepared for it)."""
    try:
        client.wait_for_workers(1, timeout=NO_WORKER_TIMEOUT_S)
    except TimeoutError:
        raise _no_worker(client.scheduler.address, NO_WORKER_TIMEOUT_S, None) from None


def _no_worker(address, seconds, waiting) -> ClusterError:
    tasks = "" if waiting is None else f" ({waiting} tasks waiting)"
    return ClusterError(f"the Dask scheduler at {address} has had no worker for "
                        f"{seconds:.0f} s{tasks}; start workers (dask worker {address}) and "
                        "run again")


def as_finished(client, futures, *, no_worker_timeout_s: float | None = None):
    """Yield each of ``futures`` as it finishes, watching the cluster in between.

    Parameters
    ----------
    client : distributed.Client
    futures : iterable of distributed.Future
    no_worker_timeout_s : float, optional
        How long the cluster may have no worker while work is pending (default
        NO_WORKER_TIMEOUT_S).

    Yields
    ------
    distributed.Future
        A finished one (its ``result()`` may still raise the task's error).

    Raises
    ------
    ClusterError
        When the cluster has had no worker for ``no_worker_timeout_s``, or the scheduler
        stopped answering (the pending futures were cancelled).
    """
    from distributed import wait

    if no_worker_timeout_s is None:
        no_worker_timeout_s = NO_WORKER_TIMEOUT_S
    pending = list(futures)
    address = getattr(client.scheduler, "address", "?")
    idle_since = None
    while pending:
        try:
            done, _ = wait(pending, timeout=POLL_S, return_when="FIRST_COMPLETED")
        except TimeoutError:
            done = set()
        except Exception as exc:        # noqa: BLE001 -- cancelled futures: scheduler lost
            raise _lost(address, exc) from None
        for fut in [f for f in pending if f in done]:
            if fut.status == "cancelled":
                raise _lost(address, "its work was cancelled")
            yield fut
        pending = [f for f in pending if f not in done]
        if not pending:
            return
        if client.status != "running":
            raise _lost(address, f"client {client.status}")
        try:
            workers = len(client.scheduler_info().get("workers", {}))
        except Exception as exc:        # noqa: BLE001 -- the client is closing
            raise _lost(address, exc) from None
        if workers:
            idle_since = None
        elif idle_since is None:
            idle_since = time.monotonic()
        elif time.monotonic() - idle_since > no_worker_timeout_s:
            raise _no_worker(address, no_worker_timeout_s, len(pending))


def _lost(address, why) -> ClusterError:
    why = f"{type(why).__name__}: {why}" if isinstance(why, BaseException) else str(why)
    return ClusterError(f"the Dask scheduler at {address} stopped answering "
                        f"({why.splitlines()[0] if why else 'no reason given'})")
