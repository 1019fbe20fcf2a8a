"""The whole ring in time: Newmark with the contact solved around the ring (docs/ring.md).

The step of shroud.core.newmark, blade by blade: the linear step operator
K_eff,j = K_j + gamma/(beta dt) C_j + 1/(beta dt^2) M_j is block diagonal,
so each blade predicts its own q_pred,j with its own S_j = K_eff,j^-1 (nb x
3 nb products per blade, not (N nb) x (3 N nb) for the ring). The blades
meet only at the interfaces: y = W q with W the relative projection of
shroud.core.ring, Phi = S W^T has blade j's columns only for interfaces j-1
and j, and the contact compliance Cc = W S W^T is cyclic block-tridiagonal
(interface j is coupled to j-1 and j+1 through the blades they share). The
implicit step solves y = W q_pred + Cc lam(y) for every interface at once
(shroud.core.contact.solve_contact: the coupled problem, not N separate
ones; from CYCLIC_FROM contact coordinates on its affine solves are the
cyclic block-tridiagonal factorization of shroud.core.cyclic_blocks, linear
in N, else dense), then q_j = q_pred,j + S_j (side2_j^T lam_j - side1_j^T
lam_j-1).
Where the ring has fewer DOFs than half its contact coordinates (the
fe-reduced ring: 3 blades of 33 modes against 594 face coordinates) that
solve works in the blades' space, Cc = W Phi with Phi = S W^T (the core's
low-rank path: an N nb system instead of one on the active coordinates,
still dense in N nb); the beams (6 DOF a blade, 2 or 4 coordinates an
interface) stay in the contact coordinates.

Blades listed in ``held`` are held still (rigid and fixed, as the paper's
neighbours): their operators are zero, so they neither move nor yield.

Records per step: each blade's v_L, w_L, each interface's total N and F
(the force on blade j along e_ws), weighted mean r and state; over the final
window the energy balance of the whole ring. Units: SI.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np
from numba import njit

from shroud.base.log import warn
from shroud.core.contact import (SLIP, STICK, ContactLaw, contact_energy, copy_into, evaluate, friction_dissipation,
                                 solve_contact, workspace)
from shroud.core.linear_solvers import dense
from shroud.core.newmark import NOT_FINITE, OK, UNBOUNDED, EnergyBalance, NewmarkScheme, divergence_cause
from shroud.core.ring import BladeRing


@dataclass(frozen=True)
class RingTrajectory:
    """What one integration of the ring recorded, one row per step (row 0 is t = 0)."""

    dt: float
    steps: int
    tip: np.ndarray             # (steps+1, N, 2): v_L, w_L of each blade, m
    normal: np.ndarray          # (steps+1, N): N of interface j (its points summed), N
    friction: np.ndarray        # (steps+1, N): F on blade j along e_ws from interface j, N
    slip: np.ndarray            # (steps+1, N): weighted mean r_j = w_s,j - w_s,j+1, m
    state: np.ndarray           # (steps+1, N) int8: 0 separate, 1 stick, 2 some point slips
    energy: EnergyBalance | None
    contact_iterations: int
    contact_unconverged: int
    diverged: str | None
    elapsed_s: float
    q: np.ndarray               # (N, nb) end state
    v: np.ndarray
    a: np.ndarray

    @property
    def t(self) -> np.ndarray:
        return self.dt * np.arange(self.steps + 1)


# The cyclic block solve pays from about 48 contact coordinates (benchmarks/bench_ring.py, CPU, 400
# periods: the reduced beam's 12 blades, 24 coordinates, 0.43 s cyclic against 0.37 s dense; 24 blades,
# 48, 0.70-0.88 s against 0.82-0.86 s; the extended beam's 24 blades, 96, 2.2 s against 4.6 s).
CYCLIC_FROM = 48


@dataclass(frozen=True)
class RingStep:
    """The ring's factorized step: per-blade operators and the interfaces' compliance."""

    A: np.ndarray        # (N, nb, 3 nb): S_j [a0 M + a1 C, a2 M + a4 C, a3 M + a5 C]
    S: np.ndarray        # (N, nb, nb): K_eff,j^-1
    Phi1: np.ndarray     # (N, nb, c): S_j side1_j^T
    Phi2: np.ndarray     # (N, nb, c): S_j side2_j^T
    Cc: np.ndarray       # (m, m) = W S W^T
    W: np.ndarray        # (m, N nb): the relative projection
    Phi: np.ndarray      # (N nb, m) = S W^T: Cc = W Phi

    @property
    def low_rank(self) -> bool:
        """The ring has fewer DOFs than half its contact coordinates (the fe-reduced ring: 3 x 33 against
        594): its contact is solved in the blades' space, Cc = W Phi (shroud.core.contact.workspace)."""
        return 2 * self.Phi.shape[0] <= self.Cc.shape[0]

    def blocks(self) -> np.ndarray:
        """Cc as cyclic block-tridiagonal blocks (N, 3, c, c): row j's interfaces j-1, j, j+1
        (shroud.core.cyclic_blocks; N >= 3, where the three are distinct)."""
        N, c = self.S.shape[0], self.Phi1.shape[2]
        Cb = np.empty((N, 3, c, c))
        for j in range(N):
            for t in range(3):
                k = (j - 1 + t) % N
                Cb[j, t] = self.Cc[j * c:(j + 1) * c, k * c:(k + 1) * c]
        return Cb

    def contact_workspace(self, law: ContactLaw):
        """shroud.core.contact.workspace for this compliance: factored as W Phi when low rank, else by
        its cyclic blocks (linear in N) from CYCLIC_FROM contact coordinates on, else dense."""
        if self.low_rank:
            return workspace(law, self.W, self.Phi)
        cyclic = self.S.shape[0] >= 3 and self.Cc.shape[0] >= CYCLIC_FROM
        return workspace(law, blocks=self.blocks()) if cyclic else workspace(law)


