"""Fig. 4 by harmonic balance: reduced against full beam, every branch with its stability, six cases.

The paper's Fig. 4 compares from-rest time-domain sweeps of the reduced
(nr modes) and full (5N DOF) beams. Here both models' steady-state
branches are followed by harmonic balance with continuation
(shroud.analysis.hb): stable solid, unstable dashed, stability changes
marked; each model's time-domain sweep is overlaid as dots and its points
are named by the branch they landed on. Where the from-rest sweeps of the
two models differ near a jump, the branches show whether they sit on two
coexisting states of one curve (the coexistence restarts of the fig4
study, read off the curves here) or whether the models differ. Each
resonance is measured again at twice the harmonics, located on its branch
(comparisons._peaks.converged_peak), and the two models' are compared there.

The study is compute (:func:`compute` -> :class:`HBFig4Result`) -> plot -> report.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import partial
from pathlib import Path

import numpy as np

from comparisons._hb import named_points, notes_line, on_stable, resonance_of, states_at, verdict_text
from comparisons._in_time import bifurcations_in_time, in_time_line
from comparisons._peaks import converged_peak, same_peak
from comparisons._study import study
from shroud.analysis.hb import run_hb
from shroud.analysis.sweep import run_sweeps
from shroud.base.markdown import markdown_table, seconds
from shroud.base.tables import write_records
from shroud.core.plotting import MODEL_COLOURS, figure, save
from shroud.core.results import HBResult, SweepResult

OPTIONS = {"gaps_um": [600.0, 100.0, 50.0], "preloads_N": [0.0, 10.0, 50.0],
           "rpm_from": 4000.0, "rpm_to": 30000.0, "td_rpm_count": 53,
           "harmonics": 10, "samples": 512, "match": 0.01}
MODELS = ("reduced", "full")


def _fold_speeds(branch) -> list[float]:
    return [float(b["rpm"]) for b in branch.bifurcations if b["kind"] == "fold"]


@dataclass(frozen=True)
class HBFig4Result:
    """Both models' branches and from-rest sweeps over the six cases, every sweep point named by the branch
    state it landed on."""

    labels: list[str]                          # the cases, in the figure's order
    branches: dict[str, list[HBResult]]        # model -> branch per case
    sweeps: dict[str, list[SweepResult]]       # model -> time-domain sweep per case
    points: list[dict]                         # every sweep point with its branch (comparisons._hb.named_points)
    in_time: dict[str, list[list[dict]]]       # model -> per case: bifurcations checked in time (_in_time)
    peaks: dict[str, list[dict]]               # model -> per case: its resonance at 2 H (_peaks.converged_peak)

    def rows(self) -> list[dict]:
        """Per case and model: resonance, folds, branch points and completeness, costs, sweep points on a
        stable branch; the two resonances' relative difference."""
        rows = []
        for i, label in enumerate(self.labels):
            row = {"case": label}
            for m in MODELS:
                br, sw = self.branches[m][i], self.sweeps[m][i]
                mine = [p for p in self.points if p["case"] == label and p["model"] == m]
                row[m] = {"resonance": br.resonance, "folds_rpm": _fold_speeds(br), "hb_points": len(br.rpm),
                          "complete": br.complete, "stopped": br.stopped, "hb_s": br.elapsed_s,
                          "td_cpu_s": sw.cpu_s, "td_on_stable": sum(on_stable(p["branch"]) for p in mine),
                          "td_points": len(mine)}
            a_r, a_f = (row[m]["resonance"]["amplitude"] for m in MODELS)
            row["resonance_difference"] = abs(a_r / a_f - 1)
            rows.append(row)
        return rows

    def conclusions(self) -> dict:
        """Per case: each model's resonance (on points not shown unstable, with its errors and stability;
        comparisons._hb.resonance_of), the same measured at twice the harmonics (``peaks``:
        comparisons._peaks.converged_peak) and whether the two models' are the same (a Verdict on the
        peaks: the paper's "good agreement" of the reduced and full beams, Fig. 4)."""
        out = {}
        for i, label in enumerate(self.labels):
            peaks = {m: self.peaks[m][i] for m in MODELS}
            out[label] = {**{m: resonance_of(self.branches[m][i]) for m in MODELS}, "peaks": peaks,
                          "same_resonance": same_peak(peaks["reduced"], peaks["full"], MODELS).to_json()}
        return out

    def cost_s(self) -> dict:
        return {"harmonic_balance": {m: sum(b.elapsed_s for b in self.branches[m]) for m in MODELS},
                "time_domain_cpu": {m: sum(s.cpu_s for s in self.sweeps[m]) for m in MODELS}}

    def to_json(self) -> dict:
        return {"conclusions": self.conclusions(), "cases": self.rows(),
                "branches": {label: {m: self.branches[m][i].to_json() for m in MODELS}
                             for i, label in enumerate(self.labels)},
                "time_domain_points": self.points, "cost_s": self.cost_s(),
                "bifurcations_in_time": {label: {m: self.in_time[m][i] for m in MODELS}
                                         for i, label in enumerate(self.labels)}}


