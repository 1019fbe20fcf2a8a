"""The OpenBLAS thread pools of this process, held to one thread for a block of serial work.

numpy, scipy, PETSc and basix each load their own OpenBLAS, and each
OpenBLAS keeps a pool of worker threads that spin for a while after every
call. In one process on the 2-core machine these pools take the cores from
each other and from the calling thread: the reduced solid's basis (a
shift-invert eigen-solve of small BLAS calls between MUMPS solves) took
1.8-2.2 s in some runs and 5-8 s in others on an otherwise idle machine,
with the same code; on one thread it took 1.8-2.4 s every time (whole
builds alternated, benchmarks/bench_fe_transient.py). ``OMP_NUM_THREADS=1``
does the same for a whole process, but only when set before numpy loads.

The pools are found the way threadpoolctl finds them (not a dependency of
the workbench): the OpenBLAS libraries mapped into this process, called
through their own ``*_set_num_threads`` (Linux; elsewhere nothing is found
and nothing changes). The thread count changes round-off only.
"""

from __future__ import annotations

import contextlib
import ctypes
from pathlib import Path
from typing import Callable, Iterator

# (prefix, suffix) of the thread-count functions: OpenBLAS's own, scipy-openblas 32- and 64-bit
_NAMES = (("openblas", ""), ("scipy_openblas", ""), ("scipy_openblas", "64_"))


def openblas_pools() -> list[tuple[Callable[[], int], Callable[[int], None]]]:
    """(get, set) of the thread count of every OpenBLAS library loaded in this process."""
    maps = Path("/proc/self/maps")
    if not maps.is_file():
        return []
    paths = sorted({line.split()[-1] for line in maps.read_text().splitlines()
                    if "openblas" in line.rsplit("/", 1)[-1].lower()})
    pools = []
    for path in paths:
        lib = ctypes.CDLL(path)            # already loaded: this only returns its handle
        for prefix, suffix in _NAMES:
            if hasattr(lib, f"{prefix}_set_num_threads{suffix}"):
                pools.append((getattr(lib, f"{prefix}_get_num_threads{suffix}"),
                              getattr(lib, f"{prefix}_set_num_threads{suffix}")))
                break
    return pools


@contextlib.contextmanager
def single_threaded_blas() -> Iterator[None]:
    """Every OpenBLAS loaded so far runs on one thread inside the block; their counts come back after it.

    Libraries loaded inside the block keep their own count: import the
    stack (numpy, scipy, petsc4py) before entering.
    """
    pools = openblas_pools()
    previous = [get() for get, _ in pools]
    for _, set_threads in pools:
        set_threads(1)
    try:
        yield
    finally:
        for (_, set_threads), count in zip(pools, previous):
            set_threads(count)
