"""Reduced Timoshenko-beam model of the twisted shrouded blade (paper Sect. 2.1).

numpy/scipy/numba only: importing it never loads DOLFINx or gmsh. Importing
the package registers its two models with the core:

* ``full``: the Galerkin beam, 5 fields x N shape functions (5N DOF);
* ``reduced``: its free-interface reduction to ``reduced.nr`` modes.
"""

from shroud.core.registry import ModelEntry, register


def _modal(params, rpm, n_modes, coriolis):
    from reduced_model.modal import modal_analysis
    return modal_analysis(params, rpm=rpm, n_modes=n_modes, coriolis=coriolis)


def _builder(reduced: bool):
    def build(params):
        from reduced_model.system import build_system
        return build_system(params, reduced=reduced)
    return build


def _at_speed(reduced: bool):
    def at_speed(params):
        from reduced_model.system import at_speed
        return at_speed(params, reduced=reduced)
    return at_speed


register(ModelEntry("reduced", build_system=_builder(True), modal=_modal, at_speed=_at_speed(True),
                    description="beam reduced to reduced.nr free-interface modes"))
register(ModelEntry("full", build_system=_builder(False), at_speed=_at_speed(False),
                    description="Galerkin beam, 5N DOF"))
