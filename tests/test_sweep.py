"""Sweeps over speed: the resonance of a linear oscillator, and the reduced model's primary resonance."""

import math

import numpy as np
import pytest

from shroud.params import Parameters
from shroud.analysis.sweep import run_sweep, run_sweeps
from shroud.core.system import StructuralSystem

F_N = 300.0      # Hz


def oscillator(p: Parameters) -> StructuralSystem:
    """SDOF, f_n = 300 Hz, 1 % damping, no contact, excited at ke Omega."""
    w = 2 * math.pi * F_N
    return StructuralSystem(model="sdof", M=np.eye(1), C=np.array([[2 * 0.01 * w]]), K=np.array([[w * w]]),
                            f_const=np.zeros(1), f_aero=np.ones(1), omega_e=p.load.ke * p.speed.omega,
                            tip=np.array([[1.0], [0.0]]), contact=None)


def test_linear_resonance_where_ke_omega_meets_the_natural_frequency():
    p = Parameters().updated({"time.periods": 300})
    rpms = np.linspace(8000, 10000, 41)
    res = run_sweeps([p], "sdof", rpms, build=oscillator)[0]
    r = 60 * F_N / p.load.ke                                       # 9000 r/min
    assert res.resonance["rpm"] == pytest.approx(r, abs=50.0)
    w = 2 * math.pi * F_N
    exact = 1 / np.abs(w * w - (p.load.ke * 2 * np.pi * rpms / 60) ** 2
                       + 2j * 0.01 * w * p.load.ke * 2 * np.pi * rpms / 60)
    assert res.amplitude_v_L == pytest.approx(exact, rel=5e-3)   # O(dt^2) frequency shift x Q


def test_reduced_model_primary_resonance_at_a_large_gap():
    """Paper Sect. 3.1: at a 0.6 mm gap, 2 f_r meets the first frequency near 8500 r/min."""
    p = Parameters().updated({"contact.gap": 6e-4, "contact.alpha_deg": 30.0, "contact.kt": 5e6,
                              "time.periods": 100})
    res = run_sweep(p, "reduced", np.arange(7000, 10001, 250))
    assert 7750 <= res.resonance["rpm"] <= 9250
    assert all(per == 1 for per in res.period)
