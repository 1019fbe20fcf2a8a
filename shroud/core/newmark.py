"""Newmark time integration with impact and stick/slip friction (paper Sect. 2.1, Eq. 9).

    M q'' + C q' + K q = f_const + f_aero sin(omega_e t) + W^T lam(W q)

Average-acceleration Newmark (gamma = 1/2, beta = 1/4, the paper's values)
from a zero state. The linear step operator
``K_eff = K + gamma/(beta dt) C + 1/(beta dt^2) M`` is factorized once; with
``S = K_eff^-1``, ``Phi = S W^T`` and the contact compliance ``Cc = W Phi``
one step is

    q_pred = S (f(t+dt) + M (a0 q + a2 v + a3 a) + C (a1 q + a4 v + a5 a))
    y      = W q_pred + Cc lam          (lam: contact forces of the step)
    q'     = q_pred + Phi lam

with ``lam = lam(y)`` solved exactly (``implicit``: the step's end state
satisfies the contact law, shroud.core.contact.solve_contact) or taken from the
start of the step (``explicit``, as the paper's scheme does).

Two code paths, one per backend, doing the same arithmetic:

* :func:`_reference_loop`: a plain Python loop, line by line the equations
  above, with ``@`` products and a factorization's ``solve``. It is the
  reference the tests hold the kernel to, and the backend for sparse or
  PETSc-backed FE systems (``M, C, K`` support ``@``, ``+`` and scalar ``*``;
  ``factorize(K_eff) -> Factorization`` may be a MUMPS factorization). Under mpirun
  (a system with a layout) each rank forms, back-substitutes and corrects
  its own rows of q_pred, and the end state is gathered once per step.
* :func:`_dense_kernel`: the same step compiled with numba for dense systems
  (reduced and full beam, reduced FE), multiplying by the precomputed inverse.

Both record the tip displacements, the per-side resultants of the contact
forces and states, and over a final window the energy balance and, per
contact element, the steps spent in each state and the peak normal force
(the contact-state map of the solid models' shroud faces). Units: SI.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import Any, Callable, NamedTuple

import numpy as np
import scipy.sparse
from numba import njit

from shroud.core.contact import (SLIP, STICK, ContactLaw, contact_energy, copy_into, evaluate,
                            friction_dissipation, solve_contact, workspace)
from shroud.base.log import Progress, warn
from shroud.core.linear_solvers import AllRows, Factorization, RowShare, default_factorization, dense
from shroud.core.system import StructuralSystem

OK, NOT_FINITE, UNBOUNDED = 0, 1, 2


@dataclass(frozen=True)
class NewmarkScheme:
    """Newmark-beta coefficients for step ``dt`` (s); defaults: average acceleration."""

    dt: float
    gamma: float = 0.5
    beta: float = 0.25

    def coefficients(self) -> tuple[float, ...]:
        """(a0 .. a5) of the displacement form of the Newmark step."""
        g, b, dt = self.gamma, self.beta, self.dt
        return (1.0 / (b * dt * dt), g / (b * dt), 1.0 / (b * dt), 1.0 / (2.0 * b) - 1.0,
                g / b - 1.0, dt * (g / (2.0 * b) - 1.0))


@dataclass(frozen=True)
class EnergyBalance:
    """Energy flows over the window [start_step, end_step], J.

    input_work (the load's) = damping + friction + change of kinetic, strain
    and contact-spring energy + residual. The residual is what the time
    discretization leaves: round-off for a smooth run, the trapezoidal error
    of the steps that cross an impact kink, and the lag of the explicit
    treatment.
    """

    start_step: int
    end_step: int
    input_work: float
    damping: float
    friction: float
    kinetic_change: float
    strain_change: float
    contact_change: float
    contact_work: float         # work of the contact forces as applied in the steps

    @property
    def residual(self) -> float:
        return (self.input_work - self.damping - self.friction - self.kinetic_change
                - self.strain_change - self.contact_change)

    @property
    def relative_error(self) -> float:
        """|residual| / |input work| (input work > 0 in a forced steady state)."""
        return abs(self.residual) / max(abs(self.input_work), 1e-300)

    def to_json(self) -> dict[str, float]:
        return {"input_work": self.input_work, "damping": self.damping, "friction": self.friction,
                "kinetic_change": self.kinetic_change, "strain_change": self.strain_change,
                "contact_change": self.contact_change,
                "contact_work": self.contact_work, "relative_error": self.relative_error}


@dataclass(frozen=True)
class Trajectory:
    """What one integration recorded, one row per step (row 0 is t = 0).

    Per-side columns (side 1, side 2) are resultants over the side's
    elements: normal force N and friction F (N), weighted mean w_s (m), and
    the side's state (0 separate: no element touches; 2 slip: some element
    slips; 1 stick otherwise).
    """

    dt: float
    steps: int                  # steps completed
    tip: np.ndarray             # (steps+1, 2): v_L, w_L, m
    normal: np.ndarray          # (steps+1, 2): N1, N2, N
    friction: np.ndarray        # (steps+1, 2): Ff1, Ff2, N
    tangential: np.ndarray      # (steps+1, 2): w_s of side 1, 2, m
    state: np.ndarray           # (steps+1, 2) int8
    energy: EnergyBalance | None
    contact_iterations: int     # most active-set iterations in one step
    contact_unconverged: int    # steps whose contact solve hit the iteration limit
    diverged: str | None        # cause, if the run left the bounded regime
    elapsed_s: float
    method: str                 # "kernel" | "reference"
    # Per contact element j over the window's steps (rows window+1 .. steps; None without a window):
    element_share: np.ndarray | None       # (k, 3): share of steps separate / stick / slip
    element_peak_normal: np.ndarray | None  # (k,): largest |N_j|, N
    end: "Motion | None" = None            # the state after the last step (None: the run diverged)

    @property
    def t(self) -> np.ndarray:
        return self.dt * np.arange(self.steps + 1)


# --- pieces shared by both loops ---------------------------------------------------

# The two record-keeping pieces below run once a step. The compiled kernel
# takes them inlined (numba IR inlining): as calls they cost 2-3 ms of the
# 12-14 ms of a 25,600-step beam run with contact, more than their work
# (benchmarks/bench_transient.py). Called from Python (the reference loop)
# they compile as any leaf. Their arithmetic is the same either way.
recorder = njit(cache=True, _nrt=False, inline="always")


@recorder
def side_resultants(y, N, F, state, rows, side, weight, i, r_N, r_F, r_w, r_state):
    """Row i of the per-side records: totals of N and F, weighted mean w_s, side state."""
    w1 = w2 = 0.0
    for s in range(2):
        r_N[i, s] = 0.0
        r_F[i, s] = 0.0
        r_w[i, s] = 0.0
        r_state[i, s] = 0
    for j in range(N.size):
        s = side[j] - 1
        r_N[i, s] += N[j]
        r_F[i, s] += F[j]
        r_w[i, s] += weight[j] * y[rows[j, 1]]
        if s == 0:
            w1 += weight[j]
        else:
            w2 += weight[j]
        if state[j] == SLIP:
            r_state[i, s] = SLIP
        elif state[j] == STICK and r_state[i, s] == 0:
            r_state[i, s] = STICK
    if w1 > 0.0:
        r_w[i, 0] /= w1
    if w2 > 0.0:
        r_w[i, 1] /= w2


@recorder
def element_tally(N, state, counts, peak_normal):
    """Add one step to each element's state count (k, 3) and raise its peak |N| (k,)."""
    for j in range(N.size):
        counts[j, state[j]] += 1
        peak_normal[j] = max(peak_normal[j], abs(N[j]))


