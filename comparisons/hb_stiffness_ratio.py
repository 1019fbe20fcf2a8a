"""Figs. 16-17 by harmonic balance: the contact stiffness ratio xi = kt / kn over gaps and preloads.

The branches, the resonance followed in N0 and the time-domain overlay of
comparisons.hb_friction, per xi (paper: 0.2, 0.5, 1 with kn = 1e7 N/m,
mu 0.3). The paper's conclusions (Sect. 3.3): xi hardly matters at gaps
>= 100 um; with a 1 um gap or a preload the resonant speed rises and the
resonant amplitude falls as xi grows; the optimal preload is unaffected;
once the shroud stays stuck through the resonance the preload no longer
matters.

Where the resonant speed does not rise with xi, the report says why from
the resonant orbits themselves: the contact's share of slip, and the
first-harmonic tangential stiffness k' = -Re(F_1 / w_1) the friction
element shows along the orbit, beside the closed form of a Jenkins element
at the same amplitude (shroud.core.contact.harmonic_stiffness), which
falls as kt grows once the element slides.

The study is comparisons.hb_friction's (compute -> :class:`comparisons.hb_friction.HBFamilyResult` -> plot ->
report) over xi, the friction elements at the tracked resonances computed with it (its ``explanation``) and
explained after its report.
"""

from __future__ import annotations

import numpy as np

from comparisons import hb_friction
from comparisons._study import study
from shroud.analysis.hb import model_at_speed
from shroud.analysis.transient import contact_law_for
from shroud.base.markdown import markdown_table
from shroud.core import harmonic_balance as hb
from shroud.core.contact import KN, KT, MU, harmonic_stiffness
from shroud.core.states import SEPARATE, SLIP

OPTIONS = {**hb_friction.OPTIONS, "values": [0.2, 0.5, 1.0]}
check = hb_friction.check


def compute(scene) -> hb_friction.HBFamilyResult:
    """The stiffness ratio's variants (kt = xi kn over ``values``), with side 1's friction element along every
    tracked resonance at the preloads (:func:`friction_at_resonance`) as its explanation."""
    kn, opts = scene.params.contact.kn, scene.options
    variants = {f"xi {v:g}": scene.params.updated({"contact.kt": v * kn}) for v in opts["values"]}
    return hb_friction.compute_variants(scene, variants, "xi", explain=lambda done: friction_rows(done, opts))


plot = hb_friction.plot


def report(result: hb_friction.HBFamilyResult, scene, files: list[str]) -> str:
    """comparisons.hb_friction's report, then why the resonant speed need not rise with xi."""
    return hb_friction.report(result, scene, files) + "".join(
        line + "\n" for line in explain(result.explanation, result.conclusions()))


def friction_at_resonance(variant, case: str, value: float, params, opts: dict) -> dict | None:
    """Side 1's friction element along the tracked resonant orbit at preload ``value`` (N): the first
    harmonic's tangential amplitude (m), the share of its contact time in slip, and k' (N/m) measured
    along the orbit and by the closed form at the same amplitude with N = N0."""
    curve = variant.preload.curve
    i = curve.index(value)
    if i is None:
        return None
    H, n = curve.harmonics, curve.samples
    system = model_at_speed(params, opts["model"])(float(curve.rpm[i]))
    lin = hb.linear_harmonics(system, H)
    law = contact_law_for(system, params.contact)
    basis = hb.fourier(H, n)
    X = curve.X[i].reshape(basis.nh, lin.nx)
    c = hb.contact_harmonics(X, lin.Wx, law, basis, jacobian=False)
    j = int(np.flatnonzero(law.side == 1)[0])
    w = (basis.E @ (X @ lin.Wx.T))[:, law.rows[j, 1]]
    phase = np.exp(-1j * basis.tau)
    w1, F1 = w @ phase, c.F[j] @ phase
    touching = c.state[j] != SEPARATE
    a = 2.0 * abs(w1) / n
    kt, mu = law.props[j, KT], law.props[j, MU]
    return {"variant": variant.name, "case": case, "N0": value, "rpm": float(curve.rpm[i]), "tangential_amplitude_m": a,
            "slip_share": float(np.mean(c.state[j][touching] == SLIP)) if touching.any() else 0.0,
            "k_orbit": float(-(F1 / w1).real), "k_jenkins": harmonic_stiffness(kt, mu * value, a).real, "kt": kt,
            "stick_ratio": mu * value / (kt * a) if a > 0 else float("inf"), "kn": law.props[j, KN]}


