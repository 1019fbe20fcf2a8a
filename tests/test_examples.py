"""Every script in examples/ runs to its last line, whose assertion holds it to an exact or published
number; the FE ones also on two MPI ranks."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = sorted((ROOT / "examples").glob("*.py"))
FE = {"fe_modal.py", "step_blade.py"}     # need the DOLFINx stack
MPI = {"fe_modal.py"}                     # also run under mpirun -n 2
MPIRUN = Path(sys.executable).parent / "mpirun"


def _run(argv: list[str], tmp_path: Path) -> subprocess.CompletedProcess:
    env = {**os.environ, "PYTHONPATH": str(ROOT), "OMP_NUM_THREADS": "1", "MPLBACKEND": "Agg"}
    return subprocess.run(argv, cwd=tmp_path, env=env, capture_output=True, text=True, timeout=1800)


def _param(path: Path):
    marks = [pytest.mark.fe] if path.name in FE else []
    return pytest.param(path, marks=marks, id=path.stem)


def test_the_examples_are_there():
    assert {"impact_oscillator.py", "table1_modal.py", "fig8_reduced.py", "api_tour.py",
            "hb_friction_oscillator.py", "ring_tuned.py"} | FE <= {p.name for p in EXAMPLES}


@pytest.mark.parametrize("path", [_param(p) for p in EXAMPLES])
def test_example_runs(path, tmp_path):
    run = _run([sys.executable, str(path)], tmp_path)
    assert run.returncode == 0, run.stdout[-2000:] + run.stderr[-4000:]
    assert "Traceback" not in run.stderr


@pytest.mark.fe
@pytest.mark.mpi
@pytest.mark.parametrize("name", sorted(MPI))
def test_fe_example_runs_on_two_ranks(name, tmp_path):
    if not MPIRUN.exists():
        pytest.skip("mpirun is not installed beside this Python")
    run = _run([str(MPIRUN), "-n", "2", sys.executable, str(ROOT / "examples" / name)], tmp_path)
    assert run.returncode == 0, run.stdout[-2000:] + run.stderr[-4000:]
    assert run.stdout.count("flap1") == 2          # the table row and the check, printed by rank 0 alone