def contact_resolution(Cc: np.ndarray, law: ContactLaw) -> float:
    """Steps per period of the stiffest contact motion, estimated from Cc.

    With every element stuck, kn Cc ~ beta (omega_c dt)^2 for a contact mode
    of frequency omega_c; the spectral radius rho of Cc D gives
    omega_c dt ~ 2 sqrt(rho), i.e. 2 pi / (omega_c dt) steps per period.
    """
    if law.count == 0:
        return math.inf
    rho = float(np.max(np.abs(np.linalg.eigvals(Cc @ stuck_stiffness(law)))))
    return math.inf if rho <= 0 else math.pi / math.sqrt(rho)


def stuck_stiffness(law: ContactLaw) -> np.ndarray:
    """D with lam = -D y + const while every element sticks: kn on normal rows, kt on tangent rows."""
    D = np.zeros((law.m, law.m))
    for (nr, tr), p in zip(law.rows, law.props):
        D[nr, nr] += p[1]
        D[tr, tr] += p[2]
    return D


@dataclass(frozen=True)
class LagStability:
    """Linear stability of the explicit contact treatment with every element stuck.

    The explicit step applies the contact force of the step's start, a force
    lagged by dt. Over a cycle of amplitude Y at frequency omega a spring
    force lagged by dt does the work pi kn Y^2 sin(omega dt) on the blade: a
    negative viscous damping kn sin(omega dt) / omega ~ kn dt. For a motion
    dominated by the contact spring (kn ~ m omega^2) its damping ratio is
    -sin(omega dt) / 2 ~ -omega dt / 2 = -pi / (steps per period), to be
    compared with the structural (Rayleigh) ratio alpha / (2 omega) +
    beta omega / 2 at that frequency. Average-acceleration Newmark adds no
    numerical damping, so the sign of the difference decides.
    """

    spectral_radius: float     # largest |eigenvalue| of the linearized explicit step
    frequency_hz: float        # of the least damped motion
    damping_ratio: float       # its net damping ratio (< 0: grows)
    dt_stable: float           # largest step (s) at which the stuck explicit step is stable

    @property
    def unstable(self) -> bool:
        return self.damping_ratio < 0.0


