"""Steady-state amplitude over speed by harmonic balance with continuation (paper Figs. 4, 7, 11-17).

The frequency-domain counterpart of shroud.analysis.sweep: the periodic
steady state of a registered model is followed in the rotation speed by
pseudo-arclength continuation (shroud.core.continuation) of the harmonic
balance (shroud.core.harmonic_balance), and each point gets its Floquet
multipliers (shroud.core.floquet). Every speed-dependent term is the
model's own: at each speed the corrector asks for the system the model's
builder makes there (K_c, K_s in Omega^2, G in Omega, Rayleigh damping
from the frequencies at that speed, the excitation ke Omega, the
centrifugal load), exactly as the time-domain sweep does; the parameter
derivative of the linear part is a central difference in the speed.
"""

from __future__ import annotations

import dataclasses
import math
import time
from dataclasses import dataclass
from typing import Callable

import numpy as np

from shroud.analysis.api import build_system
from shroud.analysis.transient import contact_law_for
from shroud.base.errors import InputError, RunDiverged
from shroud.base.log import Progress, warn
from shroud.base.resources import in_words, physical_memory
from shroud.analysis.checks import MEMORY_SHARE
from shroud.analysis.systems import solver
from shroud.core import floquet, period_map, registry
from shroud.core import harmonic_balance as hb
from shroud.core.continuation import Branch, Factorize, continue_branch
from shroud.core.linear_solvers import dense
from shroud.core.newmark import NewmarkScheme, integrate
from shroud.core.results import HBResult
from shroud.core.starts import fixed_neighbours, sector_solve
from shroud.core.signals import detect_period
from shroud.core.system import StructuralSystem
from shroud.core.verdict import with_rounding
from shroud.params import Parameters

DEFAULT_HARMONICS = 10
MIN_POINTS = 30            # at least this many points on a branch (bounds the speed step)


def check_inputs(H: int, samples: int | None, rpm_from: float, rpm_to: float) -> int:
    """Validate the harmonic-balance options; returns the number of time samples to use."""
    if H < 1:
        raise InputError("--harmonics", f"{H} is out of range; allowed: an integer >= 1")
    n = hb.default_samples(H) if samples is None else samples
    if n < 2 * H + 1:
        raise InputError("--samples", f"{n} time samples cannot resolve {H} harmonics; "
                                      f"allowed: at least 2 H + 1 = {2 * H + 1}")
    if not 0 < rpm_from < rpm_to:
        raise InputError("--rpm-from", f"{rpm_from:g} .. {rpm_to:g}: allowed: 0 < rpm-from < rpm-to")
    need, memory = 8.0 * n * (2 * H + 1), physical_memory()    # one sampled Fourier basis, samples x (2H + 1)
    if need > MEMORY_SHARE * memory:
        raise InputError("--harmonics" if samples is None else "--samples",
                         f"{H} harmonics at {n} samples a period need a {in_words(need)} Fourier basis before any "
                         f"point, more than {MEMORY_SHARE:.0%} of this machine's {in_words(memory)}; allowed: a basis "
                         f"within {in_words(MEMORY_SHARE * memory)} (the default H is {DEFAULT_HARMONICS})")
    return n


class SpeedModel:
    """The model's linear part at any speed, with its harmonic-balance operators (memoized by speed).

    ``build(rpm)`` gives the model's system at a speed. Where it also offers
    ``harmonics(rpm, H)`` (the linear part per harmonic without a system:
    reduced_model.system.BeamOverSpeed; None where it has none to give) the
    corrector's iterates use that, and a system is built only where one is
    asked for (a converged point's stability).

    The speed derivative of the linear part is a forward difference over
    ``step`` times the speed, taken afresh only when the speed has moved by
    more than ``reuse`` (relative) since it was last taken: a corrector's
    iterates and the tangent at its converged point then share the
    predictor's (the derivative changes by ~``reuse`` of itself over that
    distance; the equations solved, R = 0, are exact). (The beams' exact
    derivative, from the factors of their condensation, was tried: it cost
    as much as the second build it saved.)
    """

    MEMO = 64        # speeds kept (a corrector's iterates, the derivative's neighbours)

    def __init__(self, build: Callable[[float], StructuralSystem], H: int, condense: bool | None = None,
                 step: float = 1e-6, reuse: float = 1e-3):
        self.build, self.H, self.condense = build, H, condense
        self.step, self.reuse = step, reuse
        self._harmonics = getattr(build, "harmonics", None) if condense is not False else None
        self._linear: dict[float, tuple] = {}
        self._systems: dict[float, StructuralSystem] = {}
        self._derivative: tuple | None = None      # (rpm, dL/drpm, dF/drpm flat) taken last
        self._refined: SpeedModel | None = None

    def system(self, rpm: float) -> StructuralSystem:
        return self._kept(self._systems, rpm, self.build)

    def linear(self, rpm: float) -> tuple[hb.LinearHarmonics, np.ndarray, np.ndarray]:
        """(LinearHarmonics, L, F flat) at ``rpm``."""
        return self._kept(self._linear, rpm, self._linear_at)

    def _linear_at(self, rpm: float) -> tuple[hb.LinearHarmonics, np.ndarray, np.ndarray]:
        lin = None if self._harmonics is None else self._harmonics(rpm, self.H)
        if lin is None:
            lin = hb.linear_harmonics(self.system(rpm), self.H, self.condense)
        return lin, lin.L, lin.Fr.ravel()

    def _kept(self, store: dict, rpm: float, make: Callable):
        """``make(rpm)``, kept in ``store`` (cleared beyond MEMO speeds)."""
        got = store.get(rpm)
        if got is None:
            if len(store) > self.MEMO:
                store.clear()
            got = store[rpm] = make(rpm)
        return got

    def derivative(self, rpm: float) -> tuple[np.ndarray, np.ndarray]:
        """(dL/drpm, dF/drpm flat) near ``rpm`` (within ``reuse``)."""
        if self._derivative is None or abs(rpm - self._derivative[0]) > self.reuse * rpm:
            _, L, F = self.linear(rpm)
            h = self.step * rpm
            _, Lp, Fp = self.linear(rpm + h)
            self._derivative = (rpm, (Lp - L) / h, (Fp - F) / h)
        return self._derivative[1], self._derivative[2]

    def at(self, rpm: float):
        """(system, LinearHarmonics, L, F flat) at ``rpm``."""
        return (self.system(rpm), *self.linear(rpm))

    def refined(self) -> "SpeedModel":
        """The same model with twice the harmonics (kept: a branch's truncation checks share it), its
        systems shared with this one's."""
        if self._refined is None:
            self._refined = SpeedModel(self.build, 2 * self.H, self.condense, self.step, self.reuse)
            self._refined._systems = self._systems
        return self._refined


