"""Free-interface component mode synthesis with residual attachment modes.

The reduced FE model ("fe-reduced") keeps the blade's lowest free-interface
normal modes, as the paper does (Sect. 2.2.1: the blade is one substructure,
24 modes kept), and adds what the contact and the loads need: one residual
attachment mode per force direction that the contact or a load can apply
(MacNeal's residual flexibility). Why not Craig-Bampton: its constraint modes
would need the three displacement components of every contact node as
master DOFs, about three times as many columns as the two in-plane force
directions the 1D-friction contact law actually loads, and its fixed-
interface modes converge no faster for a structure whose interface is loaded
by a penalty spring. With residual attachment modes the reduced model is
statically exact for every force the contact and the loads can apply, so the
contact stiffness the reduced model sees is the full model's.

With the kept normal modes ``Phi`` (``K Phi = M Phi Lambda``, ``Phi^T M Phi
= I``) and the force directions ``R`` (columns of ``W^T`` and the load
vectors), the residual attachment modes are

    Psi = (K^-1 - Phi Lambda^-1 Phi^T) R,

which are M- and K-orthogonal to ``Phi`` (``Phi^T M K^-1 = Lambda^-1
Phi^T``). A small generalized eigenproblem on ``Psi`` (after dropping
numerically dependent directions) turns them into M-orthonormal, K-diagonal
vectors, so the basis ``T = [Phi, Psi V]`` gives ``T^T M T = I`` and
``T^T K T = diag``: paper Eq. (12) with a diagonal mass and stiffness.

Interface reduction. The contact attachment modes of neighbouring face nodes
are nearly parallel: a face a few millimetres wide barely deforms except
through its smooth patterns. The residual flexibility seen by the contact
coordinates, ``F_r = W Psi_W = W (K^-1 - Phi Lambda^-1 Phi^T) W^T``
(symmetric, positive semi-definite), is diagonalized, ``F_r = U S U^T``, and
only the attachment modes of the ``k`` principal face-force patterns
``W^T U_k`` are kept (``Psi_W U_k``). The reduced face compliance is then
``W Phi Lambda^-1 Phi^T W^T + U_k S_k U_k^T``: the best rank-k
approximation of the residual part, its 2-norm error the largest dropped
eigenvalue ``s_(k+1)`` (Eckart-Young). Load directions that are not contact
forces (the aerodynamic load) keep their own attachment modes.

Everything here is plain numpy/scipy on sparse matrices: the module knows
nothing of meshes, and is tested on structures with exact solutions.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from shroud.core.linear_solvers import default_factorization


@dataclass(frozen=True)
class ReductionBasis:
    """An M-orthonormal, K-diagonal reduction basis ``q = T p`` (paper Eq. 12)."""

    T: np.ndarray               # (n, r) basis, T^T M T = I
    omega2: np.ndarray          # (r,) diagonal of T^T K T, rad^2/s^2
    n_modes: int                # leading columns that are normal modes
    n_attachment: int           # trailing columns spanning the residual attachment modes

    @property
    def size(self) -> int:
        return int(self.T.shape[1])

    @property
    def mode_frequencies_hz(self) -> np.ndarray:
        """Natural frequencies of the kept normal modes, Hz."""
        return np.sqrt(np.abs(self.omega2[: self.n_modes])) / (2.0 * np.pi)


def normal_modes(K, M, count: int, lu=None) -> tuple[np.ndarray, np.ndarray]:
    """Lowest ``count`` eigenpairs of ``K phi = omega^2 M phi``, mass-normalized.

    Shift-invert about zero with a factorization of ``K`` (a
    shroud.core.linear_solvers.Factorization; SuperLU by default; K must be
    nonsingular: the clamped root makes it so). Returns ``(omega2, Phi)`` sorted ascending, the same to the
    last bit on every call.
    """
    n = K.shape[0]
    if not 1 <= count < n - 1:
        raise ValueError(f"cannot compute {count} modes of a {n}-DOF structure")
    lu = lu or default_factorization(K)
    op = spla.LinearOperator((n, n), matvec=lu.solve, dtype=float)
    # A fixed start vector: ARPACK's default one is drawn from the system's entropy, so each call (each run,
    # each rank) rounded the eigenpairs differently, and with them everything built on them.
    start = np.random.default_rng(0).uniform(-1.0, 1.0, n)
    omega2, Phi = spla.eigsh(K, k=count, M=M, sigma=0.0, which="LM", OPinv=op, v0=start)
    order = np.argsort(omega2)
    omega2, Phi = omega2[order], Phi[:, order]
    Phi /= np.sqrt(np.einsum("ij,ij->j", Phi, M @ Phi))
    return omega2, Phi


def residual_attachment_modes(lu, Phi: np.ndarray, omega2: np.ndarray, R) -> np.ndarray:
    """``(K^-1 - Phi Lambda^-1 Phi^T) R``: static response to ``R`` not carried by the kept modes.

    ``R`` dense, or scipy sparse (the contact directions W^T): a factorization
    with ``solve_sparse`` (reference_fe.factor.MumpsFactor) takes it as it is.
    """
    if sp.issparse(R):
        X = lu.solve_sparse(R) if hasattr(lu, "solve_sparse") else lu.solve(R.toarray())
        X -= Phi @ (np.asarray((R.T @ Phi).T) / omega2[:, None])     # in place: (n, hundreds) arrays
        return X
    R = np.asarray(R, dtype=float)
    return lu.solve(R) - Phi @ ((Phi.T @ R) / omega2[:, None])


def principal_interface_modes(W, Psi_W: np.ndarray, count: int) -> tuple[np.ndarray, np.ndarray]:
    """Attachment modes of the ``count`` principal face-force patterns, and all residual flexibilities.

    ``Psi_W`` (n, m) are the residual attachment modes of the columns of
    ``W^T``. Returns ``(Psi_W U_k, s)`` with ``s`` the eigenvalues of the
    residual face flexibility ``W Psi_W`` in descending order, m/N (the
    spectrum that tells how many patterns matter); ``count = 0`` keeps all m.
    """
    F = np.asarray(W @ Psi_W)
    s, U = sla.eigh(0.5 * (F + F.T))
    s, U = s[::-1], U[:, ::-1]
    k = s.size if count == 0 else min(count, s.size)
    return Psi_W @ U[:, :k], s


def _orthonormal_residual(K, M, Psi: np.ndarray, rtol: float) -> tuple[np.ndarray, np.ndarray]:
    """M-orthonormal, K-diagonal vectors spanning ``Psi`` up to relative tolerance ``rtol``.

    Attachment modes of neighbouring contact nodes are nearly parallel; the
    directions whose M-norm falls below ``rtol`` of the largest carry no
    independent information and would make the reduced mass singular.
    """
    if Psi.shape[1] == 0:
        return Psi, np.zeros(0)
    Mp = Psi.T @ (M @ Psi)
    Kp = Psi.T @ (K @ Psi)
    s, U = sla.eigh(0.5 * (Mp + Mp.T))
    keep = s > rtol * s.max()
    B = U[:, keep] / np.sqrt(s[keep])            # B^T Mp B = I
    lam, V = sla.eigh(B.T @ (0.5 * (Kp + Kp.T)) @ B)
    return Psi @ (B @ V), lam


def free_interface_basis(K, M, n_modes: int, forces: np.ndarray, rtol: float = 1e-10,
                         lu=None, W=None, interface_modes: int = 0) -> ReductionBasis:
    """Kept normal modes plus residual attachment modes for the contact and the loads.

    ``forces`` is (n, l): each column a load direction the reduced model must
    represent statically exactly. ``W`` (m, n), if given, are the contact
    coordinates: the forces ``W^T`` they can receive get attachment modes
    too, all of them (``interface_modes = 0``) or those of the leading
    ``interface_modes`` principal face-force patterns
    (principal_interface_modes).
    """
    lu = lu or default_factorization(K)
    omega2, Phi = normal_modes(K, M, n_modes, lu)
    Psi = residual_attachment_modes(lu, Phi, omega2, np.atleast_2d(forces.T).T)
    if W is not None and W.shape[0]:
        Psi_W = residual_attachment_modes(lu, Phi, omega2, sp.csc_matrix(sp.csr_matrix(W).T))
        Psi = np.hstack([principal_interface_modes(W, Psi_W, interface_modes)[0], Psi])
    # Scale each column to unit M-norm before the dependence test, so a load
    # vector in N and a unit nodal force are judged alike.
    norms = np.sqrt(np.maximum(np.einsum("ij,ij->j", Psi, M @ Psi), 0.0))
    alive = norms > rtol * max(norms.max(initial=0.0), np.finfo(float).tiny)
    Psi = Psi[:, alive] / norms[alive]
    R, lam = _orthonormal_residual(K, M, Psi, rtol)
    return ReductionBasis(T=np.hstack([Phi, R]), omega2=np.concatenate([omega2, lam]),
                          n_modes=n_modes, n_attachment=int(R.shape[1]))


def project(basis: ReductionBasis, A) -> np.ndarray:
    """``T^T A T`` as a dense array (a sparse or dense square operator)."""
    T = basis.T
    return T.T @ np.asarray(A @ T)
