"""Fig. 4: reduced (nr modes) against full (5N DOF) model over speed, six gap/preload cases.

Paper (Sect. 2.2.1, alpha 15 deg, kt = kn = 1e7 N/m, mu 0.3): the two agree
on all six cases; the reduced model takes ~70 % of the full model's time.

Where the curves differ by more than ``coexist_threshold``, both models are
restarted from the same physical initial states to tell coexisting steady
states from model error (comparisons._coexistence).
"""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np

from comparisons import _coexistence, paper
from comparisons._families import grid_limits, same_speed
from shroud.core.plotting import MODEL_COLOURS, figure, save
from shroud.base.markdown import markdown_table, seconds
from shroud.analysis.sweep import PLATEAU, Settling, run_sweeps, steady_resonance
from shroud.base.outputs import open_replacing, write_text

OPTIONS = {"gaps_um": [600.0, 100.0, 50.0], "preloads_N": [0.0, 10.0, 50.0],
           "rpm_from": 4000.0, "rpm_to": 30000.0, "rpm_count": 53, **_coexistence.OPTIONS}
MODELS = ("reduced", "full")


def run(scene, out: Path) -> dict:
    params, opts = scene.params, scene.options
    cases = [(f"gap {g:g} um", params.updated({"contact.gap": g * 1e-6})) for g in opts["gaps_um"]]
    cases += [(f"N0 {n:g} N", params.updated({"contact.N0": n})) for n in opts["preloads_N"]]
    rpms = np.linspace(opts["rpm_from"], opts["rpm_to"], int(opts["rpm_count"]))
    settling = Settling.from_options(opts)
    sweeps = {m: run_sweeps([p for _, p in cases], m, rpms, settling=settling) for m in MODELS}
    fig, axes = figure(2, 3, width=9.0)
    rows, out_json, found = [], {}, {}
    for i, (label, _) in enumerate(cases):
        red, full = sweeps["reduced"][i], sweeps["full"][i]
        ax = axes[i // 3][i % 3]
        ax.plot(rpms, full.amplitude_v_L * 1e3, color=MODEL_COLOURS["full"], label=f"full ({full.dofs} DOF)")
        ax.plot(rpms, red.amplitude_v_L * 1e3, "--", color=MODEL_COLOURS["reduced"], label=f"reduced ({red.dofs} DOF)")
        for s in (red, full):
            bad = ~np.array(s.settled, bool)
            if bad.any():
                ax.plot(rpms[bad], s.amplitude_v_L[bad] * 1e3, "x", color="k", label=f"{s.model}: not settled")
        ax.set_title(f"({'abcdef'[i]}) {label}")
        ax.set_xlabel("speed (r/min)")
        ax.set_ylabel("amplitude of v_L (mm)")
        ax.legend()
        diff = float(np.nanmax(np.abs(red.amplitude_v_L - full.amplitude_v_L)) / np.nanmax(full.amplitude_v_L))
        res = {m: steady_resonance(s) for m, s in (("reduced", red), ("full", full))}
        rows.append((label, res["reduced"]["rpm"], res["full"]["rpm"], res["reduced"]["amplitude"] * 1e3,
                     res["full"]["amplitude"] * 1e3, 100 * diff, seconds(red.cpu_s), seconds(full.cpu_s)))
        out_json[label] = {"reduced": red.to_json(), "full": full.to_json(), "max_difference_percent": 100 * diff}
        found[label] = {"reduced_resonance_rpm": res["reduced"]["rpm"], "full_resonance_rpm": res["full"]["rpm"],
                        "same_resonant_speed": same_speed(res["reduced"]["rpm"], res["full"]["rpm"],
                                                          float(rpms[1] - rpms[0]))}
    save(fig, out / "fig4_reduced_vs_full.png")
    coexist = _coexistence.coexistence(cases, sweeps, rpms, opts, MODELS)
    for label in found:      # curves apart from rest only where both models have the same or shared states
        found[label]["differing_speed_verdicts"] = sorted({c["verdict"] for c in coexist if c["case"] == label})
    unsettled = {m: sum(not x for s in sweeps[m] for x in s.settled) for m in MODELS}
    t_red = sum(s.cpu_s for s in sweeps["reduced"])
    t_full = sum(s.cpu_s for s in sweeps["full"])
    with open_replacing(out / "fig4.csv") as fh:
        w = csv.writer(fh)
        w.writerow(["case", "rpm", "reduced_m", "full_m"])
        for i, (label, _) in enumerate(cases):
            for k, r in enumerate(rpms):
                w.writerow([label, r, sweeps["reduced"][i].amplitude_v_L[k], sweeps["full"][i].amplitude_v_L[k]])
    lines = [f"# {scene.title}\n",
             f"{len(rpms)} speeds per curve, at least {params.time.periods} periods per speed, nr = "
             f"{params.reduced.nr}, N = {params.reduced.N}.\n",
             settling.describe() + " Not settled here: " + (", ".join(f"{n} {m}" for m, n in unsettled.items() if n)
                                                           or "none") + ".\n",
             f"Resonance: the largest settled amplitude, or where the top is flat (within {100 * PLATEAU:g} % "
             "of it over a band of speeds, an impacting branch) the highest speed on it.\n",
             f"What these settings cannot resolve: {grid_limits(rpms[1] - rpms[0])}.\n",
             "| paper | here |", "|---|---|",
             f"| reduced and full agree on all six cases | largest amplitude difference from rest "
             f"{max(r[5] for r in rows):.3f} % of the full model's peak{_coexistence.summary(coexist)} |",
             f"| reduced run time ~{100 * paper.FIG4_TIME_SHARE:.0f} % of the full one | {100 * t_red / t_full:.0f} % "
             f"({seconds(t_red)} vs {seconds(t_full)}, build + integration summed over all runs) |", "",
             markdown_table(["case", "resonance reduced (r/min)", "resonance full (r/min)",
                             "amplitude reduced (mm)", "amplitude full (mm)", "max difference (%)",
                             "reduced cost", "full cost"], rows),
             "\nSame resonant speed, reduced and full (each verdict with its number, threshold and margin):\n",
             *[f"- {label}: {v['same_resonant_speed'].sentence()}" for label, v in found.items()], "",
             "![fig4_reduced_vs_full.png](fig4_reduced_vs_full.png)",
             *_coexistence.section(coexist, opts, MODELS, MODELS)]
    write_text(out / "report.md", "\n".join(lines) + "\n")
    return {"cases": out_json, "reduced_to_full_time_ratio": t_red / t_full, "conclusions": found,
            "cpu_s": {"reduced": t_red, "full": t_full}, "coexisting_states": coexist}
