"""The solid models this package offers, declared to the core's registry.

``pyproject.toml`` names :data:`MODELS` under the entry-point group
``shroud.models``; the registry reads it on its first look-up, without
loading DOLFINx (that happens when a model is built).

* ``fe``: the full solid, quadratic cells, one contact element per face node;
  by harmonic balance condensed exactly on its contact coordinates per
  harmonic (reference_fe.harmonic), its Newton started from fe-reduced, its
  Floquet multipliers those of its own orbit with the perturbations on
  fe-reduced's basis (at 1x and 2x the kept modes);
* ``fe-reduced``: its free-interface component-mode-synthesis reduction, which
  also offers one basis for a speed range (``at_speed``, reference_fe.frequency);
* ``shell``, ``shell-reduced``: the Reissner-Mindlin shell of the blade's
  mid-surface (reference_fe.shell) and its reduction, on the same pieces.
"""

from shroud.core.registry import ModelEntry, lazy


def twice_the_modes(params):
    """The reduced solid with twice its kept normal modes (the same contact-face patterns)."""
    return params.updated({"fe.cms_modes": 2 * params.fe.cms_modes})


def twice_the_shell_modes(params):
    """The reduced shell with twice its kept normal modes."""
    return params.updated({"shell.cms_modes": 2 * params.shell.cms_modes})


MODELS = (
    ModelEntry("fe", build_system=lazy("reference_fe.system", "build_system", reduced=False),
               modal=lazy("reference_fe.modal", "modal_analysis"), sweepable=False,
               linear_harmonics=lazy("reference_fe.harmonic", "condensed_at"), reduced_by="fe-reduced",
               static=lazy("reference_fe.static", "static_response", kind="fe"),
               disk_sector=lazy("reference_fe.cyclic", "sector_modal"),
               description="full solid, quadratic cells"),
    ModelEntry("fe-reduced", build_system=lazy("reference_fe.system", "build_system", reduced=True),
               at_speed=lazy("reference_fe.frequency", "at_speed"), refined=twice_the_modes,
               contact_points=lazy("reference_fe.contact_map", "contact_points"),
               description="solid reduced by free-interface CMS"),
    ModelEntry("shell", build_system=lazy("reference_fe.system", "build_system", reduced=False, kind="shell"),
               modal=lazy("reference_fe.modal", "modal_analysis", kind="shell"), sweepable=False,
               linear_harmonics=lazy("reference_fe.harmonic", "condensed_at", kind="shell"),
               static=lazy("reference_fe.static", "static_response", kind="shell"),
               reduced_by="shell-reduced", description="Reissner-Mindlin shell of the mid-surface, P2/CR"),
    ModelEntry("shell-reduced", build_system=lazy("reference_fe.system", "build_system", reduced=True, kind="shell"),
               at_speed=lazy("reference_fe.frequency", "at_speed", kind="shell"), refined=twice_the_shell_modes,
               description="shell reduced by free-interface CMS"),
)
