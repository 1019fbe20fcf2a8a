"""The analyses behind the command line, one function each.

Only the model a call names is imported: a reduced-model call never loads
DOLFINx or gmsh.
"""

from __future__ import annotations

import time
from pathlib import Path

from shroud.params import Parameters
from shroud.results import ModalResult
from shroud.system import StructuralSystem

MODAL_MODELS = ("reduced", "fe")
TRANSIENT_MODELS = ("reduced", "full", "fe", "fe-reduced")
SWEEP_MODELS = ("reduced", "full", "fe-reduced")


def modal(params: Parameters, model: str, rpm: float | None = None, n_modes: int = 6,
          coriolis: bool = True) -> ModalResult:
    """Natural frequencies at ``rpm`` (default ``params.speed.rpm``), labelled by tip kinematics."""
    rpm = params.speed.rpm if rpm is None else rpm
    if model == "reduced":
        from reduced_model.modal import modal_analysis
    else:
        from reference_fe.modal import modal_analysis
    return modal_analysis(params, rpm=rpm, n_modes=n_modes, coriolis=coriolis)


def build_system(params: Parameters, model: str) -> StructuralSystem:
    """The linear structure plus contact points of ``model`` at ``params.speed.rpm``."""
    if model in ("reduced", "full"):
        from reduced_model.system import build_system as build
    else:
        from reference_fe.system import build_system as build
    return build(params, reduced=model in ("reduced", "fe-reduced"))


def transient(params: Parameters, model: str, csv_path: Path | None = None):
    """One transient run (paper Sect. 2.1): returns a shroud.transient.TransientResult."""
    from shroud.transient import simulate
    return simulate(build_system(params, model), params, csv_path=csv_path)


def sweep(params: Parameters, model: str, rpms):
    """Steady-state tip amplitude over speed: returns a shroud.sweep.SweepResult."""
    from shroud.sweep import run_sweep
    return run_sweep(params, model, rpms)


def compile_kernels(params: Parameters, models=("reduced",)) -> float:
    """Wall time (s) of one-period runs of ``models``, so later runs are timed at their steady cost.

    numba compiles (or loads from its disk cache) the integrator's kernels on
    a first run; a short run that diverges has compiled them all the same.
    """
    from shroud.transient import run
    short = params.updated({"time.periods": 1})
    t0 = time.perf_counter()
    for model in dict.fromkeys(models):
        run(build_system(short, model), short)
    return time.perf_counter() - t0