def factorize(ring: BladeRing, scheme: NewmarkScheme, held: tuple[int, ...] = ()) -> RingStep:
    """The step operators of every blade (a tuned ring inverts one K_eff); held blades get zeros."""
    a0, a1, a2, a3, a4, a5 = scheme.coefficients()
    N, nb, c = ring.count, ring.blade_dofs, ring.rows_per_interface
    A, S = np.zeros((N, nb, 3 * nb)), np.zeros((N, nb, nb))
    done: dict[int, int] = {}
    for j, b in enumerate(ring.blades):
        if j in held:
            continue
        if id(b) in done:                       # the same blade system: the same operators
            A[j], S[j] = A[done[id(b)]], S[done[id(b)]]
            continue
        M, C, K = dense(b.M), dense(b.C), dense(b.K)
        S[j] = np.linalg.inv(K + a0 * M + a1 * C)
        A[j] = S[j] @ np.hstack([a0 * M + a1 * C, a2 * M + a4 * C, a3 * M + a5 * C])
        done[id(b)] = j
    Phi1 = np.einsum("jab,jcb->jac", S, ring.side1)
    Phi2 = np.einsum("jab,jcb->jac", S, ring.side2)
    W = ring.projection()
    Phi = np.zeros((N * nb, N * c))
    for j in range(N):
        Phi[j * nb:(j + 1) * nb, j * c:(j + 1) * c] += Phi2[j]
        i = (j - 1) % N
        Phi[j * nb:(j + 1) * nb, i * c:(i + 1) * c] -= Phi1[j]
    return RingStep(A=A, S=S, Phi1=Phi1, Phi2=Phi2, Cc=W @ Phi, W=W, Phi=Phi)


@njit(cache=True, _nrt=False)
def _project(side1, side2, x, y):
    """y = W q for the q part of the stacked states x (N, 3 nb): y_j = side2_j q_j - side1_j+1 q_j+1."""
    N, c, nb = side1.shape
    for j in range(N):
        k = (j + 1) % N
        for r in range(c):
            acc = 0.0
            for l in range(nb):
                acc += side2[j, r, l] * x[j, l] - side1[k, r, l] * x[k, l]
            y[j * c + r] = acc