def _explicit_step_matrix(M, C, K, W, D, scheme: NewmarkScheme) -> np.ndarray:
    """(3n, 3n) map [q, v, a]_n -> [q, v, a]_n+1 of the explicit step with lam_n = -D W q_n."""
    n = M.shape[0]
    a0, a1, a2, a3, a4, a5 = scheme.coefficients()
    S = np.linalg.inv(K + a0 * M + a1 * C)
    I, Z = np.eye(n), np.zeros((n, n))
    Q = S @ np.hstack([a0 * M + a1 * C, a2 * M + a4 * C, a3 * M + a5 * C])
    Q[:, :n] -= S @ W.T @ D @ W                          # the lagged contact force
    A = a0 * (Q - np.hstack([I, Z, Z])) - np.hstack([Z, a2 * I, a3 * I])
    V = np.hstack([Z, I, (1.0 - scheme.gamma) * scheme.dt * I]) + scheme.gamma * scheme.dt * A
    return np.vstack([Q, V, A])


LAG_CHECK_MAX_DOFS = 200     # the eigen-check's dense (3n x 3n) eigen-solves stay below ~0.1 s each


def explicit_lag_stability(system: StructuralSystem, law: ContactLaw, scheme: NewmarkScheme) -> LagStability:
    """Eigen-analysis of the explicit step with every contact stuck (dense systems).

    The least damped eigenvalue lam = exp((-zeta omega + i omega_d) dt) gives
    the motion's frequency and net damping ratio. The largest stable step is
    bracketed by bisection on the sign of that ratio.
    """
    M, C, K = dense(system.M), dense(system.C), dense(system.K)
    W, D = dense(system.contact.W), stuck_stiffness(law)

    def least_damped(dt: float) -> tuple[float, float, float]:
        lam = np.linalg.eigvals(_explicit_step_matrix(M, C, K, W, D, NewmarkScheme(dt, scheme.gamma, scheme.beta)))
        lam = lam[np.abs(lam) > 1e-12]                   # the acceleration's zero eigenvalues
        s = np.log(lam.astype(complex)) / dt             # -zeta omega + i omega_d
        zeta = -s.real / np.abs(s)
        i = int(np.argmin(zeta))
        return float(np.abs(lam).max()), float(abs(s[i].imag) / (2 * math.pi)), float(zeta[i])

    rho, f, zeta = least_damped(scheme.dt)
    lo, hi = 0.0, scheme.dt
    if zeta < 0:
        hi = scheme.dt
        lo = scheme.dt / 2
        while least_damped(lo)[2] < 0 and lo > scheme.dt * 1e-6:
            hi, lo = lo, lo / 2
        for _ in range(20):                              # to 1e-6 of the bracket
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if least_damped(mid)[2] >= 0 else (lo, mid)
    else:
        lo = scheme.dt
    return LagStability(spectral_radius=rho, frequency_hz=f, damping_ratio=zeta, dt_stable=lo)



def _is_dense(system: StructuralSystem) -> bool:
    return all(isinstance(A, np.ndarray) for A in (system.M, system.C, system.K))


@dataclass(frozen=True)
class _Step:
    """The factorized step operator and its contact projections.

    The time loop (_reference_loop) works on this process's rows of the
    predictor: its rows of M and C, of the back-substitution and of Phi,
    and gathers the step's end state once. On one process that is every row.
    """

    factor: Factorization      # of K_eff
    W: Any                     # (m, n)
    W_rows: Any                # (m, rows): W's columns of this process's rows
    Phi: np.ndarray            # (n, m) = S W^T; sparse systems: column-major, this process's rows
    Cc: np.ndarray             # (m, m) = W S W^T
    share: RowShare            # the row share (StructuralSystem.layout, or AllRows)
    low_rank: bool = False     # n < m / 2 (dense): solve the contact in the n-space, Cc = W Phi

    def contact_workspace(self, law: ContactLaw):
        """shroud.core.contact.workspace for this step's compliance (factored as W Phi when low rank)."""
        return workspace(law, dense(self.W), self.Phi) if self.low_rank else workspace(law)

    def respond(self, q_pred: np.ndarray, lam: np.ndarray) -> np.ndarray:
        """q_pred + Phi lam on this process's rows: the step's end state under the contact forces ``lam``.

        Phi of a solid is large (36888 x 482: 142 MB) and most of its columns
        are unloaded in any step (separated face nodes), so only the loaded
        columns are read.
        """
        if not np.any(lam):
            return q_pred
        out = q_pred.copy()
        _add_loaded_columns(self.Phi, lam, out)
        return out


