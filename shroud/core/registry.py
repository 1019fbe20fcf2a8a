"""The models the workbench knows, registered by their builders.

The core never imports a model builder. Builders declare their models in
the project's metadata (``pyproject.toml``, entry-point group
``shroud.models``: ``reduced_model.models:MODELS``,
``reference_fe.models:MODELS``), each a tuple of :class:`ModelEntry` whose
functions load their heavy stack (DOLFINx, gmsh) only when called; the
registry reads them on the first look-up. A user's own model is one
:func:`register` call (``shroud.api.register_model``). Analyses look models
up by name, so a new model is a new registration, not an edit of the core.

A model offers a builder of its linear structure plus contact elements at a
constant speed (``build_system(params) -> StructuralSystem``) and, where it
has one, a modal analysis (``modal(params, rpm, n_modes, coriolis) ->
ModalResult``). ``params`` is the validated parameter set; the core only
passes it through.
"""

from __future__ import annotations

import importlib
import importlib.metadata
import sys
from dataclasses import dataclass
from typing import Any, Callable

from shroud.core.system import StructuralSystem


@dataclass(frozen=True)
class ModelEntry:
    """One registered model."""

    name: str                                         # "reduced", "full", "fe", "fe-reduced"
    build_system: Callable[[Any], StructuralSystem]   # params -> StructuralSystem at params.speed.rpm
    modal: Callable[..., Any] | None = None           # (params, rpm, n_modes, coriolis) -> ModalResult
    sweepable: bool = True                            # cheap enough to rebuild at every speed of a sweep
    description: str = ""
    # params -> (rpm -> StructuralSystem): the system at any speed without a
    # rebuild per speed (e.g. operators as polynomials in Omega on one basis),
    # for continuation in speed; None: build_system at each speed.
    at_speed: Callable[[Any], Callable[[float], StructuralSystem]] | None = None
    # (params, rpm, H) -> (StructuralSystem, shroud.core.harmonic_balance.LinearHarmonics): the model's own
    # linear part per harmonic (a large sparse model condensed on its contact coordinates by its own
    # solver); None: the core's dense one.
    linear_harmonics: Callable[[Any, float, int], tuple] | None = None
    # A model on the same contact coordinates whose harmonic-balance states start this one's Newton, and
    # on whose basis the perturbations of this one's orbit are projected for its Floquet multipliers.
    reduced_by: str | None = None
    # params -> the parameters of this model on a larger basis (a reduction's convergence check)
    refined: Callable[[Any], Any] | None = None
    # (params, rpm, force (3,) N along X, Y, Z) -> shroud.core.results.StaticResult: the static response
    # to a force at the blade tip on top of the centrifugal state; None: the model has no static solve.
    static: Callable[..., Any] | None = None
    # params -> (points (k, 3) m, normal (3,)): where each contact element sits (in the contact elements'
    # order) and the faces' normal e_vs, for a ring to pair each side-2 point with the neighbour's
    # side-1 point it touches (shroud.core.ring.paired_by_position); None: the builder lists both faces'
    # points in the same order (the beams).
    contact_points: Callable[[Any], tuple] | None = None
    # (params, rpm, n_modes, coriolis, interface) -> [(nd, ModalResult)] for nd = 0 .. N // 2: the modes per nodal
    # diameter of the model's cyclic sector of blade and flexible disk (disk.thickness > 0); None: the
    # model has no disk.
    disk_sector: Callable[..., Any] | None = None


ENTRY_POINTS = "shroud.models"          # the metadata group where builders declare their models

_MODELS: dict[str, ModelEntry] = {}          # registered at run time (they win over declared ones)
_REGISTERED_BY: dict[str, str] = {}           # model name -> the module whose import registered it
_DECLARED: dict[str, ModelEntry] | None = None   # read from the installed builders' metadata, once


def _declared() -> dict[str, ModelEntry]:
    """The models the installed builders declare under :data:`ENTRY_POINTS`."""
    global _DECLARED
    if _DECLARED is None:
        _DECLARED = {entry.name: entry for point in importlib.metadata.entry_points(group=ENTRY_POINTS)
                     for entry in point.load()}
    return _DECLARED


def _all() -> dict[str, ModelEntry]:
    return {**_declared(), **_MODELS}


def lazy(module: str, function: str, **fixed) -> Callable:
    """``module.function(*args, **fixed, **kwargs)``, importing ``module`` only when called.

    Lets a builder package register its models without loading its stack
    (DOLFINx, gmsh) until a model is built.
    """
    def call(*args, **kwargs):
        return getattr(importlib.import_module(module), function)(*args, **fixed, **kwargs)
    call.__qualname__ = f"lazy({module}.{function})"
    return call


def register(entry: ModelEntry) -> None:
    """Make ``entry`` known by its name (it replaces a declared or earlier model of that name)."""
    _MODELS[entry.name] = entry
    frame = sys._getframe(1)
    while frame is not None and frame.f_globals.get("__name__") == "shroud.api":   # api.register_model's caller
        frame = frame.f_back
    _REGISTERED_BY[entry.name] = frame.f_globals.get("__name__", "") if frame is not None else ""


def packages() -> tuple[str, ...]:
    """The modules whose import registered models at run time: what a fresh worker process imports to
    know the same models (shroud.base.parallel.map_parallel's ``preload``); the declared ones it reads
    from the installed metadata itself."""
    return tuple(sorted({m for m in _REGISTERED_BY.values() if m and m != "__main__"}))


def model(name: str) -> ModelEntry:
    """The entry registered as ``name``; KeyError naming the known models otherwise."""
    try:
        return _all()[name]
    except KeyError:
        raise KeyError(f"no model {name!r} is registered (known: {', '.join(_all()) or 'none'}); "
                       f"builders declare theirs under the entry-point group {ENTRY_POINTS!r}: "
                       "is the project installed (pip install -e .)?") from None


def names(capability: str = "transient") -> tuple[str, ...]:
    """Registered model names that offer ``capability``: "transient", "modal", "static" or "sweep"."""
    models = _all()
    if capability == "modal":
        return tuple(n for n, e in models.items() if e.modal is not None)
    if capability == "static":
        return tuple(n for n, e in models.items() if e.static is not None)
    if capability == "sweep":
        return tuple(n for n, e in models.items() if e.sweepable)
    return tuple(models)