def compute(scene) -> HBFig4Result:
    """Both models' branches over every case by continuation, their from-rest sweeps, and every sweep point
    read against its model's branch."""
    params, opts = scene.params, scene.options
    cases = [(f"gap {g:g} um", params.updated({"contact.gap": g * 1e-6})) for g in opts["gaps_um"]]
    cases += [(f"N0 {n:g} N", params.updated({"contact.N0": n})) for n in opts["preloads_N"]]
    rpms = np.linspace(opts["rpm_from"], opts["rpm_to"], int(opts["td_rpm_count"]))
    branches = {m: [run_hb(p, m, opts["rpm_from"], opts["rpm_to"], harmonics=int(opts["harmonics"]),
                           samples=int(opts["samples"])) for _, p in cases] for m in MODELS}
    sweeps = {m: run_sweeps([p for _, p in cases], m, rpms) for m in MODELS}
    points = [pt for i, (label, p) in enumerate(cases) for m in MODELS
              for pt in named_points(sweeps[m][i], partial(states_at, branches[m][i], p, m), opts["match"],
                                     case=label, model=m)]
    in_time = {m: [bifurcations_in_time(branches[m][i], p, m) for i, (_, p) in enumerate(cases)] for m in MODELS}
    peaks = {m: [converged_peak(branches[m][i], p, m) for i, (_, p) in enumerate(cases)] for m in MODELS}
    return HBFig4Result(labels=[label for label, _ in cases], branches=branches, sweeps=sweeps, points=points,
                        in_time=in_time, peaks=peaks)


def plot(result: HBFig4Result, scene, out: Path) -> list[str]:
    """One panel per case: both models' branches (stable solid, unstable dashed) and sweeps (dots: reduced,
    crosses: full); the named sweep points as CSV."""
    fig, axes = figure(2, 3, width=10.0, height=6.4)
    for i, label in enumerate(result.labels):
        ax = axes[i // 3][i % 3]
        for k, m in enumerate(MODELS):
            br, sw = result.branches[m][i], result.sweeps[m][i]
            # widest first: the reduced beam lies on the full one (dashes mean unstable here)
            br.plot(ax, label=f"{m} ({br.dofs} DOF)", colour=MODEL_COLOURS[m],
                    linewidth=1.0 + 0.9 * (len(MODELS) - 1 - k))
            ax.plot(sw.rpm, sw.amplitude_v_L * 1e3, "." if m == "reduced" else "x", color=MODEL_COLOURS[m], ms=4)
        ax.set_title(f"({'abcdef'[i]}) {label}")
        ax.legend()
    save(fig, out / "hb_fig4_reduced_vs_full.png")
    write_records(out / "td_points_by_branch.csv", result.points)
    return ["hb_fig4_reduced_vs_full.png"]


def report(result: HBFig4Result, scene, files: list[str]) -> str:
    params, opts = scene.params, scene.options
    rows, concl, cost = result.rows(), result.conclusions(), result.cost_s()
    hb_cost, td_cost = cost["harmonic_balance"], cost["time_domain_cpu"]
    off = [p for p in result.points if not on_stable(p["branch"])]
    lines = [f"# {scene.title}\n",
             f"Harmonic balance H = {opts['harmonics']}, {opts['samples']} samples per period, continuation "
             f"{opts['rpm_from']:g}-{opts['rpm_to']:g} r/min with Floquet stability; time domain "
             f"{int(opts['td_rpm_count'])} speeds x {params.time.periods} periods from rest (dots: reduced, "
             "crosses: full).\n",
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
             "Same resonance (reduced against full, relative amplitude difference): " + "; ".join(
                 f"{label}: {verdict_text(c['same_resonance'], 100, ' %')}" for label, c in concl.items()) + ". "
             + notes_line([(f"{m} {label}", result.branches[m][i]) for m in MODELS
                           for i, label in enumerate(result.labels)]), "",
             f"Time-domain points not on a stable P1 branch within {100 * opts['match']:g} %: {len(off)} of "
             f"{len(result.points)} (listed in td_points_by_branch.csv with the branch each landed on).", "",
             in_time_line([(f"{m} {label}", result.in_time[m][i]) for m in MODELS
                           for i, label in enumerate(result.labels)]),
             "", *[f"![{f}]({f})" for f in files], "",
             f"{MODELS[0]} drawn wider, {MODELS[-1]} inside it: where the two coincide, a line within a line."]
    return "\n".join(lines) + "\n"


run = study(compute, plot, report)