@njit(cache=True, fastmath={"reassoc", "contract"}, _nrt=False)   # a leaf (contact.leaf)
def _add_loaded_columns(Phi, lam, out):
    """out += Phi lam over the columns with lam != 0 (Phi column-major: each read is contiguous)."""
    for j in range(lam.size):
        scale = lam[j]
        if scale != 0.0:
            for r in range(out.size):
                out[r] += scale * Phi[r, j]


def _row_block(A):
    """This process's rows of A with every column (a row-distributed operator's ``row_block``; else A)."""
    return getattr(A, "row_block", A)


def _factorize_step(system: StructuralSystem, law: ContactLaw, scheme: NewmarkScheme,
                    factorize: Callable[[Any], Factorization] | None) -> _Step:
    a0, a1 = scheme.coefficients()[:2]
    K_eff = system.K + a0 * system.M + a1 * system.C
    factor = (factorize or system.factorize or default_factorization)(K_eff)
    n = system.dofs
    share = system.layout or AllRows(n)
    if law.count:
        W = system.contact.W
        Phi = np.asarray(factor.solve(dense(W.T))).reshape(n, -1)   # one block solve
        Cc = np.asarray(W @ Phi)
        if not _is_dense(system):        # column-major for respond(); the dense kernel reads rows
            Phi = np.asfortranarray(share.own(Phi))
    else:
        W, Phi, Cc = np.zeros((0, n)), np.zeros((n, 0), order="F"), np.zeros((0, 0))
    return _Step(factor=factor, W=W, W_rows=W if system.layout is None else W[:, share.start:share.stop],
                 Phi=Phi, Cc=0.5 * (Cc + Cc.T) if _symmetric(system) else Cc, share=share,
                 low_rank=_is_dense(system) and 2 * n <= law.m)


def _symmetric(system: StructuralSystem) -> bool:
    """C symmetric (no Coriolis) makes K_eff, hence Cc, symmetric: symmetrize round-off away."""
    C = system.C
    if hasattr(C, "is_symmetric"):      # a row-distributed operator (reference_fe.distributed)
        return C.is_symmetric()
    diff = C - C.T
    return (abs(diff).max() if scipy.sparse.issparse(diff) else np.abs(diff).max()) == 0


# --- the two loops ------------------------------------------------------------------

class Motion(NamedTuple):
    """The integrator's whole state at one step: displacements q (m), velocities v (m/s), accelerations
    a (m/s^2), n each, and the friction sliders' positions z (m, one per contact element; the law's
    memory, shroud.core.contact)."""

    q: np.ndarray
    v: np.ndarray
    a: np.ndarray
    z: np.ndarray


class LoopEnd(NamedTuple):
    """How a time loop ended: steps done, status (OK, NOT_FINITE, UNBOUNDED), end state, contact solves."""

    done: int
    status: int
    q: np.ndarray
    v: np.ndarray
    iterations: int             # active-set iterations over the run
    unconverged: int            # steps whose contact solve did not settle


@dataclass
class _Record:
    tip: np.ndarray
    normal: np.ndarray
    friction: np.ndarray
    tangential: np.ndarray
    state: np.ndarray
    energy: np.ndarray         # input, damping, friction, contact work, contact energy at start, end
    snap_q: np.ndarray         # q, v at the start of the energy window
    snap_v: np.ndarray
    element_counts: np.ndarray  # (k, 3) window steps of each element separate / stick / slip
    element_peak: np.ndarray    # (k,) largest |N| of each element in the window, N

    @classmethod
    def empty(cls, steps: int, n: int, k: int) -> "_Record":
        return cls(tip=np.zeros((steps + 1, 2)), normal=np.zeros((steps + 1, 2)),
                   friction=np.zeros((steps + 1, 2)), tangential=np.zeros((steps + 1, 2)),
                   state=np.zeros((steps + 1, 2), np.int8), energy=np.zeros(6),
                   snap_q=np.zeros(n), snap_v=np.zeros(n),
                   element_counts=np.zeros((k, 3), np.int64), element_peak=np.zeros(k))


