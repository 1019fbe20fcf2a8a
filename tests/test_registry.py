"""A model is a registration: a new one runs through the analyses without any edit of the core."""

import numpy as np
import pytest

from shroud.analysis import api
from shroud.core import registry
from shroud.core.system import StructuralSystem
from shroud.params import Parameters


def _oscillator(params: Parameters) -> StructuralSystem:
    """1 DOF, m = 1 kg, k = (2 pi 100 Hz)^2, 1 % damping, unit tip row, no contact."""
    k = (2 * np.pi * 100.0) ** 2
    return StructuralSystem(model="probe-1dof", M=np.eye(1), C=np.array([[2 * 0.01 * np.sqrt(k)]]),
                            K=np.array([[k]]), f_const=np.zeros(1), f_aero=np.array([1.0]),
                            omega_e=params.load.ke * params.speed.omega, tip=np.array([[1.0], [0.0]]),
                            contact=None)


def test_a_registered_model_runs_through_the_transient_analysis(monkeypatch):
    monkeypatch.setattr(registry, "_MODELS", dict(registry._MODELS))     # the probe leaves with the test
    registry.register(registry.ModelEntry("probe-1dof", build_system=_oscillator))
    params = Parameters().updated({"speed.rpm": 1500.0, "time.periods": 60})   # 50 Hz excitation
    result = api.transient(params, "probe-1dof")
    w, wn, zeta = params.load.ke * params.speed.omega, 2 * np.pi * 100.0, 0.01
    exact = 1.0 / np.hypot(wn ** 2 - w ** 2, 2 * zeta * wn * w)      # steady harmonic amplitude
    assert result.amplitude["v_L"] == pytest.approx(exact, rel=2e-3)
    assert "probe-1dof" in registry.names("transient") and "probe-1dof" not in registry.names("modal")


def test_an_unknown_model_names_the_known_ones():
    with pytest.raises(KeyError, match="reduced"):
        registry.model("no-such-model")
