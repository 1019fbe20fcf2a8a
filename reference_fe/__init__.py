"""3D solid FE reference of the shrouded blade on DOLFINx 0.11 (PETSc/SLEPc).

Importing the package registers its models with the core without loading
DOLFINx (that happens when one is built):

* ``fe``: the full solid, quadratic cells, one contact element per face node;
  by harmonic balance condensed exactly on its contact coordinates per
  harmonic (reference_fe.harmonic), its Newton started from fe-reduced;
* ``fe-reduced``: its free-interface component-mode-synthesis reduction, which
  also offers one basis for a speed range (``at_speed``, reference_fe.frequency).
"""

from shroud.core.registry import ModelEntry, lazy, register

register(ModelEntry("fe", build_system=lazy("reference_fe.system", "build_system", reduced=False),
                    modal=lazy("reference_fe.modal", "modal_analysis"), sweepable=False,
                    linear_harmonics=lazy("reference_fe.harmonic", "condensed_at"), reduced_by="fe-reduced",
                    description="full solid, quadratic cells"))
register(ModelEntry("fe-reduced", build_system=lazy("reference_fe.system", "build_system", reduced=True),
                    at_speed=lazy("reference_fe.frequency", "at_speed"),
                    description="solid reduced by free-interface CMS"))
