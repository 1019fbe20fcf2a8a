"""comparisons._peaks: a branch's resonance located at twice its harmonics, against the resonance found
without harmonic balance."""

from pathlib import Path

import numpy as np
from scipy.optimize import minimize_scalar

from comparisons._peaks import converged_peak, same_peak
from shroud.analysis.hb import model_at_speed, run_hb
from workbench.scene import load_scene

SCENES = Path(__file__).resolve().parents[1] / "scenes"


def test_converged_peak_is_the_linear_resonance():
    """With a 600 um gap the shroud never touches (the resonance is 553 um), so the beam is linear: its
    resonance is the top over speed of the amplitude of tip (K - w^2 M + i w C)^-1 f_aero, the system's own
    matrices at each speed, found here by a bounded scalar search. The branch (30 points over 7000-10000 r/min) puts
    its top 20 r/min and 0.2 % off; the located one must lie within its own errors of the true top."""
    params = load_scene(SCENES / "hb_fig4.toml").params.updated({"contact.gap": 600e-6})
    branch = run_hb(params, "reduced", 7000.0, 10000.0, harmonics=3, samples=64)
    peak = converged_peak(branch, params, "reduced")
    build = model_at_speed(params, "reduced")

    def minus_amplitude(rpm: float) -> float:
        """-(max - min) / 2 of v_L = Im(z e^(i tau)) on 512 instants of the period, as the project's amplitude
        is read (shroud.core.harmonic_balance.amplitude_over_period): up to 1 - cos(pi / 512) = 1.9e-5 below
        |z| depending on the phase, which moves the top by 0.5 r/min here."""
        s = build(rpm)
        z = s.tip[0] @ np.linalg.solve(s.K - s.omega_e ** 2 * s.M + 1j * s.omega_e * s.C, s.f_aero)
        v = np.imag(z * np.exp(2j * np.pi * np.arange(512) / 512))
        return -(v.max() - v.min()) / 2

    top = minimize_scalar(minus_amplitude, bounds=(8000.0, 9000.0), method="bounded", options={"xatol": 1e-4})
    assert peak["where"] == "inside" and peak["rpm_error"] < 1.0, peak
    assert abs(peak["rpm"] - top.x) <= peak["rpm_error"], (peak, top.x)
    assert abs(peak["amplitude_m"] + top.fun) <= peak["amplitude_error_m"] + 1e-9 * -top.fun, (peak, -top.fun)
    at_end = converged_peak(run_hb(params, "reduced", 7000.0, 8200.0, harmonics=3, samples=64), params, "reduced")
    assert at_end["where"] == "range end" and at_end["rpm"] == 8200.0
    assert abs(at_end["amplitude_m"] + minus_amplitude(8200.0)) <= at_end["amplitude_error_m"]
    assert same_peak(peak, at_end, ("top", "below it")).answer == "different"
