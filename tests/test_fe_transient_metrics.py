"""Agreement metrics and the Pareto front used by the Fig. 8 and error-against-time studies."""

import math

import numpy as np
import pytest

from shroud.analysis.agreement import SIGNALS, agreement, nrmse, peak_error
from comparisons.error_vs_time import pareto


def test_nrmse_of_a_phase_shifted_sine_is_exact():
    """rms(sin(t + phi) - sin t) / ptp(sin) = |sin(phi/2)| / sqrt(2) over whole periods."""
    t = np.linspace(0, 2 * np.pi, 20001)[:-1]
    for phi in (0.01, 0.3, 1.0):
        assert nrmse(np.sin(t + phi), np.sin(t)) == pytest.approx(abs(math.sin(phi / 2)) / math.sqrt(2), rel=1e-9)
    assert peak_error(1.1 * np.sin(t), np.sin(t)) == pytest.approx(0.1, rel=1e-9)


def test_agreement_interpolates_a_coarser_run_onto_the_reference_window():
    period = 1e-3
    t_ref = np.linspace(0, 20 * period, 20 * 256 + 1)
    t = np.linspace(0, 20 * period, 20 * 64 + 1)
    w = 2 * np.pi / period
    ref = {s: np.sin(w * t_ref) for s in SIGNALS}
    same = {s: np.sin(w * t) for s in SIGNALS}
    fit = agreement(t, same, t_ref, ref, period, periods=10)
    # Linear interpolation of a sine sampled 64 times per period: error <= (w dt)^2 / 8.
    assert fit.worst_nrmse < (2 * np.pi / 64) ** 2 / 8
    shifted = {s: np.sin(w * t + 0.2) for s in SIGNALS}
    fit = agreement(t, shifted, t_ref, ref, period, periods=10)
    assert fit.nrmse["v_L"] == pytest.approx(math.sin(0.1) / math.sqrt(2), rel=2e-3)


def test_agreement_refuses_a_run_that_stops_before_the_window():
    t_ref = np.linspace(0, 1.0, 101)
    ref = {s: np.sin(t_ref) for s in SIGNALS}
    with pytest.raises(ValueError, match="does not cover"):
        agreement(t_ref[:50], {s: v[:50] for s, v in ref.items()}, t_ref, ref, 0.1, periods=3)


def test_pareto_front_keeps_only_undominated_points():
    times = np.array([1.0, 2.0, 3.0, 4.0, 2.5])
    errors = np.array([0.5, 0.1, 0.2, 0.01, 0.1])
    assert pareto(times, errors).tolist() == [True, True, False, True, False]
