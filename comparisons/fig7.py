"""Fig. 7 of the paper: amplitude-frequency curves of the beam model against the reduced FE model.

Paper Sect. 2.2.1 (alpha 15 deg, kn = kt = 1e7 N/m, mu 0.3): the lines of
its reduced beam model pass through the points of its reduced FE model for
(a) several initial gaps and (b) a 1 um gap and several initial preloads.
Here the lines are our beam model (reduced.nr modes) and the points our
reduced solid FE model ("fe-reduced": fe.cms_modes normal modes plus the
residual attachment modes of the contact nodes). The solid's reduction
depends on the speed only (not on the gap or preload), so it is built once
per speed, before the sweeps, and every curve reuses it from the cache.

Per curve: the resonance (speed and amplitude of the largest steady v_L
amplitude) of both models, and the gap between the curves (RMS difference
over the speeds divided by the beam curve's peak). Where the curves differ
by more than ``coexist_threshold`` at a speed, both models are restarted
from the same initial states to tell coexisting steady states (a jump
reached from rest by one model and not the other) from model error
(shroud.analysis.coexistence).

The study is compute (:func:`compute` -> :class:`Fig7Result`) -> plot -> report.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from shroud.analysis import coexistence
from comparisons import _families as fam
from comparisons._study import study
from shroud.base.errors import InputError
from shroud.base.log import Progress, info
from shroud.core.plotting import figure, save
from shroud.base.markdown import markdown_table, seconds
from shroud.analysis.sweep import PLATEAU, Settling, run_sweeps, steady_resonance
from shroud.base.tables import write_records
from shroud.core.verdict import Verdict

OPTIONS = {
    "gaps_um": [600.0, 100.0, 50.0],
    "small_gap_um": 1.0,
    "preloads_N": [0.0, 10.0, 50.0],
    "rpm_from": 6000.0, "rpm_to": 14000.0, "rpm_count": 17,
    "models": ["reduced", "fe-reduced"],
    **coexistence.OPTIONS,
}
LINE, POINTS = "reduced", "fe-reduced"
PEAKED = 1.5     # a curve has a resonance peak in the range when its largest amplitude is this many times its smallest


def check(scene) -> None:
    o = scene.options
    if sorted(o["models"]) != sorted([LINE, POINTS]):
        raise InputError("options.models", f"{o['models']!r}; allowed: [\"reduced\", \"fe-reduced\"]")
    if not 0 < o["rpm_from"] < o["rpm_to"] or o["rpm_count"] < 2:
        raise InputError("options.rpm_from", "allowed: 0 < rpm_from < rpm_to and rpm_count >= 2")
    if any(g < 0 for g in o["gaps_um"]) or o["small_gap_um"] < 0:
        raise InputError("options.gaps_um", "allowed: gaps >= 0 um")


def prebuild_reductions(params, rpms) -> float:
    """The FE reduction at every speed (cached on disk): wall time spent building, s."""
    from reference_fe.system import reduced_operators
    t0 = time.perf_counter()
    progress = Progress("FE reductions over speed", len(rpms))
    for i, rpm in enumerate(rpms):
        reduced_operators(params, float(rpm))
        progress.update(i + 1)
    progress.done()
    return time.perf_counter() - t0


def curve_gap(line: np.ndarray, points: np.ndarray) -> float:
    """RMS of (points - line) over the speeds, divided by the line's peak."""
    ok = np.isfinite(line) & np.isfinite(points)
    return float(np.sqrt(np.mean((points[ok] - line[ok]) ** 2)) / np.max(line[ok])) if ok.any() else float("nan")


def conclusions(rows: list[dict], coexist: list[dict], step_rpm: float, threshold: float, tolerance: float) -> dict:
    """What the report concludes, per case, as data (verdicts with their margins, shroud.core.verdict):
    whether the beam curve has a resonance peak in the range (its largest amplitude over its smallest
    against PEAKED, each known to the settling ``tolerance``), then each model's resonant speed (r/min,
    settled points only) and whether both resonate at the same speed (comparisons._families.same_speed;
    None without a peak), whether the curves agree (curve gap against ``threshold``, the two amplitudes'
    settling tolerance as the margin), and the verdicts at differing speeds."""
    out = {}
    for r in rows:
        verdicts = sorted({c["verdict"] for c in coexist if c["case"] == r["case"]})
        peaked = Verdict.of(r["peak_ratio"], PEAKED, 2 * tolerance * PEAKED, below=False, above=True,
                            reason="a peak: the largest amplitude PEAKED times the smallest; each known to the "
                                   "settling tolerance")
        has_peak = peaked.answer is True
        out[r["case"]] = {"peaked": peaked,
                          "beam_resonance_rpm": r["reduced_resonance_rpm"] if has_peak else None,
                          "solid_resonance_rpm": r["fe_reduced_resonance_rpm"] if has_peak else None,
                          "same_resonant_speed": fam.same_speed(r["reduced_resonance_rpm"],
                                                                r["fe_reduced_resonance_rpm"], step_rpm)
                          if has_peak else None,
                          "curves_agree": Verdict.of(r["curve_gap"], threshold, 2 * tolerance, below=True,
                                                     above=False, reason="curve gap (RMS difference over the "
                                                     "beam's peak); each amplitude known to the settling tolerance"),
                          "differing_speed_verdicts": verdicts}
    return out


