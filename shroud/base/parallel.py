"""Independent runs spread over local processes, or over MPI ranks under mpirun.

A sweep or a campaign calls ``map_parallel(func, items)`` and gets the results
in order on every caller; a cluster job needs no other code. mpi4py is only
imported when the process was started by an MPI launcher.
"""

from __future__ import annotations

import importlib
import os
import signal
from multiprocessing import get_context
from typing import Callable, Iterable, TypeVar

T = TypeVar("T")
R = TypeVar("R")

_MPI_ENV = ("PMI_SIZE", "OMPI_COMM_WORLD_SIZE", "MPI_LOCALNRANKS", "PMIX_RANK")
_IN_TASK = False


def mpi_size() -> int:
    """Number of MPI ranks this process belongs to (1 outside mpirun)."""
    if not any(k in os.environ for k in _MPI_ENV):
        return 1
    from mpi4py import MPI
    return MPI.COMM_WORLD.size


def mpi_rank() -> int:
    """This process's MPI rank (0 outside mpirun)."""
    if mpi_size() == 1:
        return 0
    from mpi4py import MPI
    return MPI.COMM_WORLD.rank


def in_task() -> bool:
    """True while running one item of ``map_parallel`` (a run on its own)."""
    return _IN_TASK


def task_comm():
    """The MPI communicator an FE build should use.

    The whole job (COMM_WORLD) when all ranks run one scene together; the
    rank alone (COMM_SELF) inside a ``map_parallel`` item, where each rank
    runs a different scene and a collective call would deadlock.
    """
    from mpi4py import MPI
    return MPI.COMM_SELF if _IN_TASK else MPI.COMM_WORLD


def workers() -> int:
    """Local worker processes: ``$SHROUD_WORKERS`` or the number of usable cores."""
    env = os.environ.get("SHROUD_WORKERS")
    return max(1, int(env)) if env else max(1, len(os.sched_getaffinity(0)))


def map_parallel(func: Callable[[T], R], items: Iterable[T], processes: int | None = None,
                 preload: Iterable[str] = ()) -> list[R]:
    """``[func(x) for x in items]``, spread over MPI ranks or local processes.

    Under mpirun each rank takes every size-th item and the results are
    gathered on all ranks. Otherwise a process pool is used when more than
    one worker and more than one item are available; its workers are forked
    from a fresh single-threaded server (``forkserver``, ``func``'s module
    preloaded there), never from this process, whose BLAS and numba threads
    a fork would copy half-held (the deadlock Python warns of). ``func`` must
    be a module-level function (it is pickled); ``preload`` names modules a
    fresh worker imports first (e.g. the packages that register the models
    ``func`` looks up: shroud.core.registry.packages()). Inside an item of an outer
    map (a sweep within a campaign) the map runs serially in place.
    """
    items = list(items)
    if _IN_TASK:
        return [func(x) for x in items]
    size = mpi_size()
    if size > 1:
        from mpi4py import MPI
        comm = MPI.COMM_WORLD
        mine = [(i, _as_task(func, x)) for i, x in enumerate(items) if i % size == comm.rank]
        merged = dict(pair for part in comm.allgather(mine) for pair in part)
        return [merged[i] for i in range(len(items))]
    n = min(processes or workers(), len(items))
    if n <= 1:
        return [func(x) for x in items]
    chunk = max(1, len(items) // (4 * n))
    # Leaving the block terminates the workers: an interrupted map stops at
    # once instead of finishing every queued item first.
    preload = [func.__module__, *preload]
    context = get_context("forkserver")
    context.set_forkserver_preload(preload)                # takes effect when the server first starts
    with context.Pool(n, initializer=_enter_worker, initargs=(tuple(preload),)) as pool:
        return pool.map(func, items, chunksize=chunk)


def on_rank_zero(func: Callable[[], R]) -> R:
    """``func()`` run by rank 0 alone (FE work on COMM_SELF) while the others wait; its result on every rank.

    For serial-only work inside a job whose ranks run one study together:
    a reduction basis built once and shared through the disk cache. An
    error raised on rank 0 is raised on every rank. Outside mpirun, or
    inside an item of a spread map, it is just ``func()``.
    """
    if _IN_TASK or mpi_size() == 1:
        return func()
    from mpi4py import MPI
    comm = MPI.COMM_WORLD
    result, error = None, None
    if comm.rank == 0:
        try:
            result = _as_task(lambda _: func(), None)
        except Exception as exc:       # handed to every rank below
            error = exc
    result, error = comm.bcast((result, error), root=0)
    if error is not None:
        raise error
    return result


def _as_task(func: Callable[[T], R], item: T) -> R:
    global _IN_TASK
    _IN_TASK = True
    try:
        return func(item)
    finally:
        _IN_TASK = False


def _enter_worker(preload: tuple[str, ...] = ()) -> None:
    # A worker runs its items on its own (no nested pools, FE on COMM_SELF);
    # Ctrl-C is the parent's to handle, and a terminate ends the worker.
    global _IN_TASK
    _IN_TASK = True
    for module in preload:              # imported in the server already, unless it started earlier
        importlib.import_module(module)
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
