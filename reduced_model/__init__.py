"""Reduced Timoshenko-beam model of the twisted shrouded blade (paper Sect. 2.1).

numpy/scipy/numba only: importing it never loads DOLFINx or gmsh. Importing
the package registers its models with the core:

* ``full``: the Galerkin beam, 5 fields x N shape functions (5N DOF), 6N with reduced.torsion;
* ``reduced``: its free-interface reduction to ``reduced.nr`` modes;
* ``extended``: the reduced beam with the twist field and the rigid shroud
  (``reduced.torsion = true``, ``reduced.shroud = "rigid"`` whatever the
  parameters say): the beam that matches the solid (reduced_model.beam).
"""

import dataclasses

from shroud.core.registry import ModelEntry, register

EXTENDED = {"reduced.torsion": True, "reduced.shroud": "rigid"}   # what makes the "extended beam"


def _modal(overrides: dict, name: str | None = None):
    def modal(params, rpm, n_modes, coriolis):
        from reduced_model.modal import modal_analysis
        result = modal_analysis(params.updated(overrides), rpm=rpm, n_modes=n_modes, coriolis=coriolis)
        return dataclasses.replace(result, model=name) if name else result
    return modal


def _builder(reduced: bool, overrides: dict, name: str | None = None):
    def build(params):
        from reduced_model.system import build_system
        system = build_system(params.updated(overrides), reduced=reduced)
        return dataclasses.replace(system, model=name) if name else system
    return build


register(ModelEntry("reduced", build_system=_builder(True, {}), modal=_modal({}),
                    description="beam reduced to reduced.nr free-interface modes"))
register(ModelEntry("full", build_system=_builder(False, {}),
                    description="Galerkin beam, 5N DOF (6N with reduced.torsion)"))
register(ModelEntry("extended", build_system=_builder(True, EXTENDED, "extended"),
                    modal=_modal(EXTENDED, "extended"),
                    description="beam with torsion and a rigid shroud, reduced to reduced.nr modes"))
