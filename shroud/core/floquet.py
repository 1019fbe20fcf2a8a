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
are constant and the flow is exp(A dt) (:func:`expm`, compiled with the
loop over the period, on the blade's block: the sliders are carried by the
structure of A); the product over the period is the monodromy matrix, whose
eigenvalues are the Floquet multipliers.

Hill's method (frequency domain): the perturbation e^{s t} p(t) with p
periodic in the same harmonics gives the quadratic eigenproblem
(J + s Delta_1 + s^2 Delta_2) P = 0 with J the harmonic-balance Jacobian on
all DOFs, Delta_1 = I (x) C + 2 D (x) M, Delta_2 = I (x) M (D the time
derivative on the coefficients); the exponents with |Im s| <= omega / 2
are the Floquet exponents, multipliers exp(s T).

A point is stable when every multiplier lies inside the unit circle by
more than the multipliers' own error, unstable when one lies outside by
more than it, and undecided (None) within it (:func:`verdict`). The error
(:func:`sampling_error`) is the change of the largest modulus when the law
is sampled at half the instants (the states are piecewise constant over a
sample: a first-order error, so the change estimates the error at the
finer sampling), never taken below MULTIPLIER_FLOOR, how far the monodromy
and Hill's method are measured apart (tests/test_hb.py). A touch whose
normal speed is within GRAZING of zero (a grazing touch: the touch time's
shift -dv / v' is unbounded there) is left out of the onset capture and
marks the point undecided: its linearization is singular. Along a branch,
a multiplier leaving through +1 marks a fold, through -1 a period
doubling, a complex pair a Neimark-Sacker bifurcation.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
import scipy.linalg
from numba import njit

from shroud.core.contact import SEPARATE, SIGN, SLIP, STICK, ContactLaw, tangents
from shroud.core.linear_solvers import dense

UNIT_CIRCLE_TOL = 1e-6    # |mu| = 1 within round-off: where a branch's nominal stability changes (bifurcation)
# The least error of the largest |multiplier|: the monodromy and Hill's method on the same orbits (reduced beam,
# gap 0.1 mm, H 12, 1024 samples) differ by 0.0046 (9000 r/min, mu 0), 0.020 (8000, mu 0.3), < 1e-4 (12000,
# mu 0.3; 10000, mu 0.1): Hill takes the sliders' history at s = 0 (docs/hb-stability.md). The sampling and
# truncation errors are taken instead where larger.
MULTIPLIER_FLOOR = 0.02
GRAZING = 1e-3            # a touch at a normal speed below this share of the element's largest: grazing


def monodromy(M, C, K, W, law: ContactLaw, state: np.ndarray, F: np.ndarray, omega: float,
              y_rate: np.ndarray | None = None) -> np.ndarray:
    """Monodromy matrix of the linearized motion over one period 2 pi / omega.

    ``state``, ``F`` (elements, samples): each element's state and friction
    force at the samples of the period (sample i holds over [t_i, t_i+1]).
    The state [dq, dq', dz] is carried run by run (a run: samples with the
    same states; :func:`_monodromy`, compiled): the blade's part by the flow
    of its block, a sticking slider's dz unchanged, a released one set at
    the run's end from the blade; so a run costs the exponential of a
    matrix of order 2 n + (at most n), whatever the number of sliders, and
    runs in the same states share it.

    ``y_rate`` (samples, m): the projected velocities dy/dt along the orbit
    (m/s). With it, a slider that sticks from the instant of touching
    captures the tangential position of that instant, z = w(t_c), whose
    perturbation holds the shift of t_c itself (``onset_capture``);
    without it that term is left out.
    """
    return _monodromy_grazing(M, C, K, W, law, state, F, omega, y_rate)[0]


def _monodromy_grazing(M, C, K, W, law: ContactLaw, state, F, omega: float, y_rate) -> tuple[np.ndarray, int]:
    """(:func:`monodromy`, the number of grazing touches left out of the onset capture)."""
    return _flow_grazing(M, C, K, W, law, state, F, omega, y_rate, state.shape[1])


def _flow_grazing(M, C, K, W, law: ContactLaw, state, F, omega: float, y_rate, stop: int) -> tuple[np.ndarray, int]:
    """(the flow over the period's first ``stop`` samples, the number of grazing touches left out)."""
    M, C, K, W = (np.ascontiguousarray(dense(A)) for A in (M, C, K, W))
    rates = np.zeros((0, W.shape[0])) if y_rate is None else np.ascontiguousarray(y_rate, dtype=float)
    return _monodromy(M, C, K, W, law.rows, law.props, np.ascontiguousarray(state),
                      np.ascontiguousarray(F, dtype=float), 2 * np.pi / omega / state.shape[1], rates, stop)


@njit(cache=True, error_model="numpy")
def onset_capture(y_rate, rows):
    """d z / d v at the touch of elements that stick from it: -w' / v' (1), per element.

    ``y_rate`` (m,): the projected velocities at the touch, ``rows``
    (elements, 2): the elements' [normal, tangent] rows. The caller asks
    only at touches whose normal speed v' is clear of zero (GRAZING). A separated slider
    follows the blade, z = w; an element that sticks from the instant t_c
    it touches keeps z = w(t_c). Perturbed by dv, dw the touch moves by
    dt_c = -dv / v' (the normal force N0 + s kn v is zero at it), so
    dz = dw + w' dt_c = dw - (w' / v') dv: the captured slider depends on
    the normal perturbation too (a saltation term: the force is continuous
    at the touch but the slider's memory is not). Without it the monodromy
    of an orbit that sticks from the touch is off by as much as its
    neighbour's that slides first (tests/test_hb.py).
    """
    out = np.empty(rows.shape[0])
    for j in range(rows.shape[0]):
        out[j] = -y_rate[rows[j, 1]] / y_rate[rows[j, 0]]
    return out


@njit(cache=True)
def _same_states(state, F, a, b):
    """Whether samples a and b have the same element states (and slip directions)."""
    for j in range(state.shape[0]):
        if state[j, a] != state[j, b] or (state[j, a] == SLIP and (F[j, a] > 0.0) != (F[j, b] > 0.0)):
            return False
    return True


@njit(cache=True)
def _runs(state, F):
    """The runs of samples with the same states: their first samples, lengths, and for each the first
    run in the same states (itself if none before)."""
    nt = state.shape[1]
    starts, lengths = np.empty(nt, np.int64), np.empty(nt, np.int64)
    count = i = 0
    while i < nt:
        last = i
        while last + 1 < nt and _same_states(state, F, i, last + 1):
            last += 1
        starts[count], lengths[count] = i, last - i + 1
        count += 1
        i = last + 1
    first = np.arange(count)
    for r in range(count):
        for q in range(r):
            if first[q] == q and _same_states(state, F, starts[q], starts[r]):
                first[r] = q
                break
    return starts[:count], lengths[:count], first


@njit(cache=True)
def _power(ladder, length):
    """exp(A dt)^length from ladder[j] = exp(A dt)^(2^j): the product of the powers of length's binary
    digits."""
    j = 0
    while not (length >> j) & 1:
        j += 1
    X = ladder[j].copy()
    for k in range(j + 1, ladder.shape[0]):
        if (length >> k) & 1:
            X = X @ ladder[k]
    return X


@njit(cache=True)
def _mass_solved(M, C, K, W, rows):
    """W_n, W_t (the elements' normal and tangent rows of W) and M^-1 K, M^-1 C, M^-1 W_n^T, M^-1 W_t^T."""
    n, k = M.shape[0], rows.shape[0]
    Wn, Wt = W[rows[:, 0]], W[rows[:, 1]]
    G = np.linalg.solve(M, np.hstack((K, C, Wn.T, Wt.T)))
    return (Wn, Wt, np.ascontiguousarray(G[:, :n]), np.ascontiguousarray(G[:, n:2 * n]),
            np.ascontiguousarray(G[:, 2 * n:2 * n + k]), np.ascontiguousarray(G[:, 2 * n + k:]))


@njit(cache=True)
def _stiffness_block(MK, MWn, MWt, Wn, Wt, tan, props):
    """The stiffness block of the first-order matrix in the states whose tangents are ``tan``:
    -M^-1 (K + W_n^T s dN/dv W_n - W_t^T (dF/dv W_n + dF/dw W_t))."""
    s_dN = props[:, SIGN] * tan[:, 0]
    return MWt @ (tan[:, 1:2] * Wn + tan[:, 2:3] * Wt) - MWn @ (s_dN[:, None] * Wn) - MK


@njit(cache=True)
def _steady_flow_matrix(M, C, K, W, rows, props, state, F):
    """[[0, I], [stiffness block, -M^-1 C]]: the first-order matrix of the blade in one set of states
    (the sliders are either slaved or held all along, so they add no state)."""
    n = M.shape[0]
    Wn, Wt, MK, MC, MWn, MWt = _mass_solved(M, C, K, W, rows)
    A = np.zeros((2 * n, 2 * n))
    A[n:, :n] = _stiffness_block(MK, MWn, MWt, Wn, Wt, tangents(state, F, props), props)
    A[n:, n:] = -MC
    for l in range(n):
        A[l, n + l] = 1.0
    return A


@njit(cache=True)
def history(state):
    """The elements whose slider carries a history (they both stick and are released during the period),
    in order: the sliders in the monodromy's state [dq, dq', dz], slot by slot."""
    k, nt = state.shape
    hist = np.empty(k, np.int64)
    nz = 0
    for j in range(k):
        sticks = released = False
        for i in range(nt):
            sticks = sticks or state[j, i] == STICK
            released = released or state[j, i] != STICK
        if sticks and released:
            hist[nz] = j
            nz += 1
    return hist[:nz]


@njit(cache=True)
def _monodromy(M, C, K, W, rows, props, state, F, dt, y_rate, stop):
    """:func:`monodromy`'s run loop over the first ``stop`` samples of the period (all of them: the
    monodromy; fewer: the flow from 0 to stop dt, in the period's state, whose sliders are those with a
    history over the whole period); ``y_rate`` with no rows: without the onset capture. Returns the
    flow and the number of grazing touches (normal speed below GRAZING of the element's largest over
    the period), whose onset capture -w'/v' is left out (unbounded; the caller marks the point undecided).

    In one run's states the law's tangent ``tan`` (elements, 7;
    shroud.core.contact.tangent) makes the contact force on the projected
    coordinates, dlam_n = -s dN, dlam_t = dF, a low-rank change of the free
    blade's first-order matrix [[0, I], [-M^-1 K, -M^-1 C]]: its stiffness
    block gains -M^-1 (W_n^T s dN/dv W_n - W_t^T (dF/dv W_n + dF/dw W_t)),
    and a sticking slider forces the velocities by Bv dz, Bv = M^-1 W_t^T
    dF/dz. A slider that does not stick is slaved to the blade,
    dz = dz/dv dv + dz/dw dw, set at the run's end.

    The run's flow over tau: exp of [[A, [0; Bv]], [0, 0]] tau gives the
    blade's E = exp(A tau) and P = int_0^tau exp(A s) ds [0; Bv], through
    one exponential of order 2n + min(held, n): [[A, [0; Bv]], [0, 0]]
    itself with few sticking sliders, [[A, [0; I]], [0, 0]] (P then times
    Bv) with many. The displacements are scaled by w = sqrt(|M^-1 K|) first
    (the similarity S = diag(w I, I, I), exact): the stiffness block of A
    is of order omega^2 against 1 in the velocity block, and its norm sets
    how many squarings the exponential takes (over 80 harmonic-balance
    orbits of each beam, gaps 0 to 0.1 mm, mu 0 to 0.5: 2.2 squarings a run
    against 3.5 unscaled on the reduced beam, 12.1 against 14.0 on the full
    one).

    A run in states met once takes exp of its matrix times tau. States that
    recur (the blade separated before, between and after its contacts)
    take it over one sample, exp(A dt), once, squared up to their longest
    run, and each run the product of the powers of its length's binary
    digits: the Pade approximant and the squarings are shared (per call on
    the orbits at 9000 r/min, gap 0.1 mm: 0.15 -> 0.12 ms on the reduced
    beam, 2.75 -> 2.2 ms on the full beam; the same states over the same
    length, 4 runs in 530 on 80 orbits, are no help).
    """
    n, nt = M.shape[0], state.shape[1]
    m = 2 * n
    Wn, Wt, MK, MC, MWn, MWt = _mass_solved(M, C, K, W, rows)
    hist = history(state)
    nz = hist.size
    starts, lengths, first = _runs(state[:, :stop], F[:, :stop])
    uses, longest = np.zeros(starts.size, np.int64), np.zeros(starts.size, np.int64)
    for r in range(starts.size):
        uses[first[r]] += 1
        longest[first[r]] = max(longest[first[r]], lengths[r])
    left = uses.copy()
    powers = [np.empty((0, 0, 0)) for _ in range(starts.size)]   # exp(A dt)^(2^j) of recurring states
    Phi = np.eye(m + nz)
    grazing = 0
    for r in range(starts.size):
        i, last, key = starts[r], starts[r] + lengths[r] - 1, first[r]
        tan = tangents(state[:, i], F[:, i], props)   # dN/dv, dF/dv, dF/dw, dF/dz, dz/dv, dz/dw, dz/dz
        stiff = _stiffness_block(MK, MWn, MWt, Wn, Wt, tan, props)
        held = np.flatnonzero(tan[hist, 3] != 0.0)
        free = np.flatnonzero(tan[hist, 6] == 0.0)
        Bv = MWt[:, hist[held]] * tan[hist[held], 3]
        few = held.size <= n
        size = m + min(held.size, n)
        w = math.sqrt(max(np.abs(stiff).max(), 1.0))
        aug = np.zeros((size, size))
        aug[n:m, :n] = stiff / w
        aug[n:m, n:m] = -MC
        for l in range(n):
            aug[l, n + l] = w
        if few:
            aug[n:m, m:] = Bv
        else:
            for l in range(n):
                aug[n + l, m + l] = 1.0
        if uses[key] == 1:
            X = expm(aug * (dt * lengths[r]))
        else:
            if powers[key].shape[0] == 0:
                ladder = np.empty((int(math.log2(longest[key])) + 1, size, size))
                ladder[0] = expm(aug * dt)
                for j in range(1, ladder.shape[0]):
                    ladder[j] = ladder[j - 1] @ ladder[j - 1]
                powers[key] = ladder
            X = _power(powers[key], lengths[r])
            left[key] -= 1
            if left[key] == 0:                   # the states' last run: their powers are done with
                powers[key] = np.empty((0, 0, 0))
        X[:n] /= w
        X[:, :n] *= w
        top = np.ascontiguousarray(X[:m, :m]) @ Phi[:m]
        if held.size:
            P = np.ascontiguousarray(X[:m, m:])
            top += (P if few else P @ Bv) @ Phi[m + held]
        h = hist[free]                           # released sliders follow the blade
        Phi[m + free] = (tan[h, 4:5] * Wn[h] + tan[h, 5:6] * Wt[h]) @ top[:n]
        after = (last + 1) % nt
        if y_rate.shape[0]:
            for slot in range(nz):               # stuck from the touch at the run's end
                j = hist[slot]
                if state[j, last] == SEPARATE and state[j, after] == STICK:
                    if abs(y_rate[after, rows[j, 0]]) <= GRAZING * np.abs(y_rate[:, rows[j, 0]]).max():
                        grazing += 1
                    else:
                        Phi[m + slot] += onset_capture(y_rate[after], rows[j:j + 1])[0] * (Wn[j] @ top[:n])
        Phi[:m] = top
    return Phi, grazing


# Pade approximants r_m of exp, m = 3, 5, 7, 9, 13: their numerators' coefficients b_0 .. b_m, the
# bounds theta_m on A's power norms within which r_m is exact to double precision (Al-Mohy & Higham
# 2009, Table 3.1 and Algorithm 5.1), and 1 / |c_2m+1| = (2m)! (2m+1)! / (m!)^2 of their error's
# leading term.
_B3 = (120.0, 60.0, 12.0, 1.0)
_B5 = (30240.0, 15120.0, 3360.0, 420.0, 30.0, 1.0)
_B7 = (17297280.0, 8648640.0, 1995840.0, 277200.0, 25200.0, 1512.0, 56.0, 1.0)
_B9 = (17643225600.0, 8821612800.0, 2075673600.0, 302702400.0, 30270240.0, 2162160.0, 110880.0, 3960.0,
       90.0, 1.0)
_B13 = (64764752532480000.0, 32382376266240000.0, 7771770303897600.0, 1187353796428800.0, 129060195264000.0,
        10559470521600.0, 670442572800.0, 33522128640.0, 1323241920.0, 40840800.0, 960960.0, 16380.0, 182.0,
        1.0)
_THETA3, _THETA5, _THETA7, _THETA9, _THETA13 = (1.495585217958292e-2, 2.539398330063230e-1,
                                                9.504178996162932e-1, 2.097847961257068e0, 4.25)
_C3, _C5, _C7, _C9, _C13 = (100800.0, 10059033600.0, 4487938430976000.0, 5.914384781877412e21,
                            1.1325077560602111e35)


@njit(cache=True)
def _norm1(A):
    """The 1-norm of A: its largest column sum of |a_ij|."""
    norm = 0.0
    for c in range(A.shape[1]):
        col = 0.0
        for r in range(A.shape[0]):
            col += abs(A[r, c])
        norm = max(norm, col)
    return norm


@njit(cache=True)
def _ell(absA, norm, m, c_recip, scale):
    """Extra squarings for r_m of scale A: the bound of its relative error's leading term brought to 2^-53.

    Al-Mohy & Higham 2009, eq. (5.3): alpha = |c_2m+1| || |scale A|^(2m+1) ||_1 / ||scale A||_1,
    ell = max(ceil(log2(alpha / u) / 2m), 0); ``absA`` = |A|, ``norm`` = ||A||_1. The norm of the
    nonnegative power is that of the vector 1^T |A|^(2m+1), normalized at each product (its logarithm
    cannot overflow).
    """
    n = absA.shape[0]
    v, u = np.ones(n), np.empty(n)
    log_norm = (2 * m + 1) * math.log2(scale)
    for _ in range(2 * m + 1):
        u[:] = 0.0
        for r in range(n):
            for c in range(n):
                u[c] += v[r] * absA[r, c]
        top = u.max()
        if top == 0.0:
            return 0
        log_norm += math.log2(top)
        for c in range(n):
            v[c] = u[c] / top
    log_alpha = log_norm - math.log2(c_recip * scale * norm)
    return max(int(math.ceil((log_alpha + 53.0) / (2 * m))), 0)


@njit(cache=True)
def expm(A):
    """exp(A) of a square real matrix by scaling and squaring (Al-Mohy & Higham 2009, Algorithm 5.1).

    The Pade approximant r_m = (V - U)^-1 (V + U) (U the odd part, V the
    even) of the least degree m in 3, 5, 7, 9 whose theta_m bounds
    d_p = ||A^p||_1^(1/p) (exact norms of the powers), the error bound's
    ``_ell`` permitting; else r_13 of A / 2^s squared s times, s the least
    with 2^-s min(max(d6, d8), max(d8, d10)) <= theta_13, plus ``_ell``'s.
    The powers' norms, not ||A||_1 (Higham 2005), set s: a structure's
    first-order matrix is far from normal, and on the full beam's runs
    ||A||_1 asks for 6 to 7 more squarings. Powers of two scale exactly, so
    A's powers are scaled, not recomputed.

    r_m is formed as I + 2 (V - U)^-1 U with the inverse itself (scipy's
    expm divides by the LU of V - U from the right): the squarings magnify
    the error of r_m - I, and solved for as (V - U)^-1 (V + U) or
    (V - U)^-1 U the full beam's run exponentials came out 1e-9 off a
    long-double reference, formed so 3e-12 (scipy's: 3e-12).
    """
    ident, absA = np.eye(A.shape[0]), np.abs(A)
    norm = _norm1(A)
    A2 = A @ A
    A4 = A2 @ A2
    A6 = A4 @ A2
    d6 = _norm1(A6) ** (1.0 / 6.0)
    eta1 = max(_norm1(A4) ** 0.25, d6)
    s = 0
    if eta1 <= _THETA3 and _ell(absA, norm, 3, _C3, 1.0) == 0:
        b = _B3
        U = A @ (b[3] * A2 + b[1] * ident)
        V = b[2] * A2 + b[0] * ident
    elif eta1 <= _THETA5 and _ell(absA, norm, 5, _C5, 1.0) == 0:
        b = _B5
        U = A @ (b[5] * A4 + b[3] * A2 + b[1] * ident)
        V = b[4] * A4 + b[2] * A2 + b[0] * ident
    else:
        A8 = A4 @ A4
        d8 = _norm1(A8) ** 0.125
        eta3 = max(d6, d8)
        if eta3 <= _THETA7 and _ell(absA, norm, 7, _C7, 1.0) == 0:
            b = _B7
            U = A @ (b[7] * A6 + b[5] * A4 + b[3] * A2 + b[1] * ident)
            V = b[6] * A6 + b[4] * A4 + b[2] * A2 + b[0] * ident
        elif eta3 <= _THETA9 and _ell(absA, norm, 9, _C9, 1.0) == 0:
            b = _B9
            U = A @ (b[9] * A8 + b[7] * A6 + b[5] * A4 + b[3] * A2 + b[1] * ident)
            V = b[8] * A8 + b[6] * A6 + b[4] * A4 + b[2] * A2 + b[0] * ident
        else:
            b = _B13
            eta5 = min(eta3, max(d8, _norm1(A4 @ A6) ** 0.1))
            s = max(int(math.ceil(math.log2(eta5 / _THETA13))), 0) if eta5 > 0.0 else 0
            s += _ell(absA, norm, 13, _C13, 2.0 ** -s)
            A1, A2, A4, A6 = A * 2.0 ** -s, A2 * 4.0 ** -s, A4 * 16.0 ** -s, A6 * 64.0 ** -s
            U = A1 @ (A6 @ (b[13] * A6 + b[11] * A4 + b[9] * A2) + b[7] * A6 + b[5] * A4 + b[3] * A2
                      + b[1] * ident)
            V = A6 @ (b[12] * A6 + b[10] * A4 + b[8] * A2) + b[6] * A6 + b[4] * A4 + b[2] * A2 + b[0] * ident
    X = ident + 2.0 * (np.linalg.inv(V - U) @ U)
    for _ in range(s):
        X = X @ X
    return X


@dataclass(frozen=True)
class Symmetry:
    """A linearized flow that a permutation of its DOFs and elements and a shift of time by T / q map onto
    itself: Phi(t + T / q, s + T / q) = G^-1 Phi(t, s) G, with (G x)_i = x_g(i) on the DOFs (``dofs``: g
    on dq and on dq') and on the sliders (``elements``: element e's slider takes element elements[e]'s),
    each times its sign where signs are given (a flow on an antiperiodic subspace: the ring's
    perturbations with blade j + N / 2 moving as minus blade j, ring_hb.ring_blocks).

    A tuned ring on a travelling wave (docs/ring.md) is one: interface j at time t is interface 0 at
    t + j T ke / N, so relabelling the blades by r (r ke = gcd(N, ke) mod N) and shifting time by
    T gcd(N, ke) / N maps the linearized ring onto itself, q = N / gcd(N, ke). Then
    Phi(T) = Phi(q dt, (q-1) dt) ... Phi(dt, 0) = G^-q (G Phi(dt, 0))^q, dt = T / q
    (:func:`symmetric_monodromy`): the flow is integrated over T / q only.
    """

    dofs: np.ndarray       # (n,) int
    elements: np.ndarray   # (elements,) int
    q: int
    dof_signs: np.ndarray | None = None       # (n,) +-1: (G x)_i = sign_i x_g(i) (None: all +1)
    element_signs: np.ndarray | None = None   # (elements,) +-1, the same on the sliders

    def state(self, hist: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(g, signs) on the monodromy's state [dq, dq', dz] (dz: the sliders of elements ``hist``, slot by
        slot): (G x)_i = signs_i x_g(i)."""
        n = self.dofs.size
        slot = np.full(self.elements.size, -1)
        slot[hist] = np.arange(hist.size)
        moved = slot[self.elements[hist]]
        if np.any(moved < 0):
            raise ValueError("the symmetry maps a slider with a history onto one without: the orbit is not "
                             "symmetric")
        dof = np.ones(n) if self.dof_signs is None else self.dof_signs
        element = np.ones(hist.size) if self.element_signs is None else self.element_signs[hist]
        return np.concatenate([self.dofs, n + self.dofs, 2 * n + moved]), np.concatenate([dof, dof, element])


def symmetric_monodromy(M, C, K, W, law: ContactLaw, state: np.ndarray, F: np.ndarray, omega: float,
                        y_rate: np.ndarray | None, symmetry: Symmetry) -> tuple[np.ndarray, int]:
    """(:func:`monodromy`, grazing touches) of a flow with ``symmetry``, from its first T / q:
    Phi(T) = G^-q (G Phi(T / q, 0))^q, the flow over T / q carrying the whole period's sliders (those with
    a history over the period: a slider stuck over the first T / q may be released later). ``state``'s
    samples must be a multiple of q."""
    nt, q = state.shape[1], symmetry.q
    if nt % q:
        raise ValueError(f"{nt} samples do not split the period into {q} equal parts")
    short, grazing = _flow_grazing(M, C, K, W, law, state, F, omega, y_rate, nt // q)
    g, sign = symmetry.state(history(np.ascontiguousarray(state)))
    power = np.linalg.matrix_power(sign[:, None] * short[g], q)    # (G Phi(T / q))^q
    gq, sq = np.arange(g.size), np.ones(g.size)
    for _ in range(q):
        gq, sq = gq[g], sign * sq[g]                     # G^q x = sq x[gq]
    return (sq[:, None] * power)[np.argsort(gq)], grazing * q      # G^-q y = (sq y)[gq^-1] (sq = 1 / sq)


def multipliers(Phi: np.ndarray) -> np.ndarray:
    """Floquet multipliers, largest modulus first."""
    return _largest_first(np.linalg.eigvals(Phi))


def _largest_first(mu: np.ndarray) -> np.ndarray:
    return mu[np.argsort(-np.abs(mu))]


def orbit_multipliers(M, C, K, W, law: ContactLaw, state: np.ndarray, F: np.ndarray, omega: float,
                      y_rate: np.ndarray | None = None, symmetry: Symmetry | None = None) -> np.ndarray:
    """Floquet multipliers of the orbit whose states and friction over the period are ``state``, ``F``
    (:func:`monodromy`'s arguments), largest modulus first; with ``symmetry`` the monodromy from a q-th of
    the period (:func:`symmetric_monodromy`).

    Where every element keeps its state all period (no touch, or a contact
    stuck, or sliding one way, throughout) the linearized motion is one
    linear flow, the monodromy exp(A T), and its multipliers are exp(s T)
    of A's eigenvalues s: the same numbers without the exponential (on the
    full beam's contact-free orbits 0.34 ms against 0.71 ms a point, the
    largest multiplier within 1e-14). Otherwise the eigenvalues of the
    monodromy matrix.
    """
    return _orbit_multipliers(M, C, K, W, law, state, F, omega, y_rate, symmetry)[0]


def _orbit_multipliers(M, C, K, W, law, state, F, omega, y_rate, symmetry=None) -> tuple[np.ndarray, int]:
    """(:func:`orbit_multipliers`, the number of grazing touches left out)."""
    state, F = np.ascontiguousarray(state), np.ascontiguousarray(F, dtype=float)
    if state.shape[0] and _runs(state, F)[0].size == 1:
        M, C, K, W = (np.ascontiguousarray(dense(A)) for A in (M, C, K, W))
        A = _steady_flow_matrix(M, C, K, W, law.rows, law.props, state[:, 0].copy(), F[:, 0].copy())
        return _largest_first(np.exp(np.linalg.eigvals(A) * (2 * np.pi / omega))), 0
    if symmetry is None:
        Phi, grazing = _monodromy_grazing(M, C, K, W, law, state, F, omega, y_rate)
    else:
        Phi, grazing = symmetric_monodromy(M, C, K, W, law, state, F, omega, y_rate, symmetry)
    return multipliers(Phi), grazing


@dataclass(frozen=True)
class Stability:
    """The Floquet multipliers of an orbit with their own error.

    ``multipliers`` largest modulus first; ``error``: that of the largest
    modulus (:func:`sampling_error`, at least MULTIPLIER_FLOOR); ``grazing``:
    touches at a normal speed within GRAZING of zero, left out of the onset
    capture; ``stable``: :func:`verdict` (None: undecided).
    """

    multipliers: np.ndarray
    error: float
    grazing: int = 0

    @property
    def largest(self) -> float:
        return float(np.abs(self.multipliers).max(initial=0.0))

    @property
    def stable(self) -> bool | None:
        return None if self.grazing else verdict(self.largest, self.error)

    def truncated(self, refined: float | None) -> "Stability":
        """The same with the harmonics' truncation in the error: ``refined``, the largest |multiplier| of
        the orbit solved again with twice the harmonics (None: no such state found: the error is
        infinite, the point undecided). The error is then the largest of MULTIPLIER_FLOOR, the change at
        half the samples and the change at twice the harmonics (docs/hb-stability.md)."""
        error = math.inf if refined is None else max(self.error, abs(refined - self.largest))
        return replace(self, error=error)


def verdict(largest: float, error: float) -> bool | None:
    """Stable (True) when the largest |multiplier| is below 1 by more than its ``error``, unstable (False)
    when above by more, None (undecided) within it.

    >>> verdict(0.95, 0.01), verdict(1.02, 0.01), verdict(1.005, 0.01)
    (True, False, None)
    """
    if largest < 1.0 - error:
        return True
    if largest > 1.0 + error:
        return False
    return None


def sampling_error(largest: float, coarse: float) -> float:
    """The error of the largest |multiplier| ``largest`` of an orbit whose law is sampled at n instants,
    from ``coarse``, the same at n / 2: the states hold over a sample, an error of first order in the
    sample interval, so the change from n / 2 to n estimates the error at n; at least MULTIPLIER_FLOOR."""
    return max(MULTIPLIER_FLOOR, abs(largest - coarse))


def orbit_stability(M, C, K, W, law: ContactLaw, state: np.ndarray, F: np.ndarray, omega: float,
                    y_rate: np.ndarray | None, coarse: tuple[np.ndarray, np.ndarray, np.ndarray | None],
                    symmetry: Symmetry | None = None) -> Stability:
    """:func:`orbit_multipliers` of the orbit with their error: ``coarse`` (state, F, y_rate) is the same
    orbit's law sampled at half the instants (:func:`sampling_error`)."""
    return blocks_stability([(M, C, K, W, law, symmetry)], state, F, omega, y_rate, coarse)


