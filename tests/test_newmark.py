"""Newmark with contact against exact solutions: the discrete oscillator, harmonic steady
states, an impact oscillator, a Coulomb-braked block, and the kernel against the reference."""

import dataclasses
import math

import numpy as np
import pytest
import scipy.sparse

from shroud.core import signals
from shroud.core.contact import contact_law
from shroud.core.states import STATE_NAMES
from shroud.core.linear_solvers import Factorization
from shroud.core.newmark import NewmarkScheme, _factorize_step, explicit_lag_stability, integrate
from shroud.core.system import ContactElements, StructuralSystem


def two_sided(n, W):
    """Side 1 and side 2 on shared rows [v_s, w_s], as the beam has."""
    return ContactElements(W=W, normal_row=np.array([0, 0]), tangent_row=np.array([1, 1]),
                           side=np.array([1, 2]), weight=np.array([1.0, 1.0]))


def system(M, C, K, f_aero, omega_e, W=None, tip=None, f_const=None):
    n = len(M)
    M, C, K = (np.atleast_2d(np.asarray(A, float)) for A in (M, C, K))
    tip = np.eye(2, n) if tip is None else tip
    return StructuralSystem(model="test", M=M, C=C, K=K, f_const=np.zeros(n) if f_const is None else f_const,
                            f_aero=np.asarray(f_aero, float), omega_e=omega_e, tip=tip,
                            contact=None if W is None else two_sided(n, W))


def no_contact(n):
    return contact_law(None, m=0)


def test_undamped_oscillator_is_the_exact_discrete_solution():
    """Average acceleration: q_n = q_1 sin(n theta)/sin(theta), theta = 2 atan(omega dt / 2)."""
    w, dt, V = 2 * math.pi * 50.0, 1e-3, 0.3
    sys_ = system([[2.0]], [[0.0]], [[2.0 * w * w]], [0.0], 1.0, tip=np.array([[1.0], [0.0]]))
    tr = integrate(sys_, no_contact(1), NewmarkScheme(dt=dt), 2000, v0=[V], method="reference")
    theta = 2 * math.atan(w * dt / 2)
    q1 = dt * V / (1 + (w * dt) ** 2 / 4)
    exact = q1 * np.sin(np.arange(2001) * theta) / math.sin(theta)
    assert np.abs(tr.tip[:, 0] - exact).max() < 1e-12 * V / w


@pytest.mark.parametrize("method", ["kernel", "reference"])
def test_gyroscopic_2dof_steady_state_matches_frequency_domain(method):
    """M q'' + (D + G) q' + K q = f sin(W t): amplitude |(K - W^2 M + i W (D + G))^-1 f|, O(dt^2)."""
    M = np.diag([1.0, 1.5])
    K = np.array([[4.0e4, -1.0e4], [-1.0e4, 6.0e4]])
    G = np.array([[0.0, 30.0], [-30.0, 0.0]])
    D = 0.002 * K + 2.0 * M
    f = np.array([1.0, 0.3])
    We = 190.0
    sys_ = system(M, D + G, K, f, We)
    spp, periods = 256, 60
    tr = integrate(sys_, no_contact(2), NewmarkScheme(dt=2 * math.pi / We / spp), spp * periods,
                   method=method, energy_window=10 * spp)
    Q = np.linalg.solve(K - We ** 2 * M + 1j * We * (D + G), f)
    last = tr.tip[-10 * spp - 1:]
    amp = 0.5 * (last.max(axis=0) - last.min(axis=0))
    assert amp == pytest.approx(np.abs(Q), rel=2e-4)
    # steady state: the load's work goes into damping only (G does no work)
    e = tr.energy
    assert e.damping == pytest.approx(e.input_work, rel=1e-3)
    assert abs(e.residual) < 1e-10 * e.input_work


