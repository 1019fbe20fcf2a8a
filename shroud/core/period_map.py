"""Floquet multipliers of a periodic state from the period map of the project's own Newmark integrator.

The integrator (shroud.core.newmark, average acceleration, the contact law
solved implicitly at each step) maps its state at t = 0,

    s = (q, q', z_h),

displacements q (m), velocities q' (m/s) and the positions z_h (m) of the
friction sliders that carry a history (shroud.core.contact), to its state one
excitation period T = 2 pi / omega_e later, P(s) (``steps`` steps of
dt = T / steps; the excitation f_aero sin(omega_e t) restarts at t = 0 each
period). The acceleration is not a state of its own: after any step it
satisfies the motion's equation, M q'' = f - C q' - K q + W^T lam(W q, z)
(paper Eq. 9), and a period is started with that one
(:func:`equilibrium_acceleration`).

A periodic state of the integrator is a fixed point, P(s) = s, found by
Newton from a harmonic-balance state (shooting, :func:`periodic_state`); the
eigenvalues of dP/ds there are its Floquet multipliers. dP/ds is formed by
central differences, each column from two period maps started at s +- h_j
e_j. Nothing of the contact's events (touch, separation, stick, slip) is
linearized by hand: the perturbed runs meet them as the integrator does.
The law is piecewise linear, so P is continuous and piecewise affine with
pieces about as wide as a step's worth of event shift; the perturbations h
are set well above that (PERTURBATION of each component's range over the
period), so that the differences see the events' shift (e.g. a slider's
captured position moving with the instant of touching) and not one piece's
slope. The error of the largest |multiplier| (:func:`period_map_stability`)
is the larger of its change when h is divided by PERTURBATION_RATIO and its
change at twice the steps a period.

A slider stuck all period holds an arbitrary position: the orbit has a
neutral family and a multiplier exactly 1 in that direction. Such sliders
are held fixed (not part of s), as the time-domain monodromy
(shroud.core.floquet) leaves them out; sliders never stuck are slaved to the
blade and add nothing either, but are kept (their multiplier is 0).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from shroud.core import floquet
from shroud.core.contact import STICK, ContactLaw, evaluate
from shroud.core.linear_solvers import dense
from shroud.core.newmark import Motion, NewmarkScheme, Trajectory, integrate
from shroud.core.system import StructuralSystem
from shroud.core.verdict import NOT_DECIDED, Verdict

PERTURBATION = 0.02          # h_j: this share of component j's range over the period (see the module's note)
PERTURBATION_RATIO = 4.0     # the second perturbation, h / 4: the differences' own error
SHOOTING_TOL = 1e-6          # max |P(s) - s| / range at the periodic state (HB starts 1e-2 off: ample)
SHOOTING_ITERATIONS = 12


def equilibrium_acceleration(system: StructuralSystem, law: ContactLaw, q: np.ndarray, v: np.ndarray,
                             z: np.ndarray, t: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """(q'' m/s^2, sliders z m after the law's return mapping) satisfying the motion's equation at time
    ``t`` (paper Eq. 9): M q'' = f_const + f_aero sin(omega_e t) - C q' - K q + W^T lam(W q, z)."""
    f = system.f_const + math.sin(system.omega_e * t) * system.f_aero - system.C @ v - system.K @ q
    z_new = np.array(z, dtype=float)
    if law.count:
        W = dense(system.contact.W)
        lam, N, F = np.zeros(law.m), np.zeros(law.count), np.zeros(law.count)
        state = np.zeros(law.count, np.int64)
        evaluate(W @ q, np.array(z, dtype=float), law.rows, law.props, lam, N, F, z_new, state)
        f = f + W.T @ lam
    return np.linalg.solve(dense(system.M), f), z_new


@dataclass(frozen=True)
class PeriodMap:
    """P: the integrator's state at t = 0 to its state one period later, ``steps`` steps a period.

    ``held``: the elements whose sliders are held (stuck all period), ``held_z`` their positions (m);
    the state s = (q, q', z of the other elements)."""

    system: StructuralSystem
    law: ContactLaw
    steps: int
    held: np.ndarray
    held_z: np.ndarray

    @property
    def free(self) -> np.ndarray:
        return np.setdiff1d(np.arange(self.law.count), self.held)

    def sliders(self, s: np.ndarray) -> np.ndarray:
        z = np.empty(self.law.count)
        z[self.free] = s[2 * self.system.dofs:]
        z[self.held] = self.held_z
        return z

    def run(self, s: np.ndarray, periods: int = 1) -> Trajectory:
        """The integrator from the state ``s`` over ``periods`` periods (the last one's element shares)."""
        n = self.system.dofs
        q, v = s[:n], s[n:2 * n]
        a, z = equilibrium_acceleration(self.system, self.law, q, v, self.sliders(s))
        return integrate(self.system, self.law, NewmarkScheme(2 * math.pi / self.system.omega_e / self.steps),
                         self.steps * periods, q0=q, v0=v, acc0=a, z0=z, energy_window=self.steps)

    def __call__(self, s: np.ndarray) -> np.ndarray:
        end = self.run(s).end
        if end is None:
            raise FloatingPointError("the integrator diverged within one period from the state")
        return self.state(end)

    def state(self, motion: Motion) -> np.ndarray:
        return np.concatenate([motion.q, motion.v, motion.z[self.free]])

    def jacobian(self, s: np.ndarray, h: np.ndarray) -> np.ndarray:
        """dP/ds at ``s`` by central differences, column j over s +- h_j e_j."""
        J = np.empty((s.size, s.size))
        for j in range(s.size):
            e = np.zeros(s.size)
            e[j] = h[j]
            J[:, j] = (self(s + e) - self(s - e)) / (2 * h[j])
        return J


def period_map(system: StructuralSystem, law: ContactLaw, steps: int, q: np.ndarray, v: np.ndarray,
               z: np.ndarray) -> tuple[PeriodMap, np.ndarray]:
    """The period map of ``system`` at ``steps`` steps a period about the state (q, q', z) at t = 0, and
    that state as its s: the sliders that stick over the whole first period from it are held."""
    free_all = PeriodMap(system, law, steps, np.zeros(0, np.int64), np.zeros(0))
    s = np.concatenate([q, v, z])
    share = free_all.run(s).element_share
    held = np.flatnonzero(share[:, STICK] == 1.0) if law.count else np.zeros(0, np.int64)
    pm = PeriodMap(system, law, steps, held, np.asarray(z, dtype=float)[held])
    return pm, np.concatenate([q, v, np.asarray(z, dtype=float)[pm.free]])


def periodic_state(pm: PeriodMap, s0: np.ndarray, scale: np.ndarray) -> tuple[np.ndarray, np.ndarray, float]:
    """Newton on P(s) = s from ``s0`` (shooting): (the periodic state, dP/ds there, max |P(s) - s| / ``scale``
    where it stopped: above SHOOTING_TOL, none found). The Jacobian is taken with h = PERTURBATION ``scale``
    (:meth:`PeriodMap.jacobian`) at the start and again at the end; a step that does not lower the
    defect is halved (P is piecewise affine: a full step can cross into another piece)."""
    def defect_at(x):
        r = pm(x) - x
        return r, float(np.max(np.abs(r) / scale))
    s = s0.copy()
    J = pm.jacobian(s, PERTURBATION * scale)
    r, defect = defect_at(s)
    for _ in range(SHOOTING_ITERATIONS):
        if defect <= SHOOTING_TOL:
            break
        step = np.linalg.solve(J - np.eye(s.size), r)
        for _ in range(6):
            try:
                r_new, d_new = defect_at(s - step)
            except FloatingPointError:
                d_new = math.inf
            if d_new < defect:
                break
            step = step / 2
        else:
            break
        s, r, defect = s - step, r_new, d_new
    return s, pm.jacobian(s, PERTURBATION * scale), defect


@dataclass(frozen=True)
class PeriodMapStability:
    """Multipliers of the integrator's own periodic state (largest modulus first) and their error.

    ``distance``: how far the integrator's periodic state lies from the start (harmonic balance's),
    max over components of |s - s0| / range; ``defect``: |P(s) - s| / range where shooting stopped
    (above SHOOTING_TOL: no periodic state found, the error infinite); ``error``: the largest
    |multiplier|'s change at h / PERTURBATION_RATIO and at 2 ``steps``."""

    multipliers: np.ndarray
    error: float
    steps: int
    distance: float
    defect: float
    finite_difference_change: float
    step_change: float

    @property
    def largest(self) -> float:
        return float(np.abs(self.multipliers).max(initial=0.0))

    @property
    def stable(self) -> bool | None:
        return floquet.verdict(self.largest, self.error)


def _largest(J: np.ndarray) -> float:
    return float(np.abs(np.linalg.eigvals(J)).max(initial=0.0))


def state_scale(q: np.ndarray, v: np.ndarray, z: np.ndarray) -> np.ndarray:
    """Each component's range over the period (rows: samples), floored at 1e-3 of its kind's largest
    (a component that hardly moves is perturbed on its kind's scale)."""
    parts = []
    for x in (q, v, z):
        r = x.max(axis=0) - x.min(axis=0) if x.size else np.zeros(x.shape[1])
        parts.append(np.maximum(r, 1e-3 * max(r.max(initial=0.0), 1e-300)))
    return np.concatenate(parts)


def period_map_stability(system: StructuralSystem, law: ContactLaw, steps: int,
                         samples: tuple[np.ndarray, np.ndarray, np.ndarray]) -> PeriodMapStability:
    """The Floquet multipliers of the integrator's periodic state nearest the orbit ``samples`` = (q, q', z)
    at instants over the period (rows; row 0 at t = 0, the start; e.g. a harmonic-balance orbit's,
    shroud.core.harmonic_balance.orbit_samples), ``steps`` steps a period, with their error
    (:class:`PeriodMapStability`; the scales of the perturbations: :func:`state_scale`)."""
    q, v, z = samples
    results = []
    for k in (steps, 2 * steps):
        pm, s0 = period_map(system, law, k, q[0], v[0], z[0])
        scale = state_scale(q, v, z[:, pm.free])
        results.append((pm, s0, scale, *periodic_state(pm, s0, scale)))
    pm, s0, scale, s, J, defect = results[0]
    fine = results[1]
    fd = abs(_largest(pm.jacobian(s, PERTURBATION / PERTURBATION_RATIO * scale)) - _largest(J))
    dt = abs(_largest(fine[4]) - _largest(J))
    found = max(defect, fine[5]) <= SHOOTING_TOL
    mult = np.linalg.eigvals(J)
    return PeriodMapStability(multipliers=mult[np.argsort(-np.abs(mult))], error=max(fd, dt) if found else math.inf,
                              steps=steps, distance=float(np.max(np.abs(s - s0) / scale)), defect=defect,
                              finite_difference_change=fd, step_change=dt)


def combined(orbit: floquet.Stability, integrator: PeriodMapStability | None) -> tuple[bool | None, str]:
    """One verdict from two ways (stable True, unstable False, undecided None) and why:
    the time-domain monodromy along the harmonic-balance orbit (``orbit``, shroud.core.floquet) and the
    period map of the integrator's own periodic state beside it (``integrator``; None: not taken).

    Where both decide and disagree the point is undecided, with the reason. Where one decides and the
    other lies within its error of the unit circle, the deciding one stands (the period map's error
    holds the step size's and the differences'; the monodromy's the sampling's and the truncation's).
    The two measured on the 1 um gap branch (docs/hb-stability.md): the same side everywhere both decide.
    """
    a = orbit.stable
    if integrator is None:
        return a, ""
    b = integrator.stable
    if a is not None and b is not None and a != b:
        return None, (f"the two ways disagree: the monodromy along the harmonic-balance orbit gives "
                      f"|multiplier| {orbit.largest:.3f} +- {orbit.error:.3f}, the integrator's period map "
                      f"{integrator.largest:.3f} +- {integrator.error:.3f}")
    if a is None and b is not None:
        return b, (f"the monodromy along the orbit is undecided (|multiplier| {orbit.largest:.3f} +- "
                   f"{orbit.error:.3f}); the integrator's period map decides ({integrator.largest:.3f} +- "
                   f"{integrator.error:.3f})")
    return a, ""


@dataclass(frozen=True)
class InTime:
    """Whether the integrator started on a state stays on it (:func:`check_in_time`): ``distance``, the
    verdict ("stays" / "leaves") of the largest distance of the period-sampled state from the start over
    the last periods, ``drift``, the verdict ("settled" / "drifts") of the largest change from one period
    to the next there, and the distances after each period. ``answer``: "leaves" where either says so (a
    run that drifts has left the periodic state, for a torus beside it if not farther), "stays" where
    both say stays and settled, else not decided."""

    distance: Verdict
    drift: Verdict
    distances: np.ndarray

    @property
    def answer(self):
        if self.distance.answer == "leaves" or self.drift.answer == "drifts":
            return "leaves"
        if self.distance.answer == "stays" and self.drift.answer == "settled":
            return "stays"
        return NOT_DECIDED

    def sentence(self) -> str:
        return f"{self.answer}: distance {self.distance.sentence()}; drift {self.drift.sentence()}"

    def to_json(self) -> dict:
        return {"answer": self.answer, "distance": self.distance.to_json(), "drift": self.drift.to_json(),
                "first_period": float(self.distances[0]), "last_period": float(self.distances[-1]),
                "periods": int(self.distances.size)}


STAY_THRESHOLD = 0.1    # the distance (energy norm, relative to the orbit's) between staying and leaving
STAY_MARGIN = 3.0       # times the first period's distance: the integrator's own periodic state's offset
# The change from one period to the next at the end of a run: on the 1 um gap branch (H 10, 256 steps,
# 200 periods) 5e-14 to 6e-4 where it settles on a P1 state (6e-4 at |multiplier| 0.993, slowly), 0.038-0.10
# where it circles a torus beside an unstable state (10181-10431 r/min) within 0.05-0.10 of the start.
DRIFT_THRESHOLD, DRIFT_MARGIN = 0.01, 0.005


def energy_scale(system: StructuralSystem, q: np.ndarray, v: np.ndarray) -> float:
    """The orbit's size in the energy norm: max over the samples (rows) of
    sqrt((q - mean q)^T K (q - mean q) + q'^T M q'), sqrt(J)."""
    K, M = dense(system.K), dense(system.M)
    dq = q - q.mean(axis=0)
    return float(np.sqrt(np.max(np.einsum("ti,ij,tj->t", dq, K, dq) + np.einsum("ti,ij,tj->t", v, M, v))))


def check_in_time(system: StructuralSystem, law: ContactLaw, steps: int,
                  samples: tuple[np.ndarray, np.ndarray, np.ndarray], periods: int = 100) -> InTime:
    """Start the integrator (``steps`` steps a period) on the orbit's state at t = 0 (``samples`` as
    :func:`period_map_stability`'s) and run ``periods`` periods: does the state stay or leave?

    The distance after each period is that of the period-sampled state from the start in the energy
    norm, sqrt(dq^T K dq + dq'^T M dq'), relative to the orbit's (:func:`energy_scale`). Its verdict reads
    the largest over the last tenth of the periods against STAY_THRESHOLD, with a margin of STAY_MARGIN
    times the first period's; the drift's, the largest change from one period to the next there against
    DRIFT_THRESHOLD (:class:`InTime`: a run that circles a torus near the start has not stayed). The
    start is harmonic balance's state and a run that stays settles on the integrator's own periodic state
    beside it: on the 1 um gap branch (H 10, 256 or 512 steps a period) that offset is 0.007-0.016, and
    runs that leave reach 0.2-0.48 (docs/hb-stability.md)."""
    q, v, z = samples
    pm, s = period_map(system, law, steps, q[0], v[0], z[0])
    n, scale = system.dofs, energy_scale(system, q, v)
    K, M = dense(system.K), dense(system.M)
    start, distances, changes = s.copy(), np.full(periods, np.inf), np.full(periods, np.inf)

    def norm(d):
        return math.sqrt(d[:n] @ K @ d[:n] + d[n:2 * n] @ M @ d[n:2 * n]) / scale
    for k in range(periods):
        try:
            s, before = pm(s), s
        except FloatingPointError:
            break
        distances[k], changes[k] = norm(s - start), norm(s - before)
    tail = max(periods // 10, 1)
    last = distances[-tail:]
    margin = STAY_MARGIN * distances[0] if math.isfinite(distances[0]) else math.inf
    finite = bool(np.all(np.isfinite(distances)))
    value = float(np.max(last)) if finite else 1e300              # a run that diverged left
    run = f"the integrator started on the state, {periods} periods of {steps} steps"
    distance = Verdict.of(value, STAY_THRESHOLD, margin, below="stays", above="leaves",
                          reason=(f"{run}: the largest distance of its period-sampled state from the start over "
                                  f"the last {tail} (energy norm, relative to the orbit's) against "
                                  f"{STAY_THRESHOLD:g}, margin {STAY_MARGIN:g} x the first period's (the "
                                  "integrator's own periodic state's offset from the start)"))
    drift = Verdict.of(float(np.max(changes[-tail:])) if finite else 1e300, DRIFT_THRESHOLD, DRIFT_MARGIN,
                       below="settled", above="drifts",
                       reason=(f"{run}: the largest change of the period-sampled state from one period to the "
                               f"next over the last {tail} (relative, as the distance) against "
                               f"{DRIFT_THRESHOLD:g} +- {DRIFT_MARGIN:g}: settled runs 5e-14 to 6e-4, runs "
                               "circling a torus 0.04-0.10 (1 um gap, docs/hb-stability.md)"))
    return InTime(distance=distance, drift=drift, distances=distances)