def _reference_loop(system, law, scheme, steps, implicit, bound, window, step, start, rec, progress):
    """Newmark step by step, as written in the module docstring (Python; any backend)."""
    a0, a1, a2, a3, a4, a5 = scheme.coefficients()
    dt, gamma, w_e = scheme.dt, scheme.gamma, system.omega_e
    M, C, W, Cc = system.M, system.C, step.W, step.Cc
    share = step.share
    mine = slice(share.start, share.stop)             # this process's rows of the predictor
    M_rows, C_rows = _row_block(M), _row_block(C)
    f_const_rows, f_aero_rows = system.f_const[mine], system.f_aero[mine]
    tip = system.tip
    k, m = law.count, law.m
    ws = step.contact_workspace(law)
    q, v, a, z = (x.copy() for x in start)
    N, F, state, lam = np.zeros(k), np.zeros(k), np.zeros(k, np.int64), np.zeros(m)
    y = np.asarray(W @ q) if k else np.zeros(0)
    evaluate(y, z, law.rows, law.props, lam, N, F, z, state)
    lam_eq = lam.copy()                                # contact force in Eq. 9 at the current time
    _record_row(rec, 0, tip @ q, y, N, F, state, law)
    iterations, unconverged = 0, 0
    for i in range(steps):
        s0, s1 = math.sin(w_e * i * dt), math.sin(w_e * (i + 1) * dt)
        rhs = (f_const_rows + s1 * f_aero_rows + M_rows @ (a0 * q + a2 * v + a3 * a)
               + C_rows @ (a1 * q + a4 * v + a5 * a))
        q_pred = step.factor.solve_rows(rhs)                   # this process's rows
        z_old, F_old, N_old, y_old = z.copy(), F.copy(), N.copy(), y.copy()
        if k and implicit:                              # the law holds at t + dt
            y_pred = share.sum(np.asarray(step.W_rows @ q_pred))
            it, ok = solve_contact(y_pred, Cc, z_old, law.rows, law.props, y, lam, N, F, z, state, ws)
            iterations, unconverged = max(iterations, it), unconverged + (not ok)
        lam_step = lam.copy()                           # explicit: the law at t
        q_new = share.gather(step.respond(q_pred, lam_step))
        if k and not implicit:                          # the law at t + dt, for the next step
            y = np.asarray(W @ q_new)
            evaluate(y, z_old, law.rows, law.props, lam, N, F, z, state)
        a_new = a0 * (q_new - q) - a2 * v - a3 * a
        v_new = v + dt * ((1.0 - gamma) * a + gamma * a_new)
        if i == window:
            rec.snap_q[:], rec.snap_v[:] = q, v
            rec.energy[4] = contact_energy(N_old, F_old, law.props)
        if i >= window:
            v_mid = 0.5 * (v + v_new)
            f_mid = system.f_const + 0.5 * (s0 + s1) * system.f_aero
            rec.energy[:4] += (float((q_new - q) @ f_mid), dt * float(v_mid @ (C @ v_mid)),
                               friction_dissipation(F_old, F, z_old, z) if k else 0.0,
                               float((y - y_old) @ (0.5 * (lam_eq + lam_step))) if k else 0.0)
        lam_eq = lam_step
        q, v, a = q_new, v_new, a_new
        tip_now = tip @ q
        _record_row(rec, i + 1, tip_now, y, N, F, state, law)
        if i >= window:
            element_tally(N, state, rec.element_counts, rec.element_peak)
        if not np.all(np.isfinite(tip_now)):
            return LoopEnd(i + 1, NOT_FINITE, q, v, iterations, unconverged)
        if np.max(np.abs(tip_now)) > bound:
            return LoopEnd(i + 1, UNBOUNDED, q, v, iterations, unconverged)
        progress.update(i + 1)
    rec.energy[5] = contact_energy(N, F, law.props)
    start.a[:], start.z[:] = a, z
    return LoopEnd(steps, OK, q, v, iterations, unconverged)


def _record_row(rec, i, tip_now, y, N, F, state, law):
    rec.tip[i] = tip_now
    side_resultants(y, N, F, state, law.rows, law.side, law.weight, i,
                    rec.normal, rec.friction, rec.tangential, rec.state)


@njit(cache=True, fastmath={"reassoc", "contract"}, _nrt=False)   # a leaf (contact.leaf)
def _affine(A, x, b, c, s, out):
    """out = A x + b + s c (the sums reassociated so they vectorize: round-off level changes only).

    ``out`` may alias ``b``: each row reads b[r] before it writes out[r].
    """
    for r in range(A.shape[0]):
        acc = 0.0
        for l in range(A.shape[1]):
            acc += A[r, l] * x[l]
        out[r] = acc + b[r] + s * c[r]


