"""Stability of a periodic steady state: Floquet multipliers, two ways.

Monodromy (time domain): the motion linearized about the periodic orbit,

    M dq'' + C dq' + K dq = W^T dlam,

with the contact law's tangent along the orbit, integrated over one period.
The tangent of each element is the law's own (shroud.core.contact.tangent)
in its state at each sample of the harmonic-balance solution
(shroud.core.harmonic_balance's AFT record): separated 0; normal contact
dlam_n = -kn dy_n; stick dF = kt (dz - dw) with the slider perturbation dz
held from the start of the stick; slip dF = sigma mu s kn dv and the slider
slaved, dz = dw + dF / kt; a slider that sticks from the instant of touching
keeps the tangential position of that instant, which moves with the touch
(``onset_capture``). The state
is [dq, dq', dz] (dz of the elements that both stick and release during the
period; a slider stuck all period only adds the neutral multiplier 1 of its
arbitrary offset, which is left out). Over each sample interval the states
are constant and the flow is exp(A dt) (scipy's expm, on the blade's
block: the sliders are carried by the structure of A); the product over
the period is the monodromy matrix, whose eigenvalues are the Floquet multipliers.

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

import math
from dataclasses import dataclass

import numpy as np
import scipy.linalg

from shroud.core.contact import SEPARATE, SIGN, SLIP, STICK, ContactLaw, tangents
from shroud.core.linear_solvers import dense

UNIT_CIRCLE_TOL = 1e-6


def monodromy(M, C, K, W, law: ContactLaw, state: np.ndarray, F: np.ndarray, omega: float,
              y_rate: np.ndarray | None = None) -> np.ndarray:
    """Monodromy matrix of the linearized motion over one period 2 pi / omega.

    ``state``, ``F`` (elements, samples): each element's state and friction
    force at the samples of the period (sample i holds over [t_i, t_i+1]).
    The state [dq, dq', dz] is carried run by run (a run: samples with the
    same states): the blade's part by the flow of its block (``_flow``), a
    sticking slider's dz unchanged, a released one set at the run's end
    from the blade; so a run costs the exponential of a matrix of order
    2 n + (at most n), whatever the number of sliders.

    ``y_rate`` (samples, m): the projected velocities dy/dt along the orbit
    (m/s). With it, a slider that sticks from the instant of touching
    captures the tangential position of that instant, z = w(t_c), whose
    perturbation holds the shift of t_c itself (``onset_capture``);
    without it that term is left out.
    """
    M, C, K, W = dense(M), dense(C), dense(K), dense(W)
    n, (k, nt) = M.shape[0], state.shape
    dt = 2 * np.pi / omega / nt
    sticks = (state == STICK).any(axis=1)
    released = (state != STICK).any(axis=1)
    hist = np.flatnonzero(sticks & released)           # elements whose slider carries a history
    nz = hist.size
    Minv = np.linalg.inv(M)
    free_blade = np.zeros((2 * n, 2 * n))               # A without contact: [[0, I], [-M^-1 K, -M^-1 C]]
    free_blade[:n, n:] = np.eye(n)
    free_blade[n:, :n], free_blade[n:, n:] = -Minv @ K, -Minv @ C
    sigma = np.where(F > 0, 1.0, -1.0)
    key = state * 2 + (sigma > 0) * (state == SLIP)
    Phi = np.eye(2 * n + nz)
    Wn, Wt = W[law.rows[:, 0]], W[law.rows[:, 1]]
    forced = (Minv @ Wn.T, Minv @ Wt.T)                 # M^-1 W_n^T, M^-1 W_t^T: where the contact forces act
    change = np.flatnonzero(np.any(key[:, 1:] != key[:, :-1], axis=0)) + 1
    starts = np.r_[0, change]
    lengths = np.diff(np.r_[starts, nt])
    runs: dict[bytes, Linearized] = {}
    touch = (state[hist] == SEPARATE) & (np.roll(state[hist], -1, axis=1) == STICK)   # stuck from the touch
    for i, length in zip(starts, lengths):              # runs of samples with the same states
        tag = key[:, i].tobytes()
        lin = runs.get(tag)
        if lin is None:
            tan = tangents(state[:, i], F[:, i], law.props)
            lin = runs[tag] = linearized(free_blade, forced, Wn, Wt, law.props[:, SIGN], tan, hist)
        E, P = _flow(lin.A, lin.Bv, dt * length)
        top = E @ Phi[:2 * n]
        if lin.held.size:
            top += P @ Phi[2 * n + lin.held]
        if lin.free.size:                               # released sliders follow the blade
            Phi[2 * n + lin.free] = lin.release @ top[:n]
        last = i + length - 1
        if y_rate is not None and touch[:, last].any():
            slots = np.flatnonzero(touch[:, last])
            rate = y_rate[(last + 1) % nt]
            Phi[2 * n + slots] += onset_capture(rate, law.rows[hist[slots]])[:, None] * (Wn[hist[slots]] @ top[:n])
        Phi[:2 * n] = top
    return Phi


def onset_capture(y_rate: np.ndarray, rows: np.ndarray) -> np.ndarray:
    """d z / d v at the touch of elements that stick from it: -w' / v' (1), per element.

    A separated slider follows the blade, z = w; an element that sticks from
    the instant t_c it touches keeps z = w(t_c). Perturbed by dv, dw the
    touch moves by dt_c = -dv / v' (the normal force N0 + s kn v is zero at
    it), so dz = dw + w' dt_c = dw - (w' / v') dv: the captured slider
    depends on the normal perturbation too (a saltation term: the force is
    continuous at the touch but the slider's memory is not). Without it the
    monodromy of an orbit that sticks from the touch is off by as much as
    its neighbour's that slides first (tests/test_hb.py).
    """
    v_rate, w_rate = y_rate[rows[:, 0]], y_rate[rows[:, 1]]
    return -w_rate / v_rate


@dataclass(frozen=True)
class Linearized:
    """The motion linearized in one set of element states.

    [dq, dq']' = A [dq, dq'] + [0; Bv dz[held]]; ``held``: the slots (in
    dz) of the sliders that stick, ``free`` those released (slipping or
    separated), whose dz = ``release`` dq at the run's end.
    """

    A: np.ndarray            # (2n, 2n)
    Bv: np.ndarray           # (n, held) M^-1 W_t^T dF/dz
    held: np.ndarray
    free: np.ndarray
    release: np.ndarray      # (free, n)


def linearized(free_blade, forced, Wn, Wt, s, tan, hist) -> Linearized:
    """The flow in one set of states from the law's tangent ``tan`` (elements, 7; shroud.core.contact.tangent).

    The contact force on the projected coordinates, dlam_n = -s dN,
    dlam_t = dF, gives the stiffness Kc = -W^T dlam/dy and the sliders'
    forcing W_t^T dF/dz; ``s`` the elements' sides (-1, +1), ``hist`` the
    elements whose slider is carried (slot = position in ``hist``). A slider
    that does not stick is slaved to the blade, dz = dz/dv dv + dz/dw dw.
    ``free_blade``: the first-order matrix without contact, ``forced``:
    (M^-1 W_n^T, M^-1 W_t^T), so that the contact is a low-rank change of it.
    """
    n = Wn.shape[1]
    MWn, MWt = forced
    dN_dv, dF_dv, dF_dw, dF_dz, dz_dv, dz_dw, dz_dz = tan.T
    A = free_blade.copy()
    A[n:, :n] -= MWn @ ((s * dN_dv)[:, None] * Wn) - MWt @ (dF_dv[:, None] * Wn + dF_dw[:, None] * Wt)
    held = np.flatnonzero(dF_dz[hist] != 0.0)
    free = np.flatnonzero(dz_dz[hist] == 0.0)
    h, f = hist[held], hist[free]
    return Linearized(A=A, Bv=MWt[:, h] * dF_dz[h], held=held, free=free,
                      release=dz_dv[f, None] * Wn[f] + dz_dw[f, None] * Wt[f])


def _flow(A, Bv, tau):
    """exp of [[A, [0; Bv]], [0, 0]] tau: the blade's flow E = exp(A tau) and P = int_0^tau exp(A s) ds [0; Bv].

    Through one exponential of order 2n + min(held, n): [[A, [0; Bv]], [0, 0]]
    itself with few sticking sliders, [[A, [0; I]], [0, 0]] (P then times Bv)
    with many. The displacements are scaled by w = sqrt(|M^-1 K|) first
    (the similarity S = diag(w I, I, I), exact): the stiffness block of A is
    of order omega^2 against 1 in the velocity block, and its norm sets how
    many squarings the exponential takes (the reduced beam's monodromy on
    its contact orbit at 9000 r/min, gap 0.1 mm: 1.77 ms unscaled, 0.81 ms
    scaled; the full beam's 6.0 and 3.8 ms; multipliers equal to 1e-12).
    """
    m, (n, c) = A.shape[0], Bv.shape
    few = c <= n
    w = math.sqrt(max(float(np.abs(A[n:, :n]).max()), 1.0))
    aug = np.zeros((m + min(c, n), m + min(c, n)))
    aug[:n, :n] = A[:n, :n]
    aug[:n, n:m] = A[:n, n:] * w
    aug[n:m, :n] = A[n:, :n] / w
    aug[n:m, n:m] = A[n:, n:]
    aug[n:m, m:] = Bv if few else np.eye(n)
    X = scipy.linalg.expm(aug * tau)
    X[:n] /= w
    X[:, :n] *= w
    return X[:m, :m], (X[:m, m:] if few else X[:m, m:] @ Bv)


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
    return crossing(after if not is_stable(after) else before)[0]   # the unstable side holds the critical one


def crossing(mult: np.ndarray) -> tuple[str, float | None]:
    """How the largest multiplier lies, and so what replaces P1 when it leaves the unit circle.

    "Neimark-Sacker" (a complex pair; n = 2 pi / |arg mu| is the period, in
    excitation periods, of the motion it brings: quasi-periodic unless locked
    at a P-n nearby), "period-doubling" (real, negative: P2, then P4 ...) or
    "fold" (real, positive); n is None for the real ones.

    >>> crossing(np.array([1.1 * np.exp(2j * np.pi / 5), 1.1 * np.exp(-2j * np.pi / 5), 0.3]))
    ('Neimark-Sacker', 5.0...)
    """
    m = mult[np.argmax(np.abs(mult))]
    if abs(m.imag) > 1e-6 * abs(m):
        return "Neimark-Sacker", float(2 * np.pi / abs(np.angle(m)))
    return ("fold" if m.real > 0 else "period-doubling"), None
