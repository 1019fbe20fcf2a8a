"""Figs. 16-17: the contact stiffness ratio xi = kt / kn over gaps and preloads.

Paper (Sect. 3.3, mu 0.3, kn 1e7 N/m): at gaps >= 100 um xi has almost no
effect; with a 1 um gap or a preload the resonant speed rises and the
resonant amplitude falls as xi grows; the optimal preload is unaffected.
"""

from __future__ import annotations

from comparisons import friction
from comparisons._study import study

OPTIONS = {**friction.OPTIONS, "values": [0.2, 0.5, 1.0]}


def compute(scene) -> friction.FamilyComparison:
    """The stiffness ratio's variants (kt = xi kn over ``values``) over the gap and preload cases."""
    kn = scene.params.contact.kn
    base = {f"xi {v:g}": scene.params.updated({"contact.kt": v * kn}) for v in scene.options["values"]}
    return friction.compute_variants(scene, base, "the stiffness ratio xi")


plot, report = friction.plot, friction.report
run = study(compute, plot, report)
