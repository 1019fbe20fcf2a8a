"""One writer per output folder, and every file of a run in place whole or not at all.

Two runs into one ``--out`` folder once left a time series ending in the other
run's row under ``# status: complete``. Now the second run is refused with one
line (exit 2) while the first holds the folder, and the first run's files are
those of the same run made alone.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from shroud.core.verdict import is_cost_record
from workbench.compare import is_timing

from workbench.cli import main
from shroud.base.outputs import LOCK_NAME, FolderLock, open_replacing, write_text

ROOT = Path(__file__).resolve().parents[1]
SHROUD = [sys.executable, "-m", "workbench.cli"]


def _env() -> dict:
    return {**os.environ, "OMP_NUM_THREADS": "1", "PYTHONPATH": str(ROOT)}


def _files(folder: Path) -> dict[str, bytes]:
    return {str(p.relative_to(folder)): p.read_bytes() for p in sorted(folder.rglob("*"))
            if p.is_file() and p.name != LOCK_NAME}


def _numbers(value):
    """``value`` without its costs (what the machine took, not results), recognised as `shroud compare`
    recognises them (workbench.compare.is_timing, and values whose unit says they were drawn from run time or
    memory)."""
    if isinstance(value, dict):
        return {k: _numbers(v) for k, v in value.items()
                if not (is_timing(k) or is_cost_record(v))}
    if isinstance(value, list):
        return [_numbers(v) for v in value]
    return value


def test_a_folder_held_by_another_run_is_refused_with_one_line(tmp_path, capsys):
    out = tmp_path / "out"
    with FolderLock(out):
        code = main(["run", str(ROOT / "scenes/fig3.toml"), "--quick", "--out", str(out)])
        err = capsys.readouterr().err.strip().splitlines()
        assert code == 2
        assert err[-1].startswith("error: --out:") and "being written by another run" in err[-1]
        assert f"pid {os.getpid()}" in err[-1] and "allowed:" in err[-1]
        assert _files(out) == {}                      # nothing of the refused run
        for argv in (["transient", "--out", str(out)],):
            assert main(argv) == 2
            assert capsys.readouterr().err.count("being written by another run") == 1


@pytest.mark.slow
def test_two_concurrent_runs_into_one_folder(tmp_path):
    """The second of two real runs is refused while the first writes; the first's files equal a lone run's."""
    scene = [str(ROOT / "scenes/fig4.toml"), "--quick"]
    shared, alone = tmp_path / "shared", tmp_path / "alone"
    first = subprocess.Popen([*SHROUD, "run", *scene, "--out", str(shared)], env=_env(),
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    lock = shared / LOCK_NAME
    deadline = time.monotonic() + 120
    while not (lock.exists() and f"pid {first.pid} " in lock.read_text()):
        assert first.poll() is None and time.monotonic() < deadline, "the first run never held its folder"
        time.sleep(0.05)
    second = subprocess.run([*SHROUD, "run", *scene, "--out", str(shared)], env=_env(),
                            capture_output=True, text=True, timeout=300)
    assert first.poll() is None, "the first run ended before the second tried: no concurrency was tested"
    assert second.returncode == 2, second.stderr
    assert second.stderr.count("\n") == 1 and "being written by another run" in second.stderr
    assert first.wait(timeout=600) == 0, first.stderr
    subprocess.run([*SHROUD, "run", *scene, "--out", str(alone)], env=_env(), check=True,
                   capture_output=True, timeout=600)
    a, b = _files(shared), _files(alone)
    assert sorted(a) == sorted(b)
    csvs = [name for name in a if name.endswith(".csv")]
    assert csvs and all(a[n] == b[n] for n in csvs)              # the time series: byte for byte
    ra, rb = (json.loads(x["results.json"]) for x in (a, b))
    assert ra["status"] == rb["status"] == "complete" and _numbers(ra["results"]) == _numbers(rb["results"])
    assert not [p for p in shared.rglob("*") if ".tmp" in p.name]


def test_a_killed_run_leaves_no_lock_behind(tmp_path, capsys):
    out = tmp_path / "out"
    holder = subprocess.Popen([sys.executable, "-c", "import signal, sys; from shroud.base.outputs import "
                               "FolderLock; lock = FolderLock(sys.argv[1]); lock.acquire(); print('held', flush=True); "
                               "signal.pause()", str(out)], env=_env(), stdout=subprocess.PIPE, text=True)
    assert holder.stdout.readline().strip() == "held"
    assert main(["run", str(ROOT / "scenes/fig3.toml"), "--quick", "--out", str(out)]) == 2
    capsys.readouterr()
    holder.send_signal(signal.SIGKILL)
    holder.wait()
    assert main(["run", str(ROOT / "scenes/fig3.toml"), "--quick", "--out", str(out)]) == 0
    assert json.loads((out / "results.json").read_text())["status"] == "complete"


def test_a_write_cut_short_leaves_the_earlier_file_whole(tmp_path):
    path = tmp_path / "table.csv"
    write_text(path, "a,b\n1,2\n")
    with pytest.raises(RuntimeError):
        with open_replacing(path) as fh:
            fh.write("a,b\n3,")
            raise RuntimeError("killed mid-write")
    assert path.read_text() == "a,b\n1,2\n"
    assert [p.name for p in tmp_path.iterdir()] == ["table.csv"]
