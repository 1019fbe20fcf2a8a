"""Fig. 4 by harmonic balance: reduced against full beam, every branch with its stability, six cases.

The paper's Fig. 4 compares from-rest time-domain sweeps of the reduced
(nr modes) and full (5N DOF) beams. Here both models' steady-state
branches are followed by harmonic balance with continuation
(shroud.analysis.hb): stable solid, unstable dashed, stability changes
marked; each model's time-domain sweep is overlaid as dots and its points
are named by the branch they landed on. Where the from-rest sweeps of the
two models differ near a jump, the branches show whether they sit on two
coexisting states of one curve (the coexistence restarts of the fig4
study, read off the curves here) or whether the models differ.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from comparisons._hb import (landed_on, notes_line, on_stable, resonance_of, same_resonance, states_at,
                             verdict_text)
from shroud.analysis.hb import run_hb
from shroud.analysis.sweep import run_sweeps
from shroud.base.markdown import markdown_table, seconds
from shroud.core.plotting import MODEL_COLOURS, figure, save
from shroud.base.tables import write_records
from shroud.base.outputs import write_text

OPTIONS = {"gaps_um": [600.0, 100.0, 50.0], "preloads_N": [0.0, 10.0, 50.0],
           "rpm_from": 4000.0, "rpm_to": 30000.0, "td_rpm_count": 53,
           "harmonics": 10, "samples": 512, "match": 0.01}
MODELS = ("reduced", "full")


def _fold_speeds(branch) -> list[float]:
    return [float(b["rpm"]) for b in branch.bifurcations if b["kind"] == "fold"]


def conclusions(labels: list[str], branches: dict) -> dict:
    """Per case: each model's resonance (on points not shown unstable, with its errors and stability;
    comparisons._hb.resonance_of) and whether the two are the same (a Verdict: the paper's "good
    agreement" of the reduced and full beams, Fig. 4)."""
    out = {}
    for i, label in enumerate(labels):
        res = {m: resonance_of(branches[m][i]) for m in MODELS}
        out[label] = {**res, "same_resonance": same_resonance(res["reduced"], res["full"], MODELS).to_json()}
    return out


def run(scene, out: Path) -> dict:
    params, opts = scene.params, scene.options
    cases = [(f"gap {g:g} um", params.updated({"contact.gap": g * 1e-6})) for g in opts["gaps_um"]]
    cases += [(f"N0 {n:g} N", params.updated({"contact.N0": n})) for n in opts["preloads_N"]]
    rpms = np.linspace(opts["rpm_from"], opts["rpm_to"], int(opts["td_rpm_count"]))
    branches = {m: [run_hb(p, m, opts["rpm_from"], opts["rpm_to"], harmonics=int(opts["harmonics"]),
                           samples=int(opts["samples"])) for _, p in cases] for m in MODELS}
    sweeps = {m: run_sweeps([p for _, p in cases], m, rpms) for m in MODELS}
    fig, axes = figure(2, 3, width=10.0, height=6.4)
    rows, out_json, points = [], {}, []
    for i, (label, p) in enumerate(cases):
        ax = axes[i // 3][i % 3]
        row = {"case": label}
        for k, m in enumerate(MODELS):
            br, sw = branches[m][i], sweeps[m][i]
            # widest first: the reduced beam lies on the full one (dashes mean unstable here)
            br.plot(ax, label=f"{m} ({br.dofs} DOF)", colour=MODEL_COLOURS[m],
                    linewidth=1.0 + 0.9 * (len(MODELS) - 1 - k))
            ax.plot(sw.rpm, sw.amplitude_v_L * 1e3, "." if m == "reduced" else "x", color=MODEL_COLOURS[m], ms=4)
            names = [landed_on(states_at(br, p, m, r), a, per, opts["match"])
                     for r, a, per in zip(sw.rpm, sw.amplitude_v_L, sw.period)]
            points += [{"case": label, "model": m, "rpm": float(r), "amplitude_m": float(a), "period": per,
                        "branch": n} for r, a, per, n in zip(sw.rpm, sw.amplitude_v_L, sw.period, names)]
            row[m] = {"resonance": br.resonance, "folds_rpm": _fold_speeds(br), "hb_points": len(br.rpm),
                      "complete": br.complete, "stopped": br.stopped, "hb_s": br.elapsed_s, "td_cpu_s": sw.cpu_s,
                      "td_on_stable": sum(on_stable(n) for n in names), "td_points": len(names)}
            out_json.setdefault(label, {})[m] = br.to_json()
        a_r, a_f = (row[m]["resonance"]["amplitude"] for m in MODELS)
        row["resonance_difference"] = abs(a_r / a_f - 1)
        rows.append(row)
        ax.set_title(f"({'abcdef'[i]}) {label}")
        ax.legend()
    save(fig, out / "hb_fig4_reduced_vs_full.png")
    write_records(out / "td_points_by_branch.csv", points)
    hb_cost = {m: sum(r[m]["hb_s"] for r in rows) for m in MODELS}
    td_cost = {m: sum(r[m]["td_cpu_s"] for r in rows) for m in MODELS}
    off = [p for p in points if not on_stable(p["branch"])]
    lines = [f"# {scene.title}\n",
             f"Harmonic balance H = {opts['harmonics']}, {opts['samples']} samples per period, continuation "
             f"{opts['rpm_from']:g}-{opts['rpm_to']:g} r/min with Floquet stability; time domain {len(rpms)} speeds "
             f"x {params.time.periods} periods from rest (dots: reduced, crosses: full).\n",
             f"Largest difference of the resonant (largest P1) amplitude between the reduced and full branches: "
             f"{100 * max(r['resonance_difference'] for r in rows):.3f} %.\n",
             f"Cost: harmonic balance reduced {seconds(hb_cost['reduced'])}, full {seconds(hb_cost['full'])} "
             f"(wall, one process); time domain reduced {seconds(td_cost['reduced'])}, full "
             f"{seconds(td_cost['full'])} (CPU summed over the runs).\n",
             markdown_table(["case", "resonance reduced (r/min, mm)", "resonance full (r/min, mm)", "difference (%)",
                             "folds reduced (r/min)", "folds full (r/min)", "TD on a stable branch (reduced, full)"],
                            [(r["case"],
                              f"{r['reduced']['resonance']['rpm']:.0f}, {r['reduced']['resonance']['amplitude'] * 1e3:.4f}",
                              f"{r['full']['resonance']['rpm']:.0f}, {r['full']['resonance']['amplitude'] * 1e3:.4f}",
                              100 * r["resonance_difference"],
                              ", ".join(f"{x:.0f}" for x in r["reduced"]["folds_rpm"]) or "none",
                              ", ".join(f"{x:.0f}" for x in r["full"]["folds_rpm"]) or "none",
                              f"{r['reduced']['td_on_stable']}/{r['reduced']['td_points']}, "
                              f"{r['full']['td_on_stable']}/{r['full']['td_points']}") for r in rows]),
             "",
             f"Time-domain points not on a stable P1 branch within {100 * opts['match']:g} %: {len(off)} of "
             f"{len(points)} (listed in td_points_by_branch.csv with the branch each landed on).",
             "", "![hb_fig4_reduced_vs_full.png](hb_fig4_reduced_vs_full.png)", "",
             f"{MODELS[0]} drawn wider, {MODELS[-1]} inside it: where the two coincide, a line within a line."]
    concl = conclusions([label for label, _ in cases], branches)
    lines[-4:-4] = ["Same resonance (reduced against full, relative amplitude difference): " + "; ".join(
        f"{label}: {verdict_text(c['same_resonance'], 100, ' %')}" for label, c in concl.items()) + ". " + notes_line([(f"{m} {label}", branches[m][i]) for m in MODELS
                                                             for i, (label, _) in enumerate(cases)]), ""]
    write_text(out / "report.md", "\n".join(lines) + "\n")
    return {"conclusions": concl, "cases": rows, "branches": out_json, "time_domain_points": points,
            "cost_s": {"harmonic_balance": hb_cost, "time_domain_cpu": td_cost}}