@dataclass(frozen=True)
class Fig7Result:
    """Beam and reduced solid swept over the cases, their resonances, and where they differ, their states."""

    cases: list[fam.Case]
    rpms: np.ndarray               # the speeds, r/min
    sweeps: dict[str, list]        # model -> SweepResult per case
    build_s: float                 # the FE reductions' build, every speed, s
    rows: list[dict]               # per case: both resonances, peak, curve gap, costs
    coexist: list[dict]            # shroud.analysis.coexistence rows
    threshold: float               # coexist_threshold: curves apart by more differ
    tolerance: float               # the settling tolerance

    @property
    def dofs(self) -> dict[str, int]:
        return {m: self.sweeps[m][0].dofs for m in (LINE, POINTS)}

    @property
    def step(self) -> float:
        return float(self.rpms[1] - self.rpms[0])

    def conclusions(self) -> dict:
        return conclusions(self.rows, self.coexist, self.step, self.threshold, self.tolerance)

    def to_json(self) -> dict:
        return {"rpm": self.rpms, "dofs": self.dofs, "reduction_build_s": self.build_s, "resonances": self.rows,
                "coexisting_states": self.coexist, "conclusions": self.conclusions(),
                "curves": {c.label: {m: self.sweeps[m][k].to_json() for m in (LINE, POINTS)}
                           for k, c in enumerate(self.cases)}}


def resonance_rows(cases, sweeps) -> list[dict]:
    """Per case both models' resonances, whether the beam curve has a peak, the curve gap, the costs."""
    rows = []
    for k, c in enumerate(cases):
        line, pts = sweeps[LINE][k], sweeps[POINTS][k]
        res_line, res_pts = steady_resonance(line), steady_resonance(pts)
        rows.append({"case": c.label, "kind": c.kind, "value": c.value,
                     "reduced_resonance_rpm": res_line["rpm"],
                     "reduced_resonance_amplitude_m": res_line["amplitude"],
                     "fe_reduced_resonance_rpm": res_pts["rpm"],
                     "fe_reduced_resonance_amplitude_m": res_pts["amplitude"],
                     "peaked": bool(np.nanmax(line.amplitude_v_L) > PEAKED * np.nanmin(line.amplitude_v_L)),
                     "peak_ratio": float(np.nanmax(line.amplitude_v_L) / np.nanmin(line.amplitude_v_L)),
                     "unsettled_speeds": {m: int(sum(not x for x in s.settled)) for m, s in ((LINE, line), (POINTS, pts))},
                     "curve_gap": curve_gap(line.amplitude_v_L, pts.amplitude_v_L),
                     "reduced_cpu_s": line.cpu_s, "fe_reduced_cpu_s": pts.cpu_s})
    return rows


def compute(scene) -> Fig7Result:
    """The FE reductions at every speed, then both models over every case; both restarted from common
    states where their curves differ."""
    check(scene)
    params, o = scene.params, scene.options
    cases = fam.cases(params, o)
    rpms = fam.rpms(o)
    settling = Settling.from_options(o)
    build_s = prebuild_reductions(params, rpms)
    info(f"FE reductions at {len(rpms)} speeds ready ({build_s:.1f} s)")
    sweeps = {m: run_sweeps([c.params for c in cases], m, rpms, settling=settling) for m in (LINE, POINTS)}
    coexist = coexistence.coexistence([(c.label, c.params) for c in cases], sweeps, rpms, o, (LINE, POINTS))
    return Fig7Result(cases=cases, rpms=rpms, sweeps=sweeps, build_s=build_s, rows=resonance_rows(cases, sweeps),
                      coexist=coexist, threshold=o["coexist_threshold"], tolerance=settling.tolerance)


def plot(result: Fig7Result, scene, out: Path) -> list[str]:
    """Fig. 7 (fig7.png); the curves and resonances as CSV."""
    curves = []
    for k, c in enumerate(result.cases):
        line, pts = result.sweeps[LINE][k], result.sweeps[POINTS][k]
        for i, rpm in enumerate(result.rpms):
            curves.append({"case": c.label, "rpm": rpm, "reduced_v_L_m": line.amplitude_v_L[i],
                           "fe_reduced_v_L_m": pts.amplitude_v_L[i], "reduced_w_L_m": line.amplitude_w_L[i],
                           "fe_reduced_w_L_m": pts.amplitude_w_L[i], "reduced_settled": line.settled[i],
                           "fe_reduced_settled": pts.settled[i]})
    write_records(out / "fig7_curves.csv", curves)
    write_records(out / "fig7_resonances.csv", result.rows)
    return [_figure(result.cases, result.sweeps, out)]


