"""Fig. 4: reduced (nr modes) against full (5N DOF) model over speed, six gap/preload cases.

Paper (Sect. 2.2.1, alpha 15 deg, kt = kn = 1e7 N/m, mu 0.3): the two agree
on all six cases; the reduced model takes ~70 % of the full model's time.

Where the curves differ by more than ``coexist_threshold``, both models are
restarted from the same physical initial states to tell coexisting steady
states from model error (shroud.analysis.coexistence).

The study is compute (:func:`compute` -> :class:`Fig4Result`) -> plot -> report.
"""

from __future__ import annotations

import csv
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from comparisons import paper
from comparisons._study import study
from shroud.analysis import coexistence
from comparisons._families import grid_limits, same_speed
from shroud.core.plotting import MODEL_COLOURS, figure, save
from shroud.base.markdown import markdown_table, seconds
from shroud.analysis.sweep import PLATEAU, Settling, run_sweeps, steady_resonance
from shroud.base.outputs import open_replacing

OPTIONS = {"gaps_um": [600.0, 100.0, 50.0], "preloads_N": [0.0, 10.0, 50.0],
           "rpm_from": 4000.0, "rpm_to": 30000.0, "rpm_count": 53, **coexistence.OPTIONS}
MODELS = ("reduced", "full")


@dataclass(frozen=True)
class Fig4Result:
    """Both models' curves over the six cases, and where they differ, the states each reaches."""

    labels: list[str]              # the cases, in the figure's order
    rpms: np.ndarray               # the speeds, r/min
    sweeps: dict[str, list]        # model -> SweepResult per case
    coexist: list[dict]            # shroud.analysis.coexistence rows

    def resonances(self, i: int) -> dict[str, dict]:
        return {m: steady_resonance(self.sweeps[m][i]) for m in MODELS}

    def difference(self, i: int) -> float:
        """Largest amplitude difference of case i over the full model's peak."""
        red, full = self.sweeps["reduced"][i].amplitude_v_L, self.sweeps["full"][i].amplitude_v_L
        return float(np.nanmax(np.abs(red - full)) / np.nanmax(full))

    def cpu_s(self, model: str) -> float:
        return sum(s.cpu_s for s in self.sweeps[model])

    def conclusions(self) -> dict:
        """Per case both resonant speeds, whether they are the same (shroud.core.verdict, within the grid),
        and the verdicts at the speeds where the curves differ from rest."""
        found = {}
        for i, label in enumerate(self.labels):
            res = self.resonances(i)
            found[label] = {"reduced_resonance_rpm": res["reduced"]["rpm"], "full_resonance_rpm": res["full"]["rpm"],
                            "same_resonant_speed": same_speed(res["reduced"]["rpm"], res["full"]["rpm"],
                                                              float(self.rpms[1] - self.rpms[0]))}
        for label in found:      # curves apart from rest only where both models have the same or shared states
            found[label]["differing_speed_verdicts"] = sorted({c["verdict"] for c in self.coexist
                                                               if c["case"] == label})
        return found

    def to_json(self) -> dict:
        t_red, t_full = self.cpu_s("reduced"), self.cpu_s("full")
        cases = {label: {"reduced": self.sweeps["reduced"][i].to_json(), "full": self.sweeps["full"][i].to_json(),
                         "max_difference_percent": 100 * self.difference(i)} for i, label in enumerate(self.labels)}
        return {"cases": cases, "reduced_to_full_time_ratio": t_red / t_full, "conclusions": self.conclusions(),
                "cpu_s": {"reduced": t_red, "full": t_full}, "coexisting_states": self.coexist}


