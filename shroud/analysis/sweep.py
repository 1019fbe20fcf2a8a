"""Steady-state amplitude over speed (paper Figs. 4, 7, 11, 12, 16).

At every speed the model is rebuilt (its stiffness, damping and load depend
on Omega), run from rest for ``params.time.periods`` excitation periods, and
reduced to the steady-state amplitude of v_L ((max - min)/2 over the last 10
periods). All points of all curves go through one ``map_parallel`` so the
cores stay busy across curves.

A run counts as a steady state only once it has settled (``Settling``): the
tip amplitudes over the last 10 periods differ from those over the 10
periods before by less than ``tolerance``. A run that has not settled is
run again from rest for twice the periods (the same trajectory, continued:
a run from rest is deterministic) up to ``max_periods``; a point still
unsettled there is marked ``settled = False`` and must not be read as a
steady state.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import Callable, Sequence

import numpy as np

from shroud.analysis.checks import check_run, check_speed_count
from shroud.analysis.transient import contact_law_for, run
from shroud.base.errors import InputError
from shroud.base.log import Progress
from shroud.base.parallel import map_parallel
from shroud.core import registry, signals
from shroud.core.newmark import NewmarkScheme, Trajectory, integrate
from shroud.core.results import SweepResult, steady_state
from shroud.core.system import StructuralSystem
from shroud.params import Parameters


@dataclass(frozen=True)
class Settling:
    """When a run counts as settled: the relative change of the v_L and w_L amplitudes between the
    last ``window`` periods and the ``window`` periods before stays within ``tolerance``; runs are
    extended (from rest, doubling the periods) up to ``max_periods``."""

    tolerance: float = 2e-3
    max_periods: int = 800
    window: int = signals.STEADY_PERIODS

    @classmethod
    def from_options(cls, options: dict) -> "Settling":
        """From a study's ``settle_tolerance`` and ``settle_max_periods`` options (SETTLING_OPTIONS)."""
        tol, cap = options["settle_tolerance"], options["settle_max_periods"]
        if not 0 < tol < 1:
            raise InputError("options.settle_tolerance", f"{tol!r}; allowed: 0 < tolerance < 1")
        if not isinstance(cap, int) or cap < 2 * signals.STEADY_PERIODS:
            raise InputError("options.settle_max_periods",
                             f"{cap!r}; allowed: an integer >= {2 * signals.STEADY_PERIODS}")
        return cls(tolerance=float(tol), max_periods=cap)

    def describe(self) -> str:
        """One sentence for a report."""
        return (f"A point counts as a steady state once its tip amplitudes over the last {self.window} "
                f"periods differ from those over the {self.window} before by less than "
                f"{100 * self.tolerance:g} %; unsettled runs are extended (from rest, doubling the "
                f"periods) up to {self.max_periods} periods, and a point still unsettled there is "
                "marked *not settled* and never read as a steady state.")


SETTLING_OPTIONS = {"settle_tolerance": Settling.tolerance, "settle_max_periods": Settling.max_periods}


def amplitude_change(tr: Trajectory, steps_per_period: int, window: int) -> float:
    """Largest relative change of the v_L, w_L amplitudes ((max - min)/2; every blade's of a ring's trajectory)
    between the last ``window`` periods and the ``window`` periods before (inf when the run is shorter than two
    windows)."""
    n = window * steps_per_period
    if tr.steps < 2 * n:
        return math.inf
    change = 0.0
    for x in tr.tip.reshape(len(tr.tip), -1).T:       # every tip record (a ring's: every blade's)
        last = signals.amplitude(x, steps_per_period, window)
        before = signals.amplitude(x[:len(x) - n], steps_per_period, window)
        scale = max(last, before)
        change = max(change, abs(last - before) / scale if scale > 0 else 0.0)
    return change


def settle(integrate_periods: Callable[[int], Trajectory], periods: int, steps_per_period: int,
           settling: Settling) -> tuple[Trajectory, bool]:
    """Run ``integrate_periods(n)`` (a run of n periods from one fixed initial state) for ``periods``,
    doubling n until the amplitudes have settled or n reaches ``settling.max_periods``."""
    n = max(periods, 2 * settling.window)
    while True:
        tr = integrate_periods(n)
        if tr.diverged is not None:
            return tr, False
        if amplitude_change(tr, steps_per_period, settling.window) <= settling.tolerance:
            return tr, True
        if n >= settling.max_periods:
            return tr, False
        n = min(2 * n, settling.max_periods)


def _model_builder(model: str) -> Callable[[Parameters], StructuralSystem]:
    return registry.model(model).build_system


def steady_point(task: tuple[Parameters, str, float, Callable | None, Settling]) -> tuple:
    """One speed: (amp v_L, amp w_L, period, slip fraction, dofs, seconds, settled)."""
    params, model, rpm, build, settling = task
    t0 = time.perf_counter()
    p = params.updated({"speed.rpm": rpm})
    system = (build or _model_builder(model))(p)
    spp = p.time.steps_per_period
    tr, settled = settle(lambda n: run(system, p.updated({"time.periods": n})), p.time.periods, spp, settling)
    if tr.diverged is not None:
        return math.nan, math.nan, None, math.nan, system.dofs, time.perf_counter() - t0, False
    s = steady_state(tr, spp)
    slip = 0.5 * (s["state_fraction"]["side1"]["slip"] + s["state_fraction"]["side2"]["slip"])
    return (s["amplitude"]["v_L"], s["amplitude"]["w_L"], s["period"], slip, system.dofs,
            time.perf_counter() - t0, settled)