@njit(cache=True)
def _ring_kernel(A, S, fc, fs, fk, side1, side2, Phi1, Phi2, Cc, M, C, tip, rows, props, e,
                 w_e, dt, gamma, a0, a2, a3, steps, implicit, bound, window, x,
                 r_tip, r_N, r_F, r_r, r_state, energy, snap, ws):
    """The ring's Newmark steps (module docstring); x (N, 3 nb) = [q, v, a] per blade, in and out."""
    N, nb, c = A.shape[0], A.shape[1], side1.shape[1]
    m, k = N * c, rows.shape[0]
    xn = np.zeros((N, 3 * nb))
    Sfc, Sfs, Sfk = np.zeros((N, nb)), np.zeros((N, nb)), np.zeros((N, nb))
    for j in range(N):                      # the loads through S_j
        for r in range(nb):
            for l in range(nb):
                Sfc[j, r] += S[j, r, l] * fc[j, l]
                Sfs[j, r] += S[j, r, l] * fs[j, l]
                Sfk[j, r] += S[j, r, l] * fk[j, l]
    y, y_pred, y_old = np.zeros(m), np.zeros(m), np.zeros(m)
    lam, lam_eq, lam_step = np.zeros(m), np.zeros(m), np.zeros(m)
    N_, F, F_old, N_old = np.zeros(k), np.zeros(k), np.zeros(k), np.zeros(k)
    z, z_old = np.zeros(k), np.zeros(k)
    state = np.zeros(k, np.int64)
    v_mid = np.zeros(nb)
    _project(side1, side2, x, y)
    for i in range(k):
        z[i] = y[rows[i, 1]]
    copy_into(z_old, z)
    evaluate(y, z_old, rows, props, lam, N_, F, z, state)
    copy_into(lam_eq, lam)
    _record(x, y, N_, F, state, tip, props, e, 0, r_tip, r_N, r_F, r_r, r_state)
    iterations, unconverged = 0, 0
    s1, c1 = 0.0, 1.0
    for i in range(steps):
        s0, c0 = s1, c1
        s1, c1 = math.sin(w_e * (i + 1) * dt), math.cos(w_e * (i + 1) * dt)
        for j in range(N):                  # q_pred, blade by blade
            for r in range(nb):
                acc = Sfc[j, r] + s1 * Sfs[j, r] + c1 * Sfk[j, r]
                for l in range(3 * nb):
                    acc += A[j, r, l] * x[j, l]
                xn[j, r] = acc
        if k > 0:
            copy_into(z_old, z)
            if i >= window:
                copy_into(F_old, F)
                copy_into(N_old, N_)
                copy_into(y_old, y)
            if implicit:                    # the law at t + dt, every interface at once
                _project(side1, side2, xn, y_pred)
                it, ok = solve_contact(y_pred, Cc, z_old, rows, props, y, lam, N_, F, z, state, ws)
                iterations = max(iterations, it)
                if not ok:
                    unconverged += 1
            copy_into(lam_step, lam)
            for j in range(N):              # q_j += S_j (side2_j^T lam_j - side1_j^T lam_j-1)
                p = (j - 1 + N) % N
                for r in range(nb):
                    acc = 0.0
                    for l in range(c):
                        acc += Phi2[j, r, l] * lam_step[j * c + l] - Phi1[j, r, l] * lam_step[p * c + l]
                    xn[j, r] += acc
            if not implicit:                # explicit: the law at t + dt is the next step's force
                _project(side1, side2, xn, y)
                evaluate(y, z_old, rows, props, lam, N_, F, z, state)
        for j in range(N):
            for r in range(nb):
                an = a0 * (xn[j, r] - x[j, r]) - a2 * x[j, nb + r] - a3 * x[j, 2 * nb + r]
                xn[j, 2 * nb + r] = an
                xn[j, nb + r] = x[j, nb + r] + dt * ((1.0 - gamma) * x[j, 2 * nb + r] + gamma * an)
        if i == window:
            copy_into(snap, x.ravel())
            energy[4] = contact_energy(N_old, F_old, props)
        if i >= window:
            w_in, d_damp, w_c = 0.0, 0.0, 0.0
            for j in range(N):
                for r in range(nb):
                    w_in += (xn[j, r] - x[j, r]) * (fc[j, r] + 0.5 * (s0 + s1) * fs[j, r]
                                                    + 0.5 * (c0 + c1) * fk[j, r])
                    v_mid[r] = 0.5 * (x[j, nb + r] + xn[j, nb + r])
                for r in range(nb):
                    acc = 0.0
                    for l in range(nb):
                        acc += C[j, r, l] * v_mid[l]
                    d_damp += dt * v_mid[r] * acc
            for l in range(m):
                w_c += (y[l] - y_old[l]) * 0.5 * (lam_eq[l] + lam_step[l])
            energy[0] += w_in
            energy[1] += d_damp
            energy[2] += friction_dissipation(F_old, F, z_old, z)
            energy[3] += w_c
        copy_into(lam_eq, lam_step)
        for j in range(N):
            for r in range(3 * nb):
                x[j, r] = xn[j, r]
        _record(x, y, N_, F, state, tip, props, e, i + 1, r_tip, r_N, r_F, r_r, r_state)
        for j in range(N):
            for s in range(2):
                value = r_tip[i + 1, j, s]
                if not math.isfinite(value):
                    return i + 1, NOT_FINITE, iterations, unconverged
                if abs(value) > bound:
                    return i + 1, UNBOUNDED, iterations, unconverged
    energy[5] = contact_energy(N_, F, props)
    return steps, OK, iterations, unconverged


