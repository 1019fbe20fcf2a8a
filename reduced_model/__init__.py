"""Reduced Timoshenko-beam model of the twisted shrouded blade (paper Sect. 2.1).

numpy/scipy/numba only: importing it never loads DOLFINx or gmsh. Importing
the package registers its two models with the core:

* ``full``: the Galerkin beam, 5 fields x N shape functions (5N DOF);
* ``reduced``: its free-interface reduction to ``reduced.nr`` modes.
"""

from shroud.core.registry import ModelEntry, lazy, register

register(ModelEntry("reduced", build_system=lazy("reduced_model.system", "build_system", reduced=True),
                    modal=lazy("reduced_model.modal", "modal_analysis"),
                    description="beam reduced to reduced.nr free-interface modes"))
register(ModelEntry("full", build_system=lazy("reduced_model.system", "build_system", reduced=False),
                    description="Galerkin beam, 5N DOF"))
