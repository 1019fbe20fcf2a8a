"""Stability of a periodic steady state: Floquet multipliers, two ways.

Monodromy (time domain): the motion linearized about the periodic orbit,

    M dq'' + C dq' + K dq = W^T dlam,

with the contact law's tangent along the orbit, integrated over one period.
The tangent of each element is the law's own (shroud.core.contact.tangent)
in its state at each sample of the harmonic-balance solution
(shroud.core.harmonic_balance's AFT record): separated 0; normal contact dlam_n = -kn dy_n; stick dF = kt (dz - dw) with
the slider perturbation dz held from the start of the stick; slip
dF = sigma mu s kn dv and the slider slaved, dz = dw + dF / kt. The state
is [dq, dq', dz] (dz of the elements that both stick and release during the
period; a slider stuck all period only adds the neutral multiplier 1 of its
arbitrary offset, which is left out). Over each sample interval the states
are constant and the flow is exp(A dt); the product over the period is the
monodromy matrix, whose eigenvalues are the Floquet multipliers.

Hill's method (frequency domain): the perturbation e^{s t} p(t) with p
periodic in the same harmonics gives the quadratic eigenproblem
(J + s Delta_1 + s^2 Delta_2) P = 0 with J the harmonic-balance Jacobian on
all DOFs, Delta_1 = I (x) C + 2 D (x) M, Delta_2 = I (x) M (D the time
derivative on the coefficients); the exponents with |Im s| <= omega / 2
are the Floquet exponents, multipliers exp(s T).

A point is stable when every multiplier lies inside the unit circle. Along
a branch, a multiplier leaving through +1 marks a fold, through -1 a
period doubling, a complex pair a Neimark-Sacker bifurcation.
"""

from __future__ import annotations

import numpy as np
import scipy.linalg
from numba import njit

from shroud.core.contact import SIGN, SLIP, STICK, ContactLaw, tangents
from shroud.core.linear_solvers import dense

UNIT_CIRCLE_TOL = 1e-6
SMALL = 128       # state dimension up to which the compiled loops beat LAPACK/BLAS calls (and their threads)


@njit(cache=True)
def _matmul(A, B):
    """A @ B by loops: small matrices, no BLAS threads (which cost more than the product here)."""
    n, m, p = A.shape[0], A.shape[1], B.shape[1]
    out = np.zeros((n, p))
    for i in range(n):
        for k in range(m):
            a = A[i, k]
            if a != 0.0:
                for j in range(p):
                    out[i, j] += a * B[k, j]
    return out


@njit(cache=True)
def expm_small(A):
    """exp(A) of a small dense matrix: scaling and squaring of a degree-18 Taylor sum (error < 1e-16 ||A||)."""
    n = A.shape[0]
    norm = 0.0
    for i in range(n):
        row = 0.0
        for j in range(n):
            row += abs(A[i, j])
        norm = max(norm, row)
    s = 0
    while norm > 0.5:
        norm *= 0.5
        s += 1
    B = A / 2.0 ** s
    E = np.eye(n)
    term = np.eye(n)
    for k in range(1, 19):
        term = _matmul(term, B) / k
        E += term
    for _ in range(s):
        E = _matmul(E, E)
    return E



def monodromy(M, C, K, W, law: ContactLaw, state: np.ndarray, F: np.ndarray, omega: float) -> np.ndarray:
    """Monodromy matrix of the linearized motion over one period 2 pi / omega.

    ``state``, ``F`` (elements, samples): each element's state and friction
    force at the samples of the period (sample i holds over [t_i, t_i+1]).
    """
    M, C, K, W = dense(M), dense(C), dense(K), dense(W)
    n, (k, nt) = M.shape[0], state.shape
    dt = 2 * np.pi / omega / nt
    sticks = (state == STICK).any(axis=1)
    released = (state != STICK).any(axis=1)
    hist = np.flatnonzero(sticks & released)           # elements whose slider carries a history
    nz = hist.size
    slot = -np.ones(k, np.int64)
    slot[hist] = np.arange(nz)
    Minv = np.linalg.inv(M)
    d = 2 * n + nz
    sigma = np.where(F > 0, 1.0, -1.0)
    key = state * 2 + (sigma > 0) * (state == SLIP)
    Phi = np.eye(d)
    Wn, Wt = W[law.rows[:, 0]], W[law.rows[:, 1]]
    change = np.flatnonzero(np.any(key[:, 1:] != key[:, :-1], axis=0)) + 1
    starts = np.r_[0, change]
    lengths = np.diff(np.r_[starts, nt])
    flows: dict[bytes, tuple] = {}
    for i, length in zip(starts, lengths):              # runs of samples with the same states
        tag = key[:, i].tobytes()
        got = flows.get(tag)
        if got is None:
            tan = tangents(state[:, i], F[:, i], law.props)
            A, release = _linearized(Minv, K, C, Wn, Wt, law.props[:, SIGN], tan, hist, slot)
            flows[tag] = got = (A, release)
        A, release = got
        step = expm_small(A * (dt * length)) if d <= SMALL else scipy.linalg.expm(A * (dt * length))
        if release.size:                                # released sliders follow the blade (at the
            step[2 * n + release[:, 0].astype(np.int64)] = release[:, 1:] @ step    # run's end)
        Phi = _matmul(step, Phi) if d <= SMALL else step @ Phi
    return Phi


