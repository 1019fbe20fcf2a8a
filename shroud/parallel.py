"""Independent runs spread over local processes, or over MPI ranks under mpirun.

A sweep or a campaign calls ``map_parallel(func, items)`` and gets the results
in order on every caller; a cluster job needs no other code. mpi4py is only
imported when the process was started by an MPI launcher.
"""

from __future__ import annotations

import os
from concurrent.futures import ProcessPoolExecutor
from multiprocessing import get_context
from typing import Callable, Iterable, TypeVar

T = TypeVar("T")
R = TypeVar("R")

_MPI_ENV = ("PMI_SIZE", "OMPI_COMM_WORLD_SIZE", "MPI_LOCALNRANKS", "PMIX_RANK")


def mpi_size() -> int:
    """Number of MPI ranks this process belongs to (1 outside mpirun)."""
    if not any(k in os.environ for k in _MPI_ENV):
        return 1
    from mpi4py import MPI
    return MPI.COMM_WORLD.size


def workers() -> int:
    """Local worker processes: ``$SHROUD_WORKERS`` or the number of usable cores."""
    env = os.environ.get("SHROUD_WORKERS")
    return max(1, int(env)) if env else max(1, len(os.sched_getaffinity(0)))


def map_parallel(func: Callable[[T], R], items: Iterable[T], processes: int | None = None) -> list[R]:
    """``[func(x) for x in items]``, spread over MPI ranks or local processes.

    Under mpirun each rank takes every size-th item and the results are
    gathered on all ranks. Otherwise a fork-based process pool is used when
    more than one worker and more than one item are available. ``func`` must
    be a module-level function (it is pickled).
    """
    items = list(items)
    size = mpi_size()
    if size > 1:
        from mpi4py import MPI
        comm = MPI.COMM_WORLD
        mine = [(i, func(x)) for i, x in enumerate(items) if i % size == comm.rank]
        merged = dict(pair for part in comm.allgather(mine) for pair in part)
        return [merged[i] for i in range(len(items))]
    n = min(processes or workers(), len(items))
    if n <= 1:
        return [func(x) for x in items]
    chunk = max(1, len(items) // (4 * n))
    with ProcessPoolExecutor(max_workers=n, mp_context=get_context("fork")) as pool:
        return list(pool.map(func, items, chunksize=chunk))
