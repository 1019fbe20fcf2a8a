"""Free-interface CMS with residual attachment modes, against exact and direct solutions."""

import numpy as np
import pytest
import scipy.linalg as sla
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from reference_fe.cms import free_interface_basis, normal_modes, project


def chain(n: int, k: float = 1.0e6, m: float = 0.1):
    """Fixed-free chain of n masses m joined by springs k (the first to the wall)."""
    main = np.full(n, 2.0 * k)
    main[-1] = k
    K = sp.diags([main, -k * np.ones(n - 1), -k * np.ones(n - 1)], [0, 1, -1], format="csr")
    M = sp.identity(n, format="csr") * m
    return K, M


def chain_omega2(n: int, k: float = 1.0e6, m: float = 0.1) -> np.ndarray:
    """Exact: omega_j = 2 sqrt(k/m) sin((2j-1) pi / (2(2n+1)))."""
    j = np.arange(1, n + 1)
    return 4.0 * k / m * np.sin((2 * j - 1) * np.pi / (2 * (2 * n + 1))) ** 2


def membrane(nx: int, ny: int):
    """Spring grid clamped on one edge, consistent-like banded mass (SPD, not diagonal)."""
    def line(n, clamp):
        d = np.full(n, 2.0)
        if not clamp:
            d[-1] = 1.0
        return sp.diags([d, -np.ones(n - 1), -np.ones(n - 1)], [0, 1, -1])
    K = (sp.kron(line(nx, True), sp.identity(ny)) + sp.kron(sp.identity(nx), line(ny, False))) * 1e5
    m = sp.diags([np.full(nx * ny, 4.0), np.ones(nx * ny - 1), np.ones(nx * ny - 1)], [0, 1, -1]) / 6.0
    return sp.csr_matrix(K), sp.csr_matrix(m) * 0.01


def test_normal_modes_match_the_exact_chain_frequencies():
    K, M = chain(200)
    omega2, Phi = normal_modes(K, M, 8)
    np.testing.assert_allclose(omega2, chain_omega2(200)[:8], rtol=1e-9)
    np.testing.assert_allclose(Phi.T @ (M @ Phi), np.eye(8), atol=1e-10)


def test_normal_modes_are_the_same_to_the_last_bit_on_every_call():
    """One input, one answer: ARPACK's default start vector is drawn from the system's entropy, so two calls
    rounded the eigenpairs differently (the full solid's Rayleigh coefficients, from its first two
    frequencies, changed between identical runs of hb_fig7, and with them its converged residual)."""
    K, M = membrane(30, 20)
    first, again = normal_modes(K, M, 6), normal_modes(K, M, 6)
    assert first[0].tobytes() == again[0].tobytes() and first[1].tobytes() == again[1].tobytes()


def test_kept_modes_are_exact_and_the_rest_are_upper_bounds():
    K, M = chain(300)
    forces = np.zeros((300, 2))
    forces[-1, 0] = 1.0          # a contact node at the tip
    forces[150, 1] = 1.0
    basis = free_interface_basis(K, M, 6, forces)
    Kr, Mr = project(basis, K), project(basis, M)
    np.testing.assert_allclose(Mr, np.eye(basis.size), atol=1e-9)
    lam = np.sort(np.linalg.eigvalsh(Kr))
    exact = chain_omega2(300)
    np.testing.assert_allclose(lam[:6], exact[:6], rtol=1e-9)
    # Rayleigh-Ritz: every reduced eigenvalue bounds the exact one of its rank from above.
    assert np.all(lam >= exact[: basis.size] * (1 - 1e-9))


