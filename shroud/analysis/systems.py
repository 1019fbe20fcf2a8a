"""The one dispatch: which system a call solves, and the function that solves it (docs/ring.md).

``ring.blades = 0`` is the paper's blade between fixed neighbours;
``ring.blades = N`` a ring of N blades, tuned (every d_j = 0) or mistuned.
Every command and API call asks :func:`solver` for its analysis: it gets
the function that solves that system, or an InputError on ``ring.blades``
(one line, exit 2) naming what is not supported and what is allowed. No
path solves the blade where a ring was asked for.

| analysis | blade | tuned ring | mistuned ring |
|---|---|---|---|
| transient | the blade | the ring in time | the ring in time |
| sweep (time) | the blade | the ring in time, every blade | the same |
| checkpoint (HB, one speed) | the blade | one sector | the whole ring |
| continuation (HB) | the blade | one sector | the whole ring |
| continuation to a tail | the blade | refused | refused |
| modal | the blade | refused: ``--interface`` | refused |
| linear limits | the blade | per nodal diameter | refused (on ring.mistuning) |
| check in time (HB states started in time) | the blade | refused | refused |
| static | the blade | refused | refused |
| system (api.build_system) | the blade | refused | refused |
"""

from __future__ import annotations

import importlib
from typing import Callable

from shroud.base.errors import InputError
from shroud.params import Parameters

BLADE, TUNED_RING, MISTUNED_RING = "blade", "tuned ring", "mistuned ring"
RINGS = (TUNED_RING, MISTUNED_RING)


def system_of(params: Parameters) -> str:
    """The system ``params`` describe: BLADE, TUNED_RING or MISTUNED_RING."""
    if not params.ring.blades:
        return BLADE
    return TUNED_RING if params.ring.tuned else MISTUNED_RING


def _every(blade: str, ring: str | None) -> dict[str, str | None]:
    return {BLADE: blade, TUNED_RING: ring, MISTUNED_RING: ring}


# analysis -> system -> "module:function" solving it (None: refused, REFUSED says why and what is allowed)
SOLVERS: dict[str, dict[str, str | None]] = {
    "transient": _every("shroud.analysis.transient:simulate_model", "shroud.analysis.ring:simulate_ring"),
    "sweep": _every("shroud.analysis.sweep:run_sweep", "shroud.analysis.ring:run_ring_sweep"),
    "checkpoint": _every("shroud.analysis.hb:checkpoint", "shroud.analysis.ring_hb:ring_checkpoint"),
    "continuation": _every("shroud.analysis.hb:run_hb", "shroud.analysis.ring_hb:run_ring_hb"),
    "continuation to a spectral tail": _every("shroud.analysis.hb:run_hb_to_tail", None),
    "modal": _every("shroud.analysis.api:blade_modal", None),
    "linear limits": _every("shroud.analysis.limits:interface_modal",       # it refuses a mistuned ring itself
                            "shroud.analysis.limits:interface_modal"),
    "check in time": _every("shroud.analysis.hb:check_in_time", None),
    "static": _every("shroud.analysis.api:blade_static", None),
    "system": _every("shroud.analysis.api:build_system", None),
}
REFUSED: dict[str, tuple[str, str]] = {      # analysis -> (why a ring is not solved, what is allowed)
    "continuation to a spectral tail": ("a ring's branch is solved at one H",
                                        "--harmonics (api: continuation) with ring.blades"),
    "modal": ("these are one blade's modes without its neighbours",
              "the ring's per nodal diameter: modal --interface free or stuck (api: linear_limits)"),
    "check in time": ("the integrator is started on one blade's HB state (shroud.analysis.hb.startable)",
                      "ring.blades = 0; the ring in time from rest: transient"),
    "static": ("a tip force on one blade is solved without its neighbours", "ring.blades = 0"),
    "system": ("a ring's travelling-wave load has no single StructuralSystem",
               "ring.blades = 0; the ring's blades: shroud.analysis.ring.build_ring"),
}


def solver(analysis: str, params: Parameters) -> Callable:
    """The function that runs ``analysis`` (a key of SOLVERS) on the system ``params`` describe; InputError
    on ``ring.blades`` where that system is not supported there."""
    system = system_of(params)
    path = SOLVERS[analysis][system]
    if path is None:
        why, allowed = REFUSED[analysis]
        raise InputError("ring.blades", f"{analysis} of a {system} of {params.ring.blades} blades is not "
                                        f"supported ({why}); allowed: {allowed}")
    module, name = path.split(":")
    return getattr(importlib.import_module(module), name)