def _linearized(Minv, K, C, Wn, Wt, s, tan, hist, slot):
    """The flow matrix A of [dq, dq', dz] in one set of states, and the released sliders' rows.

    ``s`` the elements' sides (-1, +1), ``tan`` (elements, 7) the law's tangent (shroud.core.contact.tangent) of
    every element. The contact force on the projected coordinates,
    dlam_n = -s dN, dlam_t = dF, gives the stiffness Kc = -W^T dlam/dy and
    the sliders' forcing W_t^T dF/dz. A slider that is not sticking is
    slaved to the blade: its rows (slot, then the row vector on the state)
    set it at the run's end from dz = dz/dv dv + dz/dw dw.
    """
    n, nz = K.shape[0], hist.size
    dN_dv, dF_dv, dF_dw, dF_dz, dz_dv, dz_dw = (tan[:, c] for c in range(6))
    Kc = Wn.T @ ((s * dN_dv)[:, None] * Wn) - Wt.T @ (dF_dv[:, None] * Wn) - Wt.T @ (dF_dw[:, None] * Wt)
    A = np.zeros((2 * n + nz, 2 * n + nz))
    A[:n, n:2 * n] = np.eye(n)
    A[n:2 * n, :n] = -Minv @ (K + Kc)
    A[n:2 * n, n:2 * n] = -Minv @ C
    A[n:2 * n, 2 * n:] = Minv @ (Wt[hist].T * dF_dz[hist])
    free = hist[tan[hist, 6] == 0.0]                       # dz/dz = 0: released
    release = np.zeros((free.size, 1 + 2 * n + nz))
    release[:, 0] = slot[free]
    release[:, 1:n + 1] = dz_dv[free, None] * Wn[free] + dz_dw[free, None] * Wt[free]
    return A, release


def multipliers(Phi: np.ndarray) -> np.ndarray:
    """Floquet multipliers, largest modulus first."""
    mu = np.linalg.eigvals(Phi)
    return mu[np.argsort(-np.abs(mu))]


def hill_exponents(J: np.ndarray, M, C, omega: float, H: int) -> np.ndarray:
    """Floquet exponents by Hill's method from the all-DOF harmonic-balance Jacobian J (nh n square).

    Returns the 2n exponents with |Im s| <= omega / 2 (1/s), largest real part first.
    """
    M, C = dense(M), dense(C)
    n, nh = M.shape[0], 2 * H + 1
    Dt = np.zeros((nh, nh))                             # d/dt on [a_0, a_1, b_1, ...]
    for k in range(1, H + 1):
        Dt[2 * k - 1, 2 * k] = k * omega                # cos coefficient of x' gets k w b_k
        Dt[2 * k, 2 * k - 1] = -k * omega
    D1 = np.kron(np.eye(nh), C) + 2 * np.kron(Dt, M)
    D2 = np.kron(np.eye(nh), M)
    N = nh * n
    A = np.block([[np.zeros((N, N)), np.eye(N)], [-J, -D1]])
    B = np.block([[np.eye(N), np.zeros((N, N))], [np.zeros((N, N)), D2]])
    s = scipy.linalg.eigvals(A, B)
    s = s[np.isfinite(s)]
    central = s[np.abs(s.imag) <= omega / 2 * (1 + 1e-9)]
    central = central[np.argsort(-central.real)]
    return central[:2 * n]


def is_stable(mult: np.ndarray) -> bool:
    return bool(np.max(np.abs(mult), initial=0.0) < 1.0 + UNIT_CIRCLE_TOL)


def bifurcation(before: np.ndarray, after: np.ndarray) -> str | None:
    """Kind of the loss or gain of stability between two neighbouring points, from their multipliers.

    "fold" (a real multiplier through +1), "period-doubling" (through -1),
    "Neimark-Sacker" (a complex pair); None when stability does not change.
    """
    if is_stable(before) == is_stable(after):
        return None
    crit = after if not is_stable(after) else before      # the unstable side holds the critical one
    m = crit[np.argmax(np.abs(crit))]
    if abs(m.imag) > 1e-6 * abs(m):
        return "Neimark-Sacker"
    return "fold" if m.real > 0 else "period-doubling"