@njit(cache=True)
def _dense_kernel(A, WA, Sfc, Sfa, WSfc, WSfa, fc, fa, C, w_e, dt, gamma, a0, a2, a3, steps,
                  W, Phi, Cc, tip, rows, props, side, weight, implicit, bound, window,
                  q0, v0, acc0, z0, r_tip, r_N, r_F, r_w, r_state, energy, snap_q, snap_v, r_counts, r_peak, ws):
    """The step of _reference_loop, compiled for dense systems.

    The state is stacked, x = [q, v, a], and S = K_eff^-1 folded into
    A = S [a0 M + a1 C, a2 M + a4 C, a3 M + a5 C] (n x 3n) and the loads, so the
    predictor is q_pred = A x + S f(t+dt); its contact coordinates come
    straight from WA = W A (m x 3n), so a step without contact forces costs
    (n + m) 3n products and never forms W q. Small arrays are copied with
    loops (numba's slice assignment costs more than the contact law here).
    """
    n, m, k = q0.size, Cc.shape[0], rows.shape[0]
    x, x_new = np.zeros(3 * n), np.zeros(3 * n)
    q, v, a = x[:n], x[n:2 * n], x[2 * n:]
    qn, vn, an = x_new[:n], x_new[n:2 * n], x_new[2 * n:]
    copy_into(q, q0)
    copy_into(v, v0)
    copy_into(a, acc0)
    zero_n, zero_m, zero_2 = np.zeros(n), np.zeros(m), np.zeros(2)
    v_mid, Cv, tip_now = np.zeros(n), np.zeros(n), np.zeros(2)
    y, y_pred, y_old = np.zeros(m), np.zeros(m), np.zeros(m)
    lam, lam_eq, lam_step = np.zeros(m), np.zeros(m), np.zeros(m)
    N, F, F_old, N_old = np.zeros(k), np.zeros(k), np.zeros(k), np.zeros(k)
    z, z_old = np.zeros(k), np.zeros(k)
    state = np.zeros(k, np.int64)
    _affine(W, q, zero_m, zero_m, 0.0, y)
    copy_into(z_old, z0)
    evaluate(y, z_old, rows, props, lam, N, F, z, state)
    copy_into(lam_eq, lam)
    _affine(tip, q, zero_2, zero_2, 0.0, tip_now)
    r_tip[0, 0], r_tip[0, 1] = tip_now[0], tip_now[1]
    side_resultants(y, N, F, state, rows, side, weight, 0, r_N, r_F, r_w, r_state)
    iterations, unconverged = 0, 0
    s1 = math.sin(0.0)
    for i in range(steps):
        s0, s1 = s1, math.sin(w_e * (i + 1) * dt)
        _affine(A, x, Sfc, Sfa, s1, qn)                  # q_pred
        if k > 0:
            copy_into(z_old, z)
            if i >= window:                              # the step's start, for the energy balance
                copy_into(F_old, F)
                copy_into(N_old, N)
                copy_into(y_old, y)
            if implicit:
                _affine(WA, x, WSfc, WSfa, s1, y_pred)
                it, ok = solve_contact(y_pred, Cc, z_old, rows, props, y, lam, N, F, z, state, ws)
                iterations = max(iterations, it)
                if not ok:
                    unconverged += 1
            copy_into(lam_step, lam)
            loaded = False
            for l in range(m):
                loaded = loaded or lam_step[l] != 0.0
            if loaded:                                   # q' = q_pred + Phi lam
                _affine(Phi, lam_step, qn, zero_n, 0.0, qn)
            if not implicit:
                _affine(W, qn, zero_m, zero_m, 0.0, y)
                evaluate(y, z_old, rows, props, lam, N, F, z, state)
        for r in range(n):
            an[r] = a0 * (qn[r] - q[r]) - a2 * v[r] - a3 * a[r]
            vn[r] = v[r] + dt * ((1.0 - gamma) * a[r] + gamma * an[r])
        if i == window:
            copy_into(snap_q, q)
            copy_into(snap_v, v)
            energy[4] = contact_energy(N_old, F_old, props)
        if i >= window:
            w_in, d_damp, w_c = 0.0, 0.0, 0.0
            for r in range(n):
                w_in += (qn[r] - q[r]) * (fc[r] + 0.5 * (s0 + s1) * fa[r])
                v_mid[r] = 0.5 * (v[r] + vn[r])
            _affine(C, v_mid, zero_n, zero_n, 0.0, Cv)
            for r in range(n):
                d_damp += dt * v_mid[r] * Cv[r]
            for l in range(m):
                w_c += (y[l] - y_old[l]) * 0.5 * (lam_eq[l] + lam_step[l])
            energy[0] += w_in
            energy[1] += d_damp
            energy[2] += friction_dissipation(F_old, F, z_old, z)
            energy[3] += w_c
        copy_into(lam_eq, lam_step)
        copy_into(x, x_new)
        _affine(tip, q, zero_2, zero_2, 0.0, tip_now)
        r_tip[i + 1, 0], r_tip[i + 1, 1] = tip_now[0], tip_now[1]
        if k > 0:
            side_resultants(y, N, F, state, rows, side, weight, i + 1, r_N, r_F, r_w, r_state)
            if i >= window:
                element_tally(N, state, r_counts, r_peak)
        for s in range(2):
            if not math.isfinite(tip_now[s]):
                return i + 1, NOT_FINITE, iterations, unconverged
            if abs(tip_now[s]) > bound:
                return i + 1, UNBOUNDED, iterations, unconverged
    copy_into(q0, q)
    copy_into(v0, v)
    copy_into(acc0, a)
    copy_into(z0, z)
    energy[5] = contact_energy(N, F, props)
    return steps, OK, iterations, unconverged


