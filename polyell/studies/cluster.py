"""A local Dask cluster set up for sweeps: one single-threaded worker process per core.

Dask's nannies start workers with ``MALLOC_TRIM_THRESHOLD_=65536``
(``distributed.nanny.pre-spawn-environ``).  Setting it switches off glibc's adaptive
allocation thresholds, so that every numpy temporary above 128 kB is a fresh ``mmap``
that page-faults on first touch; a sweep, which allocates many such temporaries, then
ran 1.4 to 2 times more slowly in a worker than in a plain process on the benchmark
machine (``docs/performance.md`` measures it).  :func:`local_cluster` leaves the
variable unset and gives every worker one BLAS thread, whatever this process's
``OPENBLAS_NUM_THREADS``.  Workers of a cluster started
elsewhere (``scheduler="tcp://..."``) profit from the same setting.
"""

from __future__ import annotations

import os
import re
from typing import Any

from polyell.errors import InputError, MissingDependencyError, install_hint

__all__ = ["check_scheduler", "local_cluster"]

#: A Dask scheduler address: ``tcp://`` or ``tls://`` with a host name, an IPv4 address or
#: an IPv6 address in brackets and an optional port (Dask's default 8786), or
#: ``inproc://ip/pid/suffix``, the address of a scheduler in this process.
_ADDRESS = re.compile(
    r"(?:(?:tcp|tls)://(?:\[[0-9A-Fa-f:.]+\]|[A-Za-z0-9_](?:[A-Za-z0-9_.-]{0,252}))"
    r"(?::(?P<port>[0-9]{1,5}))?"
    r"|inproc://[0-9A-Za-z.:_-]{1,100}/[0-9]{1,10}/[0-9A-Za-z_-]{1,100})"
)
#: What a scheduler may be, for messages.
SCHEDULERS = "None, 'processes' or a Dask scheduler address tcp://host:port (or tls://, inproc://)"


def check_scheduler(scheduler: object) -> str | None:
    """Check where a sweep runs: ``None``, ``"processes"`` or a Dask scheduler address.

    The address is checked before any connection is tried, so a malformed one (a port that
    is not a number from 1 to 65535, an unclosed IPv6 bracket, a path) is refused with its
    expected form instead of failing inside Dask.

    Parameters
    ----------
    scheduler : object
        What the caller gave.

    Returns
    -------
    None or str
        ``scheduler`` unchanged.

    Raises
    ------
    InputError
        If it is none of the three.
    """
    if scheduler is None:
        return None
    if not isinstance(scheduler, str):
        raise InputError(
            "scheduler",
            SCHEDULERS,
            f"{type(scheduler).__name__} {scheduler!r}"[:120],
            "pass the address as a string, e.g. 'tcp://127.0.0.1:8786', or None to run here.",
        )
    if scheduler == "processes":
        return scheduler
    match = _ADDRESS.fullmatch(scheduler)
    port = None if match is None or match.group("port") is None else int(match.group("port"))
    if match is None or (port is not None and not 1 <= port <= 65535):
        shown = repr(scheduler) if len(scheduler) <= 80 else repr(scheduler[:77]) + "..."
        raise InputError(
            "scheduler",
            SCHEDULERS,
            shown,
            "give the address 'dask scheduler' prints, e.g. tcp://127.0.0.1:8786 "
            "(IPv6 in brackets: tcp://[::1]:8786), or 'processes' for a local cluster.",
        )
    return scheduler


#: The thread counts of the BLAS and OpenMP runtimes: one per worker process.
_ONE_THREAD = ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS")


def local_cluster(n_workers: int | None = None) -> Any:
    """Start a Dask cluster of worker processes on this machine, on the loopback interface.

    Parameters
    ----------
    n_workers : int, optional
        Worker processes, one thread each; default one per core.

    Returns
    -------
    distributed.LocalCluster
        Pass ``cluster.scheduler_address`` as ``scheduler=`` to :func:`polyell.sweep`; use
        it as a context manager (``with pe.local_cluster() as cluster:``) to close it.

    Raises
    ------
    MissingDependencyError
        Without Dask (extra ``polyell[studies]``).
    """
    try:
        import dask
        from dask.distributed import LocalCluster
    except ImportError as exn:
        raise MissingDependencyError(
            "Distributed sweeps need Dask. Fix: " + install_hint("studies") + "."
        ) from exn
    count = (os.cpu_count() or 1) if n_workers is None else n_workers
    if not isinstance(count, int) or isinstance(count, bool) or count < 1:
        raise InputError(
            "n_workers",
            "a positive number of worker processes",
            repr(n_workers),
            "pass an int of at least 1, e.g. n_workers=4, or None for one per core.",
        )
    # None unsets a variable of the nannies' environment (distributed.nanny).  The nannies
    # take a thread count from this process's environment before their own defaults of 1,
    # and numpy reads it when a worker imports it: set it for the spawns, then restore it.
    saved = {name: os.environ.pop(name, None) for name in _ONE_THREAD}
    os.environ.update(dict.fromkeys(_ONE_THREAD, "1"))
    try:
        with dask.config.set({"distributed.nanny.pre-spawn-environ.MALLOC_TRIM_THRESHOLD_": None}):
            return LocalCluster(
                n_workers=count,
                threads_per_worker=1,
                processes=True,
                host="127.0.0.1",
                dashboard_address=None,
            )
    finally:
        for name, value in saved.items():
            if value is None:
                os.environ.pop(name, None)
            else:
                os.environ[name] = value