def residual_in_speed(speeds: SpeedModel, law, basis: hb.Fourier):
    """R(X, rpm), dR/dX (analytic through the law) and, on demand, dR/drpm = dL/drpm X - dF/drpm (the law
    does not depend on the speed; SpeedModel.derivative)."""

    def residual(X, rpm):
        lin, L, F = speeds.linear(rpm)
        b = hb.balance(X, lin, law, basis, L, F.reshape(basis.nh, lin.nx))
        residual.last = (X, rpm, b)

        def d_rpm():
            dL, dF = speeds.derivative(rpm)
            return dL @ X - dF
        return b.R, b.J, d_rpm
    residual.last = None       # (X, rpm, Balance) of the latest evaluation: a converged point's own
    return residual


def point_details(speeds: SpeedModel, law, basis: hb.Fourier, X: np.ndarray, rpm: float,
                  evaluated: tuple | None = None, previous: dict | None = None, stability: bool = True) -> dict:
    """Amplitudes, spectral tail and Floquet multipliers (with their error) of a converged point.

    ``evaluated``: (X, rpm, Balance) of the latest evaluation of the residual; used where it is of this
    very point (continuation returns the points its correctors evaluated last, not a step beyond).
    ``previous``: the details of the branch's previous point (its 2 H state starts this point's where
    Newton fails from this point's own harmonics, :func:`refined_point`).
    ``stable`` is True, False or None (within the multipliers' error: floquet.Stability). The error of
    the largest |multiplier| is the largest of its sampling error (floquet.sampling_error) and its change
    when the point is solved again with twice the harmonics (:func:`refined_point`): the truncation can
    decide a point's stability (1 um gap, alpha 30 deg, mu 0.3, 6000 r/min: |multiplier| 2.47 at H 10,
    0.62 at H 20, 0.68 at H 30, where a run from rest settles on the state). ``amplitude_error``: the
    v_L amplitude's change there (m). ``X``, ``refined_X``: the point's harmonics and its 2 H ones (None
    where Newton found no 2 H state: the error is then infinite, the point undecided).
    ``stability=False``: no multipliers, no 2 H solve (stable None, errors nan; a branch's amplitudes only).
    The verdict is checked against the integrator's own dynamics (:func:`integrator_check`):
    ``period_map_multiplier``, ``period_map_error``, ``in_time`` and ``stability_reason`` say how.
    """
    system, lin, L, F = speeds.at(rpm)
    if evaluated is not None and evaluated[1] == rpm and np.array_equal(evaluated[0], X):
        b = evaluated[2]
    else:
        b = hb.balance(X, lin, law, basis, L, F.reshape(basis.nh, lin.nx), jacobian=False)
    tip = lin.tip(X.reshape(basis.nh, lin.nx), b.contact.Lam)
    amp = hb.amplitude_over_period(tip)
    shape = {"amplitude_v_L": float(amp[0]), "amplitude_w_L": float(amp[1]),
             "tail": hb.spectral_tail(b.contact.lam, basis.H), "force_rms": float(np.std(b.contact.lam)), "X": X}
    if not stability:
        return {**shape, "multipliers": np.array([np.nan]), "multiplier_error": math.nan, "grazing": 0,
                "stable": None, "amplitude_error": math.nan, "refined_X": None, **UNCHECKED}
    st = orbit_stability(system, law, X.reshape(basis.nh, lin.nx) @ lin.Wx.T, basis, b.contact)
    near = None if previous is None or previous["refined_X"] is None else (previous["X"], previous["refined_X"])
    refined = refined_point(speeds, law, basis, X, rpm, near)
    st = st.truncated(None if refined is None else refined[1])
    amplitude_error = float("nan") if refined is None else abs(refined[0] - float(amp[0]))
    refined_X = None if refined is None else refined[2]
    return {**shape, "multipliers": st.multipliers, "multiplier_error": st.error, "grazing": st.grazing,
            "amplitude_error": amplitude_error, "refined_X": refined_X,
            **integrator_check(system, law, lin, X, basis, st)}


# The integrator's period map is taken where the monodromy along the orbit puts the largest |multiplier| at
# or beyond 1 - PERIOD_MAP_BAND (on the 1 um gap branch, 5000-30000 r/min, where both decide: 0.015 apart
# (median), 0.133 at most, never on opposite sides; a point well inside needs no second way), on systems
# whose state (2 n + sliders) is at most PERIOD_MAP_MAX_STATES: its differences take 2 periods a state
# component, some 5 Jacobians a point. The reduced beam (14): the 1 um branch's 244 points 4.3-4.8 s CPU
# with it, 0.7-0.8 s without (benchmarks/bench_hb_in_time.py); the reduced solid of hb_fig7's quick scene (33 DOF
# and its face nodes' sliders) took 20 s a point, its branches 271 and 770 s against 12 s: left out.
PERIOD_MAP_BAND = 0.2
PERIOD_MAP_STEPS = 256       # the time-domain sweep's default steps a period; the error from 512
PERIOD_MAP_MAX_STATES = 64
IN_TIME_STEPS = PERIOD_MAP_STEPS
IN_TIME_PERIODS = 100
UNCHECKED = {"period_map_multiplier": math.nan, "period_map_error": math.nan, "in_time": None,
             "stability_reason": ""}


def integrator_check(system: StructuralSystem, law, lin: hb.LinearHarmonics, X: np.ndarray, basis: hb.Fourier,
                     st: floquet.Stability) -> dict:
    """The point's verdict from two ways and the integrator started on it (docs/hb-stability.md):
    ``stable`` (True, False, None), ``stability_reason`` (why it is what it is where the second way or the
    time check set it; "" otherwise), ``period_map_multiplier`` / ``period_map_error`` (the largest
    |multiplier| of the integrator's own periodic state beside the orbit and its error,
    shroud.core.period_map; nan where not taken) and ``in_time`` (the check in time's JSON where taken).

    The period map is taken where the monodromy ``st`` is within PERIOD_MAP_BAND of the unit circle or
    beyond, on a :func:`startable` system of at most PERIOD_MAP_MAX_STATES (shroud.core.period_map.combined
    joins the two). A point the two call unstable is then started in time (IN_TIME_PERIODS periods of
    IN_TIME_STEPS steps, shroud.core.period_map.check_in_time): where the integrator stays on it the point
    is undecided, never unstable (near a fold a stable branch runs closer beside it than the check
    resolves)."""
    if (st.largest < 1.0 - PERIOD_MAP_BAND or 2 * system.dofs + law.count > PERIOD_MAP_MAX_STATES
            or not startable(system, lin)):
        return {"stable": st.stable, **UNCHECKED}
    samples = hb.orbit_samples(system, lin, law, X, basis)
    pm = period_map.period_map_stability(system, law, PERIOD_MAP_STEPS, samples)
    stable, reason = period_map.combined(st, pm)
    in_time = None
    if stable is False:
        check = period_map.check_in_time(system, law, IN_TIME_STEPS, samples, IN_TIME_PERIODS)
        in_time = check.to_json()
        if check.answer == "stays":
            stable, reason = None, ("called unstable (|multiplier| {:.3f}), but the integrator started on it stays: "
                                    .format(max(st.largest, pm.largest)) + check.sentence())
    return {"stable": stable, "stability_reason": reason, "period_map_multiplier": pm.largest,
            "period_map_error": pm.error, "in_time": in_time}


