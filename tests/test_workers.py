"""Worker processes start without fork() from this (threaded) process.

Python warns that fork() from a multi-threaded process may deadlock the child
(the child holds copies of locks other threads held); the sweeps' pool once
did exactly that. Its workers now come from a fresh single-threaded server.
"""

from __future__ import annotations

import os
import threading
import warnings

from shroud.base.parallel import map_parallel


def square_and_pid(x: int) -> tuple[int, int]:
    return x * x, os.getpid()


def test_a_pool_from_a_threaded_process_forks_nothing_here_and_warns_nothing():
    stop = threading.Event()
    busy = threading.Thread(target=stop.wait, daemon=True)     # this process is multi-threaded now
    busy.start()
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            out = map_parallel(square_and_pid, range(6), processes=2)
    finally:
        stop.set()
    assert [v for v, _ in out] == [0, 1, 4, 9, 16, 25]
    assert os.getpid() not in {pid for _, pid in out}          # the items ran in worker processes
    assert not [w for w in caught if "fork" in str(w.message)], [str(w.message) for w in caught]