def compute(scene) -> Fig4Result:
    """Both models swept over every case; both restarted from common states where their curves differ."""
    params, opts = scene.params, scene.options
    cases = [(f"gap {g:g} um", params.updated({"contact.gap": g * 1e-6})) for g in opts["gaps_um"]]
    cases += [(f"N0 {n:g} N", params.updated({"contact.N0": n})) for n in opts["preloads_N"]]
    rpms = np.linspace(opts["rpm_from"], opts["rpm_to"], int(opts["rpm_count"]))
    settling = Settling.from_options(opts)
    sweeps = {m: run_sweeps([p for _, p in cases], m, rpms, settling=settling) for m in MODELS}
    return Fig4Result(labels=[label for label, _ in cases], rpms=rpms, sweeps=sweeps,
                      coexist=coexistence.coexistence(cases, sweeps, rpms, opts, MODELS))


def plot(result: Fig4Result, scene, out: Path) -> list[str]:
    """One panel per case, both models' curves (crosses: not settled); the curves as CSV."""
    rpms, sweeps = result.rpms, result.sweeps
    fig, axes = figure(2, 3, width=9.0)
    for i, label in enumerate(result.labels):
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
    files = [save(fig, out / "fig4_reduced_vs_full.png").name]
    with open_replacing(out / "fig4.csv") as fh:
        w = csv.writer(fh)
        w.writerow(["case", "rpm", "reduced_m", "full_m"])
        for i, label in enumerate(result.labels):
            for k, r in enumerate(rpms):
                w.writerow([label, r, sweeps["reduced"][i].amplitude_v_L[k], sweeps["full"][i].amplitude_v_L[k]])
    return files


def report(result: Fig4Result, scene, files: list[str]) -> str:
    params, opts, rpms, sweeps, coexist = scene.params, scene.options, result.rpms, result.sweeps, result.coexist
    rows = []
    for i, label in enumerate(result.labels):
        red, full, res = sweeps["reduced"][i], sweeps["full"][i], result.resonances(i)
        rows.append((label, res["reduced"]["rpm"], res["full"]["rpm"], res["reduced"]["amplitude"] * 1e3,
                     res["full"]["amplitude"] * 1e3, 100 * result.difference(i), seconds(red.cpu_s),
                     seconds(full.cpu_s)))
    found = result.conclusions()
    unsettled = {m: sum(not x for s in sweeps[m] for x in s.settled) for m in MODELS}
    t_red, t_full = result.cpu_s("reduced"), result.cpu_s("full")
    lines = [f"# {scene.title}\n",
             f"{len(rpms)} speeds per curve, at least {params.time.periods} periods per speed, nr = "
             f"{params.reduced.nr}, N = {params.reduced.N}.\n",
             Settling.from_options(opts).describe() + " Not settled here: "
             + (", ".join(f"{n} {m}" for m, n in unsettled.items() if n) or "none") + ".\n",
             f"Resonance: the largest settled amplitude, or where the top is flat (within {100 * PLATEAU:g} % "
             "of it over a band of speeds, an impacting branch) the highest speed on it.\n",
             f"What these settings cannot resolve: {grid_limits(rpms[1] - rpms[0])}.\n",
             "| paper | here |", "|---|---|",
             f"| reduced and full agree on all six cases | largest amplitude difference from rest "
             f"{max(r[5] for r in rows):.3f} % of the full model's peak{coexistence.summary(coexist)} |",
             f"| reduced run time ~{100 * paper.FIG4_TIME_SHARE:.0f} % of the full one | {100 * t_red / t_full:.0f} % "
             f"({seconds(t_red)} vs {seconds(t_full)}, build + integration summed over all runs) |", "",
             markdown_table(["case", "resonance reduced (r/min)", "resonance full (r/min)",
                             "amplitude reduced (mm)", "amplitude full (mm)", "max difference (%)",
                             "reduced cost", "full cost"], rows),
             "\nSame resonant speed, reduced and full (each verdict with its number, threshold and margin):\n",
             *[f"- {label}: {v['same_resonant_speed'].sentence()}" for label, v in found.items()], "",
             *[f"![{f}]({f})" for f in files],
             *coexistence.section(coexist, opts, MODELS, MODELS)]
    return "\n".join(lines) + "\n"


run = study(compute, plot, report)