def report(result: Fig7Result, scene, files: list[str]) -> str:
    return _report(scene, result.rows, result.dofs, result.build_s, files[0], len(result.rpms), result.coexist,
                   Settling.from_options(scene.options), result.step, result.conclusions())


run = study(compute, plot, report)


def _figure(cases, sweeps, out: Path) -> str:
    fig, axes = figure(1, 2, width=8.0, height=3.4)
    colours = iter(["tab:blue", "tab:orange", "tab:purple", "tab:brown", "tab:olive", "tab:cyan",
                    "tab:pink", "tab:gray"] * 4)
    for k, c in enumerate(cases):
        ax = axes[0][0 if c.kind == "gap" else 1]
        colour = next(colours)
        line, pts = sweeps[LINE][k], sweeps[POINTS][k]
        ax.plot(line.rpm, 1e6 * line.amplitude_v_L, "-", color=colour, label=f"{c.label} (beam)")
        ax.plot(pts.rpm, 1e6 * pts.amplitude_v_L, "o", ms=3.5, mfc="none", color=colour,
                label=f"{c.label} (solid FE, reduced)")
        for s in (line, pts):
            bad = ~np.array(s.settled, bool)
            if bad.any():
                ax.plot(s.rpm[bad], 1e6 * s.amplitude_v_L[bad], "x", ms=6, color="k",
                        label="not settled" if "not settled" not in ax.get_legend_handles_labels()[1] else None)
    for ax, title in zip(axes[0], ("(a) initial gaps", "(b) small gap and initial preloads")):
        ax.set_title(title)
        ax.set_xlabel("speed (r/min)")
        ax.set_ylabel("amplitude of v_L (um)")
        ax.legend(fontsize=6, loc="best")
    return save(fig, out / "fig7.png").name


def _report(scene, rows, dofs, build_s, figure_name, n_speeds, coexist, settling, step, found) -> str:
    p = scene.params
    unsettled = [f"{r['case']}: {n} {'beam' if m == LINE else 'solid'}" for r in rows
                 for m, n in r["unsettled_speeds"].items() if n]
    lines = [f"# {scene.title}\n",
             f"alpha = {p.contact.alpha_deg:g} deg, kn = {p.contact.kn:g} N/m, kt = {p.contact.kt:g} N/m, "
             f"mu = {p.contact.mu:g}; at least {p.time.periods} periods per speed, {n_speeds} speeds per curve. "
             f"Lines: beam model, {dofs[LINE]} DOF (nr = {p.reduced.nr}); points: reduced solid FE, "
             f"{dofs[POINTS]} DOF (mesh {p.fe.mesh_size:g} m, order {p.fe.order}, {p.fe.cms_modes} modes "
             f"+ attachment modes). The FE reductions (one per speed) took {seconds(build_s)}.\n",
             settling.describe() + " Not settled here: " + (", ".join(unsettled) or "none") + ".\n",
             f"What these settings cannot resolve: {fam.grid_limits(step)}, and coexisting states whose "
             f"basins the starts "
             f"({', '.join(f'{c:g}' for c in scene.options['coexist_starts'])} x the amplitude) miss.\n",
             f"![Fig. 7]({figure_name})\n",
             markdown_table(("case", "beam resonance (r/min)", "FE resonance (r/min)", "beam peak (um)",
                             "FE peak (um)", "curve gap", "beam cost", "FE cost"),
                            [(r["case"],
                              r["reduced_resonance_rpm"] if r["peaked"] else "no peak",
                              r["fe_reduced_resonance_rpm"] if r["peaked"] else "no peak",
                              1e6 * r["reduced_resonance_amplitude_m"], 1e6 * r["fe_reduced_resonance_amplitude_m"],
                              r["curve_gap"], seconds(r["reduced_cpu_s"]), seconds(r["fe_reduced_cpu_s"]))
                             for r in rows]),
             f"\nResonance: the largest settled amplitude, or where the top is flat (within {100 * PLATEAU:g} % "
             "of it over a band of speeds, an impacting branch) the highest speed on it. "
             f"No peak: the beam curve's largest amplitude is less than {PEAKED:g} times its smallest, so no "
             "resonant speed is read off it (the largest amplitude is the peak column). "
             "Curve gap: RMS of (FE - beam) amplitude over the speeds divided by the beam curve's peak. "
             "The paper shows the two models agreeing by eye; its numbers are not printed.\n",
             "Verdicts per case (each with its number, threshold and margin; inside the margin 'not decided'):\n",
             *[f"- {case}: peak {v['peaked'].sentence()}; curves agree {v['curves_agree'].sentence()}"
               + (f"; same resonant speed {v['same_resonant_speed'].sentence()}" if v["same_resonant_speed"]
                  else "") for case, v in found.items()], "",
             "Data: `fig7_curves.csv`, `fig7_resonances.csv`.\n",
             *coexistence.section(coexist, scene.options, (LINE, POINTS), ("beam", "solid FE"))]
    return "\n".join(lines)