def test_impact_oscillator_between_two_walls():
    """A free mass bouncing between walls at +-g: period 4 g / V + 2 pi sqrt(m / kn) (exact)."""
    m, kn, g, V = 0.5, 1e6, 1e-3, 0.2
    el_W = np.array([[1.0], [0.0]])
    sys_ = system([[m]], [[0.0]], [[0.0]], [0.0], 1.0, W=el_W, tip=np.array([[1.0], [0.0]]))
    law = contact_law(sys_.contact, kn=kn, kt=0.0, mu=0.0, N0=-kn * g)
    T_exact = 4 * g / V + 2 * math.pi * math.sqrt(m / kn)
    dt = math.pi * math.sqrt(m / kn) / 400
    steps = int(3.2 * T_exact / dt)
    tr = integrate(sys_, law, NewmarkScheme(dt=dt), steps, v0=[V], method="kernel",
                   energy_window=steps // 2)
    x = tr.tip[:, 0]
    up = np.flatnonzero((x[:-1] < 0) & (x[1:] >= 0))
    t_up = (up + (-x[up]) / (x[up + 1] - x[up])) * dt
    assert np.diff(t_up).mean() == pytest.approx(T_exact, rel=1e-4)
    assert np.abs(x).max() == pytest.approx(g + V * math.sqrt(m / kn), rel=1e-4)
    assert tr.energy.relative_error < 1e-12 or abs(tr.energy.residual) < 1e-6 * 0.5 * m * V * V


def test_coulomb_braked_block_stops_where_the_energy_runs_out():
    """Block with velocity V pressed by N0 on both sides: slider travel (m V^2/2 - (mu N0)^2/kt)/(2 mu N0)."""
    m, V, N0, mu, kt = 0.2, 0.5, 40.0, 0.3, 1e8
    W = np.array([[0.0], [1.0]])                     # the block moves along w_s only
    sys_ = system([[m]], [[0.0]], [[1e-9]], [0.0], 1.0, W=W, tip=np.array([[0.0], [1.0]]))
    law = contact_law(sys_.contact, kn=1e7, kt=kt, mu=mu, N0=N0)
    t_stop = m * V / (2 * mu * N0)
    dt = t_stop / 4000
    tr = integrate(sys_, law, NewmarkScheme(dt=dt), 6000, v0=[V], method="kernel")
    travel = (0.5 * m * V * V - (mu * N0) ** 2 / kt) / (2 * mu * N0)
    tail = tr.tip[-1500:, 1]                        # stuck: oscillates about the slider
    assert 0.5 * (tail.max() + tail.min()) == pytest.approx(travel, rel=1e-3)
    assert np.all(tr.state[-1500:] == 1)
    assert np.abs(tr.friction[-1500:]).max() <= mu * N0 * (1 + 1e-12)


def _contact_2dof():
    M = np.diag([1.0, 0.8])
    K = np.array([[5.0e5, -1.0e5], [-1.0e5, 3.0e5]])
    C = 1e-4 * K + np.array([[0.0, 5.0], [-5.0, 0.0]])
    a = math.radians(30)
    W = np.array([[math.cos(a), math.sin(a)], [-math.sin(a), math.cos(a)]])
    return system(M, C, K, [30.0, 10.0], 2 * math.pi * 100, W=W)


@pytest.mark.parametrize("implicit", [True, False])
def test_kernel_equals_reference_to_round_off(implicit):
    sys_ = _contact_2dof()
    law = contact_law(sys_.contact, kn=1e6, kt=5e5, mu=0.3, N0=2.0)
    scheme = NewmarkScheme(dt=1 / 100 / 256)
    runs = [integrate(sys_, law, scheme, 256 * 30, implicit=implicit, method=m, energy_window=2560)
            for m in ("kernel", "reference")]
    k, r = runs
    assert set(np.unique(k.state)) >= {1, 2}          # stick and slip both visited
    scale = np.abs(r.tip).max()
    assert np.abs(k.tip - r.tip).max() < 1e-9 * scale
    assert np.abs(k.friction - r.friction).max() < 1e-9 * np.abs(r.friction).max()
    assert np.array_equal(k.state, r.state)
    assert k.energy.friction == pytest.approx(r.energy.friction, rel=1e-8)
    assert np.array_equal(k.element_share, r.element_share)
    assert np.abs(k.element_peak_normal - r.element_peak_normal).max() < 1e-9 * r.element_peak_normal.max()


@pytest.mark.parametrize("method", ["kernel", "reference"])
def test_a_run_continued_from_its_end_state_is_the_run_in_one_piece(method):
    """The end state (q, q', q'', the sliders) is the integrator's whole state: N periods, then N more started
    from it, are the 2 N periods of one run (the excitation restarts at t = 0: whole periods), stick and
    slip visited; without the sliders (each at its element's w, as a run from rest starts) they are not."""
    sys_ = _contact_2dof()
    law = contact_law(sys_.contact, kn=1e6, kt=5e5, mu=0.3, N0=2.0)
    scheme, n = NewmarkScheme(dt=1 / 100 / 256), 256 * 10
    whole = integrate(sys_, law, scheme, 2 * n, method=method)
    first = integrate(sys_, law, scheme, n, method=method)
    end = first.end
    second = integrate(sys_, law, scheme, n, method=method, q0=end.q, v0=end.v, acc0=end.a, z0=end.z)
    forgetful = integrate(sys_, law, scheme, n, method=method, q0=end.q, v0=end.v, acc0=end.a)
    assert set(np.unique(whole.state)) >= {1, 2}
    scale = np.abs(whole.tip).max()
    assert np.abs(second.tip - whole.tip[n:]).max() < 1e-9 * scale
    assert np.abs(second.end.z - whole.end.z).max() < 1e-9 * scale
    assert np.abs(forgetful.tip - whole.tip[n:]).max() > 1e-4 * scale


def test_low_rank_contact_solve_in_a_run_matches_the_dense_one():
    """More contact coordinates than DOFs (m = 12 > 2 n, as the reduced solid's faces): the
    compiled run solves the contact in the n-space (Cc = W Phi); the same system given as
    scipy.sparse runs the reference loop with the dense m x m solve. Both end where the law holds."""
    base = _contact_2dof()
    a = math.radians(30)
    e_vs, e_ws = np.array([math.cos(a), math.sin(a)]), np.array([-math.sin(a), math.cos(a)])
    lever = [0.7, 1.0, 1.3]                           # three nodes per face, each its own state
    W = np.vstack([row for c in lever + lever for row in (c * e_vs, e_ws + 0.2 * (c - 1) * e_vs)])
    contact = ContactElements(W=W, normal_row=np.arange(0, 12, 2), tangent_row=np.arange(1, 12, 2),
                              side=np.repeat([1, 2], 3), weight=np.full(6, 1 / 3))
    dense = dataclasses.replace(base, contact=contact)
    sparse = dataclasses.replace(dense, M=scipy.sparse.csr_matrix(dense.M), C=scipy.sparse.csr_matrix(dense.C),
                                 K=scipy.sparse.csr_matrix(dense.K))
    law = contact_law(contact, kn=1e6, kt=5e5, mu=0.3, N0=2.0)
    scheme = NewmarkScheme(dt=1 / 100 / 256)
    assert _factorize_step(dense, law, scheme, None).low_rank
    assert not _factorize_step(sparse, law, scheme, None).low_rank
    k = integrate(dense, law, scheme, 256 * 20, method="kernel")
    r = integrate(sparse, law, scheme, 256 * 20, method="reference")
    assert set(np.unique(k.state)) >= {1, 2}
    assert np.abs(k.tip - r.tip).max() < 1e-8 * np.abs(r.tip).max()
    assert np.abs(k.normal - r.normal).max() < 1e-8 * np.abs(r.normal).max()
    assert np.array_equal(k.state, r.state)


def test_element_state_map_is_the_side_record_for_one_element_per_side():
    """With one element per side, an element's state shares are its side's, counted a second way."""
    sys_ = _contact_2dof()
    law = contact_law(sys_.contact, kn=1e6, kt=5e5, mu=0.3, N0=2.0)
    spp = 256
    tr = integrate(sys_, law, NewmarkScheme(dt=1 / 100 / spp), spp * 30, energy_window=10 * spp)
    assert tr.element_share.shape == (2, 3)
    assert tr.element_share.sum(axis=1) == pytest.approx([1.0, 1.0], abs=1e-15)
    for j in range(2):
        expected = signals.state_fractions(tr.state[:, j], spp)
        assert tr.element_share[j] == pytest.approx([expected[s] for s in STATE_NAMES], abs=1e-15)
        window = tr.normal[-10 * spp:, j]
        assert tr.element_peak_normal[j] == pytest.approx(np.abs(window).max(), rel=1e-15)
    assert tr.element_share[:, 2].max() > 0.01             # slip visited: the test can tell states apart


def test_full_stick_map_is_all_stick_and_no_window_no_map():
    sys_ = _contact_2dof()
    law = contact_law(sys_.contact, kn=1e6, kt=5e5, mu=0.3, N0=1e6)
    scheme = NewmarkScheme(dt=1 / 100 / 64)
    tr = integrate(sys_, law, scheme, 64 * 5, energy_window=64)
    assert np.array_equal(tr.element_share, [[0.0, 1.0, 0.0]] * 2)
    # the preload alone puts N0 on each element; the vibration only adds to it in compression
    assert np.all(tr.element_peak_normal >= 1e6)
    assert integrate(sys_, law, scheme, 64).element_share is None


class _LapackSolve:
    """A model's own factorization, as a model brings one (shroud.core.linear_solvers.Factorization)."""

    def __init__(self, A):
        self.A = np.asarray(A)

    def solve(self, b):
        return np.linalg.solve(self.A, b)

    solve_rows = solve

    def close(self):
        self.A = None


@pytest.mark.parametrize("solver", ["model's own", "default dense", "default sparse"])
def test_contact_condensation_through_any_factorization(solver):
    """Phi = K_eff^-1 W^T and Cc = W Phi, whichever Factorization the model brings."""
    sys_ = _contact_2dof()
    law = contact_law(sys_.contact, kn=1e6, kt=5e5, mu=0.3, N0=2.0)
    scheme = NewmarkScheme(dt=1e-4)
    assert isinstance(_LapackSolve(np.eye(2)), Factorization)

    if solver == "default sparse":
        sparse = dataclasses.replace(sys_, M=scipy.sparse.csr_matrix(sys_.M),
                                     C=scipy.sparse.csr_matrix(sys_.C), K=scipy.sparse.csr_matrix(sys_.K))
        step = _factorize_step(sparse, law, scheme, None)
    else:
        step = _factorize_step(sys_, law, scheme, _LapackSolve if solver == "model's own" else None)
    a0, a1 = scheme.coefficients()[:2]
    K_eff = sys_.K + a0 * sys_.M + a1 * sys_.C
    Phi = np.linalg.inv(K_eff) @ sys_.contact.W.T
    assert np.allclose(step.Phi, Phi, rtol=1e-12, atol=0)
    assert np.allclose(step.Cc, sys_.contact.W @ Phi, rtol=1e-12, atol=0)


def test_friction_dissipates_and_energy_balance_closes():
    sys_ = _contact_2dof()
    law = contact_law(sys_.contact, kn=1e6, kt=5e5, mu=0.3, N0=2.0)
    tr = integrate(sys_, law, NewmarkScheme(dt=1 / 100 / 256), 256 * 40, energy_window=2560)
    e = tr.energy
    assert e.friction > 0.005 * e.input_work
    assert e.relative_error < 1e-2                    # what the impact kinks leave: the 1 % goal
    # exact discrete identity: load + contact work = kinetic + strain change + damping
    assert (e.input_work + e.contact_work - e.kinetic_change - e.strain_change - e.damping) \
        == pytest.approx(0.0, abs=1e-10 * e.input_work)


def test_full_stick_is_the_linear_system_with_contact_springs():
    """A huge preload never lets go: the response is that of K + W^T diag(2 kn, 2 kt) W."""
    sys_ = _contact_2dof()
    kn, kt = 1e6, 5e5
    law = contact_law(sys_.contact, kn=kn, kt=kt, mu=0.3, N0=1e6)
    spp = 256
    tr = integrate(sys_, law, NewmarkScheme(dt=1 / 100 / spp), spp * 40)
    assert np.all(tr.state[1:] == 1)
    W = sys_.contact.W
    K_stuck = sys_.K + W.T @ np.diag([2 * kn, 2 * kt]) @ W
    We = sys_.omega_e
    Q = np.linalg.solve(K_stuck - We ** 2 * sys_.M + 1j * We * sys_.C, sys_.f_aero)
    last = tr.tip[-10 * spp - 1:]
    assert 0.5 * (last.max(axis=0) - last.min(axis=0)) == pytest.approx(np.abs(Q), rel=5e-3)


def test_unbounded_run_stops_and_names_the_cause():
    """Explicit contact with kn far beyond the step's reach diverges; the trajectory so far is kept."""
    sys_ = _contact_2dof()
    law = contact_law(sys_.contact, kn=1e12, kt=5e11, mu=0.3, N0=0.0)
    tr = integrate(sys_, law, NewmarkScheme(dt=1 / 100 / 32), 32 * 20, implicit=False, bound=0.15)
    assert tr.diverged is not None and tr.steps < 32 * 20
    assert len(tr.tip) == tr.steps + 1
    ok = integrate(sys_, law, NewmarkScheme(dt=1 / 100 / 32), 32 * 20, implicit=True, bound=0.15)
    assert ok.diverged is None


def test_explicit_contact_lag_is_a_negative_damping():
    """A spring force lagged by dt does the work pi kn X^2 sin(w dt) per cycle: a damping ratio
    -sin(w dt)/2 for a contact-spring oscillator (k = 0; both preloaded sides: w^2 = 2 kn/m). With viscous ratio zeta_c
    the explicit step is stable iff sin(w dt)/2 < zeta_c, i.e. dt < asin(2 zeta_c)/w."""
    m, kn, zeta_c = 0.5, 2e6, 0.01
    w = math.sqrt(2 * kn / m)
    el_W = np.array([[1.0], [0.0]])
    sys_ = system([[m]], [[2 * zeta_c * m * w]], [[0.0]], [0.0], 1.0, W=el_W, tip=np.array([[1.0], [0.0]]))
    law = contact_law(sys_.contact, kn=kn, kt=0.0, mu=0.0, N0=1.0)   # preloaded: stays closed
    dt_star = math.asin(2 * zeta_c) / w
    for ratio in (0.5, 2.0):
        lag = explicit_lag_stability(sys_, law, NewmarkScheme(dt=ratio * dt_star))
        assert lag.frequency_hz == pytest.approx(w / (2 * math.pi), rel=2e-3)
        assert lag.damping_ratio == pytest.approx(zeta_c - math.sin(w * ratio * dt_star) / 2, abs=2e-4)
    assert explicit_lag_stability(sys_, law, NewmarkScheme(dt=2 * dt_star)).dt_stable == \
        pytest.approx(dt_star, rel=2e-3)
    # the time-domain run grows beyond the bound exactly on the unstable side
    for ratio, grows in ((0.8, False), (1.25, True)):
        dt = ratio * dt_star
        tr = integrate(sys_, law, NewmarkScheme(dt=dt), int(400 * 2 * math.pi / w / dt), v0=[1e-3],
                       implicit=False, method="kernel")
        x = tr.tip[:, 0]
        quarter = len(x) // 4
        assert (np.abs(x[-quarter:]).max() > np.abs(x[:quarter]).max()) == grows
