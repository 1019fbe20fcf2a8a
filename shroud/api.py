"""The workbench as a library: one call per analysis, each returning a results object.

The command line (``shroud modal``, ``transient``, ``sweep``, ...) and the
studies are built on these calls; a script needs nothing else::

    from shroud import api

    p = api.parameters({"speed.rpm": 8500.0})                  # validated once
    modes = api.modal(p, "reduced", n_modes=4)                 # ModalResult
    tip = api.static(p, "reduced", force=(0.0, 100.0, 0.0))    # StaticResult: tip displacement, m
    run = api.transient(p.updated({"speed.rpm": 10000.0}), "reduced")   # TransientResult
    point = api.harmonic_balance(p, "reduced", rpm=10000.0)    # Checkpoint: one speed
    branch = api.continuation(p, "reduced", 5000.0, 20000.0)   # HBResult: a branch with stability
    curve = api.sweep(p, "reduced", [8000.0, 8500.0, 9000.0])  # SweepResult: time domain
    ring = api.parameters({"ring.blades": 12}, base=p)         # a ring of 12 blades (geometry.md)
    limits = api.linear_limits(ring, "reduced", interface="stuck")   # per nodal diameter
    wave = api.continuation(ring, "reduced", 5000.0, 12000.0)  # the tuned ring by one sector

Every result serializes itself (``to_json``) and the branch and curves draw
themselves (``plot``). Models are looked up by name in the core's registry
(:func:`models` lists them): the installed builders declare theirs
(``reduced``, ``full``, ``extended`` from ``reduced_model``; ``fe``,
``fe-reduced`` from ``reference_fe``), and :func:`register_model` adds a
user's own: a :class:`ModelEntry` whose ``build_system(params)`` returns a
:class:`StructuralSystem` (M, C, K, loads) with its :class:`ContactElements`
(examples/hb_friction_oscillator.py). Units: SI, speeds in r/min.

>>> "reduced" in models()
True
>>> round(parameters({"speed.rpm": 8500.0}).speed.omega, 3)
890.118
"""

from __future__ import annotations

from pathlib import Path
from typing import Any, Mapping, Sequence

from shroud.analysis import api as _analysis
from shroud.analysis import hb as _hb
from shroud.analysis.systems import solver
from shroud.core import registry as _registry
from shroud.core.registry import ModelEntry
from shroud.core.results import ModalResult, RingSweepResult, StaticResult, SweepResult
from shroud.core.system import ContactElements, StructuralSystem
from shroud.params import Parameters

__all__ = ["ContactElements", "ModelEntry", "Parameters", "StructuralSystem", "build_system", "check_in_time", "continuation", "harmonic_balance", "modal", "models",
           "linear_limits", "parameters", "register_model", "static", "sweep", "transient"]


def parameters(values: Mapping[str, Any] | None = None, base: Parameters | None = None) -> Parameters:
    """The paper's defaults (or ``base``) with ``values`` set: dotted keys (``{"contact.gap": 1e-4}``)
    or tables (``{"contact": {"gap": 1e-4}}``); validated here, once (InputError names a bad key)."""
    base = base or Parameters()
    values = dict(values or {})
    if any(isinstance(v, Mapping) for v in values.values()):
        return Parameters.from_mapping(values, base=base)
    return base.updated(values)


def models(capability: str = "transient") -> tuple[str, ...]:
    """Names of the registered models offering ``capability`` ("transient", "modal" or "sweep")."""
    return _registry.names(capability)


def register_model(entry: ModelEntry) -> None:
    """Make a model of one's own known to every analysis (it replaces one of the same name)."""
    _registry.register(entry)


def build_system(params: Parameters, model: str) -> StructuralSystem:
    """``model``'s linear part (M, C, K, loads) plus its contact elements at ``params.speed.rpm`` (the blade's;
    a ring: refused, shroud.analysis.systems)."""
    return solver("system", params)(params, model)


def modal(params: Parameters, model: str, rpm: float | None = None, n_modes: int = 6,
          coriolis: bool = True) -> ModalResult:
    """Natural frequencies (Hz) at ``rpm`` (default ``params.speed.rpm``), labelled by tip kinematics."""
    return _analysis.modal(params, model, rpm, n_modes, coriolis)


def static(params: Parameters, model: str, force: Sequence[float], rpm: float | None = None) -> StaticResult:
    """Tip displacement (m) under ``force`` (N, global X, Y, Z) at the blade tip, on top of the centrifugal
    state at ``rpm`` (default ``params.speed.rpm``)."""
    return _analysis.static(params, model, force, rpm)


def linear_limits(params: Parameters, model: str, interface: str = "stuck", rpm: float | None = None,
                  n_modes: int = 6, coriolis: bool = True):
    """The contact's linear limits: modes with no contact springs (``interface="free"``) or with every
    contact point as springs k_n, k_t (``"stuck"``); with ``ring.blades = N``, per nodal diameter."""
    return _analysis.linear_limits(params, model, rpm, n_modes, coriolis, interface)


def transient(params: Parameters, model: str, csv_path: Path | None = None):
    """One Newmark run with impact and friction (paper Sect. 2): a TransientResult (with
    ``ring.blades = N``, the whole ring's)."""
    return _analysis.transient(params, model, csv_path)


def sweep(params: Parameters, model: str, rpms: Sequence[float]) -> SweepResult | RingSweepResult:
    """Settled steady-state tip amplitude at each speed of ``rpms`` (r/min), in the time domain (with
    ``ring.blades = N``, the ring's: every blade's)."""
    return _analysis.sweep(params, model, rpms)


def harmonic_balance(params: Parameters, model: str, rpm: float, harmonics: int = _hb.DEFAULT_HARMONICS,
                     samples: int | None = None, start=None, retry: bool = True,
                     multipliers: bool = True) -> _hb.Checkpoint:
    """The periodic steady state at one speed by harmonic balance, with its Floquet stability
    (shroud.analysis.hb.checkpoint: ``start`` the harmonics Newton begins from, ``retry`` from the linear
    starts where it fails from there, ``multipliers=False`` without stability); with ``ring.blades = N``,
    the ring's (one sector when tuned, the whole ring when mistuned: ``blades_amplitude_v_L``). Read
    ``converged`` before the amplitudes: where Newton did not converge they are no answer; then ``stable``:
    a ring's state decided unstable is not the ring's response (``shroud sweep --checkpoints`` refuses it,
    shroud.analysis.hb.ring_steady_states)."""
    return _analysis.harmonic_balance(params, model, rpm, harmonics, samples, start, retry, multipliers)


def continuation(params: Parameters, model: str, rpm_from: float, rpm_to: float,
                 harmonics: int = _hb.DEFAULT_HARMONICS, min_points: int | None = None):
    """The steady-state branch from ``rpm_from`` to ``rpm_to`` by harmonic balance with continuation: an
    HBResult; with ``ring.blades = N``, the ring's (one sector when tuned, the whole ring when mistuned)."""
    return _analysis.continuation(params, model, rpm_from, rpm_to, harmonics, min_points=min_points)


def check_in_time(params: Parameters, model: str, result, points, periods: int = _hb.IN_TIME_PERIODS):
    """Start the project's integrator on branch points ``points`` (indices) of the HBResult ``result`` and
    run ``periods`` periods: per point a shroud.core.period_map.InTime whose verdict answers "stays" or
    "leaves" (shroud.analysis.hb.check_in_time; a ring is refused, shroud.analysis.systems)."""
    return solver("check in time", params)(params, model, result, points, periods)
