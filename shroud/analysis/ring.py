"""The ring of ``ring.blades`` blades from the parameters: its build and its transient (docs/ring.md).

Blade j is the registered model's blade with E_j = E (1 + d_j) (and so G_j),
its own basis when mistuned, and the tuned blade's Rayleigh coefficients
(geometry.md, "Moving neighbours"); a tuned ring builds one blade and uses
it N times. The transient's JSON is the single blade's for blade 0 (its
side 1 is interface N-1, its side 2 interface 0) plus ``blades``
(docs/interface.md).
"""

from __future__ import annotations

import dataclasses
import math
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from shroud.analysis.checks import MEMORY_SHARE, check_run, check_speed_count
from shroud.analysis.sweep import Settling, settle
from shroud.analysis.transient import written
from shroud.base.resources import in_words, physical_memory
from shroud.base.errors import InputError
from shroud.base.parallel import map_parallel
from shroud.core import registry, signals
from shroud.core.contact import ContactLaw, contact_law
from shroud.core.newmark import NewmarkScheme, Trajectory
from shroud.core.results import RingSweepResult, SweepResult, TransientResult, steady_state
from shroud.core.ring import BladeRing, paired_by_position, ring_of, with_rayleigh
from shroud.core.system import StructuralSystem
from shroud.core.ring_newmark import RingTrajectory, integrate_ring
from shroud.params import Parameters

RING_MODELS = ("reduced", "full", "extended", "fe-reduced")


def blade_parameters(params: Parameters, j: int) -> Parameters:
    """Blade j's parameters: E (1 + d_j)."""
    d = params.ring.deviations[j]
    return params if d == 0.0 else params.updated({"material.E": params.material.E * (1.0 + d)})


def build_ring(params: Parameters, model: str) -> BladeRing:
    """The ring of ``params.ring.blades`` blades of ``model`` at ``params.speed.rpm``."""
    if model not in RING_MODELS:
        raise InputError("ring.blades", f"a ring of {model} blades is not built yet; allowed with ring.blades > 0: "
                                        f"--model {', '.join(RING_MODELS)}")
    if not params.contact.enabled or params.shroud.thickness == 0:
        raise InputError("ring.blades", "the blades of a ring meet only at their shrouds; allowed: "
                                        "contact.enabled = true and shroud.thickness > 0")
    build = registry.model(model).build_system
    pair = pairing(params, model)
    tuned = pair(build(params))
    blades = []
    for j, d in enumerate(params.ring.deviations):
        blades.append(tuned if d == 0.0 else with_rayleigh(pair(build(blade_parameters(params, j))), tuned.rayleigh))
    return ring_of(blades, params.load.ke)


def pairing(params: Parameters, model: str):
    """system -> the system with its faces' points paired across the interface (the solid's face nodes by
    their positions: shroud.core.ring.paired_by_position); the beams list them paired already. A blade's
    mistuning changes E only, so every blade's faces sit where the tuned blade's do."""
    where = registry.model(model).contact_points
    if where is None:
        return lambda system: system
    points, normal = where(params)

    def paired(system: StructuralSystem) -> StructuralSystem:
        return dataclasses.replace(system, contact=paired_by_position(system.contact, points, normal))
    return paired


def ring_law(ring: BladeRing, params: Parameters) -> ContactLaw:
    """The interfaces' contact law: each interface's kn, kt, N0 shared over its points (weights)."""
    c = params.contact
    return contact_law(ring.contact(), kn=c.kn, kt=c.kt, mu=c.mu, N0=c.N0)


RING_BYTES_PER_BLADE_STEP = 5 * 8 + 1     # tip (2), N, F, r (float64) and the state (int8) of each blade a step


