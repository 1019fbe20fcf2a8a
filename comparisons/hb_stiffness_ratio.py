"""Figs. 16-17 by harmonic balance: the contact stiffness ratio xi = kt / kn over gaps and preloads.

The branches, the resonance followed in N0 and the time-domain overlay of
comparisons.hb_friction, per xi (paper: 0.2, 0.5, 1 with kn = 1e7 N/m,
mu 0.3). The paper's conclusions (Sect. 3.3): xi hardly matters at gaps
>= 100 um; with a 1 um gap or a preload the resonant speed rises and the
resonant amplitude falls as xi grows; the optimal preload is unaffected;
once the shroud stays stuck through the resonance the preload no longer
matters.
"""

from __future__ import annotations

from pathlib import Path

from comparisons import hb_friction

OPTIONS = {**hb_friction.OPTIONS, "values": [0.2, 0.5, 1.0]}
check = hb_friction.check


def run(scene, out: Path) -> dict:
    kn = scene.params.contact.kn
    variants = {f"xi {v:g}": scene.params.updated({"contact.kt": v * kn}) for v in scene.options["values"]}
    return hb_friction.run_variants(scene, out, variants, "xi")
