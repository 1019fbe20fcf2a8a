"""Tip-kinematics labels and the modal assurance criterion."""

import math

import numpy as np
import pytest

from reduced_model.modal import modal_analysis
from shroud.core.modes import label_modes, mac
from shroud.params import Parameters


def test_untwisted_rectangle_labels_follow_the_two_bending_stiffnesses():
    """At rest, untwisted: flap modes bend about the weak axis (EI_v = E b h^3/12),
    chord about the strong one; the k-th flap and chord frequencies stand in the
    ratio b/h (Euler-Bernoulli, slender), whatever the stagger."""
    b, h = 0.004, 0.001
    params = Parameters.from_mapping({
        "blade": {"length": 0.5, "width": b, "thickness": h, "stagger_deg": 37.0, "twist_deg": 0.0},
        "shroud": {"thickness": 0.0}, "reduced": {"N": 10}})
    result = modal_analysis(params, rpm=0.0, n_modes=5, coriolis=False)
    labels = [m.label for m in result.modes]
    assert labels == ["flap1", "chord1", "flap2", "flap3", "chord2"]   # 3.52, 14.1, 22.0, 61.7, 88.1
    f = result.by_label()
    assert f["chord1"] / f["flap1"] == pytest.approx(b / h, rel=1e-4)
    assert f["chord2"] / f["flap2"] == pytest.approx(b / h, rel=1e-3)
    for m in result.modes:
        assert max(m.participation.values()) > 0.999


def test_labels_are_numbered_per_kind_in_frequency_order():
    comps = np.array([[0, 0, 0, 1.0], [1.0, 0.2, 0, 0], [0.1, 1.0, 0, 0], [0, 0.1, 0.5, 0], [0.9, 0, 0, 0]])
    labels, shares = label_modes(comps)
    assert labels == ["axial1", "flap1", "chord1", "torsion1", "flap2"]
    assert shares[1]["flap"] == pytest.approx(1 / 1.04, rel=1e-3)
    assert all(math.isclose(sum(s.values()), 1.0, rel_tol=1e-3) for s in shares)


def test_mac_is_one_for_the_same_shape_and_zero_for_orthogonal_ones():
    rng = np.random.default_rng(1)
    a = rng.standard_normal((20, 3))
    q, _ = np.linalg.qr(a)
    m = mac(q, q * np.array([2.0, -3.0, 0.5j]))
    np.testing.assert_allclose(m, np.eye(3), atol=1e-12)
