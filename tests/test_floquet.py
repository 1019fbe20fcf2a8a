"""The compiled matrix exponential and the monodromy against second methods (closed forms, scipy)."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg

from shroud.core import floquet
from shroud.core.contact import SEPARATE, SLIP, STICK, ContactLaw


def _relative_error(X, exact):
    return float(np.abs(X - exact).max() / np.abs(exact).max())


def _oscillators(omega, zeta, tau, seed=0):
    """tau times the first-order matrix of unit oscillators scaled as the monodromy scales them,
    [[0, w], [-w, -2 zeta w]] per mode, mixed by an orthogonal similarity Q; and its exponential in
    closed form (each 2 x 2 block's from its eigenvalues, then Q)."""
    blocks, exact = [], []
    for w, z in zip(omega, zeta):
        B = tau * np.array([[0.0, w], [-w, -2.0 * z * w]])
        l1, l2 = np.linalg.eigvals(B.astype(complex))
        f = (np.exp(l1) - np.exp(l2)) / (l1 - l2)             # exp(B) = g I + f B (Sylvester)
        g = (l1 * np.exp(l2) - l2 * np.exp(l1)) / (l1 - l2)
        blocks.append(B)
        exact.append((g * np.eye(2) + f * B).real)
    Q = np.linalg.qr(np.random.default_rng(seed).normal(size=(2 * len(omega),) * 2))[0]
    A, E = scipy.linalg.block_diag(*blocks), scipy.linalg.block_diag(*exact)
    return Q @ A @ Q.T, Q @ E @ Q.T


@pytest.mark.parametrize("norm", [0.0, 1e-3, 0.1, 0.5, 1.5, 3.0, 50.0, 200.0])
def test_expm_of_random_matrices_of_every_size_of_norm_equals_scipys(norm):
    """Norms that take each Pade degree (3 ... 13) and the scaling: the same exponential as scipy's."""
    A = np.random.default_rng(1).normal(size=(7, 7))
    A *= norm / max(np.abs(A).sum(axis=0).max(), 1e-300)
    assert _relative_error(floquet.expm(A), scipy.linalg.expm(A)) <= 1e-14


def test_expm_of_a_stiff_damped_structure_equals_the_closed_form_and_scipys():
    """Modes from 10^3 to 10^6 rad/s with stiffness-proportional damping (the fastest overdamped, as in
    the full beam) over 1 ms: ||A||_1 ~ 10^4, squared some 12 times; the decaying modes do not spoil
    the slow ones."""
    omega = np.geomspace(1e3, 1e6, 12)
    A, exact = _oscillators(omega, 0.01 + 1e-5 * omega, 1e-3)
    X = floquet.expm(A)
    assert _relative_error(X, exact) <= 5e-12
    assert _relative_error(X, scipy.linalg.expm(A)) <= 5e-12


def test_expm_of_a_nilpotent_matrix_is_its_finite_series():
    """A large non-normal matrix whose powers vanish: its powers' norms (not ||A||_1 = 10^3) choose the
    approximant, which is then exact."""
    N = 1e3 * np.eye(5, k=1)
    exact = sum(np.linalg.matrix_power(N, p) / float(np.prod(range(1, p + 1))) for p in range(5))
    assert _relative_error(floquet.expm(N), exact) <= 1e-15


def _blade(n=3):
    """A small chain: M, C (Rayleigh), K, and W giving (v, w) = the last DOF and the one before."""
    M = np.diag([1.0, 0.5, 0.2])
    K = 1e6 * np.array([[2.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 1.0]])
    C = 2.0 * M + 1e-5 * K
    W = np.array([[0.0, 0.0, 1.0], [0.0, 1.0, 0.0]])
    return M, C, K, W


def _law(kn=2e5, kt=1e5, mu=0.3, s=1.0):
    return ContactLaw(rows=np.array([[0, 1]]), props=np.array([[s, kn, kt, mu, 10.0]]), side=np.array([2]),
                      weight=np.array([1.0]), m=2)


def _first_order(M, C, K):
    n = M.shape[0]
    return np.block([[np.zeros((n, n)), np.eye(n)], [-np.linalg.solve(M, K), -np.linalg.solve(M, C)]])


def test_monodromy_of_a_free_blade_and_of_one_stuck_all_period_is_one_exponential():
    """Separated all period: exp(A T) of the blade; stuck all period: of the blade with the springs kn
    on v and kt on w (the slider's offset, constant, is left out)."""
    M, C, K, W = _blade()
    law, omega, samples = _law(), 300.0, 64
    T = 2 * np.pi / omega
    for state, Kc in ((SEPARATE, 0.0 * K), (STICK, W.T @ np.diag([2e5, 1e5]) @ W)):
        Phi = floquet.monodromy(M, C, K, W, law, np.full((1, samples), state), np.ones((1, samples)), omega)
        assert _relative_error(Phi, scipy.linalg.expm(T * _first_order(M, C, K + Kc))) <= 1e-12


@pytest.mark.parametrize("state", [SEPARATE, STICK, SLIP])
def test_multipliers_of_an_orbit_in_one_state_are_those_of_its_exponential(state):
    """One state all period (separated; stuck; slipping one way, its non-symmetric stiffness): the
    multipliers from the first-order matrix's eigenvalues, exp(s T), are the eigenvalues of scipy's
    exp(A T) of the same blade and springs."""
    M, C, K, W = _blade()
    law, omega, samples = _law(), 300.0, 64
    Kc = {SEPARATE: 0.0 * K, STICK: W.T @ np.diag([2e5, 1e5]) @ W,
          SLIP: W.T @ np.array([[2e5, 0.0], [-0.3 * 2e5, 0.0]]) @ W}[state]
    mu = floquet.orbit_multipliers(M, C, K, W, law, np.full((1, samples), state), np.ones((1, samples)), omega)
    exact = np.linalg.eigvals(scipy.linalg.expm(2 * np.pi / omega * _first_order(M, C, K + Kc)))
    assert mu.size == exact.size
    assert np.abs(np.sort_complex(mu) - np.sort_complex(exact)).max() <= 1e-12 * np.abs(exact).max()


def test_monodromy_of_runs_is_the_product_of_their_exponentials_in_time_order():
    """Separated, then slipping along +e_ws (the friction mu kn s v slaved to the normal motion: a
    non-symmetric stiffness), then separated: exp(A0 t3) exp(A_slip t2) exp(A0 t1), the separated runs
    through the powers of one exponential over a sample."""
    M, C, K, W = _blade()
    law, omega, samples = _law(), 300.0, 64
    dt = 2 * np.pi / omega / samples
    state = np.full((1, samples), SEPARATE)
    state[0, 10:40] = SLIP
    F = np.ones((1, samples))
    Kc = W.T @ np.array([[2e5, 0.0], [-0.3 * 2e5, 0.0]]) @ W    # -W^T dlam/dy; dlam_n = -kn dv, dF = mu kn dv
    expected = (scipy.linalg.expm(24 * dt * _first_order(M, C, K))
                @ scipy.linalg.expm(30 * dt * _first_order(M, C, K + Kc))
                @ scipy.linalg.expm(10 * dt * _first_order(M, C, K)))
    assert _relative_error(floquet.monodromy(M, C, K, W, law, state, F, omega), expected) <= 1e-12
