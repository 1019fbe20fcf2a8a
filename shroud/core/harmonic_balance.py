"""Multi-harmonic balance with alternating frequency-time (AFT) evaluation of the contact law.

The periodic steady state of paper Eq. 9,

    M q'' + C q' + K q = f_const + f_aero sin(omega t) + W^T lam(W q),

is sought as a truncated Fourier series in tau = omega t (omega the
excitation frequency ke Omega, one period T = 2 pi / omega):

    x(tau) = a_0 + sum_{k=1..H} a_k cos(k tau) + b_k sin(k tau).

The coefficients of every coordinate are stacked harmonic-major,
X[(c_k, i)] with c_0 = a_0, c_{2k-1} = a_k, c_{2k} = b_k (``nh = 2H + 1``
coefficients per coordinate). Harmonic k of the linear part is the complex
dynamic stiffness Z_k = K - (k omega)^2 M + i k omega C acting on
a_k - i b_k; written in real numbers the residual is

    R(X) = L X - F - Wx^T Lam(Wx X) = 0.

The unknown coordinates x are either all of q, or, where there are fewer
contact coordinates than DOFs (the beams), the contact coordinates y = W q
themselves: the linear part is then condensed exactly per harmonic,
Z_k -> (W Z_k^-1 W^T)^-1 (the dynamic stiffness seen by the contact,
Petrov & Ewins 2003), and Wx = I.

AFT: the coefficients of y are sampled at ``samples`` equidistant instants,
the contact law of shroud.core.contact (the one law: ``normal_force`` and
``friction_return_map``) is evaluated sample by sample with each friction
slider marched around the period until it is periodic, and the forces are
projected back on the harmonics. The Jacobian is analytic: the law is
piecewise linear, its derivatives in each state are the law's own tangent
(shroud.core.contact.tangent), and the derivative of the slider is carried
through its history by the chain rule (stick: z held from the start of the
stick; slip: z = w + F / kt; separated: z = w), so dF/dX in a stick phase
is kt (dz/dX - dw/dX) with dz/dX that of the instant the stick began.

Units: SI (m, N, rad/s).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
from numba import njit

from shroud.core.continuation import continue_branch
from shroud.core.contact import (KN, KT, MU, N0, SEPARATE, SIGN, STICK, ContactLaw, friction_return_map,
                                 normal_force, tangent)
from shroud.core.linear_solvers import dense
from shroud.core.system import StructuralSystem

MAX_PASSES = 3          # periods the sliders are marched at most (2 make any slider periodic)
NO_JACOBIAN, BLOCKS, DIRECT = 0, 1, 2   # what the AFT kernel derives (_aft_kernel)



@njit(cache=True)
def lu_solve_in_place(A: np.ndarray, B: np.ndarray) -> None:
    """B <- A^-1 B for a small dense A (n, n) and B (n, r), real or complex, by Gaussian elimination
    with partial pivoting; A is overwritten. For compiled kernels that solve many tiny systems (a
    6-DOF beam per harmonic, a contact receptance of order 2), where a library call's allocations
    and dispatch cost more than the arithmetic."""
    n, r = A.shape[0], B.shape[1]
    for c in range(n):
        p, big = c, abs(A[c, c])
        for i in range(c + 1, n):
            if abs(A[i, c]) > big:
                p, big = i, abs(A[i, c])
        if p != c:
            for j in range(c, n):
                A[c, j], A[p, j] = A[p, j], A[c, j]
            for j in range(r):
                B[c, j], B[p, j] = B[p, j], B[c, j]
        inv = 1.0 / A[c, c]
        for i in range(c + 1, n):
            f = A[i, c] * inv
            if f != 0:
                for j in range(c + 1, n):
                    A[i, j] -= f * A[c, j]
                for j in range(r):
                    B[i, j] -= f * B[c, j]
    for c in range(n - 1, -1, -1):
        inv = 1.0 / A[c, c]
        for j in range(r):
            acc = B[c, j]
            for i in range(c + 1, n):
                acc -= A[c, i] * B[i, j]
            B[c, j] = acc * inv

@dataclass(frozen=True)
class Fourier:
    """Real Fourier basis of H harmonics sampled at ``samples`` instants of one period.

    E (samples, nh): coefficients -> samples; A (nh, samples): samples ->
    coefficients (exact for trigonometric polynomials of degree < samples / 2).
    """

    H: int
    samples: int
    E: np.ndarray
    A: np.ndarray

    @property
    def nh(self) -> int:
        return 2 * self.H + 1

    @property
    def tau(self) -> np.ndarray:
        return 2 * np.pi * np.arange(self.samples) / self.samples

    def rates(self, X: np.ndarray, omega: float) -> np.ndarray:
        """Samples (samples, n) of dx/dt from the coefficients X (nh, n) of x(omega t), omega in rad/s:
        a_k cos + b_k sin differentiates to k omega (b_k cos - a_k sin)."""
        D = np.zeros_like(X)
        k = np.arange(1, self.H + 1)[:, None] * omega
        D[1::2], D[2::2] = k * X[2::2], -k * X[1::2]
        return self.E @ D


@functools.lru_cache(maxsize=16)
def fourier(H: int, samples: int) -> Fourier:
    """The basis for harmonics 0..H from ``samples`` instants (at least 2 H + 1 of them; shared, read-only)."""
    if H < 1:
        raise ValueError(f"harmonic balance needs H >= 1 harmonics, got {H}")
    if samples < 2 * H + 1:
        raise ValueError(f"{samples} time samples cannot resolve {H} harmonics; at least {2 * H + 1} needed")
    tau = 2 * np.pi * np.arange(samples) / samples
    k = np.arange(1, H + 1)
    E = np.ones((samples, 2 * H + 1))
    E[:, 1::2] = np.cos(np.outer(tau, k))
    E[:, 2::2] = np.sin(np.outer(tau, k))
    A = E.T * (2.0 / samples)
    A[0] /= 2.0
    E.flags.writeable = A.flags.writeable = False
    return Fourier(H=H, samples=samples, E=E, A=A)


def default_samples(H: int) -> int:
    """Time samples per period for H harmonics: 8 per harmonic rounded up to a power of two, at least 512.

    Impacts and stick-slip switch inside a sample interval: the residual is
    piecewise smooth with a kink wherever a switch crosses a sample, and a
    coarse sampling turns a smooth branch into a saw-tooth of tiny folds
    that the continuation would have to follow (0.1 mm gap case: 128
    samples give a jagged upper fold, 512 a smooth one).
    """
    return max(512, 1 << math.ceil(math.log2(8 * H)))


# --- AFT: the contact law along one period, with its derivative -------------------

@njit(cache=True)
def _aft_kernel(Ys, E, A, rows, props, passes_max, N, F, state, Bn, Bt, lam, jacobian, dLam):
    """March every element's law around the period (shroud.core.contact's functions).

    Ys (samples, m): y at the samples; E (samples, nh) synthesis, A (nh,
    samples) analysis. Fills per element j and sample i N, F, state, and
    the harmonics' derivatives Bn[j] = d(N harmonics)/d(normal coefficients)
    (nh, nh) and Bt[j] = d(F harmonics)/d([normal, tangent] coefficients)
    (nh, 2 nh) (``jacobian`` BLOCKS; added to: the caller zeroes them), or
    their sum on the projected coordinates dLam (nh, m, nh, m) =
    d(Lam harmonics)/d(Y harmonics) itself (``jacobian`` DIRECT: the
    unknowns are y, a condensed model), or neither (NO_JACOBIAN), and the
    forces lam (samples, m) on the projected
    coordinates (-s N on the normal row, F on the tangent row). The slider
    starts at the mean of w and is marched until it closes (after a slip or
    a separation z no longer depends on its start, so two periods suffice);
    the last period is recorded. The derivative of the slider is carried
    from the period's last release (slip or separation), which is where the
    periodic slider was last set, or is that of the mean of w when the
    element sticks all period; through a separation only its last sample
    counts (dz/dz = 0 there).
    Returns the most periods marched.
    """
    nt, nh = E.shape
    k = rows.shape[0]
    most = 0
    dz = np.zeros(2 * nh)
    rows_kept = nt if jacobian != NO_JACOBIAN else 0
    G = np.empty((rows_kept, 3 * nh))
    At = np.empty((rows_kept, nh))
    for j in range(k):
        nr, tr = rows[j, 0], rows[j, 1]
        s, kn, kt, mu, n0 = props[j, SIGN], props[j, KN], props[j, KT], props[j, MU], props[j, N0]
        wmax, z = 0.0, 0.0
        for i in range(nt):
            wmax = max(wmax, abs(Ys[i, tr]))
            z += Ys[i, tr]
        z /= nt                             # the mean of w: a neutral start for a stuck slider
        passes = 0
        touching = False
        for p in range(passes_max):
            z_start = z
            for i in range(nt):
                Nj = normal_force(Ys[i, nr], n0, kn, s)
                Fj, z, st = friction_return_map(Ys[i, tr], z, Nj, kt, mu)
                N[j, i], F[j, i], state[j, i] = Nj, Fj, st
                touching = touching or st != SEPARATE
            passes = p + 1
            if p > 0 and abs(z - z_start) <= 1e-13 * (abs(z) + wmax + 1e-300):
                break
        most = max(most, passes)
        if not touching:
            continue
        for i in range(nt):
            lam[i, nr] -= s * N[j, i]
            lam[i, tr] += F[j, i]
        if jacobian == NO_JACOBIAN:
            continue
        # the slider's derivative at the period's start: from its last release (where it no longer
        # depends on its past, dz/dz = 0), or that of the mean of w when it sticks all period
        for c in range(2 * nh):
            dz[c] = 0.0
        dz[nh] = 1.0
        for i in range(nt - 1, -1, -1):
            if state[j, i] != STICK:
                _, _, _, _, dz_dv, dz_dw, _ = tangent(state[j, i], F[j, i], s, kn, kt, mu)
                for c in range(nh):
                    dz[c] = dz_dv * E[i, c]
                    dz[nh + c] = dz_dw * E[i, c]
                break
        # the derivative rows of the touching samples, G[l] = d(N, F at sample l)/d(normal, tangent
        # coefficients), then their harmonics A G as one matrix product
        touched = 0
        separated = -1                      # the last sample of a separation not yet applied to dz
        for i in range(nt):                 # the chain rule through the law's tangent, sample by sample
            if state[j, i] == SEPARATE:
                separated = i
                continue
            if separated >= 0:
                _, _, _, _, dz_dv, dz_dw, _ = tangent(SEPARATE, 0.0, s, kn, kt, mu)
                for c in range(nh):
                    dz[c] = dz_dv * E[separated, c]
                    dz[nh + c] = dz_dw * E[separated, c]
                separated = -1
            dN_dv, dF_dv, dF_dw, dF_dz, dz_dv, dz_dw, dz_dz = tangent(state[j, i], F[j, i], s, kn, kt, mu)
            for c in range(nh):
                e = E[i, c]
                G[touched, c] = dN_dv * e
                G[touched, nh + c] = dF_dv * e + dF_dz * dz[c]
                G[touched, 2 * nh + c] = dF_dw * e + dF_dz * dz[nh + c]
                dz[c] = dz_dv * e + dz_dz * dz[c]
                dz[nh + c] = dz_dw * e + dz_dz * dz[nh + c]
                At[touched, c] = A[c, i]
            touched += 1
        AG = At[:touched].T @ G[:touched]   # (nh, 3 nh): harmonics of dN/dv, dF/dv, dF/dw
        if jacobian == DIRECT:              # the normal force acts as -s N on the normal row
            for r in range(nh):
                for c in range(nh):
                    dLam[r, nr, c, nr] -= s * AG[r, c]
                    dLam[r, tr, c, nr] += AG[r, nh + c]
                    dLam[r, tr, c, tr] += AG[r, 2 * nh + c]
        else:
            for r in range(nh):
                for c in range(nh):
                    Bn[j, r, c] += AG[r, c]
                for c in range(2 * nh):
                    Bt[j, r, c] += AG[r, nh + c]
    return most


@dataclass(frozen=True)
class ContactHarmonics:
    """The law along one period: forces, their harmonics and derivatives."""

    lam: np.ndarray          # (samples, m) forces on the projected coordinates, N
    Lam: np.ndarray          # (nh, m) their harmonics
    dLam_x: np.ndarray | None   # (nh*nx, nh*nx) d(Wx^T Lam)/dX
    N: np.ndarray            # (k, samples) normal force per element
    F: np.ndarray            # (k, samples) friction per element
    state: np.ndarray        # (k, samples) 0 separate, 1 stick, 2 slip
    passes: int              # periods the sliders were marched


def contact_harmonics(X: np.ndarray, Wx: np.ndarray, law: ContactLaw, basis: Fourier,
                      jacobian: bool = True, condensed: bool | None = None) -> ContactHarmonics:
    """AFT of ``law`` at the coefficients X (nh, nx) of the unknown coordinates, y = Wx x.

    Where the unknowns are y themselves (Wx = I: a condensed model) the
    kernel sums the Jacobian on y as it marches; otherwise it is projected on
    x element by element, over the elements that touch at some instant (the
    others contribute nothing). ``jacobian=False`` skips it (dLam_x is then None).
    ``condensed``: whether Wx = I, if the caller knows (else Wx is compared with I).
    """
    nh, nt, k, m = basis.nh, basis.samples, law.count, law.m
    nx = Wx.shape[1]
    direct = (Wx.shape[0] == nx and np.array_equal(Wx, np.eye(nx))) if condensed is None else condensed
    Ys = basis.E @ (X if direct else X @ Wx.T)           # y at the samples
    N, F = np.empty((k, nt)), np.empty((k, nt))
    state = np.empty((k, nt), np.int64)
    blocks, direct = jacobian and not direct, jacobian and direct
    mode = DIRECT if direct else BLOCKS if blocks else NO_JACOBIAN
    Bn, Bt = np.zeros((k, nh, nh) if blocks else (0, 0, 0)), np.zeros((k, nh, 2 * nh) if blocks else (0, 0, 0))
    dLam = np.zeros((nh, nx, nh, nx) if direct else (0, 0, 0, 0))
    lam = np.zeros((nt, m))
    passes = _aft_kernel(Ys, basis.E, basis.A, law.rows, law.props, MAX_PASSES, N, F, state, Bn, Bt,
                         lam, mode, dLam) if k else 0
    Lam = basis.A @ lam
    if not jacobian:
        return ContactHarmonics(lam=lam, Lam=Lam, dLam_x=None, N=N, F=F, state=state, passes=int(passes))
    if blocks:                                            # per touching element, projected on x
        dLam = np.zeros((nh, nx, nh, nx))
        act = np.flatnonzero(N.any(axis=1))
        s = law.props[act, SIGN]
        n_rows, t_rows = law.rows[act, 0], law.rows[act, 1]
        for B, a, b in ((-s[:, None, None] * Bn[act], n_rows, n_rows),   # the normal force acts as -s N
                        (Bt[act, :, :nh], t_rows, n_rows), (Bt[act, :, nh:], t_rows, t_rows)):
            Wa, Wb = Wx[a], Wx[b]                         # (touching elements, nx)
            outer = (Wa[:, :, None] * Wb[:, None, :]).reshape(act.size, nx * nx)
            dLam += np.tensordot(B, outer, axes=(0, 0)).reshape(nh, nh, nx, nx).transpose(0, 2, 1, 3)
    return ContactHarmonics(lam=lam, Lam=Lam, dLam_x=dLam.reshape(nh * nx, nh * nx), N=N, F=F,
                            state=state, passes=int(passes))


# --- the linear part per harmonic ---------------------------------------------------

@dataclass(frozen=True)
class LinearHarmonics:
    """The linear part of one system at one speed on the unknown coordinates x.

    Z (H+1, nx, nx) complex dynamic stiffness per harmonic; F (H+1, nx)
    complex load (a_k - i b_k convention); L (nh nx, nh nx) and Fr (nh, nx)
    the same in real coefficients (the residual's L X - Fr); y = Wx x. The
    tip outputs are tip_k = tip_x[k] X_k + tip_lam[k] Lam_k + tip_f[k]
    (complex, per harmonic).
    """

    omega: float
    Z: np.ndarray
    F: np.ndarray
    L: np.ndarray
    Fr: np.ndarray
    Wx: np.ndarray
    tip_x: np.ndarray
    tip_lam: np.ndarray
    tip_f: np.ndarray
    condensed: bool

    @property
    def nx(self) -> int:
        return self.Wx.shape[1]

    def tip(self, X: np.ndarray, Lam: np.ndarray) -> np.ndarray:
        """(nh, 2) coefficients of v_L, w_L."""
        out = np.einsum("kij,kj->ki", self.tip_lam, _complex_coefficients(Lam)) + self.tip_f
        if not self.condensed:                    # (condensed, tip_x is 0)
            out += np.einsum("kij,kj->ki", self.tip_x, _complex_coefficients(X))
        return _real_coefficients(out)


def _real_coefficients(Xc: np.ndarray) -> np.ndarray:
    """(H+1, n) complex a_k - i b_k -> (2H+1, n) real [a_0, a_1, b_1, ...]."""
    out = np.empty((2 * Xc.shape[0] - 1, Xc.shape[1]))
    out[0] = Xc[0].real
    out[1::2] = Xc[1:].real
    out[2::2] = -Xc[1:].imag
    return out


_real_coefficients_compiled = njit(cache=True)(_real_coefficients)     # the same, inside compiled kernels


def _complex_coefficients(X: np.ndarray) -> np.ndarray:
    """(2H+1, n) real -> (H+1, n) complex a_k - i b_k."""
    out = np.empty(((X.shape[0] + 1) // 2, X.shape[1]), complex)
    out[0] = X[0]
    out[1:] = X[1::2] - 1j * X[2::2]
    return out


@njit(cache=True)
def _real_blocks(Z: np.ndarray) -> np.ndarray:
    """Block-diagonal real matrix of the complex Z_k on [a_k; b_k]: [[Zr, Zi], [-Zi, Zr]]."""
    H1, n = Z.shape[0], Z.shape[1]
    nh = 2 * H1 - 1
    L = np.zeros((nh * n, nh * n))
    for i in range(n):
        for j in range(n):
            L[i, j] = Z[0, i, j].real
    for k in range(1, H1):
        a, b = (2 * k - 1) * n, 2 * k * n
        for i in range(n):
            for j in range(n):
                zr, zi = Z[k, i, j].real, Z[k, i, j].imag
                L[a + i, a + j] = L[b + i, b + j] = zr
                L[a + i, b + j] = zi
                L[b + i, a + j] = -zi
    return L


@njit(cache=True)
def _solved_columns(M, C, K, O, m, f_const, f_aero, omega, H):
    """O Z_k^-1 [W^T, F_k] for k = 0..H, complex (H+1, o, m+1): each harmonic's dynamic stiffness
    Z_k = K - (k omega)^2 M + i k omega C solved against the contact directions W^T = O[:m]^T and
    the load's harmonic F_k (:func:`load_harmonics`: f_const at k = 0, -i f_aero at k = 1, else 0),
    seen through the outputs O (o, n). One work array for every harmonic: on a 6-DOF model the
    allocations of a library solve per harmonic cost more than its arithmetic."""
    n, o = M.shape[0], O.shape[0]
    out = np.empty((H + 1, o, m + 1), np.complex128)
    Z = np.empty((n, n), np.complex128)
    S = np.empty((n, m + 1), np.complex128)
    for k in range(H + 1):
        w = k * omega
        for i in range(n):
            for j in range(n):
                Z[i, j] = complex(K[i, j] - w * w * M[i, j], w * C[i, j])
            for j in range(m):
                S[i, j] = O[j, i]
            S[i, m] = f_const[i] if k == 0 else complex(0.0, -f_aero[i]) if k == 1 else 0.0
        lu_solve_in_place(Z, S)
        for a in range(o):
            for b in range(m + 1):
                acc = 0j
                for i in range(n):
                    acc += O[a, i] * S[i, b]
                out[k, a, b] = acc
    return out


def dynamic_stiffness(system: StructuralSystem, H: int, omega: float | None = None) -> np.ndarray:
    """Z_k = K - (k omega)^2 M + i k omega C for k = 0..H, complex (H+1, n, n)."""
    w = system.omega_e if omega is None else omega
    M, C, K = dense(system.M), dense(system.C), dense(system.K)
    k = np.arange(H + 1)[:, None, None]
    return K[None] - (k * w) ** 2 * M[None] + 1j * k * w * C[None]


def load_harmonics(system: StructuralSystem, H: int) -> np.ndarray:
    """f_const at k = 0 and f_aero sin(tau) (b_1 = f_aero, i.e. -i f_aero) at k = 1."""
    F = np.zeros((H + 1, system.dofs), complex)
    F[0] = system.f_const
    F[1] = -1j * np.asarray(system.f_aero, float)
    return F


def condenses(m: int, n: int) -> bool:
    """Whether a model of n DOFs with m contact coordinates is balanced condensed on them (fewer than n)."""
    return 0 < m < n


def linear_harmonics(system: StructuralSystem, H: int, condense: bool | None = None) -> LinearHarmonics:
    """The linear part of ``system`` at its speed, on all DOFs or condensed on y = W q.

    ``condense=None`` condenses where :func:`condenses` says (W Z_k^-1 W^T per
    harmonic, exact).
    """
    n = system.dofs
    W = dense(system.contact.W) if system.contact is not None else np.zeros((0, n))
    tip = dense(system.tip)
    m = W.shape[0]
    condense = condenses(m, n) if condense is None else condense
    if not condense:
        Z, F = dynamic_stiffness(system, H), load_harmonics(system, H)
        return LinearHarmonics(omega=system.omega_e, Z=Z, F=F, L=_real_blocks(Z), Fr=_real_coefficients(F),
                               Wx=W, tip_x=np.broadcast_to(tip.astype(complex), (H + 1, 2, n)),
                               tip_lam=np.zeros((H + 1, 2, m), complex), tip_f=np.zeros((H + 1, 2), complex),
                               condensed=False)
    return from_condensation(system.omega_e, *condensation(dense(system.M), dense(system.C), dense(system.K),
                                                          np.vstack([W, tip]), m, dense(system.f_const),
                                                          dense(system.f_aero), system.omega_e, H))


@njit(cache=True)
def condensation(M, C, K, O, m, f_const, f_aero, omega, H):
    """The dense linear part condensed exactly on y = W q per harmonic, W = O[:m] (the contact
    directions; O's other rows the tip outputs): (Z, F, L, Fr, tipS) for :func:`from_condensation`.
    Compiled, so that a model's own kernel can build its matrices at a speed and condense them in one
    call (reduced_model.system.BeamOverSpeed.harmonics)."""
    WS = _solved_columns(M, C, K, O, m, f_const, f_aero, omega, H)
    Zc, Fc, L, Fr = _inverse_receptance(WS[:, :m])
    return Zc, Fc, L, Fr, WS[:, m:]


def condensed(omega: float, WS: np.ndarray, tipS: np.ndarray) -> LinearHarmonics:
    """The linear part condensed exactly on y = W q, from the solved columns of each harmonic.

    WS (H+1, m, m+1) = W Z_k^-1 [W^T, F_k] and tipS (H+1, 2, m+1) = tip Z_k^-1 [W^T, F_k]
    (complex; however the model solves with Z_k): the receptance on the contact coordinates
    R_k = W Z_k^-1 W^T gives Z = R_k^-1 and F = R_k^-1 W Z_k^-1 F_k (Petrov & Ewins 2003).
    """
    return from_condensation(omega, *_inverse_receptance(WS), tipS)


def from_condensation(omega: float, Z: np.ndarray, F: np.ndarray, L: np.ndarray, Fr: np.ndarray,
                      tipS: np.ndarray) -> LinearHarmonics:
    """LinearHarmonics on the contact coordinates from Z_k = R_k^-1, F_k, their real forms L, Fr and
    tipS = tip Z_k^-1 [W^T, F_k] (H+1, 2, m+1)."""
    identity, zeros = _condensed_constants(Z.shape[0], Z.shape[1])
    m = Z.shape[1]
    return LinearHarmonics(omega=omega, Z=Z, F=F, L=L, Fr=Fr, Wx=identity, tip_x=zeros, tip_lam=tipS[:, :, :m],
                           tip_f=tipS[:, :, m], condensed=True)


@functools.lru_cache(maxsize=8)
def _condensed_constants(H1: int, m: int) -> tuple[np.ndarray, np.ndarray]:
    """Wx = I and tip_x = 0 of a condensation on m coordinates with H1 - 1 harmonics (shared, read-only:
    a continuation makes hundreds of condensations)."""
    identity, zeros = np.eye(m), np.zeros((H1, 2, m), complex)
    identity.flags.writeable = zeros.flags.writeable = False
    return identity, zeros


@njit(cache=True)
def _inverse_receptance(WS):
    """From WS[k] = [R_k, w_k] (m, m+1, complex) per harmonic: Z_k = R_k^-1 and F_k = R_k^-1 w_k,
    and both in real coefficients, L (:func:`_real_blocks`) and Fr (nh, m)."""
    H1, m = WS.shape[0], WS.shape[1]
    Zc = np.empty((H1, m, m), np.complex128)
    Fc = np.empty((H1, m), np.complex128)
    R = np.empty((m, m), np.complex128)
    S = np.empty((m, m + 1), np.complex128)
    for k in range(H1):
        for i in range(m):
            for j in range(m):
                R[i, j] = WS[k, i, j]
                S[i, j] = 1.0 if i == j else 0.0
            S[i, m] = WS[k, i, m]
        lu_solve_in_place(R, S)                    # [R^-1, R^-1 w]
        Zc[k] = S[:, :m]
        Fc[k] = S[:, m]
    return Zc, Fc, _real_blocks(Zc), _real_coefficients_compiled(Fc)


# --- residual, Newton at one speed ---------------------------------------------------

@dataclass(frozen=True)
class Balance:
    """Residual of the harmonic balance at one speed and its pieces."""

    R: np.ndarray                # (nh nx,) N
    J: np.ndarray | None         # (nh nx, nh nx) dR/dX
    contact: ContactHarmonics


def balance(X: np.ndarray, lin: LinearHarmonics, law: ContactLaw, basis: Fourier,
            L: np.ndarray | None = None, Fr: np.ndarray | None = None, jacobian: bool = True) -> Balance:
    """R(X) = L X - F - Wx^T Lam(Wx X) and its analytic Jacobian (X flat, harmonic-major; None if not asked)."""
    nh, nx = basis.nh, lin.nx
    L = lin.L if L is None else L
    Fr = lin.Fr if Fr is None else Fr
    Xm = X.reshape(nh, nx)
    ch = contact_harmonics(Xm, lin.Wx, law, basis, jacobian, lin.condensed)
    R = L @ X - Fr.ravel() - (ch.Lam if lin.condensed else ch.Lam @ lin.Wx).ravel()
    return Balance(R=R, J=L - ch.dLam_x if jacobian else None, contact=ch)


def linear_solution(lin: LinearHarmonics) -> np.ndarray:
    """X of the contact-free linear part, L X = F (flat)."""
    Xc = np.linalg.solve(lin.Z, lin.F[:, :, None])[:, :, 0]
    return _real_coefficients(Xc).ravel()


@dataclass(frozen=True)
class HarmonicSolution:
    """A periodic steady state found by harmonic balance (one speed)."""

    X: np.ndarray               # (nh nx,) coefficients of the unknown coordinates
    tip: np.ndarray             # (nh, 2) coefficients of v_L, w_L, m
    amplitude_v_L: float        # (max - min)/2 of v_L over the period, m
    amplitude_w_L: float
    residual: float             # |R| / |F| at the solution
    iterations: int
    converged: bool             # |R| / |F| within ACCEPT (usable), not necessarily within ``tolerance``
    spectral_tail: float        # share of the contact forces' spectrum above H
    contact: ContactHarmonics
    basis: Fourier
    tolerance: float = 1e-10    # the |R| / |F| Newton was asked for

    @property
    def short(self) -> bool:
        """Newton stopped short of the tolerance asked (converged only within ACCEPT, or not at all)."""
        return bool(self.residual > self.tolerance)


ACCEPT = 1e-6    # |R| / |F| a Newton that stalls short of its tolerance is still accepted at (and says so)


class NewtonResult(NamedTuple):
    """hb.newton's answer: X, its Balance, iterations, ``converged`` (|R| / |F| <= ACCEPT), the relative
    residual reached and the tolerance asked; ``short`` when the residual is above the tolerance."""

    X: np.ndarray
    balance: Balance
    iterations: int
    converged: bool
    residual: float
    tolerance: float

    @property
    def short(self) -> bool:
        return bool(self.residual > self.tolerance)


def damped_newton(evaluate, X0: np.ndarray, scale: float, tol: float, max_iterations: int, solve=np.linalg.solve,
                  shortest_step: float = 1e-3) -> tuple[np.ndarray, object, int, float, bool]:
    """Newton on R(X) = 0, halving a step that does not lower |R| down to ``shortest_step``: the one loop of
    every harmonic balance at one speed (the blade's :func:`newton`, the ring's sectors,
    shroud.core.starts.sector_newton).

    ``evaluate(X, jacobian)`` gives an object with R (and J when asked); ``solve(J, r)`` the step's linear
    solve (a structured one where the Jacobian has a known structure). Ends when |R| <= ``tol`` ``scale``,
    when the steps stall (below 1e-12 of |X|: a sampled law's kinks can hold |R| above a tight tol) or the
    iterations run out. Returns (X, its evaluation with J, iterations, |R| / scale, whether it ended by
    the tolerance or a stall rather than by running out of iterations)."""
    X = X0.copy()
    b = evaluate(X, True)
    r = np.linalg.norm(b.R)
    for it in range(1, max_iterations + 1):
        if r <= tol * scale:
            return X, b, it - 1, float(r / scale), True
        dX = solve(b.J, -b.R)
        t = 1.0
        while True:
            Xt = X + t * dX
            rt = np.linalg.norm(evaluate(Xt, False).R)
            if rt < r or t < shortest_step:
                break
            t *= 0.5
        X = Xt
        b = evaluate(X, True)
        r = np.linalg.norm(b.R)
        if np.linalg.norm(t * dX) <= 1e-12 * (np.linalg.norm(X) + 1e-300):
            return X, b, it, float(r / scale), True
    return X, b, max_iterations, float(r / scale), False


def newton(X0: np.ndarray, lin: LinearHarmonics, law: ContactLaw, basis: Fourier, tol: float = 1e-10,
           max_iterations: int = 50) -> NewtonResult:
    """Newton on the blade's R(X) = 0 at one speed (:func:`damped_newton`); ``converged`` says whether
    |R| / |F| <= ACCEPT (False where the iterations ran out), and the residual reached is returned with ``tol``, so a Newton that stopped short
    of it says so (``short``)."""
    scale = np.linalg.norm(lin.Fr) + 1e-300
    X, b, it, residual, ended = damped_newton(
        lambda X, jacobian: balance(X, lin, law, basis, lin.L, lin.Fr, jacobian), X0, scale, tol, max_iterations)
    return NewtonResult(X, b, it, bool(ended and residual <= ACCEPT), residual, tol)


def spectral_tail(lam: np.ndarray, H: int) -> float:
    """Share of the contact forces' oscillating spectrum above harmonic H (RMS ratio, 0 without force)."""
    spec = np.abs(np.fft.rfft(lam, axis=0)) ** 2
    total = spec[1:].sum()
    return float(np.sqrt(spec[H + 1:].sum() / total)) if total > 0 else 0.0


def amplitude_over_period(coefficients: np.ndarray, samples: int = 512) -> np.ndarray:
    """(max - min)/2 over one period of each column of real coefficients (nh, c), finely sampled."""
    H = (coefficients.shape[0] - 1) // 2
    E = fourier(H, max(samples, 2 * H + 1)).E
    x = coefficients.T @ E.T            # (c, samples): rows, whose max and min numpy takes 5x faster than columns'
    return 0.5 * (x.max(axis=1) - x.min(axis=1))


def solution(X: np.ndarray, b: Balance, lin: LinearHarmonics, basis: Fourier, iterations: int,
             converged: bool, tolerance: float = 1e-10) -> HarmonicSolution:
    """Package a converged point with its tip amplitudes and the contact forces' tail."""
    tip = lin.tip(X.reshape(basis.nh, lin.nx), b.contact.Lam)
    amp = amplitude_over_period(tip)
    return HarmonicSolution(X=X, tip=tip, amplitude_v_L=float(amp[0]), amplitude_w_L=float(amp[1]),
                            residual=float(np.linalg.norm(b.R) / (np.linalg.norm(lin.Fr) + 1e-300)),
                            iterations=iterations, converged=converged,
                            spectral_tail=spectral_tail(b.contact.lam, basis.H), contact=b.contact,
                            basis=basis, tolerance=tolerance)


def solve(system: StructuralSystem, law: ContactLaw, H: int, samples: int | None = None,
          X0: np.ndarray | None = None, condense: bool | None = None, load_steps: int = 20,
          lin: LinearHarmonics | None = None) -> HarmonicSolution:
    """The periodic steady state of ``system`` with contact ``law`` by harmonic balance (one speed).

    Newton from ``X0`` (default: the contact-free linear solution); when that
    fails, the loads are raised from 1/``load_steps`` of their value to all
    of it by pseudo-arclength continuation in the load factor, at most
    1/``load_steps`` per step (a homotopy from the small, contact-free
    motion; the solution can fold back in the load: a 10 um gap at
    4000 r/min turns near 0.69 of the load, back to 0.60, and on, where
    fixed load steps stopped). ``lin``: the linear part when the model supplies it (a large
    model's own condensation); default :func:`linear_harmonics`.
    """
    basis = fourier(H, samples or default_samples(H))
    lin = linear_harmonics(system, H, condense) if lin is None else lin
    start = linear_solution(lin) if X0 is None else X0
    X, b, it, ok, _, tol = newton(start, lin, law, basis)
    if not ok and X0 is None:
        # the load factor by pseudo-arclength: the solution can fold back in the load
        L, Fr = lin.L, lin.Fr

        def residual(X, c):
            bc = balance(X, lin, law, basis, L, c * Fr)
            return bc.R, bc.J, lambda: -Fr.ravel()
        path = continue_branch(residual, start / load_steps, 1.0 / load_steps, 1.0,
                               float(np.abs(start).max()) + 1e-300, ds=0.05, ds_max=0.5, dp_max=1.0 / load_steps,
                               p_scale=1.0)
        ok = path.complete and bool(path.p) and path.p[-1] == 1.0
        if ok:      # the path's end lies within continuation.CONVERGED of the solution: Newton finishes it
            X, b, it, ok, _, _ = newton(path.x[-1], lin, law, basis)
            it += sum(path.iterations)
        else:
            X, it = (path.x[-1] if path.x else start), sum(path.iterations)
            b = balance(X, lin, law, basis, L, Fr)
    return solution(X, b, lin, basis, it, ok, tol)


def state_vector(system: StructuralSystem, sol: HarmonicSolution, lin: LinearHarmonics) -> tuple:
    """(q, q') at tau = 0 of a solution (for starting a time run on it), full DOFs, and the harmonics Q
    (nh, n) of q (:func:`dof_harmonics`)."""
    Q = dof_harmonics(system, lin, sol.X, sol.contact.Lam, sol.basis.H)
    k = np.arange(1, sol.basis.H + 1)
    q0 = Q[0] + Q[1::2].sum(axis=0)
    v0 = lin.omega * (k[:, None] * Q[2::2]).sum(axis=0)
    return q0, v0, Q


def dof_harmonics(system: StructuralSystem, lin: LinearHarmonics, X: np.ndarray, Lam: np.ndarray,
                  H: int) -> np.ndarray:
    """The harmonics (nh, n) of every DOF of the orbit whose unknowns have the harmonics ``X`` and contact
    forces ``Lam`` (nh, m): X itself, or, condensed, q_k = Z_k^-1 (F_k + W^T Lam_k)."""
    if not lin.condensed:
        return X.reshape(2 * H + 1, lin.nx)
    W = dense(system.contact.W)
    Z = dynamic_stiffness(system, H)
    rhs = load_harmonics(system, H) + _complex_coefficients(Lam) @ W
    return _real_coefficients(np.linalg.solve(Z, rhs[:, :, None])[:, :, 0])


def orbit_samples(system: StructuralSystem, lin: LinearHarmonics, law: ContactLaw, X: np.ndarray,
                  basis: Fourier) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(q m, q' m/s, the sliders z m) of the orbit with harmonics ``X`` at the samples of ``basis``
    (rows; row 0 is tau = 0): the integrator's whole state along the orbit
    (shroud.core.period_map). The sliders are the AFT's, z = w + F / kt (the law's return mapping
    leaves F = kt (z - w); separated, z = w)."""
    Y = X.reshape(basis.nh, lin.nx) @ lin.Wx.T
    contact = contact_harmonics(Y, np.eye(Y.shape[1]), law, basis, jacobian=False)
    Q = dof_harmonics(system, lin, X, contact.Lam, basis.H)
    q, v = basis.E @ Q, basis.rates(Q, lin.omega)
    w = (basis.E @ Y)[:, law.rows[:, 1]]
    kt = law.props[:, KT]
    z = w + np.divide(contact.F.T, kt, out=np.zeros_like(w), where=kt > 0)
    return q, v, z
