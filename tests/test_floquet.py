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


# --- the verdict with the multipliers' own error ---------------------------------------------------------

@pytest.mark.parametrize("largest, error, expected", [
    (0.97, 0.02, True), (1.03, 0.02, False),          # beyond the error either side: decided
    (0.99, 0.02, None), (1.01, 0.02, None),           # within it: undecided, whichever side |mu| falls
    (0.99, 0.005, True), (1.01, 0.005, False),        # the same |mu|, a smaller error: decided again
])
def test_a_multiplier_within_its_error_of_the_unit_circle_is_undecided(largest, error, expected):
    assert floquet.verdict(largest, error) is expected


def test_the_sampling_error_is_the_change_from_half_the_samples_and_never_below_the_floor():
    """A separated-then-slipping orbit sampled at 64 and at 32 instants (the slip starting at the same time):
    its error is the change of the largest |multiplier| between them, at least MULTIPLIER_FLOOR; at 4096
    samples the largest |multiplier| lies within the error estimated at 64 of the 64-sample one."""
    M, C, K, W = _blade()
    law, omega = _law(), 300.0

    def largest(samples):
        state = np.full((1, samples), SEPARATE)
        state[0, int(0.17 * samples):int(0.61 * samples)] = SLIP
        mu = floquet.orbit_multipliers(M, C, K, W, law, state, np.ones((1, samples)), omega)
        return float(np.abs(mu).max())

    error = floquet.sampling_error(largest(64), largest(32))
    assert error == max(floquet.MULTIPLIER_FLOOR, abs(largest(64) - largest(32)))
    assert abs(largest(4096) - largest(64)) <= error


def test_a_grazing_touch_is_left_out_of_the_onset_capture_and_counted_not_divided_by():
    """An element separated, then stuck from the touch, then separated again, touching at a normal speed
    of exactly zero (a grazing touch: the touch time's shift -dv / v' is unbounded): the monodromy stays
    finite and equals the one without the capture term; the touch is counted as grazing, so the point's
    stability is undecided. At a clear normal speed the capture term is taken (the monodromy differs)."""
    M, C, K, W = _blade()
    law, omega, samples = _law(), 300.0, 64
    state = np.full((1, samples), SEPARATE)
    state[0, 20:40] = STICK
    F = np.ones((1, samples))
    rates = np.zeros((samples, 2))
    rates[:, 0] = np.cos(np.linspace(0, 2 * np.pi, samples, endpoint=False))     # the normal speed
    rates[:, 1] = 0.7                                                            # the tangential speed
    rates[20, 0] = 0.0                                                           # grazing at the touch
    Phi, grazing = floquet._monodromy_grazing(M, C, K, W, law, state, F, omega, rates)
    assert np.all(np.isfinite(Phi)) and grazing == 1
    assert _relative_error(Phi, floquet.monodromy(M, C, K, W, law, state, F, omega)) <= 1e-14
    st = floquet.Stability(multipliers=floquet.multipliers(Phi), error=0.01, grazing=grazing)
    assert st.stable is None
    rates[20, 0] = 0.5
    Phi_clear, grazing = floquet._monodromy_grazing(M, C, K, W, law, state, F, omega, rates)
    assert grazing == 0 and _relative_error(Phi_clear, Phi) > 1e-6