@njit(cache=True, _nrt=False, inline="always")
def _record(x, y, N_, F, state, tip, props, e, i, r_tip, r_N, r_F, r_r, r_state):
    """Row i: each blade's tip and each interface's totals (its e points), weighted mean r, state."""
    nb = tip.shape[2]
    for j in range(tip.shape[0]):
        for s in range(2):
            acc = 0.0
            for l in range(nb):
                acc += tip[j, s, l] * x[j, l]
            r_tip[i, j, s] = acc
        n_sum, f_sum, r_sum, w_sum, st = 0.0, 0.0, 0.0, 0.0, 0
        for p in range(j * e, (j + 1) * e):
            n_sum += N_[p]
            f_sum += F[p]
            w = props[p, 1]                 # the point's kn: its weight times the interface's
            r_sum += w * y[2 * p + 1]
            w_sum += w
            if state[p] == SLIP:
                st = SLIP
            elif state[p] == STICK and st == 0:
                st = STICK
        r_N[i, j], r_F[i, j], r_state[i, j] = n_sum, f_sum, st
        r_r[i, j] = r_sum / w_sum if w_sum > 0.0 else 0.0


def integrate_ring(ring: BladeRing, law: ContactLaw, scheme: NewmarkScheme, steps: int, implicit: bool = True,
                   energy_window: int | None = None, bound: float = math.inf, held: tuple[int, ...] = (),
                   q0: np.ndarray | None = None, v0: np.ndarray | None = None,
                   a0: np.ndarray | None = None) -> RingTrajectory:
    """Integrate ``steps`` Newmark steps of the ring with the interfaces' contact ``law`` (paper Eq. 9).

    ``law``: the law on ``ring.contact()`` (its elements interface by
    interface). ``held``: blades held still. ``q0, v0, a0``: the initial
    state, (N, nb) each (default zero, as the paper). ``energy_window``,
    ``bound``: as shroud.core.newmark.integrate.
    """
    t_start = time.perf_counter()
    N, nb = ring.count, ring.blade_dofs
    step = factorize(ring, scheme, held)
    f_const, f_sin, f_cos = ring.loads()
    c0, _, c2, c3 = scheme.coefficients()[:4]
    M = np.array([dense(b.M) for b in ring.blades])
    C = np.array([dense(b.C) for b in ring.blades])
    K = np.array([dense(b.K) for b in ring.blades])
    x = np.zeros((N, 3 * nb))
    for part, init in enumerate((q0, v0, a0)):
        if init is not None:
            x[:, part * nb:(part + 1) * nb] = init
    x[list(held)] = 0.0
    window = steps - energy_window if energy_window else steps + 1
    r_tip = np.zeros((steps + 1, N, 2))
    r_N, r_F, r_r = np.zeros((steps + 1, N)), np.zeros((steps + 1, N)), np.zeros((steps + 1, N))
    r_state = np.zeros((steps + 1, N), np.int8)
    energy, snap = np.zeros(6), np.zeros(N * 3 * nb)
    e = ring.weight.size
    done, status, iterations, unconverged = _ring_kernel(
        step.A, step.S, f_const, f_sin, f_cos, ring.side1, ring.side2, step.Phi1, step.Phi2, step.Cc, M, C,
        ring.tip(), law.rows, law.props, e, float(ring.omega_e), scheme.dt, scheme.gamma, c0, c2, c3, steps,
        implicit, bound, window, x, r_tip, r_N, r_F, r_r, r_state, energy, snap, step.contact_workspace(law))
    balance = None
    if status == OK and energy_window:
        s = snap.reshape(N, 3 * nb)

        def mechanical(state):
            q, v = state[:, :nb], state[:, nb:2 * nb]
            return (0.5 * float(np.einsum("ja,jab,jb->", v, M, v)),
                    0.5 * float(np.einsum("ja,jab,jb->", q, K, q)))
        (kin0, str0), (kin1, str1) = mechanical(s), mechanical(x)
        balance = EnergyBalance(start_step=window, end_step=steps, input_work=float(energy[0]),
                                damping=float(energy[1]), friction=float(energy[2]),
                                kinetic_change=kin1 - kin0, strain_change=str1 - str0,
                                contact_change=float(energy[5] - energy[4]), contact_work=float(energy[3]))
    cause = divergence_cause(status, done, scheme.dt, bound)
    if unconverged:
        warn(f"the ring's contact solve did not settle in {unconverged} of {done} steps "
             "(element states kept cycling); results near those steps are approximate")
    sl = slice(0, done + 1)
    return RingTrajectory(dt=scheme.dt, steps=int(done), tip=r_tip[sl], normal=r_N[sl], friction=r_F[sl],
                          slip=r_r[sl], state=r_state[sl], energy=balance, contact_iterations=int(iterations),
                          contact_unconverged=int(unconverged), diverged=cause,
                          elapsed_s=time.perf_counter() - t_start, q=x[:, :nb].copy(),
                          v=x[:, nb:2 * nb].copy(), a=x[:, 2 * nb:].copy())
