"""The transient command and driver: bad input through `shroud`, outputs, linear limits."""

import json
import subprocess
import sys

import numpy as np
import pytest

from shroud.core import signals
from shroud.analysis.api import build_system
from shroud.params import Parameters
from shroud.analysis.transient import simulate

SHROUD = [sys.executable, "-m", "workbench.cli"]


@pytest.mark.parametrize("args, key", [
    (["--set", "contact.kn=-1e7"], "contact.kn"),
    (["--set", "contact.mu=-0.1"], "contact.mu"),
    (["--rpm", "0"], "speed.rpm"),
    (["--set", "time.steps_per_period=8"], "time.steps_per_period"),
    (["--set", "contact.gap=1e-4", "--set", "contact.N0=10"], "contact.gap"),
])
def test_bad_input_is_one_line_and_exit_2(tmp_path, args, key):
    out = tmp_path / "o"
    proc = subprocess.run(SHROUD + ["transient", "--out", str(out), *args], capture_output=True, text=True)
    assert proc.returncode == 2
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"error: {key}:")
    assert not out.exists()


def test_transient_command_writes_json_and_csv(tmp_path):
    proc = subprocess.run(SHROUD + ["transient", "--json", "--out", str(tmp_path), "--set", "time.periods=40"],
                          capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    data = json.loads(proc.stdout)
    assert data["steps"] == 40 * 256 and data["dofs"] == 6
    assert set(data["state_fraction"]["side1"]) == {"separate", "stick", "slip"}
    assert data["energy_balance"]["relative_error"] < 0.01
    with open(data["timeseries"]) as fh:
        head = [next(fh) for _ in range(3)]
    assert head[0].startswith("# status: complete") and "N1" in head[2]
    rows = np.loadtxt(data["timeseries"], delimiter=",")
    assert rows.shape == (40 * 256 + 1, 11)
    # Eq. 3 on the record: side forces are never negative, friction within the Coulomb cone
    assert rows[:, 5:7].min() >= 0.0
    assert np.all(np.abs(rows[:, 7:9]) <= 0.3 * rows[:, 5:7] * (1 + 1e-9) + 1e-12)


def test_gap_never_reached_is_the_free_blade():
    """The reduced blade with an unreachable gap against its linear frequency-domain steady state."""
    p = Parameters().updated({"contact.gap": 0.01, "time.periods": 120})
    system = build_system(p, "reduced")
    res = simulate(system, p)
    assert res.state_fraction["side1"]["separate"] == 1.0
    w = system.omega_e
    Q = np.linalg.solve(system.K - w * w * system.M + 1j * w * system.C, system.f_aero)
    assert res.amplitude["v_L"] == pytest.approx(abs(system.tip[0] @ Q), rel=2e-3)


def test_diverged_run_keeps_the_csv_marked_incomplete(tmp_path):
    proc = subprocess.run(SHROUD + ["transient", "--out", str(tmp_path), "--set", "time.contact=explicit",
                                    "--set", "contact.kn=1e10", "--set", "contact.kt=1e10",
                                    "--set", "time.steps_per_period=16"], capture_output=True, text=True)
    assert proc.returncode != 0
    assert "too coarse" in proc.stderr and "without bound" in proc.stderr
    with open(tmp_path / "transient_reduced.csv") as fh:
        assert fh.readline().startswith("# status: incomplete")


def test_period_detection_on_known_signals():
    spp = 64
    t = np.arange(100 * spp + 1) / spp                     # in excitation periods
    assert signals.detect_period(np.sin(2 * np.pi * t), spp) == 1
    assert signals.detect_period(np.sin(2 * np.pi * t) + 0.3 * np.sin(2 * np.pi * t / 10), spp) == 10
    assert signals.detect_period(np.sin(2 * np.pi * t) + np.sin(2 * np.pi * t / 3), spp) == 3
    assert signals.detect_period(np.sin(2 * np.pi * t) + np.sin(2 * np.pi * t * np.sqrt(2) / 7), spp) is None
    assert signals.amplitude(0.7 * np.sin(2 * np.pi * t) + 3.0, spp) == pytest.approx(0.7, rel=1e-3)
