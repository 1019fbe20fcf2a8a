"""Figs. 14-15: P1 motion at mu = 0.1 and P10 motion at mu = 0.5, 25500 r/min.

Paper (Sect. 3.2): with a small gap or a preload, the response at 25500 r/min
is period-one at mu 0.1 and period-ten at mu 0.5 (the impact repeats every
ten excitation periods; friction shares that period). The paper does not
state the gap or preload of Figs. 14-15; this study runs every case in
``cases`` and reports the period found for each.
"""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np

from shroud import signals
from shroud.api import build_system
from shroud.plotting import figure, save
from shroud.report import markdown_table, seconds
from shroud.transient import simulate

OPTIONS = {"mu_values": [0.1, 0.5], "gaps_um": [1.0], "preloads_N": [10.0, 25.0, 50.0],
           "plot_periods": 20}


def run(scene, out: Path) -> dict:
    params, opts = scene.params, scene.options
    spp = params.time.steps_per_period
    cases = [(f"gap {g:g} um", {"contact.gap": g * 1e-6}) for g in opts["gaps_um"]]
    cases += [(f"N0 {n:g} N", {"contact.N0": n}) for n in opts["preloads_N"]]
    rows, found, shown = [], {}, {}
    for mu in opts["mu_values"]:
        for label, change in cases:
            p = params.updated({**change, "contact.mu": mu})
            system = build_system(p, "reduced")
            res = simulate(system, p, csv_path=out / f"mu{mu:g}_{label.replace(' ', '')}.csv")
            found[(mu, label)] = res.period
            rows.append((mu, label, f"P{res.period}" if res.period else "none up to P10",
                         res.amplitude["v_L"] * 1e3, res.peak["N1"], res.peak["Ff1"], seconds(res.elapsed_s)))
            if mu not in shown or (res.period or 99) == (10 if mu >= 0.5 else 1):
                shown[mu] = (label, res)
    fig, axes = figure(3, 2, width=9.0)
    for col, (mu, (label, res)) in enumerate(sorted(shown.items())[:2]):
        tr = res.trajectory
        n = opts["plot_periods"] * spp
        t = tr.t[-n:]
        for row, (x, name) in enumerate(((tr.tip[:, 0] * 1e3, "v_L (mm)"), (tr.friction[:, 0], "F_f1 (N)"),
                                         (tr.normal[:, 0], "N_1 (N)"))):
            ax = axes[row][col]
            ax.plot(t, x[-n:], lw=0.8)
            ax.set_xlabel("t (s)")
            ax.set_ylabel(name)
        axes[0][col].set_title(f"mu = {mu:g}, {label}: "
                               + (f"P{res.period}" if res.period else "no period up to P10"))
    save(fig, out / "waveforms.png")
    fig, axes = figure(3, 2, width=9.0)
    f_e = params.load.ke * params.speed.rpm / 60.0
    for col, (mu, (label, res)) in enumerate(sorted(shown.items())[:2]):
        tr = res.trajectory
        for row, (x, name) in enumerate(((tr.tip[:, 0], "v_L (m)"), (tr.friction[:, 0], "F_f1 (N)"),
                                         (tr.normal[:, 0], "N_1 (N)"))):
            f, a = signals.spectrum(x, tr.dt, spp, periods=opts["plot_periods"])
            ax = axes[row][col]
            ax.plot(f / f_e, a, lw=0.8)
            ax.set_xlim(0, 4)
            ax.set_xlabel("frequency / f_e")
            ax.set_ylabel(f"|{name}|")
        axes[0][col].set_title(f"spectra, mu = {mu:g}, {label}")
    save(fig, out / "spectra.png")
    with open(out / "periods.csv", "w", newline="") as fh:
        csv.writer(fh).writerows([("mu", "case", "period", "amplitude_v_L_mm", "peak_N1", "peak_Ff1", "time"), *rows])
    p1 = [f"{c}" for (mu, c), per in found.items() if mu == min(opts["mu_values"]) and per == 1]
    p10 = [f"{c}" for (mu, c), per in found.items() if mu == max(opts["mu_values"]) and per == 10]
    lines = [f"# {scene.title}\n",
             f"{params.speed.rpm:g} r/min, {params.time.periods} periods, period read from one sample per "
             f"excitation period over the last 30 periods.\n",
             "| paper | here |", "|---|---|",
             f"| P1 at mu = {min(opts['mu_values']):g} | P1 in: {', '.join(p1) or 'none of the cases'} |",
             f"| P10 at mu = {max(opts['mu_values']):g} | P10 in: {', '.join(p10) or 'none of the cases'} |", "",
             markdown_table(["mu", "case", "period", "amplitude v_L (mm)", "peak N1 (N)", "peak Ff1 (N)", "time"], rows),
             "![waveforms.png](waveforms.png)", "![spectra.png](spectra.png)"]
    (out / "report.md").write_text("\n".join(lines) + "\n")
    return {"periods": {f"mu {mu:g}, {c}": per for (mu, c), per in found.items()},
            "rows": [list(r) for r in rows]}
