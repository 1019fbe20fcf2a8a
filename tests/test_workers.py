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


def test_a_sweep_over_fresh_workers_knows_the_models_and_gives_the_serial_answers(tmp_path):
    """The workers start without the parent's imports: they read the declared models from the installed
    metadata and import the modules that registered others (shroud.core.registry.packages) before their
    first point. Same amplitudes as one process."""
    import json
    import subprocess
    import sys
    from pathlib import Path
    root = Path(__file__).resolve().parents[1]
    argv = [sys.executable, "-m", "workbench.cli", "sweep", "--rpm-from", "8000", "--rpm-to", "10000",
            "--rpm-count", "3", "--set", "time.periods=20", "--json"]
    runs = {}
    for workers in ("1", "2"):
        env = {**os.environ, "OMP_NUM_THREADS": "1", "PYTHONPATH": str(root), "SHROUD_WORKERS": workers}
        proc = subprocess.run(argv, capture_output=True, text=True, env=env, timeout=600)
        assert proc.returncode == 0, proc.stderr[-2000:]
        assert "fork" not in proc.stderr
        runs[workers] = json.loads(proc.stdout)
    assert runs["2"]["amplitude_v_L"] == runs["1"]["amplitude_v_L"]