def check_ring_records(params: Parameters, blades: int) -> None:
    """Refuse a ring run whose records (every blade's, every step) this machine cannot hold."""
    steps = params.time.periods * params.time.steps_per_period
    need, limit = (steps + 1) * blades * RING_BYTES_PER_BLADE_STEP, MEMORY_SHARE * physical_memory()
    if need > limit:
        most = int(limit // (blades * RING_BYTES_PER_BLADE_STEP * params.time.steps_per_period))
        raise InputError("time.periods", f"{params.time.periods} periods of a {blades}-blade ring would record "
                                         f"{in_words(need)}, more than {MEMORY_SHARE:.0%} of this machine's "
                                         f"{in_words(physical_memory())}; allowed: at most {most} periods here")


def run_ring(ring: BladeRing, params: Parameters, held: tuple[int, ...] = (), **initial) -> RingTrajectory:
    """Integrate the ring as ``params.time`` and ``params.contact`` say (no output files)."""
    check_run(ring.blades[0], params)          # each blade's records and contact stiffness
    check_ring_records(params, ring.count)
    spp, periods = params.time.steps_per_period, params.time.periods
    return integrate_ring(ring, ring_law(ring, params), NewmarkScheme(dt=params.time_step), spp * periods,
                          implicit=params.time.contact == "implicit",
                          energy_window=min(signals.STEADY_PERIODS, periods) * spp,
                          bound=params.blade.length, held=held, **initial)


def ring_point(task: tuple[Parameters, str, float, Settling]) -> tuple:
    """One speed of the ring in time, run from rest and settled as the single blade's sweep
    (shroud.analysis.sweep.settle: every blade's amplitudes): (every blade's v_L, w_L amplitudes (N, 2) m,
    blade 0's period, its slip share, the ring's DOFs, seconds, settled); NaN amplitudes where it diverged."""
    params, model, rpm, settling = task
    t0 = time.perf_counter()
    p = params.updated({"speed.rpm": rpm})
    ring = build_ring(p, model)
    spp = p.time.steps_per_period
    tr, settled = settle(lambda n: run_ring(ring, p.updated({"time.periods": n})), p.time.periods, spp, settling)
    if tr.diverged is not None:
        return np.full((ring.count, 2), np.nan), None, math.nan, ring.dofs, time.perf_counter() - t0, False
    s = steady_state(blade_view(tr, 0), spp)
    amplitudes = [[signals.amplitude(tr.tip[:, j, k], spp) for k in (0, 1)] for j in range(ring.count)]
    return (np.array(amplitudes), s["period"], 0.5 * (s["state_fraction"]["side1"]["slip"]
                                                       + s["state_fraction"]["side2"]["slip"]),
            ring.dofs, time.perf_counter() - t0, settled)


def run_ring_sweep(params: Parameters, model: str, rpms, settling: Settling = Settling()) -> RingSweepResult:
    """The ring's steady state in time at each speed of ``rpms`` (r/min), every blade's amplitude
    (shroud.analysis.sweep.run_sweep's ring: each run from rest, extended until every blade has settled)."""
    rpms = np.asarray(rpms, dtype=float)
    check_speed_count(rpms.size * params.ring.blades, "speeds")
    for r in (rpms.min(), rpms.max()) if rpms.size else ():
        params.updated({"speed.rpm": float(r)}).time_step          # the speeds' bounds, before any run
    tasks = [(params, model, float(r), settling) for r in rpms]
    t0 = time.perf_counter()
    points = [ring_point(tasks[0])] + map_parallel(ring_point, tasks[1:], preload=registry.packages()) if tasks else []
    col = list(zip(*points)) if points else [[]] * 6
    amplitudes = np.array(col[0], float).reshape(rpms.size, params.ring.blades, 2)
    blade0 = SweepResult(model=model, rpm=rpms, amplitude_v_L=amplitudes[:, 0, 0], amplitude_w_L=amplitudes[:, 0, 1],
                         period=tuple(col[1]), slip_fraction=np.array(col[2], float),
                         dofs=int(col[3][0]) if points else 0, elapsed_s=time.perf_counter() - t0,
                         cpu_s=float(np.sum(col[4])), settled=tuple(bool(x) for x in col[5]))
    return RingSweepResult(sweep=blade0, blades_amplitude_v_L=amplitudes[:, :, 0],
                           blades_amplitude_w_L=amplitudes[:, :, 1])


def blade_view(tr: RingTrajectory, j: int) -> Trajectory:
    """Blade j's records as the single blade's: side 1 is interface j-1 (the force on blade j is the
    interface's reaction, -F; its w_s the relative slip seen from blade j, -r), side 2 interface j."""
    i = (j - 1) % tr.normal.shape[1]
    return Trajectory(dt=tr.dt, steps=tr.steps, tip=tr.tip[:, j], normal=tr.normal[:, [i, j]],
                      friction=np.column_stack([-tr.friction[:, i], tr.friction[:, j]]),
                      tangential=np.column_stack([-tr.slip[:, i], tr.slip[:, j]]),
                      state=tr.state[:, [i, j]], energy=tr.energy, contact_iterations=tr.contact_iterations,
                      contact_unconverged=tr.contact_unconverged, diverged=tr.diverged, elapsed_s=tr.elapsed_s,
                      method="ring", element_share=None, element_peak_normal=None)


@dataclass(frozen=True)
class RingTransientResult:
    """A ring's transient: blade 0 as the single blade's result, and every blade's measures."""

    blade0: TransientResult
    blades: list[dict[str, Any]]     # per blade j: amplitude {v_L, w_L} (m), peak {N, Ff} of interface j (N)
    trajectory: RingTrajectory

    def to_json(self) -> dict[str, Any]:
        return {**self.blade0.to_json(), "blades": self.blades}


def simulate_ring(params: Parameters, model: str, csv_path: Path | None = None) -> RingTransientResult:
    """The whole ring's transient; raises RunDiverged (blade 0's CSV so far kept) if unbounded."""
    ring = build_ring(params, model)
    spp = params.time.steps_per_period
    tr = run_ring(ring, params)
    view = written(blade_view(tr, 0), csv_path, f"ring of {ring.count} {model} blades at {params.speed.rpm:g} r/min",
                   rows=", blade 0")
    blades = [{"amplitude": {"v_L": signals.amplitude(tr.tip[:, j, 0], spp),
                             "w_L": signals.amplitude(tr.tip[:, j, 1], spp)},
               "peak": {"N": signals.peak(tr.normal[:, j], spp), "Ff": signals.peak(tr.friction[:, j], spp)}}
              for j in range(ring.count)]
    blade0 = TransientResult.from_trajectory(view, model=model, rpm=params.speed.rpm, dofs=ring.dofs,
                                             steps_per_period=spp, contact_treatment=params.time.contact,
                                             timeseries=str(csv_path) if csv_path else None)
    return RingTransientResult(blade0=blade0, blades=blades, trajectory=tr)
