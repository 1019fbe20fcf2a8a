"""The beam model as a StructuralSystem: reduction, loads, contact rows."""

import math

import numpy as np
import pytest
import scipy.linalg
from scipy.integrate import quad

from reduced_model.system import build_system
from shroud.params import Parameters

NU = 0.3


def eigenfrequencies(system):
    return np.sqrt(scipy.linalg.eigh(system.K, system.M, eigvals_only=True)) / (2 * math.pi)


def test_free_interface_reduction_keeps_the_lowest_modes_exactly():
    """Eigenvectors span invariant subspaces: nr kept modes give the nr lowest
    frequencies of the full 5N model, and nr = 5N gives all of them."""
    params = Parameters.from_mapping({"speed": {"rpm": 8500.0}})
    full = build_system(params, reduced=False)
    reduced = build_system(params, reduced=True)
    assert (full.dofs, reduced.dofs, full.model, reduced.model) == (30, 6, "full", "reduced")
    np.testing.assert_allclose(eigenfrequencies(reduced), eigenfrequencies(full)[:6], rtol=1e-10)
    every = build_system(params.with_overrides(["reduced.nr=30"]), reduced=True)
    np.testing.assert_allclose(eigenfrequencies(every), eigenfrequencies(full), rtol=1e-9)


def test_contact_rows_are_eq7_of_the_tip_rows():
    params = Parameters.from_mapping({"contact": {"alpha_deg": 30.0}})
    for reduced in (False, True):
        s = build_system(params, reduced)
        a = math.radians(30.0)
        np.testing.assert_allclose(s.contact.W[0], math.cos(a) * s.tip[0] + math.sin(a) * s.tip[1])
        np.testing.assert_allclose(s.contact.W[1], -math.sin(a) * s.tip[0] + math.cos(a) * s.tip[1])
        assert list(s.contact.side) == [1, 2] and list(s.contact.normal_row) == [0, 0]
        assert list(s.contact.tangent_row) == [1, 1] and list(s.contact.weight) == [1.0, 1.0]
    assert build_system(params.with_overrides(["contact.enabled=false"]), True).contact is None
    assert build_system(params.with_overrides(["shroud.thickness=0"]), True).contact is None


def test_excitation_and_loads_scale_with_speed_and_F0():
    params = Parameters.from_mapping({"speed": {"rpm": 6000.0}, "load": {"F0": 300.0, "ke": 3}})
    s = build_system(params, reduced=False)
    assert s.omega_e == pytest.approx(3 * 2 * math.pi * 6000 / 60)
    half = build_system(params.with_overrides(["load.F0=150", "speed.rpm=3000"]), reduced=False)
    np.testing.assert_allclose(s.f_aero, 2 * half.f_aero)
    np.testing.assert_allclose(s.f_const, 4 * half.f_const)


def test_angular_acceleration_lag_load_matches_exact_cantilever_deflection():
    """Omega_dot > 0 at Omega = 0: the blade lags, q(x) = -rho A Omega_dot (R_d + x) along Y
    plus the shroud's -m_s Omega_dot (R_d + L); tip deflection by the unit-load method
    (bending + shear). The rotary lag moment (-rho I Omega_dot, ~(h/L)^2) is the residue."""
    rpm_per_s = 6000.0
    params = Parameters.from_mapping({
        "blade": {"stagger_deg": 0.0, "twist_deg": 0.0}, "speed": {"rpm": 0.0, "rpm_per_s": rpm_per_s},
        "reduced": {"N": 10, "nr": 0}})
    s = build_system(params, reduced=False)
    v_L = (s.tip @ np.linalg.solve(s.K, s.f_const))[0]
    b, L, Rd, E, rho = params.blade, 0.15, 0.15, 200e9, 7800.0
    acc = 2 * math.pi * rpm_per_s / 60
    q = lambda x: -rho * b.area * acc * (Rd + x)
    P = -params.shroud_mass * acc * (Rd + L)
    shear = lambda x: quad(q, x, L)[0] + P
    moment = lambda x: quad(lambda t: q(t) * (t - x), x, L)[0] + P * (L - x)
    kGA = 10 * (1 + NU) / (12 + 11 * NU) * E / (2 * (1 + NU)) * b.area
    exact = quad(lambda x: moment(x) * (L - x), 0, L)[0] / (E * b.I_v) + quad(shear, 0, L)[0] / kGA
    assert exact < 0
    assert v_L == pytest.approx(exact, rel=1e-3)
    # and it is absent at constant speed
    steady = build_system(params.with_overrides(["speed.rpm_per_s=0"]), reduced=False)
    assert np.all(steady.f_const == 0) and np.all(steady.K == steady.K.T)