def run_sweeps(cases: Sequence[Parameters], model: str, rpms: Sequence[float],
               build: Callable[[Parameters], StructuralSystem] | None = None,
               settling: Settling = Settling()) -> list[SweepResult]:
    """One sweep over ``rpms`` per parameter set in ``cases``, all points spread over the cores.

    ``build(params) -> StructuralSystem`` replaces the model dispatch (shroud.analysis.api)
    when given; it must be a module-level function (it is pickled). Each point runs at least
    ``params.time.periods`` and is extended as ``settling`` says.
    """
    rpms = np.asarray(rpms, dtype=float)
    check_speed_count(len(cases) * rpms.size, "speeds")
    # Every speed checked before any runs (the rules: Parameters.time_step and the root strain's bound).
    # The speeds allowed form one interval (0, max_rpm], so the lowest and highest decide for all
    # (a NaN among them is the lowest's and highest's: np.min and np.max return it).
    ends = (float(np.min(rpms)), float(np.max(rpms))) if rpms.size else ()
    for p in cases:
        for r in ends:
            p.updated({"speed.rpm": r}).time_step
    tasks = [(p, model, float(r), build, settling) for p in cases for r in rpms]
    progress = Progress(f"sweep {model} ({len(cases)} x {len(rpms)} speeds)", len(tasks))
    t0 = time.perf_counter()
    # The first point in this process compiles (or loads) the kernel into numba's on-disk cache,
    # which the workers then load instead of compiling it each.
    points = ([steady_point(tasks[0])] + map_parallel(steady_point, tasks[1:], preload=registry.packages())
              if tasks else [])
    elapsed = time.perf_counter() - t0
    progress.update(len(tasks))
    progress.done()
    out = []
    for c in range(len(cases)):
        rows = points[c * len(rpms):(c + 1) * len(rpms)]
        col = list(zip(*rows)) if rows else [[]] * 7
        out.append(SweepResult(model=model, rpm=rpms, amplitude_v_L=np.array(col[0], float),
                               amplitude_w_L=np.array(col[1], float), period=tuple(col[2]),
                               slip_fraction=np.array(col[3], float), dofs=int(col[4][0]) if rows else 0,
                               elapsed_s=elapsed * len(rows) / max(len(tasks), 1),
                               cpu_s=float(np.sum(col[5])), settled=tuple(bool(x) for x in col[6])))
    return out


PLATEAU = 0.02      # settled amplitudes within 2 % of the largest form the top of the resonance


def steady_resonance(sweep: SweepResult) -> dict[str, float]:
    """Speed (r/min) and v_L amplitude (m) of the resonance, read off the settled points only.

    A sharp peak: the largest settled amplitude. An impacting branch has a flat top (amplitudes
    within PLATEAU of the largest over a band of speeds, where argmax picks a point at random):
    the highest speed on it, where the branch ends and the response jumps down. NaN when no
    point has settled.
    """
    a = np.where(np.array(sweep.settled, bool), sweep.amplitude_v_L, np.nan)
    if not np.any(np.isfinite(a)):
        return {"rpm": math.nan, "amplitude": math.nan}
    top = np.flatnonzero(a >= (1 - PLATEAU) * np.nanmax(a))[-1]
    return {"rpm": float(sweep.rpm[top]), "amplitude": float(a[top])}


def run_sweep(params: Parameters, model: str, rpms: Sequence[float],
              settling: Settling = Settling()) -> SweepResult:
    """Steady-state v_L amplitude of ``model`` at each speed in ``rpms`` (r/min)."""
    return run_sweeps([params], model, rpms, settling=settling)[0]


@dataclass(frozen=True)
class States:
    """The distinct settled steady v_L amplitudes reached from several initial states (m, sorted),
    and how many of the runs had not settled by the period cap (or diverged)."""

    amplitudes: list[float]
    unsettled: int


def coexisting_states(params: Parameters, model: str, rpm: float, tip_deflections: Sequence[float],
                      rel: float = 0.01, settling: Settling = Settling()) -> States:
    """The distinct settled steady v_L amplitudes reached from several initial states.

    Near a jump an impacting blade has more than one steady state at one
    speed. Each run starts from the static deflection under the aerodynamic
    load scaled to a tip deflection v_L in ``tip_deflections`` (m; the same
    physical state for any model), at rest, and runs until it has settled
    (``settling``); amplitudes within ``rel`` of each other count as one
    state, and runs that did not settle count in ``unsettled`` only.
    """
    p = params.updated({"speed.rpm": rpm})
    system = _model_builder(model)(p)
    check_run(system, p)
    law = contact_law_for(system, p.contact)
    shape = np.linalg.solve(system.K, system.f_aero)
    shape = shape / (np.asarray(system.tip)[0] @ shape)
    spp = p.time.steps_per_period
    found: list[float] = []
    unsettled = 0
    for a in sorted(tip_deflections):
        tr, ok = settle(lambda n: integrate(system, law, NewmarkScheme(p.time_step), spp * n, q0=a * shape,
                                            bound=p.blade.length), p.time.periods, spp, settling)
        if ok:
            found.append(signals.amplitude(tr.tip[:, 0], spp))
        else:
            unsettled += 1
    out: list[float] = []
    for v in sorted(found):
        if not out or v > out[-1] * (1 + rel):
            out.append(v)
    return States(amplitudes=out, unsettled=unsettled)
