"""The beam models this package offers, declared to the core's registry.

``pyproject.toml`` names :data:`MODELS` under the entry-point group
``shroud.models``; the registry reads it on its first look-up. Each
builder loads its module only when called.

* ``full``: the Galerkin beam, 5 fields x N shape functions (5N DOF), 6N with reduced.torsion;
* ``reduced``: its free-interface reduction to ``reduced.nr`` modes;
* ``extended``: the reduced beam with the twist field and the rigid shroud
  (``reduced.torsion = true``, ``reduced.shroud = "rigid"`` whatever the
  parameters say): the beam that matches the solid (reduced_model.beam).

Each also offers ``at_speed(params) -> (rpm -> StructuralSystem)`` for
continuation in speed (shroud.core.continuation).
"""

import dataclasses

from shroud.core.registry import ModelEntry, lazy

EXTENDED = {"reduced.torsion": True, "reduced.shroud": "rigid"}   # what makes the "extended beam"


def _named_extended(system):
    return dataclasses.replace(system, model="extended")


def _extended(function):
    """``function`` called on the extended beam's parameters, its result named "extended"."""
    def call(params, *args):
        return _named_extended(function(params.updated(EXTENDED), *args))
    return call


def _extended_at_speed(params):
    systems = lazy("reduced_model.system", "at_speed", reduced=True)(params.updated(EXTENDED))
    return lambda rpm: _named_extended(systems(rpm))


def _extended_static(params, rpm, force):
    return lazy("reduced_model.static", "static_response", name="extended")(params.updated(EXTENDED), rpm, force)


MODELS = (
    ModelEntry("reduced", build_system=lazy("reduced_model.system", "build_system", reduced=True),
               modal=lazy("reduced_model.modal", "modal_analysis"),
               static=lazy("reduced_model.static", "static_response"),
               at_speed=lazy("reduced_model.system", "at_speed", reduced=True),
               description="beam reduced to reduced.nr free-interface modes"),
    ModelEntry("full", build_system=lazy("reduced_model.system", "build_system", reduced=False),
               at_speed=lazy("reduced_model.system", "at_speed", reduced=False),
               description="Galerkin beam, 5N DOF (6N with reduced.torsion)"),
    ModelEntry("extended", build_system=_extended(lazy("reduced_model.system", "build_system", reduced=True)),
               modal=_extended(lazy("reduced_model.modal", "modal_analysis")),
               static=_extended_static,
               at_speed=_extended_at_speed,
               description="beam with torsion and a rigid shroud, reduced to reduced.nr modes"),
)