def _trend(values: list[float]) -> str:
    return "falls" if values[-1] < values[0] else "rises"


def friction_rows(done, opts: dict) -> list[dict]:
    """:func:`friction_at_resonance` at every preload (N0 >= 0) of every variant where the curve holds it."""
    return [r for v in done for label, kind, value, p in v.cases if kind == "preload" and value >= 0
            for r in [friction_at_resonance(v, label, value, p, opts)] if r is not None]


def explain(rows: list[dict], concl: dict) -> list[str]:
    """The report's section on why the resonant speed need not rise with xi, from :func:`friction_rows`."""
    if not rows:
        return []
    falls = [c for c, t in concl["preload_cases"].items() if t["speed_trend"] != 1]
    lines = ["", "## Why the resonant speed need not rise with xi", "",
             "The shroud's friction element stiffens the blade by its tangential stiffness over a cycle, the "
             "first harmonic k' = -Re(F_1 / w_1). A larger kt raises it only while the element mostly sticks: "
             "for a Jenkins element at amplitude a and constant slip force mu N, k' grows with kt while "
             "mu N / (kt a) > 0.77 and falls beyond, towards the square wave mu N sign(w'), all damping and no "
             "stiffness (shroud.core.contact.harmonic_stiffness; tested against the law marched around a "
             "cosine). Along each tracked resonance (side 1; the closed form with N = N0, the orbit's N varies "
             "with the normal motion):", "",
             markdown_table(["variant", "N0 (N)", "resonance (r/min)", "tangential amplitude (um)",
                             "slip share of contact time", "mu N0 / (kt a)", "k' along the orbit (MN/m)",
                             "k' Jenkins (MN/m)"],
                            [(r["variant"], f"{r['N0']:g}", f"{r['rpm']:.0f}",
                              f"{r['tangential_amplitude_m'] * 1e6:.3f}", f"{r['slip_share']:.2f}",
                              f"{r['stick_ratio']:.3g}",
                              f"{r['k_orbit'] / 1e6:.3f}", f"{r['k_jenkins'] / 1e6:.3f}") for r in rows])]
    for case in falls:
        mine = [r for r in rows if r["case"] == case]
        if len(mine) < 2:
            continue
        orbit, closed = [r["k_orbit"] for r in mine], [r["k_jenkins"] for r in mine]
        lines += ["", f"{case}: the resonant speed does not rise with xi. Along its resonant orbits the element "
                  f"slides {min(r['slip_share'] for r in mine):.0%}-{max(r['slip_share'] for r in mine):.0%} of its "
                  f"contact time, and its k' {_trend(orbit)} as xi grows ("
                  + " -> ".join(f"{k / 1e6:.3g}" for k in orbit) + " MN/m): the shroud's constraint "
                  + ("softens, so the resonance moves down." if orbit[-1] < orbit[0] else "does not stiffen.")
                  + " A Jenkins element with N held at N0 "
                  + ("does the same (" if _trend(closed) == _trend(orbit) else "would not (")
                  + " -> ".join(f"{k / 1e6:.3g}" for k in closed) + " MN/m)"
                  + ("." if _trend(closed) == _trend(orbit) else
                     f": here the normal load swings with the normal motion ({mine[0]['N0']:g} N is "
                     f"{mine[0]['N0'] / mine[0]['kn'] * 1e6:.3g} um of normal travel), and the friction limit "
                     "with it, which the constant-N element leaves out.")
                  + " The paper's rise holds where the contact mostly sticks (the other cases)."]
    return lines


run = study(compute, plot, report)
