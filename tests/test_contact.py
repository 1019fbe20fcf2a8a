"""The contact law (paper Eqs. 3-6) against hand values, the Masing loop and brute force."""

import itertools
import math

import numpy as np
import pytest

from shroud.core.contact import (SEPARATE, SLIP, STICK, contact_law, evaluate, friction_return_map,
                                 harmonic_stiffness, normal_force, solve_contact, tangent, workspace)
from shroud.core.system import ContactElements


def test_normal_force_eq3_both_sides_gap_and_preload():
    kn = 1e7
    # side 1 (s = -1): N1 = N0 - kn v_s ; side 2 (s = +1): N2 = N0 + kn v_s
    assert normal_force(-2e-6, 0.0, kn, -1.0) == pytest.approx(20.0)
    assert normal_force(+2e-6, 0.0, kn, -1.0) == 0.0
    assert normal_force(+2e-6, 0.0, kn, +1.0) == pytest.approx(20.0)
    gap = 1e-4                                   # N0 = -kn gap: no force until the gap closes
    assert normal_force(0.9 * gap, -kn * gap, kn, 1.0) == 0.0
    assert normal_force(1.1 * gap, -kn * gap, kn, 1.0) == pytest.approx(0.1 * kn * gap)
    assert normal_force(0.0, 50.0, kn, -1.0) == 50.0   # preload at rest


def test_return_mapping_stick_slip_separate():
    kt, mu, N = 1e7, 0.3, 10.0                   # slip threshold mu N / kt = 3e-7 m
    F, z, s = friction_return_map(1e-7, 0.0, N, kt, mu)
    assert s == STICK and z == 0.0 and F == pytest.approx(-1.0)        # restoring, on the blade
    F, z, s = friction_return_map(1e-6, 0.0, N, kt, mu)
    assert s == SLIP and F == pytest.approx(-mu * N)                   # opposes the slip
    assert z == pytest.approx(1e-6 - 3e-7)                             # slider dragged behind
    F, z, s = friction_return_map(-1e-6, 0.0, N, kt, mu)
    assert s == SLIP and F == pytest.approx(mu * N)
    F, z, s = friction_return_map(5e-6, 1e-6, 0.0, kt, mu)
    assert s == SEPARATE and F == 0.0 and z == 5e-6                    # slider follows (Eq. 5)
    F, z, s = friction_return_map(1e-6, 0.0, N, kt, 0.0)
    assert F == 0.0 and z == 1e-6                                      # mu = 0: no friction


@pytest.mark.parametrize("s", [-1.0, 1.0])
@pytest.mark.parametrize("case", ["separate", "stick", "slip +", "slip -"])
def test_tangent_is_the_finite_difference_of_the_law(case, s):
    """dN/dv, dF/d(v, w, z), dz/d(v, w, z) of the law (Eqs. 3-6) by central differences, in each state,
    away from its switches, on both sides."""
    kn, kt, mu, N0 = 1e7, 5e6, 0.3, 20.0          # N = 20 N + s kn v; stick range |z - w| <= mu N / kt
    v = {"separate": -4e-6 * s}.get(case, 1e-6 * s)           # N = 0 (separated) or 30 N
    z = {"stick": 1e-6, "slip +": 5e-6, "slip -": -5e-6}.get(case, 0.0)   # |kt (z - w)| = 5, 25 N vs 9 N

    def law(v, w, z):
        N = normal_force(v, N0, kn, s)
        F, z_new, state = friction_return_map(w, z, N, kt, mu)
        return np.array([N, F, z_new]), state

    (N, F, _), state = law(v, 0.0, z)
    assert state == {"separate": SEPARATE, "stick": STICK}.get(case, SLIP)
    h = 1e-9
    fd = np.column_stack([(law(*(np.array([v, 0.0, z]) + h * e))[0] - law(*(np.array([v, 0.0, z]) - h * e))[0])
                          / (2 * h) for e in np.eye(3)])
    dN_dv, dF_dv, dF_dw, dF_dz, dz_dv, dz_dw, dz_dz = tangent(state, F, s, kn, kt, mu)
    np.testing.assert_allclose([dN_dv, fd[0, 1], fd[0, 2]], [fd[0, 0], 0.0, 0.0], atol=1e-6 * kn)
    np.testing.assert_allclose([dF_dv, dF_dw, dF_dz], fd[1], rtol=1e-6, atol=1e-6 * kt)
    np.testing.assert_allclose([dz_dv, dz_dw, dz_dz], fd[2], rtol=1e-6, atol=1e-6)


def test_friction_loop_dissipates_the_masing_energy():
    """Cyclic w = a sin(t) at constant N: work on the blade per cycle = -4 mu N (a - mu N / kt)."""
    kt, mu, N, a = 1e7, 0.3, 10.0, 2e-6
    w = a * np.sin(np.linspace(0.0, 4 * np.pi, 40001))
    z, F = 0.0, np.zeros(w.size)
    for i, wi in enumerate(w):
        F[i], z, _ = friction_return_map(wi, z, N, kt, mu)
    half = w.size // 2                           # second cycle: the loop is closed
    work = np.sum(0.5 * (F[half + 1:] + F[half:-1]) * np.diff(w[half:]))
    exact = -4 * mu * N * (a - mu * N / kt)
    assert work < 0
    assert work == pytest.approx(exact, rel=1e-4)