REFINED_ITERATIONS = 15    # Newton at 2 H from the point's own harmonics: at most this many iterations


def refined_point(speeds: SpeedModel, law, basis: hb.Fourier, X: np.ndarray, rpm: float,
                  near: tuple[np.ndarray, np.ndarray] | None = None) -> tuple[float, float, np.ndarray] | None:
    """The point ``X`` at ``rpm`` solved again with 2 H harmonics (the same samples where they resolve 2 H):
    (v_L amplitude m, largest |multiplier|, its 2 H harmonics), or None where Newton does not converge.

    Newton starts from the point's own harmonics (the higher ones zero), for at most REFINED_ITERATIONS
    (1 um gap, alpha 30 deg, kt 5e6 N/m, mu 0.3, 5000-25000 r/min, 115 points: of the 104 that converge
    all but one do so within 13 iterations, one in 31; the 11 others stall at |R|/|F| 9e-3 to 0.15 after
    50). Where it fails and ``near`` = (X, X at 2 H) of the branch's previous point is given, from that
    point's 2 H state moved by the step at H (the 2 H branch followed alongside): on that branch every
    point then has its 2 H state, the branch at 0.74 of the CPU (docs/hb-stability.md).
    """
    fine = speeds.refined()
    n = max(basis.samples, 4 * fine.H + 1)
    fine_basis = hb.fourier(fine.H, n)
    system, lin, _, _ = fine.at(rpm)
    own = X.reshape(basis.nh, lin.nx)
    X0 = np.zeros((fine_basis.nh, lin.nx))
    X0[:basis.nh] = own
    sol = hb.newton(X0.ravel(), lin, law, fine_basis, max_iterations=REFINED_ITERATIONS)
    if not sol.converged and near is not None:
        X0 = near[1].reshape(fine_basis.nh, lin.nx).copy()
        X0[:basis.nh] += own - near[0].reshape(basis.nh, lin.nx)
        sol = hb.newton(X0.ravel(), lin, law, fine_basis)
    if not sol.converged:
        return None
    Xf = sol.X.reshape(fine_basis.nh, lin.nx)
    amp = hb.amplitude_over_period(lin.tip(Xf, sol.balance.contact.Lam))
    W = system.contact.W if system.contact is not None else np.zeros((0, system.dofs))
    c = sol.balance.contact
    mult = floquet.orbit_multipliers(system.M, system.C, system.K, W, law, c.state, c.F, system.omega_e,
                                     fine_basis.rates(Xf @ lin.Wx.T, system.omega_e))
    return float(amp[0]), float(np.abs(mult).max(initial=0.0)), sol.X


