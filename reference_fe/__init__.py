"""3D solid FE reference of the shrouded blade on DOLFINx 0.11 (PETSc/SLEPc).

Importing the package registers its models with the core without loading
DOLFINx (that happens when one is built):

* ``fe``: the full solid, quadratic cells, one contact element per face node;
* ``fe-reduced``: its free-interface component-mode-synthesis reduction.
"""

from shroud.core.registry import ModelEntry, register


def _modal(params, rpm, n_modes, coriolis):
    from reference_fe.modal import modal_analysis
    return modal_analysis(params, rpm=rpm, n_modes=n_modes, coriolis=coriolis)


def _builder(reduced: bool):
    def build(params):
        from reference_fe.system import build_system
        return build_system(params, reduced=reduced)
    return build


register(ModelEntry("fe", build_system=_builder(False), modal=_modal, sweepable=False,
                    description="full solid, P2 cells"))
def _at_speed(params):
    from reference_fe.frequency import at_speed
    return at_speed(params)


register(ModelEntry("fe-reduced", build_system=_builder(True), at_speed=_at_speed,
                    description="solid reduced by free-interface CMS"))