def _random_case(rng, k_scale):
    """Two elements (sides 1, 2) on shared rows [v_s, w_s], as the beam has."""
    el = ContactElements(W=np.eye(2), normal_row=np.array([0, 0]), tangent_row=np.array([1, 1]),
                         side=np.array([1, 2]), weight=np.array([1.0, 1.0]))
    law = contact_law(el, kn=k_scale, kt=rng.uniform(0.2, 1.5) * k_scale,
                      mu=rng.uniform(0.05, 0.8), N0=rng.uniform(-5, 20))
    B = rng.normal(size=(2, 2))
    Cc = (B @ B.T + 0.1 * np.eye(2)) * rng.uniform(0.1, 10) / k_scale
    y_pred = rng.normal(size=2) * 3 / k_scale * 10
    z_old = rng.normal(size=2) * 1 / k_scale * 10
    return law, Cc, y_pred, z_old


def _brute_force(law, Cc, y_pred, z_old):
    """Every combination of (separate, stick, slip+, slip-) per element; keep the consistent ones."""
    sols = []
    for combo in itertools.product(range(4), repeat=law.count):
        D, e = np.zeros((2, 2)), np.zeros(2)
        for j, c in enumerate(combo):
            s, kn, kt, mu, n0 = law.props[j]
            if c == 0:
                continue
            D[0, 0] -= kn
            e[0] -= s * n0
            if c == 1:
                D[1, 1] -= kt
                e[1] += kt * z_old[j]
            else:
                sigma = 1.0 if c == 2 else -1.0
                D[1, 0] += mu * sigma * s * kn
                e[1] += mu * sigma * n0
        y = np.linalg.solve(np.eye(2) - Cc @ D, y_pred + Cc @ e)
        ok = True
        for j, c in enumerate(combo):
            s, kn, kt, mu, n0 = law.props[j]
            N = n0 + s * kn * y[0]
            trial = kt * (z_old[j] - y[1])
            if c == 0:
                ok &= N <= 0
            elif c == 1:
                ok &= N > 0 and abs(trial) <= mu * N
            else:
                ok &= N > 0 and abs(trial) > mu * N and np.sign(trial) == (1 if c == 2 else -1)
        if ok:
            sols.append(y)
    return sols


@pytest.mark.parametrize("k_scale", [1e6, 1e7, 1e10])
def test_implicit_contact_solve_matches_brute_force(k_scale):
    rng = np.random.default_rng(7)
    checked = 0
    for _ in range(300):
        law, Cc, y_pred, z_old = _random_case(rng, k_scale)
        sols = _brute_force(law, Cc, y_pred, z_old)
        y, lam = np.zeros(2), np.zeros(2)
        N, F, z, state = np.zeros(2), np.zeros(2), np.zeros(2), np.zeros(2, np.int64)
        it, ok = solve_contact(y_pred, Cc, z_old, law.rows, law.props, y, lam, N, F, z, state,
                               workspace(law))
        assert ok
        # the end state satisfies the law: y = y_pred + Cc lam(y)
        lam2, N2, F2, z2, s2 = np.zeros(2), np.zeros(2), np.zeros(2), np.zeros(2), np.zeros(2, np.int64)
        evaluate(y, z_old, law.rows, law.props, lam2, N2, F2, z2, s2)
        scale = np.abs(y_pred).max() + np.abs(Cc @ lam2).max()
        assert np.abs(y - y_pred - Cc @ lam2).max() <= 1e-10 * scale
        if len(sols) == 1:                       # unique solution: the same one
            assert np.allclose(y, sols[0], rtol=1e-9, atol=1e-12 * scale)
            checked += 1
    assert checked > 250


