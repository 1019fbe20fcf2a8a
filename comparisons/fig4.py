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
from shroud.core.plotting import MODEL_COLOURS, figure, save
from shroud.base.markdown import markdown_table, seconds
from shroud.analysis.sweep import run_sweeps

OPTIONS = {"gaps_um": [600.0, 100.0, 50.0], "preloads_N": [0.0, 10.0, 50.0],
           "rpm_from": 4000.0, "rpm_to": 30000.0, "rpm_count": 53, **_coexistence.OPTIONS}
MODELS = ("reduced", "full")


def run(scene, out: Path) -> dict:
    params, opts = scene.params, scene.options
    cases = [(f"gap {g:g} um", params.updated({"contact.gap": g * 1e-6})) for g in opts["gaps_um"]]
    cases += [(f"N0 {n:g} N", params.updated({"contact.N0": n})) for n in opts["preloads_N"]]
    rpms = np.linspace(opts["rpm_from"], opts["rpm_to"], int(opts["rpm_count"]))
    sweeps = {m: run_sweeps([p for _, p in cases], m, rpms) for m in ("reduced", "full")}
    fig, axes = figure(2, 3, width=9.0)
    rows, out_json = [], {}
    for i, (label, _) in enumerate(cases):
        red, full = sweeps["reduced"][i], sweeps["full"][i]
        ax = axes[i // 3][i % 3]
        ax.plot(rpms, full.amplitude_v_L * 1e3, color=MODEL_COLOURS["full"], label=f"full ({full.dofs} DOF)")
        ax.plot(rpms, red.amplitude_v_L * 1e3, "--", color=MODEL_COLOURS["reduced"], label=f"reduced ({red.dofs} DOF)")
        ax.set_title(f"({'abcdef'[i]}) {label}")
        ax.set_xlabel("speed (r/min)")
        ax.set_ylabel("amplitude of v_L (mm)")
        ax.legend()
        diff = float(np.nanmax(np.abs(red.amplitude_v_L - full.amplitude_v_L)) / np.nanmax(full.amplitude_v_L))
        rows.append((label, red.resonance["rpm"], full.resonance["rpm"], red.resonance["amplitude"] * 1e3,
                     full.resonance["amplitude"] * 1e3, 100 * diff, seconds(red.cpu_s), seconds(full.cpu_s)))
        out_json[label] = {"reduced": red.to_json(), "full": full.to_json(), "max_difference_percent": 100 * diff}
    save(fig, out / "fig4_reduced_vs_full.png")
    coexist = _coexistence.coexistence(cases, sweeps, rpms, opts, MODELS)
    t_red = sum(s.cpu_s for s in sweeps["reduced"])
    t_full = sum(s.cpu_s for s in sweeps["full"])
    with open(out / "fig4.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["case", "rpm", "reduced_m", "full_m"])
        for i, (label, _) in enumerate(cases):
            for k, r in enumerate(rpms):
                w.writerow([label, r, sweeps["reduced"][i].amplitude_v_L[k], sweeps["full"][i].amplitude_v_L[k]])
    lines = [f"# {scene.title}\n",
             f"{len(rpms)} speeds per curve, {params.time.periods} periods per speed, nr = {params.reduced.nr}, "
             f"N = {params.reduced.N}.\n",
             "| paper | here |", "|---|---|",
             f"| reduced and full agree on all six cases | largest amplitude difference from rest "
             f"{max(r[5] for r in rows):.3f} % of the full model's peak{_coexistence.summary(coexist)} |",
             f"| reduced run time ~{100 * paper.FIG4_TIME_SHARE:.0f} % of the full one | {100 * t_red / t_full:.0f} % "
             f"({seconds(t_red)} vs {seconds(t_full)}, build + integration summed over all runs) |", "",
             markdown_table(["case", "resonance reduced (r/min)", "resonance full (r/min)",
                             "amplitude reduced (mm)", "amplitude full (mm)", "max difference (%)",
                             "reduced cost", "full cost"], rows),
             "![fig4_reduced_vs_full.png](fig4_reduced_vs_full.png)",
             *_coexistence.section(coexist, opts, MODELS, MODELS)]
    (out / "report.md").write_text("\n".join(lines) + "\n")
    return {"cases": out_json, "time_ratio_reduced_to_full": t_red / t_full,
            "cpu_s": {"reduced": t_red, "full": t_full}, "coexisting_states": coexist}