def _kernel_array(x) -> np.ndarray:
    """Writeable C-ordered float64: one compiled signature for every model.

    (Cached model matrices are read-only; numba types those apart and would
    compile the kernel again, seconds, for the first run of such a model.)
    """
    return np.require(x, dtype=np.float64, requirements=["C", "W"])


def _run_kernel(system, law, scheme, steps, implicit, bound, window, step, start, rec):
    n = system.dofs
    a0, a1, a2, a3, a4, a5 = scheme.coefficients()
    M, C = dense(system.M), dense(system.C)
    S = step.factor.solve(np.eye(n))                                  # K_eff^-1 (n <= a few hundred)
    A = np.ascontiguousarray(S @ np.hstack([a0 * M + a1 * C, a2 * M + a4 * C, a3 * M + a5 * C]))
    W = dense(step.W) if law.count else np.zeros((0, n))
    Sfc, Sfa = S @ system.f_const, S @ system.f_aero
    done, status, iterations, unconverged = _dense_kernel(
        A, W @ A, Sfc, Sfa, W @ Sfc, W @ Sfa, _kernel_array(system.f_const),
        _kernel_array(system.f_aero), _kernel_array(C), float(system.omega_e), scheme.dt, scheme.gamma,
        a0, a2, a3, steps, _kernel_array(W), _kernel_array(step.Phi),
        _kernel_array(step.Cc), _kernel_array(dense(system.tip)), law.rows, law.props,
        law.side, law.weight, implicit, bound, window, *start, rec.tip, rec.normal, rec.friction,
        rec.tangential, rec.state, rec.energy, rec.snap_q, rec.snap_v, rec.element_counts,
        rec.element_peak, step.contact_workspace(law))
    return LoopEnd(done, status, start.q, start.v, iterations, unconverged)