def test_many_elements_fixed_point():
    """FE-like: 40 elements per side with area weights on 160 projected coordinates."""
    rng = np.random.default_rng(3)
    k = 80
    m = 2 * k
    side = np.repeat([1, 2], k // 2)
    weight = np.concatenate([rng.dirichlet(np.ones(k // 2)), rng.dirichlet(np.ones(k // 2))])
    el = ContactElements(W=np.eye(m), normal_row=np.arange(0, m, 2), tangent_row=np.arange(1, m, 2),
                         side=side, weight=weight)
    law = contact_law(el, kn=1e8, kt=5e7, mu=0.3, N0=20.0)
    B = rng.normal(size=(m, m)) / math.sqrt(m)
    Cc = (B @ B.T + 0.05 * np.eye(m)) * 1e-7
    y_pred = rng.normal(size=m) * 1e-6
    y_pred[np.arange(0, m, 2)] += np.where(side == 1, 1e-6, -1e-6)   # pushed into both faces
    z_old = rng.normal(size=k) * 1e-7
    y, lam = np.zeros(m), np.zeros(m)
    N, F, z, state = np.zeros(k), np.zeros(k), np.zeros(k), np.zeros(k, np.int64)
    it, ok = solve_contact(y_pred, Cc, z_old, law.rows, law.props, y, lam, N, F, z, state, workspace(law))
    assert ok
    assert set(np.unique(state)) >= {SEPARATE, STICK}
    assert np.abs(y - y_pred - Cc @ lam).max() <= 1e-10 * np.abs(y_pred).max()


def test_low_rank_compliance_solve_matches_the_dense_solve_over_a_sequence():
    """Cc = Wc P of rank r < m (a modal model): the r-space solve gives the dense solve's y.

    One workspace serves 300 successive steps, as in a run, so the element by
    element updates of P D Wc (and their periodic rebuild) are exercised
    against a dense solve with a fresh workspace every step.
    """
    rng = np.random.default_rng(11)
    k, r = 60, 9
    m = 2 * k
    side = np.repeat([1, 2], k // 2)
    weight = np.concatenate([rng.dirichlet(np.ones(k // 2)), rng.dirichlet(np.ones(k // 2))])
    el = ContactElements(W=np.eye(m), normal_row=np.arange(0, m, 2), tangent_row=np.arange(1, m, 2),
                         side=side, weight=weight)
    law = contact_law(el, kn=1e8, kt=5e7, mu=0.3, N0=5.0)
    Wc = rng.normal(size=(m, r))
    B = rng.normal(size=(r, r))
    S = (B @ B.T + 0.3 * np.eye(r)) * 1e-9                 # the modal step compliance (n x n)
    S[0, 1] += 2e-10                                       # a Coriolis-like skew part
    S[1, 0] -= 2e-10
    P = S @ Wc.T
    Cc = Wc @ P
    ws_low = workspace(law, Wc, P)
    z_old = np.zeros(k)
    states_seen = set()
    for step in range(300):
        y_pred = rng.normal(size=m) * 2e-7 + 1e-7 * np.sin(0.05 * step) * np.where(
            np.arange(m) % 2 == 0, np.repeat(np.where(side == 1, 1.0, -1.0), 2), 1.0)
        out = {}
        for name, ws in (("low", ws_low), ("dense", workspace(law))):
            y, lam = np.zeros(m), np.zeros(m)
            N, F, z, state = np.zeros(k), np.zeros(k), np.zeros(k), np.zeros(k, np.int64)
            it, ok = solve_contact(y_pred, Cc, z_old, law.rows, law.props, y, lam, N, F, z, state, ws)
            assert ok
            out[name] = (y, z, state.copy())
        scale = np.abs(out["dense"][0]).max()
        assert np.abs(out["low"][0] - out["dense"][0]).max() <= 1e-9 * scale
        assert np.array_equal(out["low"][2], out["dense"][2])
        states_seen.update(np.unique(out["dense"][2]).tolist())
        z_old = out["dense"][1]
    assert states_seen == {SEPARATE, STICK, SLIP}


@pytest.mark.parametrize("ratio", [0.5, 1.2, 3.0, 30.0, 1000.0])
def test_harmonic_stiffness_is_the_first_harmonic_of_the_marched_law(ratio):
    """The closed form (Jenkins element, Caughey / Iwan) against the law itself marched around a cosine
    (the one return mapping, 20 000 samples, second cycle), kt a / (mu N) from stuck to gross slip."""
    kt, mu, N = 2e6, 0.3, 10.0
    a = ratio * mu * N / kt
    tau = np.linspace(0.0, 4 * np.pi, 40001)[:-1]
    w = a * np.cos(tau)
    z, F = w[0], np.zeros(w.size)
    for i, wi in enumerate(w):
        F[i], z, _ = friction_return_map(wi, z, N, kt, mu)
    second = slice(w.size // 2, None)
    c = np.exp(-1j * tau[second])
    measured = -(F[second] @ c) / (w[second] @ c)           # -F = k w on the first harmonic
    exact = harmonic_stiffness(kt, mu * N, a)
    assert measured.real == pytest.approx(exact.real, rel=2e-3, abs=1e-6 * kt)
    assert measured.imag == pytest.approx(exact.imag, rel=2e-3, abs=1e-6 * kt)


def test_a_stiffer_tangential_spring_softens_an_element_in_gross_slip():
    """At fixed amplitude and slip force, k' rises with kt near stick and falls in gross slip (the
    turn at mu N / (kt a) = 0.769): why a larger xi can lower a sliding shroud's resonant speed."""
    F_s, a = 3.0, 5e-6
    near_stick = [harmonic_stiffness(kt, F_s, a).real for kt in (2e5, 3e5, 3.8e5)]      # mu N / (kt a) > 0.79
    gross_slip = [harmonic_stiffness(kt, F_s, a).real for kt in (2e6, 5e6, 1e7)]        # < 0.3
    assert near_stick == sorted(near_stick) and gross_slip == sorted(gross_slip, reverse=True)
