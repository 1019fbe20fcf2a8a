"""Rayleigh damping (paper Eq. 2, with the printed beta's sign corrected)."""

import math

import pytest

from reduced_model.reduction import undamped_modes
from reduced_model.system import build_system
from shroud.core.damping import rayleigh
from shroud.params import Parameters


def test_first_two_modes_of_the_beam_get_back_xi1_xi2():
    """Modal damping phi^T D phi / (2 w) of the mass-normalized modes of the built system."""
    params = Parameters.from_mapping({"speed": {"rpm": 0.0}, "damping": {"xi1": 0.02, "xi2": 0.04},
                                      "reduced": {"nr": 0}})
    system = build_system(params, reduced=False)          # at rest: C = D (no Coriolis)
    modes = undamped_modes(system.M, system.K)
    for k, xi in enumerate((0.02, 0.04)):
        phi, w = modes.shapes[:, k], 2 * math.pi * modes.f_hz[k]
        assert phi @ system.C @ phi / (2 * w) == pytest.approx(xi, rel=1e-9)


def test_printed_beta_would_miss_the_targets():
    """The paper's beta = (f2 xi2 - f1 xi1) / (pi (f1^2 - f2^2)) has the opposite sign:
    it would give modes 1 and 2 damping ratios other than xi1, xi2."""
    f1, f2, xi1, xi2 = 282.5, 1117.6, 0.02, 0.04
    alpha, beta = rayleigh(f1, f2, xi1, xi2)
    ratio = lambda f, b: alpha / (4 * math.pi * f) + b * math.pi * f
    assert ratio(f1, beta) == pytest.approx(xi1) and ratio(f2, beta) == pytest.approx(xi2)
    printed = (f2 * xi2 - f1 * xi1) / (math.pi * (f1**2 - f2**2))
    assert printed == pytest.approx(-beta)
    assert abs(ratio(f2, printed) - xi2) > 0.01


def test_equal_frequencies_are_refused():
    with pytest.raises(ValueError):
        rayleigh(100.0, 100.0, 0.02, 0.04)
