"""Floquet multipliers from the period map of the project's own integrator (shroud.core.period_map), and
the HB branch's verdicts checked in time (issue 32)."""

import numpy as np
import pytest
import scipy.linalg

from shroud import api
from shroud.analysis import hb as ahb
from shroud.analysis.transient import contact_law_for
from shroud.core import harmonic_balance as hb
from shroud.core import period_map
from shroud.core.contact import contact_law
from shroud.core.system import StructuralSystem

GAP_1UM = {"contact.gap": 1e-6, "contact.alpha_deg": 30.0, "contact.kt": 5e6, "contact.kn": 1e7, "contact.mu": 0.3}


def test_the_period_maps_multipliers_of_a_linear_oscillator_are_exp_s_T():
    """No contact: the monodromy is exp(A T), its multipliers exp(s T) of the first-order matrix's
    eigenvalues s (a damped, gyroscopic 2-DOF rotor, excited at a frequency between its two modes)."""
    M = np.diag([1.0, 2.0])
    K = np.array([[400.0, -50.0], [-50.0, 900.0]])
    C = 0.02 * K + 0.3 * M + np.array([[0.0, 1.5], [-1.5, 0.0]])
    f_aero, omega = np.array([1.0, 0.5]), 25.0
    system = StructuralSystem(model="test", M=M, C=C, K=K, f_const=np.array([0.3, 0.0]), f_aero=f_aero,
                              omega_e=omega, tip=np.eye(2), contact=None)
    law = contact_law(None, m=0)
    t = 2 * np.pi / omega * np.arange(512) / 512               # the exact steady state's samples
    Z = K - omega ** 2 * M + 1j * omega * C
    Q = np.linalg.solve(Z, -1j * f_aero)                       # f sin(w t) = Re(-i f e^{i w t})
    q = np.real(np.exp(1j * omega * t)[:, None] * Q) + np.linalg.solve(K, system.f_const)
    v = np.real(1j * omega * np.exp(1j * omega * t)[:, None] * Q)
    st = period_map.period_map_stability(system, law, 512, (q, v, np.zeros((t.size, 0))))
    A = np.block([[np.zeros((2, 2)), np.eye(2)], [-np.linalg.solve(M, K), -np.linalg.solve(M, C)]])
    exact = np.exp(scipy.linalg.eigvals(A) * 2 * np.pi / omega)
    assert st.multipliers.size == 4
    for mu in exact:
        assert np.min(np.abs(st.multipliers - mu)) < 2e-3 * abs(mu)
    assert st.largest == pytest.approx(np.abs(exact).max(), rel=2e-3)
    assert st.error < 2e-3 and st.distance < 1e-3            # the shooting found the exact steady state


@pytest.fixture(scope="module")
def gap_11250():
    """The 1 um gap case at 11250 r/min: the state a run from rest settles on (Newton from its harmonics)
    and the state Newton reaches from the linear solution (the branch continued from 5000 r/min)."""
    p = api.parameters(GAP_1UM)
    rpm = 11250.0
    Y, period = ahb.time_domain_state(p, "reduced", rpm)
    assert period == 1
    settled = ahb.checkpoint(p, "reduced", rpm, start=Y.ravel(), retry=False)
    system = api.build_system(p.updated({"speed.rpm": rpm}), "reduced")
    law = contact_law_for(system, p.contact)
    return p, rpm, settled, system, law, hb.solve(system, law, 10)


def test_the_state_the_integrator_settles_on_at_11250_is_not_called_unstable_and_stays(gap_11250):
    p, rpm, settled, _, _, _ = gap_11250
    branch = ahb.run_hb_through(p, "reduced", settled.X, rpm, rpm - 50.0, rpm + 50.0, min_points=3)
    i = int(np.argmin(np.abs(branch.rpm - rpm)))
    assert branch.rpm[i] == rpm and branch.stable[i] is not False
    assert ahb.check_in_time(p, "reduced", branch, [i])[0].answer == "stays"


def test_the_continued_branchs_state_at_11250_is_unstable_both_ways_and_the_integrator_leaves_it(gap_11250):
    """Where the monodromy along the orbit is known right: it and the integrator's period map agree
    beyond both errors, and the integrator started on the state leaves it for the one a run from rest
    settles on (0.5 % higher)."""
    p, rpm, settled, system, law, sol = gap_11250
    assert sol.converged and abs(sol.amplitude_v_L / settled.amplitude_v_L - 1) > 0.003
    lin = hb.linear_harmonics(system, 10)
    basis = sol.basis
    samples = hb.orbit_samples(system, lin, law, sol.X, basis)
    orbit = ahb.orbit_stability(system, law, sol.X.reshape(basis.nh, lin.nx) @ lin.Wx.T, basis, sol.contact)
    integrator = period_map.period_map_stability(system, law, 512, samples)
    assert orbit.stable is False and integrator.stable is False
    assert integrator.largest == pytest.approx(orbit.largest, abs=orbit.error + integrator.error)
    check = period_map.check_in_time(system, law, p.time.steps_per_period, samples)
    assert check.answer == "leaves"
    pm, start = period_map.period_map(system, law, p.time.steps_per_period, *(x[0] for x in samples))
    end = pm.run(start, 200)
    tail = end.tip[-p.time.steps_per_period:, 0]
    assert 0.5 * (tail.max() - tail.min()) == pytest.approx(settled.amplitude_v_L, rel=0.01)


def test_no_point_of_the_branch_is_called_unstable_where_the_integrator_started_on_it_stays():
    """1 um gap, 10600-11600 r/min, through the folds near 10850 r/min: the monodromy alone calls two
    points beside the upper fold unstable (|multiplier| 1.03-1.05 +- 0.02) where the integrator stays."""
    p = api.parameters(GAP_1UM)
    branch = ahb.run_hb(p, "reduced", 10600.0, 11600.0, min_points=12)
    unstable = [i for i, s in enumerate(branch.stable) if s is False]
    assert len(unstable) >= 10
    assert all(c.answer != "stays" for c in ahb.check_in_time(p, "reduced", branch, unstable))
    assert any("stays" in r for r in branch.stability_reason)