def test_static_response_to_every_contact_force_is_exact():
    K, M = membrane(30, 12)
    n = K.shape[0]
    rng = np.random.default_rng(1)
    contact_dofs = n - 12 + np.arange(0, 12, 2)           # nodes on the free edge
    forces = np.zeros((n, contact_dofs.size + 1))
    forces[contact_dofs, np.arange(contact_dofs.size)] = 1.0
    forces[:, -1] = rng.random(n)                          # a distributed load
    basis = free_interface_basis(K, M, 5, forces)
    f = forces @ rng.normal(size=forces.shape[1])
    reduced = basis.T @ np.linalg.solve(project(basis, K), basis.T.T @ f)
    direct = spla.spsolve(sp.csc_matrix(K), f)
    assert np.linalg.norm(reduced - direct) < 1e-9 * np.linalg.norm(direct)


def test_attachment_modes_improve_the_interface_frequency_response():
    """Receptance at a contact node between modes 3 and 4, against a direct solve."""
    K, M = membrane(30, 12)
    n = K.shape[0]
    node = n - 6
    forces = np.zeros((n, 1))
    forces[node, 0] = 1.0
    omega2, _ = normal_modes(K, M, 4)
    w2 = 0.5 * (omega2[2] + omega2[3])
    direct = spla.spsolve(sp.csc_matrix(K - w2 * M), forces[:, 0])[node]

    def receptance(basis):
        Kr, Mr = project(basis, K), project(basis, M)
        p = np.linalg.solve(Kr - w2 * Mr, basis.T.T @ forces[:, 0])
        return (basis.T @ p)[node]

    with_attachment = receptance(free_interface_basis(K, M, 6, forces))
    modes_only = receptance(free_interface_basis(K, M, 6, np.zeros((n, 0))))
    err_with = abs(with_attachment - direct) / abs(direct)
    err_without = abs(modes_only - direct) / abs(direct)
    assert err_with < 0.1 * err_without


def face_compliance(basis) -> np.ndarray:
    """``W T Lambda^-1 T^T W^T`` of a basis with T^T K T = diag(omega2)."""
    WT = basis.T[-12:]
    return WT @ (WT.T / basis.omega2[:, None])


@pytest.mark.parametrize("kept", [1, 3, 6])
def test_interface_reduction_is_the_best_rank_k_face_compliance(kept):
    """Eckart-Young: dropping face patterns costs exactly the largest dropped residual flexibility.

    The truth is a dense inverse of K and a dense eigen-solve, independent of
    the sparse shift-invert and the attachment-mode algebra under test.
    """
    K, M = membrane(20, 12)
    n = K.shape[0]
    W = sp.csr_matrix((np.ones(12), (np.arange(12), np.arange(n - 12, n))), shape=(12, n))  # free edge
    Kd, Md = K.toarray(), M.toarray()
    lam, X = sla.eigh(Kd, Md)
    exact = np.linalg.inv(Kd)[-12:, -12:]
    modal = X[-12:, :4] @ (X[-12:, :4].T / lam[:4, None])
    residual = np.sort(np.linalg.eigvalsh(exact - modal))[::-1]
    basis = free_interface_basis(K, M, 4, np.zeros((n, 0)), W=W, interface_modes=kept)
    assert basis.n_attachment == kept
    error = np.linalg.eigvalsh(exact - face_compliance(basis))
    assert error.min() > -1e-9 * residual[0]                     # Ritz: never more compliant than the solid
    assert error.max() == pytest.approx(residual[kept], rel=1e-6)
    everything = free_interface_basis(K, M, 4, np.zeros((n, 0)), W=W, interface_modes=0)
    assert np.abs(face_compliance(everything) - exact).max() < 1e-9 * np.abs(exact).max()


def test_dependent_force_directions_are_dropped_not_inverted():
    K, M = chain(100)
    forces = np.zeros((100, 3))
    forces[-1, 0] = 1.0
    forces[-1, 1] = 2.0          # the same direction twice
    forces[50, 2] = 1.0
    basis = free_interface_basis(K, M, 4, forces)
    assert basis.n_attachment == 2
    assert np.linalg.cond(project(basis, M)) < 1 + 1e-8


def test_too_many_modes_is_refused():
    K, M = chain(5)
    with pytest.raises(ValueError, match="cannot compute"):
        normal_modes(K, M, 5)
