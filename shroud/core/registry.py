"""The models the workbench knows, registered by their builders.

The core never imports a model builder: ``reduced_model`` and
``reference_fe`` each call :func:`register` when their package is imported,
with functions that load their heavy stack (DOLFINx, gmsh) only when called.
Analyses look models up by name, so a new model is a new registration, not
an edit of the core.

A model offers a builder of its linear structure plus contact elements at a
constant speed (``build_system(params) -> StructuralSystem``) and, where it
has one, a modal analysis (``modal(params, rpm, n_modes, coriolis) ->
ModalResult``). ``params`` is the validated parameter set; the core only
passes it through.
"""

from __future__ import annotations

import importlib
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


_MODELS: dict[str, ModelEntry] = {}


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
    """Make ``entry`` known by its name (a second registration of a name replaces the first)."""
    _MODELS[entry.name] = entry


def model(name: str) -> ModelEntry:
    """The entry registered as ``name``; KeyError naming the known models otherwise."""
    try:
        return _MODELS[name]
    except KeyError:
        raise KeyError(f"no model {name!r} is registered (known: {', '.join(_MODELS) or 'none'}); "
                       "a builder package registers its models when it is imported") from None


def names(capability: str = "transient") -> tuple[str, ...]:
    """Registered model names that offer ``capability``: "transient", "modal", "static" or "sweep"."""
    if capability == "modal":
        return tuple(n for n, e in _MODELS.items() if e.modal is not None)
    if capability == "static":
        return tuple(n for n, e in _MODELS.items() if e.static is not None)
    if capability == "sweep":
        return tuple(n for n, e in _MODELS.items() if e.sweepable)
    return tuple(_MODELS)