def orbit_stability(system: StructuralSystem, law, Y: np.ndarray, basis: hb.Fourier,
                    contact: hb.ContactHarmonics | None = None) -> floquet.Stability:
    """Floquet multipliers, with their error, of ``system`` (its M, C, K, W; excitation frequency
    system.omega_e) linearized about the orbit whose contact coordinates have the harmonics ``Y`` (nh, m):
    the law sampled on ``basis`` (``contact``: its evaluation there, if at hand) and on half its instants
    (floquet.orbit_stability)."""
    W = system.contact.W if system.contact is not None else np.zeros((0, system.dofs))
    eye = np.eye(Y.shape[1])
    if contact is None:
        contact = hb.contact_harmonics(Y, eye, law, basis, jacobian=False)
    half = hb.fourier(basis.H, max(basis.samples // 2, 2 * basis.H + 1))
    coarse = hb.contact_harmonics(Y, eye, law, half, jacobian=False)
    return floquet.orbit_stability(system.M, system.C, system.K, W, law, contact.state, contact.F,
                                   system.omega_e, basis.rates(Y, system.omega_e),
                                   (coarse.state, coarse.F, half.rates(Y, system.omega_e)))


def startable(system: StructuralSystem, lin: hb.LinearHarmonics) -> bool:
    """Whether the integrator can be started on this system's harmonic-balance states: dense M, C, K (the
    compiled kernel, the energy norm) and harmonics from which every DOF is rebuilt (a beam's, condensed on
    y or not; not a whole ring's, whose unknowns are its interfaces' coordinates)."""
    return isinstance(system.K, np.ndarray) and (lin.condensed or lin.nx == system.dofs)


def check_in_time(params: Parameters, model: str, result: HBResult, points, periods: int = IN_TIME_PERIODS,
                  build: Callable[[float], StructuralSystem] | None = None) -> list[period_map.InTime]:
    """Start the integrator on the branch points ``points`` (indices into ``result``) and run ``periods``
    periods (``params.time.steps_per_period`` steps each): does each state stay or leave
    (shroud.core.period_map.check_in_time; its ``verdict`` answers "stays", "leaves" or not decided)?
    ``build(rpm)``: the system at a speed where not the registered model's (as :func:`run_hb`)."""
    if result.X is None:
        raise InputError("--method", "the branch holds no harmonics to start the integrator from")
    basis = hb.fourier(result.harmonics, result.samples)
    speeds = SpeedModel(build or model_at_speed(params, model), result.harmonics)
    out = []
    for i in points:
        system, lin, _, _ = speeds.at(float(result.rpm[i]))
        if not startable(system, lin):
            raise InputError("--model", f"{model}: the integrator cannot be started on its harmonic-balance "
                                        "states (it needs dense M, C, K and harmonics of every DOF)")
        law = contact_law_for(system, params.contact)
        samples = hb.orbit_samples(system, lin, law, np.asarray(result.X[i]), basis)
        out.append(period_map.check_in_time(system, law, params.time.steps_per_period, samples, periods))
    return out


def bifurcation_points(result: HBResult) -> list[int]:
    """The branch points on both sides of each of ``result``'s bifurcations (indices, in order, once each):
    where the nominal stability changes between neighbours (shroud.core.floquet.bifurcation)."""
    inside = result.max_multiplier < 1 + floquet.UNIT_CIRCLE_TOL       # floquet.is_stable of each point
    points = set()
    for i in np.flatnonzero(inside[1:] != inside[:-1]) + 1:
        points.update((int(i) - 1, int(i)))
    return sorted(points)


def model_at_speed(params: Parameters, model: str) -> Callable[[float], StructuralSystem]:
    """rpm -> the registered model's system at that speed (its own builder, or its ``at_speed`` hook)."""
    entry = registry.model(model)
    if entry.at_speed is not None:
        return entry.at_speed(params)
    return lambda rpm: entry.build_system(params.updated({"speed.rpm": float(rpm)}))


def run_hb(params: Parameters, model: str, rpm_from: float, rpm_to: float, harmonics: int = DEFAULT_HARMONICS,
           samples: int | None = None, min_points: int | None = None,
           build: Callable[[float], StructuralSystem] | None = None, start: np.ndarray | None = None,
           stability: bool = True, factorize: Factorize | None = None) -> HBResult:
    """The steady-state branch of ``model`` from ``rpm_from`` to ``rpm_to`` (r/min) by harmonic balance.

    ``min_points``: the least number of points on the branch (bounds the
    speed step to (rpm_to - rpm_from) / (min_points - 1)). ``build(rpm)``
    replaces the registered model's system at a speed (raw systems, tests).
    ``start``: the harmonics of a state at ``rpm_from`` the branch goes
    through (default: the one reached from the linear solution, with a load
    homotopy if need be), e.g. a coexisting state found otherwise.
    ``factorize``: a structured factorization of the Jacobian for the continuation's linear solves
    (shroud.core.continuation; a whole ring's: shroud.analysis.ring_hb.whole_ring).
    """
    t0 = time.perf_counter()
    n = check_inputs(harmonics, samples, rpm_from, rpm_to)
    params.updated({"speed.rpm": rpm_to})            # the models' speed bound (shroud.params) holds to the end
    basis = hb.fourier(harmonics, n)
    speeds = SpeedModel(build or model_at_speed(params, model), harmonics)
    system, lin, _, _ = speeds.at(rpm_from)
    law = contact_law_for(system, params.contact)
    residual = residual_in_speed(speeds, law, basis)
    X0 = hb.solve(system, law, harmonics, n).X if start is None else start   # by a load homotopy if need be
    x_scale = branch_scale(params, X0 if start is not None else hb.linear_solution(lin))
    branch, details = follow_branch(
        residual, X0, rpm_from, rpm_to, x_scale, speed_step(rpm_from, rpm_to, min_points), f"HB branch {model}",
        lambda X, rpm, previous: point_details(speeds, law, basis, X, rpm, residual.last, previous, stability),
        factorize)
    if not branch.complete and n < hb.default_samples(harmonics) and "corrector" in (branch.stopped or ""):
        # a coarse sampling turns a smooth fold into a saw-tooth of corners (hb.default_samples): the beam's
        # 1 um gap branch at H 7 stops at 9119.66 r/min among a dozen of them at 256 samples, passes at 512
        branch.stopped += (f"; {n} samples a period, below the default {hb.default_samples(harmonics)}: "
                           "corners crowd where contact switches cross samples, more samples (--samples) "
                           "smooth them")
    return branch_result(branch, details, model=model, harmonics=harmonics, samples=n, dofs=system.dofs,
                         condensed=lin.condensed, elapsed_s=time.perf_counter() - t0)


def branch_scale(params: Parameters, X: np.ndarray) -> float:
    """The unknowns' scale in the arclength (m): the largest coefficient of ``X`` (the linear solution, or a
    given state), or the gap or interference |N0| / kn where larger (1e-7 at least)."""
    gap = abs(params.contact.N0) / params.contact.kn if params.contact.enabled else 0.0
    return max(float(np.abs(X).max()), gap, 1e-7)


def speed_step(rpm_from: float, rpm_to: float, min_points: int | None) -> float:
    """The largest speed step (r/min) of a branch of at least ``min_points`` (MIN_POINTS by default) points."""
    return (rpm_to - rpm_from) / (max(min_points or MIN_POINTS, 2) - 1)


def follow_branch(residual, X0: np.ndarray, rpm_from: float, rpm_to: float, x_scale: float, dp_max: float,
                  label: str, point_at: Callable[[np.ndarray, float, dict | None], dict],
                  factorize: Factorize | None = None) -> tuple[Branch, list[dict]]:
    """The one continuation in speed of every system's harmonic balance (the blade, a tuned ring's
    sector, a whole ring; shroud.core.continuation: corners passed forward, folds located, never
    retracing): the branch of ``residual`` (X, rpm) from X0 at ``rpm_from`` towards ``rpm_to`` (r/min;
    a falling speed as rpm -> -rpm, :func:`run_hb_through`), and the details of each point,
    ``point_at(X, rpm, previous point's details or None)``; ``dp_max`` the largest speed step
    (:func:`speed_step`)."""
    details: list[dict] = []
    progress = Progress(f"{label} {abs(rpm_from):g}-{abs(rpm_to):g} r/min", 1)

    def on_point(X, rpm):
        details.append(point_at(X, rpm, details[-1] if details else None))
        progress.update((rpm - rpm_from) / (rpm_to - rpm_from),       # turning points step back: a share of the range
                        f"{len(details)} points, at {abs(rpm):.0f} r/min, amplitude "
                        f"{details[-1]['amplitude_v_L']:.3g} m")

    branch = continue_branch(residual, X0, rpm_from, rpm_to, x_scale, ds=0.05, ds_max=0.5,
                             dp_max=dp_max, on_point=on_point, factorize=factorize)
    progress.done()
    return branch, details


def branch_result(branch: Branch, details: list[dict], elapsed_s: float, **about) -> HBResult:
    """The HBResult of a continued branch (``about``: model, harmonics, samples, dofs, condensed), its
    corners and folds in r/min."""
    return HBResult.from_points(rpm=branch.p, details=details, iterations=branch.iterations,
                                complete=branch.complete, stopped=branch.stopped, elapsed_s=elapsed_s, X=branch.x,
                                kinks=[{"rpm": k["p"], "turn_rad": k["turn_rad"]} for k in branch.kinks],
                                folds=[{"rpm": f["p"], "kind": f["kind"]} for f in branch.folds], **about)


def run_hb_through(params: Parameters, model: str, X: np.ndarray, rpm: float, rpm_from: float, rpm_to: float,
                   harmonics: int = DEFAULT_HARMONICS, samples: int | None = None,
                   min_points: int | None = None) -> HBResult:
    """The branch through the state ``X`` (its harmonics, as HBResult.X holds them) at ``rpm``, continued
    down to ``rpm_from`` and up to ``rpm_to`` (r/min), as one branch in increasing continuation order.

    Downwards the continuation runs in p = -rpm (shroud.core.continuation follows a parameter upwards).
    A branch that turns back (an isolated loop, or a fold back out of the range) stops there and says
    so; ``min_points`` bounds the speed step over the whole range, as in :func:`run_hb`.
    """
    t0 = time.perf_counter()
    n = check_inputs(harmonics, samples, rpm_from, rpm_to)
    basis = hb.fourier(harmonics, n)
    speeds = SpeedModel(model_at_speed(params, model), harmonics)
    system, lin, _, _ = speeds.at(rpm)
    law = contact_law_for(system, params.contact)
    residual = residual_in_speed(speeds, law, basis)
    halves = []
    for sign, end in ((-1.0, rpm_from), (1.0, rpm_to)):
        if sign * (end - rpm) <= 0:
            continue

        def signed(Xc, p, sign=sign):
            R, J, d_rpm = residual(Xc, sign * p)
            return R, J, lambda: sign * d_rpm()
        branch, details = follow_branch(
            signed, X, sign * rpm, sign * end, branch_scale(params, X), speed_step(rpm_from, rpm_to, min_points),
            f"HB branch {model} through {rpm:g} r/min", lambda Xc, p, previous, sign=sign: point_details(
                speeds, law, basis, Xc, sign * p, residual.last, previous))
        halves.append((sign, branch, details))
    rpms, xs, details, its, kinks, folds, stops = [], [], [], [], [], [], []
    for sign, branch, det in halves:
        order = slice(None, None, -1) if sign < 0 else slice(None)
        skip = 1 if sign > 0 and rpms else 0          # the seed point is the downward half's last
        rpms += [sign * p for p in branch.p[order]][skip:]
        xs += branch.x[order][skip:]
        details += det[order][skip:]
        its += branch.iterations
        kinks += [{"rpm": sign * k["p"], "turn_rad": k["turn_rad"]} for k in branch.kinks]
        folds += [{"rpm": sign * f["p"], "kind": f["kind"]} for f in branch.folds]
        if not branch.complete:
            stops.append(("down: " if sign < 0 else "up: ") + str(branch.stopped))
    return HBResult.from_points(model=model, harmonics=harmonics, samples=n, rpm=rpms, details=details,
                                iterations=its, complete=not stops, stopped="; ".join(stops) or None,
                                dofs=system.dofs, condensed=lin.condensed, elapsed_s=time.perf_counter() - t0,
                                X=xs, kinks=kinks, folds=folds)


def time_domain_state(params: Parameters, model: str, rpm: float, harmonics: int = DEFAULT_HARMONICS,
                      periods: int = 300) -> tuple[np.ndarray, int | None]:
    """The harmonics of the contact coordinates y = W q over the last of ``periods`` excitation periods of
    a run from rest at ``rpm`` (the time-domain sweep's run, longer), and the period the run settled on
    (shroud.core.signals.detect_period, in excitation periods; None: none found).

    The run records y as its tracked outputs (the system's tip rows replaced by W's, two at a time), so
    the harmonics are those of the state a sweep from rest reaches: a start for Newton on a condensed
    model (unknowns y) that lands on the P1 states a continuation from the linear solution may miss.
    """
    q = params.updated({"speed.rpm": float(rpm)})
    system = build_system(q, model)
    if system.contact is None:
        raise InputError("--model", f"{model}: a time-domain seed needs a model with contact")
    W = dense(system.contact.W)
    law, spp = contact_law_for(system, q.contact), q.time.steps_per_period
    columns, period = [], None
    for r in range(0, W.shape[0], 2):
        rows = W[r:r + 2] if r + 2 <= W.shape[0] else np.vstack([W[r], W[r]])
        tr = integrate(dataclasses.replace(system, tip=rows), law, NewmarkScheme(q.time_step), spp * periods)
        columns.append(tr.tip[-spp - 1:-1])       # tau = 2 pi i / spp, i = 0 .. spp - 1
        if r == 0:
            period = detect_period(tr.tip[:, 0], spp)
    Y = np.hstack(columns)[:, :W.shape[0]]
    return hb.fourier(harmonics, spp).A @ Y, period


@dataclass(frozen=True)
class Seed:
    """A time-domain state at one speed read as a start for a branch: its run's period, the P1 state Newton
    reached from it (amplitude m, stability), and what became of it: "new branch", "on a branch" (within
    ``match`` of a computed one) or why it gave none (among them an unstable state: a disagreement of the
    two methods, reported, not followed)."""

    rpm: float
    period: int | None
    amplitude_v_L: float | None
    stable: bool | None
    outcome: str

    def to_json(self) -> dict:
        return dataclasses.asdict(self)


def on_branches(branches: list[HBResult], rpm: float, amplitude: float, match: float) -> bool:
    """Whether a stable P1 state of amplitude ``amplitude`` (m) at ``rpm`` lies on one of ``branches`` within
    ``match`` (relative), between two of its points not both shown unstable (linear interpolation of the
    amplitude): a stable state beside an unstable stretch is another state (1 um gap, 11250 r/min: 0.5 %
    beside a stretch with |multiplier| 2.4)."""
    for br in branches:
        for i in range(len(br.rpm) - 1):
            r0, r1 = br.rpm[i], br.rpm[i + 1]
            unstable = br.stable[i] is False and br.stable[i + 1] is False
            if r0 == r1 or not min(r0, r1) <= rpm <= max(r0, r1) or unstable:
                continue
            t = (rpm - r0) / (r1 - r0)
            if abs(((1 - t) * br.amplitude_v_L[i] + t * br.amplitude_v_L[i + 1]) / amplitude - 1) <= match:
                return True
    return False


@dataclass(frozen=True)
class HBFamily:
    """Every branch of a model over a speed range: the one continued from ``rpm_from``, then those through
    time-domain states it misses (:func:`run_hb_family`), with what each seed gave."""

    branches: list[HBResult]
    seeds: list[Seed]
    elapsed_s: float

    def to_json(self) -> dict:
        return {"branches": [b.to_json() for b in self.branches], "seeds": [s.to_json() for s in self.seeds],
                "elapsed_s": round(self.elapsed_s, 6)}


def run_hb_family(params: Parameters, model: str, rpm_from: float, rpm_to: float, seed_rpms,
                  harmonics: int = DEFAULT_HARMONICS, samples: int | None = None, min_points: int | None = None,
                  periods: int = 300, match: float = 0.01, continued: HBResult | None = None) -> HBFamily:
    """The branch from ``rpm_from`` (:func:`run_hb`) and every branch through a time-domain state it misses.

    At each speed of ``seed_rpms`` a run from rest (:func:`time_domain_state`) gives a state; Newton from
    its harmonics at that speed gives a P1 state; one not within ``match`` of a branch found so far is
    continued both ways over the range (:func:`run_hb_through`). A continuation from the linear solution
    follows one connected branch: states on isolated branches, or beyond a corner it stepped over, are
    found only so (1 um gap, alpha 30 deg, kt 5e6 N/m, mu 0.3: P1 states at 8000 and 11250 r/min on
    stable branches 0.7 % and 0.5 % from the continued one's unstable stretches, docs/hb-stability.md).
    Needs a model condensed on its contact coordinates (the beams: unknowns y). ``continued``: the branch
    from ``rpm_from`` where the caller has it already (the same options), so it is not computed again.
    """
    t0 = time.perf_counter()
    check_inputs(harmonics, samples, rpm_from, rpm_to)
    branches = [continued or run_hb(params, model, rpm_from, rpm_to, harmonics, samples, min_points)]
    if not branches[0].condensed:
        raise InputError("--model", f"{model}: time-domain seeds need a model condensed on its contact "
                                    "coordinates (its unknowns are y = W q)")
    seeds = []
    for rpm in seed_rpms:
        rpm = float(rpm)
        Y, period = time_domain_state(params, model, rpm, harmonics, periods)
        if period != 1:
            seeds.append(Seed(rpm, period, None, None, "no P1 run"))
            continue
        sol = checkpoint(params, model, rpm, harmonics, samples, start=Y.ravel(), retry=False)
        if not sol.converged:
            seeds.append(Seed(rpm, period, None, None, "Newton did not converge from it"))
            continue
        a = sol.amplitude_v_L
        if sol.stable is False:       # the run stayed where HB says it cannot: not a branch to follow
            seeds.append(Seed(rpm, period, a, False, "Newton reached an unstable state from it (not continued)"))
            continue
        if on_branches(branches, rpm, a, match):
            seeds.append(Seed(rpm, period, a, sol.stable, "on a branch"))
            continue
        branches.append(run_hb_through(params, model, sol.X, rpm, rpm_from, rpm_to, harmonics, samples, min_points))
        seeds.append(Seed(rpm, period, a, sol.stable, "new branch"))
    return HBFamily(branches=branches, seeds=seeds, elapsed_s=time.perf_counter() - t0)


def run_hb_to_tail(params: Parameters, model: str, rpm_from: float, rpm_to: float, tail: float,
                   first: int = 5, most: int = 40, min_points: int | None = None) -> HBResult:
    """The branch with H chosen so that the contact forces' spectral tail above H is at most ``tail``.

    H = first, 2 first, ... up to ``most``: the first branch whose tail (at its largest contact forces)
    is within ``tail`` is returned, with every H tried and its tail recorded; if none is, the last, with
    ``tail_met`` False (HBResult.tail_target holds ``tail``).
    """
    if not 0 < tail < 1:
        raise InputError("--tail", f"{tail!r} is out of range; allowed: a share in (0, 1)")
    tried, H = [], first
    while True:
        result = run_hb(params, model, rpm_from, rpm_to, harmonics=H, min_points=min_points)
        tried.append({"harmonics": H, "spectral_tail": result.spectral_tail})
        if result.spectral_tail <= tail or 2 * H > most:
            return dataclasses.replace(result, harmonics_tried=tuple(tried), tail_target=float(tail))
        H *= 2


NO_FLOQUET = ("not computed: the Floquet multipliers need the monodromy of the full M, C, K (2 n states), "
              "which a model condensed by its own solver does not offer, and it names no model to project on")
PROJECTED_TOLERANCE = 0.01     # the largest |multiplier| on two bases this close: the projection has converged


def projected_multipliers(params: Parameters, model: str, rpm: float, X: np.ndarray, basis: hb.Fourier) -> dict:
    """Floquet multipliers of an orbit given on contact coordinates, its perturbations projected on ``model``.

    ``X`` (nh, m): the harmonics of a (large) model's periodic orbit on the
    contact coordinates ``model`` shares with it. The law is evaluated along
    that orbit (its contact states and friction at the samples), and the
    motion linearized about it is integrated over the period with ``model``'s
    M, C, K and W at ``rpm`` (floquet.monodromy): exact but for the
    perturbation living in ``model``'s subspace. Done on ``model``'s own
    basis and, where it has one, on its ``refined`` (larger) basis: the
    largest |multiplier| on each, keyed by the basis' DOF count, the
    verdict of the larger, and whether the two agree within
    PROJECTED_TOLERANCE.
    """
    entry = registry.model(model)
    largest: dict[int, float] = {}
    for p in [params] + ([entry.refined(params)] if entry.refined is not None else []):
        system = entry.build_system(p.updated({"speed.rpm": float(rpm)}))
        law = contact_law_for(system, p.contact)
        st = orbit_stability(system, law, X, basis)
        largest[system.dofs] = st.largest
        stable = st.stable
    values = list(largest.values())
    return {"stable": stable, "largest": largest,
            "converged": len(values) < 2 or abs(values[-1] - values[0]) <= PROJECTED_TOLERANCE}


@dataclass(frozen=True)
class Checkpoint:
    """One harmonic-balance point of a model at one speed, without continuation (a large model's check).

    ``start``: where Newton began (the reduced model's state on the same
    contact coordinates, or the load homotopy); ``start_amplitude_v_L`` that
    state's amplitude, m. ``stable`` is None where the model offers no
    Floquet multipliers or their largest modulus is within its error of 1
    (``stability`` says why, or how they were found);
    ``largest_multiplier``: the largest |multiplier| per basis (DOF count)
    for a model whose perturbations are projected on the model reducing it
    (:func:`projected_multipliers`), or on its own DOFs. Times in s: ``linear_s``
    building the system and its linear part per harmonic (0 when an earlier
    point at the speed built them), ``start_s`` the reduced model's state,
    ``newton_s`` the model's own Newton, ``stability_s`` its multipliers
    (with the bases they are projected on, where not cached). ``X``: the
    state's harmonics (its unknowns, as HBResult.X holds a branch's; not in
    the JSON), e.g. to start a continuation through it (:func:`run_hb_through`). A ring's checkpoint
    (shroud.analysis.ring_hb.ring_checkpoint) has ``blades`` N and every blade's v_L amplitude
    (``blades_amplitude_v_L``, m); the amplitudes are blade 0's, ``dofs`` the ring's. A point Newton did not
    converge on has no amplitudes in the JSON (null): they are not an answer.
    """

    model: str
    rpm: float
    harmonics: int
    samples: int
    amplitude_v_L: float
    amplitude_w_L: float
    converged: bool
    residual: float
    short: bool              # Newton stopped short of the tolerance asked (residual above it, within hb.ACCEPT)
    tolerance: float         # the |R| / |F| Newton was asked for
    iterations: int | None   # Newton's (None: a ring's, reached by starts tried in turn)
    spectral_tail: float
    start: str
    start_amplitude_v_L: float | None
    stable: bool | None
    stability: str
    largest_multiplier: dict[int, float]
    multiplier_error: float | None      # the largest |multiplier|'s own error (own multipliers only)
    dofs: int
    condensed_on: int
    linear_s: float
    start_s: float
    newton_s: float
    stability_s: float
    X: np.ndarray = dataclasses.field(repr=False, compare=False)
    blades: int = 0                                  # 0: the blade between fixed neighbours
    blades_amplitude_v_L: tuple[float, ...] = ()     # a ring's: every blade's, m

    @property
    def elapsed_s(self) -> float:
        return self.linear_s + self.start_s + self.newton_s + self.stability_s

    @property
    def basis(self) -> hb.Fourier:
        """The harmonics and time samples the state was solved on."""
        return hb.fourier(self.harmonics, self.samples)

    def plot(self, ax=None, scale: float = 1e3, **marker):
        """The state's v_L amplitude (mm) at its speed, as HBResult.plot draws a branch's points: filled where
        stable, open where unstable, a cross where undecided; a ring's every blade as small dots behind it.
        Nothing where Newton did not converge (no answer to draw)."""
        from shroud.core.results import _axes
        ax = _axes(ax)
        if not self.converged:
            return ax
        colour = marker.pop("color", None)
        if self.blades:
            dots, = ax.plot([self.rpm] * self.blades, np.asarray(self.blades_amplitude_v_L) * scale, ".", ms=2,
                            color=colour)
            colour = dots.get_color()
        style = {True: {"marker": "o"}, False: {"marker": "o", "mfc": "none"}, None: {"marker": "x"}}[self.stable]
        ax.plot([self.rpm], [self.amplitude_v_L * scale], linestyle="none", color=colour,
                **{**style, "label": self.model + (f", {self.blades} blades" if self.blades else ""), **marker})
        ax.set_xlabel("speed (r/min)")
        ax.set_ylabel("amplitude of v_L (mm)")
        return ax

    def to_json(self) -> dict:
        """The fields but X; a residual Newton drove below its tolerance declared as rounding: its value is
        whatever the last step's rounding left (hb_fig7's full solid: 4.46e-11 and 4.18e-11 in two runs whose
        eigen-solves started from random vectors; a rank count's ordering rounds otherwise too)."""
        out = {f.name: getattr(self, f.name) for f in dataclasses.fields(self) if f.name != "X"}
        out["elapsed_s"] = round(self.elapsed_s, 6)
        if not self.blades:
            del out["blades"], out["blades_amplitude_v_L"]
        else:
            out["blades_amplitude_v_L"] = list(self.blades_amplitude_v_L)
        if not self.converged:
            out.update({k: None for k in ("amplitude_v_L", "amplitude_w_L", "blades_amplitude_v_L") if k in out})
        if self.converged and not self.short:
            return with_rounding(out, "a residual below Newton's tolerance is rounding: held to the tolerance",
                                 residual=self.tolerance)
        return out


def _start_on_contact(params: Parameters, model: str, rpm: float, harmonics: int, samples: int,
                      X: np.ndarray | None) -> hb.HarmonicSolution:
    """``model``'s state at ``rpm`` (Newton from its coefficients ``X``, or from its linear solution and a
    load homotopy), with the coefficients of its contact coordinates in ``X`` (nh, m) of the result."""
    system, lin, _, _ = SpeedModel(model_at_speed(params, model), harmonics).at(rpm)
    law = contact_law_for(system, params.contact)
    sol = hb.solve(system, law, harmonics, samples, X0=X, lin=lin)
    return dataclasses.replace(sol, X=sol.X.reshape(2 * harmonics + 1, lin.nx) @ lin.Wx.T)


NOT_ASKED = "not computed (not asked)"
NOT_CONVERGED = "not computed: Newton did not converge"


def _with_contact_springs(failed: hb.HarmonicSolution, system: StructuralSystem, law, lin: hb.LinearHarmonics,
                          how: str) -> tuple[hb.HarmonicSolution, str]:
    """The state where Newton from the free blade's linear solution and the load homotopy both failed: Newton
    from the linear blade with contact springs, then a continuation in the contact's stiffness (the ring's
    starts, shroud.core.starts.sector_solve, on the blade between fixed neighbours); (``failed``, ``how``)
    where these fail too. Preload 20 N (kn 1e7, kt 5e6 N/m, mu 0.3, alpha 30 deg), 9000 r/min: Newton stalls
    at |R| = 244 N from the free blade (near its resonance, tens of mm) and the homotopy's first step fails
    (the preload is not scaled with the load); from half springs Newton converges on 0.576 um."""
    basis = failed.basis
    try:
        X = sector_solve(lin, fixed_neighbours(law), basis)
    except RunDiverged:
        return failed, how
    sol = hb.newton(X, lin, law, basis)          # at its own tolerance (sector_solve accepts at hb.ACCEPT)
    return (hb.solution(sol.X, sol.balance, lin, basis, sol.iterations, sol.converged, sol.tolerance),
            f"{how} failed; linear solution with contact springs or a continuation in the contact's stiffness")


def checkpoint(params: Parameters, model: str, rpm: float, harmonics: int = DEFAULT_HARMONICS,
               samples: int | None = None, start: np.ndarray | None = None, retry: bool = True,
               multipliers: bool = True) -> Checkpoint:
    """The harmonic-balance state of ``model`` at ``rpm`` (r/min), one speed, no continuation: the one
    way to harmonic balance at a speed (shroud.api.harmonic_balance, ``shroud sweep --checkpoints``, the
    studies and the seeds of :func:`run_hb_family` all come here).

    A model with its own ``linear_harmonics`` (the full solid, condensed exactly
    on its contact coordinates by its own sparse solver) starts Newton from
    the state of the model that reduces it (``reduced_by``: the same contact
    coordinates), reached from ``start`` (that model's coefficients, e.g. a
    point of its branch) or from its linear solution and a load homotopy; if
    Newton fails from there, from its own linear solution and load homotopy.
    Its Floquet multipliers are those of its own orbit, the perturbations
    projected on that model (:func:`projected_multipliers`). Other models
    start from ``start`` or their linear solution and get their own.
    ``retry``: where Newton fails from ``start``, start again from the
    linear solution (False: report the failure, ``converged`` False; a state
    sought near a given one, not any state at the speed).
    ``multipliers=False``: no stability (``stable`` None), e.g. where the
    caller takes it from the branch points around the state.
    """
    n = check_inputs(harmonics, samples, 0.5 * rpm, rpm)
    entry = registry.model(model)
    t0 = time.perf_counter()
    speeds = None
    if entry.linear_harmonics is not None:
        system, lin = entry.linear_harmonics(params, rpm, harmonics)
    else:
        speeds = SpeedModel(model_at_speed(params, model), harmonics)
        system, lin, _, _ = speeds.at(rpm)
    t1 = time.perf_counter()
    X0, how, start_amplitude = start, "given" if start is not None else "linear solution, load homotopy", None
    if entry.reduced_by is not None:
        reduced = _start_on_contact(params, entry.reduced_by, rpm, harmonics, n, start)
        X0, how = None, "linear solution, load homotopy"
        if reduced.converged and lin.condensed and reduced.X.shape[1] == lin.nx:
            X0, how, start_amplitude = reduced.X.ravel(), f"{entry.reduced_by} state", reduced.amplitude_v_L
    t2 = time.perf_counter()
    law = contact_law_for(system, params.contact)
    sol = hb.solve(system, law, harmonics, n, X0=X0, lin=lin)
    if not sol.converged and X0 is not None and retry:
        sol, how = hb.solve(system, law, harmonics, n, lin=lin), f"linear solution, load homotopy ({how} failed)"
    if not sol.converged and (X0 is None or retry):
        sol, how = _with_contact_springs(sol, system, law, lin, how)
    t3 = time.perf_counter()
    stable, stability, largest, error = None, NO_FLOQUET, {}, None
    if not multipliers:
        stability = NOT_ASKED
    elif not sol.converged:
        stability = NOT_CONVERGED
    elif speeds is not None:
        details = point_details(speeds, law, sol.basis, sol.X, rpm)
        stable, stability, error = details["stable"], "Floquet multipliers", details["multiplier_error"]
        largest = {system.dofs: float(np.abs(details["multipliers"]).max(initial=0.0))}
    elif entry.reduced_by is not None and sol.converged and lin.condensed:
        proj = projected_multipliers(params, entry.reduced_by, rpm, sol.X.reshape(sol.basis.nh, lin.nx), sol.basis)
        stable, largest = proj["stable"], proj["largest"]
        stability = (f"Floquet multipliers of this orbit, perturbations on {entry.reduced_by}'s basis ("
                     + ", ".join(f"{d} DOF: {m:.4f}" for d, m in largest.items()) + ")"
                     + ("" if proj["converged"] else f"; not converged within {PROJECTED_TOLERANCE:g}"))
    return Checkpoint(model=model, rpm=float(rpm), harmonics=harmonics, samples=n,
                      amplitude_v_L=float(sol.amplitude_v_L), amplitude_w_L=float(sol.amplitude_w_L),
                      converged=bool(sol.converged), residual=float(sol.residual), short=sol.short,
                      tolerance=float(sol.tolerance), iterations=int(sol.iterations),
                      spectral_tail=float(sol.spectral_tail), start=how,
                      start_amplitude_v_L=None if start_amplitude is None else float(start_amplitude),
                      stable=stable, stability=stability, largest_multiplier=largest, multiplier_error=error,
                      dofs=system.dofs,
                      condensed_on=lin.nx if lin.condensed else 0,
                      linear_s=t1 - t0, start_s=t2 - t1, newton_s=t3 - t2, stability_s=time.perf_counter() - t3,
                      X=sol.X)


def ring_steady_states(params: Parameters, points: list[Checkpoint]) -> None:
    """Refuse (InputError on --checkpoints: exit 2, one line) a ring's checkpoints whose state is decided
    unstable by the ring's monodromy (every nodal diameter), and warn where it is undecided.

    A tuned ring's checkpoint is the travelling wave, the one state the sector holds: where a perturbation of
    another nodal diameter grows, the ring in time leaves the wave for a state the sector cannot represent
    (24 blades, preload 20 N, 12000 r/min: |mu| 1.42, the ring in time unsettled at 11.8 um against the
    wave's 10.1 um, docs/ring.md), so its amplitude is not the ring's response and the ring in time is the way
    to it. (A mistuned ring's whole-ring state is refused alike: the ring in time leaves it too.) The single
    blade's unstable states stay answers: they lie on its own branch, whose continuation finds the stable
    ones beside them."""
    kind = "travelling wave" if params.ring.tuned else "periodic state"
    N = params.ring.blades

    def where(p: Checkpoint) -> str:
        return (f"{p.rpm:g} r/min (largest |multiplier| {max(p.largest_multiplier.values()):.4g} "
                f"+- {p.multiplier_error:.2g})")
    unstable = [p for p in points if p.converged and p.stable is False]
    if unstable:
        raise InputError("--checkpoints", f"the {N}-blade ring's {kind} is unstable at "
                                          + ", ".join(where(p) for p in unstable)
                                          + f": not the ring's steady response; allowed: the ring in time "
                                            f"(shroud transient --set ring.blades={N} --rpm "
                                            f"{unstable[0].rpm:g}), the other speeds' checkpoints without "
                                            f"{'them' if len(unstable) > 1 else 'it'}")
    for p in points:
        if p.converged and p.stable is None and p.largest_multiplier:
            warn(f"the {N}-blade ring's {kind} at {where(p)} is neither stable nor unstable within its error: "
                 f"the ring in time decides (shroud transient --set ring.blades={N} --rpm {p.rpm:g})")


def run_checkpoints(params: Parameters, model: str, rpms, harmonics: int = DEFAULT_HARMONICS,
                    samples: int | None = None) -> dict:
    """The checkpoint at each speed of ``rpms`` (r/min) of the system ``params`` describe (the blade's
    :func:`checkpoint`, a ring's shroud.analysis.ring_hb.ring_checkpoint: shroud.analysis.systems), as the
    JSON of ``shroud sweep --checkpoints``: a point Newton did not converge on has null amplitudes; a ring's
    unstable states are refused (:func:`ring_steady_states`)."""
    t0 = time.perf_counter()
    solve = solver("checkpoint", params)
    for rpm in rpms:
        check_inputs(harmonics, samples, 0.5 * rpm, rpm)
        params.updated({"speed.rpm": float(rpm)})     # the models' speed bound (shroud.params)
    points = [solve(params, model, float(rpm), harmonics, samples) for rpm in rpms]
    if params.ring.blades:
        ring_steady_states(params, points)
    shown = [p.to_json() for p in points]
    ring = {"blades": params.ring.blades,
            "blades_amplitude_v_L": [p["blades_amplitude_v_L"] for p in shown]} if params.ring.blades else {}
    return {"model": model, "method": "hb", "harmonics": harmonics, "samples": points[0].samples,
            "rpm": [p.rpm for p in points], "amplitude_v_L": [p["amplitude_v_L"] for p in shown],
            "amplitude_w_L": [p["amplitude_w_L"] for p in shown], "stable": [p.stable for p in points],
            "converged": [p.converged for p in points], **ring, "checkpoints": shown,
            "elapsed_s": round(time.perf_counter() - t0, 6)}
