"""Settling (shroud.analysis.sweep.Settling): a sweep point counts as a steady state only once its
amplitude has stopped changing, checked on a linear oscillator whose steady amplitude is exact."""

import math

import numpy as np
import pytest

from shroud.analysis.sweep import Settling, run_sweeps
from shroud.base.errors import InputError
from shroud.core.system import StructuralSystem
from shroud.params import Parameters

F_N, XI = 300.0, 0.01          # Hz, damping ratio


def oscillator(p: Parameters) -> StructuralSystem:
    """SDOF, f_n = 300 Hz, 1 % damping, no contact, unit force at ke Omega."""
    w = 2 * math.pi * F_N
    return StructuralSystem(model="sdof", M=np.eye(1), C=np.array([[2 * XI * w]]), K=np.array([[w * w]]),
                            f_const=np.zeros(1), f_aero=np.ones(1), omega_e=p.load.ke * p.speed.omega,
                            tip=np.array([[1.0], [0.0]]), contact=None)


def exact_amplitude(p: Parameters, rpm: float) -> float:
    w, we = 2 * math.pi * F_N, p.load.ke * 2 * math.pi * rpm / 60
    return 1 / abs(w * w - we * we + 2j * XI * w * we)


def test_a_run_at_resonance_is_extended_until_it_reaches_the_exact_steady_amplitude():
    """At resonance the amplitude builds up over 1 / (xi omega) = 16 periods: 20 periods from rest
    are a transient (marked not settled, 10 % or more short), the settled run is the steady state."""
    p = Parameters().updated({"time.periods": 20})
    rpm = 60 * F_N / p.load.ke                        # 9000 r/min: ke Omega on the natural frequency
    exact = exact_amplitude(p, rpm)
    short = run_sweeps([p], "sdof", [rpm], build=oscillator, settling=Settling(max_periods=20))[0]
    assert short.settled == (False,)
    assert short.amplitude_v_L[0] < 0.9 * exact
    settled = run_sweeps([p], "sdof", [rpm], build=oscillator)[0]
    assert settled.settled == (True,)
    # what is left of the transient once the change per 10 periods is under 0.2 %, plus O(dt^2)
    assert settled.amplitude_v_L[0] == pytest.approx(exact, rel=1e-2)


def test_settling_options_are_checked():
    with pytest.raises(InputError, match="settle_tolerance"):
        Settling.from_options({"settle_tolerance": 0.0, "settle_max_periods": 100})
    with pytest.raises(InputError, match="settle_max_periods"):
        Settling.from_options({"settle_tolerance": 1e-3, "settle_max_periods": 10})