def integrate(system: StructuralSystem, law: ContactLaw, scheme: NewmarkScheme, steps: int,
              implicit: bool = True, method: str = "auto", energy_window: int | None = None,
              bound: float = math.inf, q0: np.ndarray | None = None, v0: np.ndarray | None = None,
              factorize: Callable | None = None, label: str = "transient", acc0: np.ndarray | None = None,
              z0: np.ndarray | None = None) -> Trajectory:
    """Integrate ``steps`` Newmark steps of ``system`` with contact ``law`` (paper Eq. 9).

    ``method``: "kernel" (compiled; dense systems), "reference" (Python loop;
    any backend) or "auto" (kernel when M, C, K are ndarrays).
    ``energy_window``: number of final steps over which the energy balance is
    accumulated (default: none). ``bound``: largest admissible |v_L|, |w_L|
    (m); beyond it, or on a non-finite value, the run stops and the
    trajectory so far is returned with ``diverged`` naming the cause.
    ``q0, v0``: initial state (default zero, as the paper); ``acc0``: initial
    acceleration (default zero, as the paper); ``z0``: the sliders' initial
    positions (default each element's tangential displacement: no friction
    force). The trajectory's ``end`` is the state after the last step, sliders
    included, from which a run continues where this one stopped
    (shroud.core.period_map).
    """
    method = ("kernel" if _is_dense(system) else "reference") if method == "auto" else method
    if method == "kernel" and not _is_dense(system):
        raise ValueError("the compiled kernel needs dense M, C, K; use method='reference'")
    t_start = time.perf_counter()
    step = _factorize_step(system, law, scheme, factorize)
    if not implicit and law.count:
        per_period = contact_resolution(step.Cc, law)
        if per_period < 10:
            warn(f"time step {scheme.dt:.3g} s is too coarse for the explicit contact treatment: "
                 f"the stiffest contact motion (kn = {law.props[:, 1].max():.3g} N/m per element) "
                 f"has a period of ~{per_period:.1f} steps (< 10); use time.contact = \"implicit\" "
                 "or more time.steps_per_period")
        if _is_dense(system) and system.dofs <= LAG_CHECK_MAX_DOFS:
            lag = explicit_lag_stability(system, law, scheme)
            if lag.unstable:
                warn(f"the explicit contact treatment is unstable at dt = {scheme.dt:.3g} s: with the "
                     f"contacts closed the motion at {lag.frequency_hz:.0f} Hz has a net damping ratio of "
                     f"{lag.damping_ratio:.3g}, because the contact force lagged one step feeds energy into it "
                     "like a negative damping kn dt that the structural damping does not remove; it is "
                     f"stable for dt < {lag.dt_stable:.3g} s ({scheme.dt / lag.dt_stable:.1f}x more "
                     "time.steps_per_period), or use time.contact = \"implicit\"")
    n = system.dofs
    q = np.zeros(n) if q0 is None else np.array(q0, dtype=float)
    v = np.zeros(n) if v0 is None else np.array(v0, dtype=float)
    a = np.zeros(n) if acc0 is None else np.array(acc0, dtype=float)
    z = (np.asarray(step.W @ q)[law.rows[:, 1]] if law.count else np.zeros(0)) if z0 is None else z0
    start = Motion(q, v, a, np.array(z, dtype=float))
    window = steps - energy_window if energy_window else steps + 1
    rec = _Record.empty(steps, n, law.count)
    try:
        if method == "kernel":
            end = _run_kernel(system, law, scheme, steps, implicit, bound, window, step, start, rec)
        else:
            progress = Progress(label, steps)
            end = _reference_loop(system, law, scheme, steps, implicit, bound, window, step, start, rec,
                                  progress)
            progress.done()
    finally:
        step.factor.close()
    done, status, q, v, iterations, unconverged = end
    energy = None
    if status == OK and energy_window:
        energy = _energy_balance(system, rec, q, v, window, steps)
    cause = divergence_cause(status, done, scheme.dt, bound)
    if unconverged:
        warn(f"the contact solve did not settle in {unconverged} of {done} steps "
             "(element states kept cycling); results near those steps are approximate")
    sl = slice(0, done + 1)
    counted = done - window
    share = rec.element_counts / counted if counted > 0 else None
    return Trajectory(dt=scheme.dt, steps=done, tip=rec.tip[sl], normal=rec.normal[sl],
                      friction=rec.friction[sl], tangential=rec.tangential[sl], state=rec.state[sl],
                      energy=energy, contact_iterations=int(iterations),
                      contact_unconverged=int(unconverged), diverged=cause,
                      elapsed_s=time.perf_counter() - t_start, method=method,
                      element_share=share, element_peak_normal=rec.element_peak if counted > 0 else None,
                      end=Motion(q, v, start.a, start.z) if status == OK else None)


def _energy_balance(system, rec, q, v, window, steps) -> EnergyBalance:
    """Close the balance with kinetic and strain energies at both ends of the window."""
    def mechanical(qq, vv):
        return 0.5 * float(vv @ (system.M @ vv)), 0.5 * float(qq @ (system.K @ qq))

    kin0, str0 = mechanical(rec.snap_q, rec.snap_v)
    kin1, str1 = mechanical(q, v)
    w_input, d_damp, d_fric, w_contact, e_c0, e_c1 = rec.energy
    return EnergyBalance(start_step=window, end_step=steps, input_work=float(w_input),
                         damping=float(d_damp), friction=float(d_fric),
                         kinetic_change=kin1 - kin0, strain_change=str1 - str0,
                         contact_change=float(e_c1 - e_c0), contact_work=float(w_contact))


def divergence_cause(status: int, done: int, dt: float, bound: float) -> str | None:
    """Why an integration that stopped with ``status`` after ``done`` steps of ``dt`` (s) did: None if OK."""
    if status == OK:
        return None
    t = done * dt
    if status == NOT_FINITE:
        return f"non-finite displacement at step {done} (t = {t:.4g} s)"
    return (f"tip displacement beyond {bound:.3g} m at step {done} (t = {t:.4g} s): "
            "the response grows without bound")
