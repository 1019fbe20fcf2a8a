"""The analyses behind the command line, one function each.

Models are looked up in the core's registry (shroud.core.registry), where
their builders put them; only the model a call names is built, so a
reduced-model call never loads DOLFINx or gmsh.
"""

from __future__ import annotations

import time
from pathlib import Path

from shroud.core import registry
from shroud.base.errors import InputError
from shroud.core.results import ModalResult, StaticResult
from shroud.analysis.systems import solver
from shroud.core.system import StructuralSystem
from shroud.params import Parameters


def modal(params: Parameters, model: str, rpm: float | None = None, n_modes: int = 6,
          coriolis: bool = True) -> ModalResult:
    """Natural frequencies at ``rpm`` (default ``params.speed.rpm``), labelled by tip kinematics (a ring:
    refused, its modes are per nodal diameter, shroud.analysis.limits)."""
    return solver("modal", params)(params, model, rpm, n_modes, coriolis)


def blade_modal(params: Parameters, model: str, rpm: float | None, n_modes: int, coriolis: bool) -> ModalResult:
    """The blade's :func:`modal`."""
    rpm = params.speed.rpm if rpm is None else rpm
    entry = registry.model(model)
    if entry.modal is None:
        raise KeyError(f"model {model!r} has no modal analysis; those that have: {', '.join(registry.names('modal'))}")
    return entry.modal(params, rpm, n_modes, coriolis)


def linear_limits(params: Parameters, model: str, rpm: float | None = None, n_modes: int = 6,
                  coriolis: bool = True, interface: str = "stuck"):
    """The contact's linear limits (shroud.analysis.limits.interface_modal): the blade's, or a tuned ring's
    per nodal diameter."""
    rpm = params.speed.rpm if rpm is None else rpm
    return solver("linear limits", params)(params, model, rpm, n_modes, coriolis, interface)


def static(params: Parameters, model: str, force, rpm: float | None = None) -> StaticResult:
    """Tip displacement under ``force`` (N, global X, Y, Z) at the blade tip, on top of the centrifugal
    state at ``rpm`` (default ``params.speed.rpm``): how stiff the model is, checked first (a ring: refused)."""
    return solver("static", params)(params, model, force, rpm)


def blade_static(params: Parameters, model: str, force, rpm: float | None) -> StaticResult:
    """The blade's :func:`static`."""
    rpm = params.speed.rpm if rpm is None else rpm
    entry = registry.model(model)
    if entry.static is None:
        raise InputError("--model", f"{model!r} has no static solve; allowed: {', '.join(registry.names('static'))}")
    return entry.static(params, rpm, tuple(float(f) for f in force))


def build_system(params: Parameters, model: str) -> StructuralSystem:
    """The linear structure plus contact points of ``model`` at ``params.speed.rpm``."""
    return registry.model(model).build_system(params)


def transient(params: Parameters, model: str, csv_path: Path | None = None):
    """One transient run (paper Sect. 2.1): returns a shroud.analysis.transient.TransientResult, or with
    ``ring.blades`` > 0 the whole ring's shroud.analysis.ring.RingTransientResult."""
    from shroud.analysis.checks import check_records
    check_records(params)                               # before a model that may take minutes to build
    return solver("transient", params)(params, model, csv_path=csv_path)


def sweep(params: Parameters, model: str, rpms):
    """Steady-state tip amplitude over speed in time: a shroud.core.results.SweepResult, or with
    ``ring.blades`` > 0 the ring's RingSweepResult (every blade's)."""
    return solver("sweep", params)(params, model, rpms)


def harmonic_balance(params: Parameters, model: str, rpm: float, harmonics: int, samples: int | None = None,
                     start=None, retry: bool = True, multipliers: bool = True):
    """The periodic steady state at one speed by harmonic balance: the blade's checkpoint
    (shroud.analysis.hb.checkpoint) or the ring's (shroud.analysis.ring_hb.ring_checkpoint)."""
    return solver("checkpoint", params)(params, model, rpm, harmonics, samples, start, retry, multipliers)


def continuation(params: Parameters, model: str, rpm_from: float, rpm_to: float, harmonics: int,
                 samples: int | None = None, min_points: int | None = None):
    """The steady-state branch by harmonic balance with continuation: the blade's HBResult
    (shroud.analysis.hb.run_hb) or the ring's RingHBResult (shroud.analysis.ring_hb.run_ring_hb)."""
    return solver("continuation", params)(params, model, rpm_from, rpm_to, harmonics, samples, min_points)


def compile_kernels(params: Parameters, models=("reduced",)) -> float:
    """Wall time (s) of one-period runs of ``models``, so later runs are timed at their steady cost.

    numba compiles (or loads from its disk cache) the integrator's kernels on
    a first run; a short run that diverges has compiled them all the same.
    """
    from shroud.analysis.transient import run
    short = params.updated({"time.periods": 1})
    t0 = time.perf_counter()
    for model in dict.fromkeys(models):
        run(build_system(short, model), short)
    return time.perf_counter() - t0