def block_multipliers(blocks, state: np.ndarray, F: np.ndarray, omega: float,
                      y_rate: np.ndarray | None = None) -> tuple[np.ndarray, int]:
    """(multipliers, grazing touches) of a flow that splits into invariant subspaces, each the same
    orbit's (``state``, ``F``, ``y_rate``) on its own (M, C, K, W, law, symmetry) of ``blocks``
    (:func:`orbit_multipliers` each): the monodromy is block diagonal in them, its multipliers the union
    of theirs, largest modulus first."""
    parts = [_orbit_multipliers(M, C, K, W, law, state, F, omega, y_rate, symmetry)
             for M, C, K, W, law, symmetry in blocks]
    return _largest_first(np.concatenate([mu for mu, _ in parts])), sum(g for _, g in parts)


def blocks_stability(blocks, state: np.ndarray, F: np.ndarray, omega: float, y_rate: np.ndarray | None,
                     coarse: tuple[np.ndarray, np.ndarray, np.ndarray | None]) -> Stability:
    """:func:`orbit_stability` of a flow split into ``blocks`` (:func:`block_multipliers`)."""
    mult, grazing = block_multipliers(blocks, state, F, omega, y_rate)
    coarse_mult, _ = block_multipliers(blocks, *coarse[:2], omega, coarse[2])
    largest = float(np.abs(mult).max(initial=0.0))
    return Stability(multipliers=mult, error=sampling_error(largest, float(np.abs(coarse_mult).max(initial=0.0))),
                     grazing=grazing)


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
