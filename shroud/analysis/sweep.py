"""Steady-state amplitude over speed (paper Figs. 4, 7, 11, 12, 16).

At every speed the model is rebuilt (its stiffness, damping and load depend
on Omega), run from rest for ``params.time.periods`` excitation periods, and
reduced to the steady-state amplitude of v_L ((max - min)/2 over the last 10
periods). All points of all curves go through one ``map_parallel`` so the
cores stay busy across curves.
"""

from __future__ import annotations

import math
import time
from typing import Callable, Sequence

import numpy as np

from shroud.analysis.checks import check_run
from shroud.analysis.transient import contact_law_for, run
from shroud.base.log import Progress
from shroud.base.parallel import map_parallel
from shroud.core import registry
from shroud.core.results import SweepResult, steady_state
from shroud.core.system import StructuralSystem
from shroud.params import Parameters


def _model_builder(model: str) -> Callable[[Parameters], StructuralSystem]:
    return registry.model(model).build_system


def steady_point(task: tuple[Parameters, str, float, Callable | None]) -> tuple:
    """One speed: (amp v_L, amp w_L, period, slip fraction, dofs, seconds)."""
    params, model, rpm, build = task
    t0 = time.perf_counter()
    p = params.updated({"speed.rpm": rpm})
    system = (build or _model_builder(model))(p)
    tr = run(system, p)
    if tr.diverged is not None:
        return math.nan, math.nan, None, math.nan, system.dofs, time.perf_counter() - t0
    s = steady_state(tr, p.time.steps_per_period)
    slip = 0.5 * (s["state_fraction"]["side1"]["slip"] + s["state_fraction"]["side2"]["slip"])
    return (s["amplitude"]["v_L"], s["amplitude"]["w_L"], s["period"], slip, system.dofs,
            time.perf_counter() - t0)


def run_sweeps(cases: Sequence[Parameters], model: str, rpms: Sequence[float],
               build: Callable[[Parameters], StructuralSystem] | None = None) -> list[SweepResult]:
    """One sweep over ``rpms`` per parameter set in ``cases``, all points spread over the cores.

    ``build(params) -> StructuralSystem`` replaces the model dispatch (shroud.analysis.api)
    when given; it must be a module-level function (it is pickled).
    """
    rpms = np.asarray(rpms, dtype=float)
    for p in cases:             # every speed checked before any runs (the rule: Parameters.time_step)
        for r in rpms:
            p.updated({"speed.rpm": float(r)}).time_step
    tasks = [(p, model, float(r), build) for p in cases for r in rpms]
    progress = Progress(f"sweep {model} ({len(cases)} x {len(rpms)} speeds)", len(tasks))
    t0 = time.perf_counter()
    # The first point in this process compiles (or loads) the kernel, which
    # the forked workers then inherit instead of loading it each.
    points = [steady_point(tasks[0])] + map_parallel(steady_point, tasks[1:]) if tasks else []
    elapsed = time.perf_counter() - t0
    progress.update(len(tasks))
    progress.done()
    out = []
    for c in range(len(cases)):
        rows = points[c * len(rpms):(c + 1) * len(rpms)]
        col = list(zip(*rows)) if rows else [[]] * 6
        out.append(SweepResult(model=model, rpm=rpms, amplitude_v_L=np.array(col[0], float),
                               amplitude_w_L=np.array(col[1], float), period=tuple(col[2]),
                               slip_fraction=np.array(col[3], float), dofs=int(col[4][0]) if rows else 0,
                               elapsed_s=elapsed * len(rows) / max(len(tasks), 1),
                               cpu_s=float(np.sum(col[5]))))
    return out


def run_sweep(params: Parameters, model: str, rpms: Sequence[float]) -> SweepResult:
    """Steady-state v_L amplitude of ``model`` at each speed in ``rpms`` (r/min)."""
    return run_sweeps([params], model, rpms)[0]


def coexisting_states(params: Parameters, model: str, rpm: float, tip_deflections: Sequence[float],
                      rel: float = 0.01) -> list[float]:
    """The distinct steady v_L amplitudes (m, sorted) reached from several initial states.

    Near a jump an impacting blade has more than one steady state at one
    speed. Each run starts from the static deflection under the aerodynamic
    load scaled to a tip deflection v_L in ``tip_deflections`` (m; the same
    physical state for any model), at rest; amplitudes within ``rel`` of
    each other count as one state.
    """
    from shroud.core.newmark import NewmarkScheme, integrate
    from shroud.core.signals import amplitude
    p = params.updated({"speed.rpm": rpm})
    system = _model_builder(model)(p)
    check_run(system, p)
    law = contact_law_for(system, p.contact)
    shape = np.linalg.solve(system.K, system.f_aero)
    shape = shape / (np.asarray(system.tip)[0] @ shape)
    spp = p.time.steps_per_period
    found: list[float] = []
    for a in sorted(tip_deflections):
        tr = integrate(system, law, NewmarkScheme(p.time_step), spp * p.time.periods, q0=a * shape,
                       bound=p.blade.length)
        if tr.diverged is None:
            found.append(amplitude(tr.tip[:, 0], spp))
    out: list[float] = []
    for v in sorted(found):
        if not out or v > out[-1] * (1 + rel):
            out.append(v)
    return out

