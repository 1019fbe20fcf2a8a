"""Fig. 7 by harmonic balance: the beam's branches against the reduced solid's, with stability.

The paper's Fig. 7 draws its beam model as lines through the points of its
reduced FE model. Here both are harmonic-balance branches followed in speed
(shroud.analysis.hb): the beam ("reduced", thick) and the reduced solid
("fe-reduced", thin; its operators on ONE free-interface basis built at
``speed.rpm`` for the whole range, reference_fe.frequency, whose error
against the per-speed bases is measured and reported), stable solid,
unstable dashed. The reduced solid's from-rest time-domain points (per-speed
bases, as the fig7 study) are overlaid as circles and each is named by the
reduced solid's HB state it landed on.

Full-solid checkpoints (diamonds): at ``checkpoint_rpms``, for the cases
named in ``checkpoint_cases``, every state of the reduced solid's branch is
solved again on the full solid ("fe", condensed exactly on its contact
coordinates per harmonic, reference_fe.harmonic), its Newton started from
that state; the report gives their difference from the reduced solid's
states, their stability (the full solid's orbit, perturbations projected on
the reduced solid's basis and on one twice as large:
shroud.analysis.hb.projected_multipliers; filled diamonds stable, open
unstable) and their cost.

Each resonance is measured again at twice the harmonics, located on its
branch (comparisons._peaks.converged_peak), and the two models' are compared
there (``same_resonance``); every bifurcation of both models' branches is
started in the project's integrator: does the state stay or leave
(comparisons._in_time; the reduced solid, beyond the period map's states, is
started in time all the same).

The study is compute (:func:`compute` -> :class:`HBFig7Result`) -> plot -> report.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from functools import partial
from pathlib import Path

import numpy as np

from comparisons import _families as fam
from comparisons._hb import named_points, notes_line, on_stable, resonance_of, starts_at, states_at, verdict_text
from comparisons._in_time import bifurcations_in_time, in_time_line
from comparisons._peaks import converged_peak, same_peak
from comparisons._study import study
from shroud.analysis.hb import Checkpoint, checkpoint, run_hb
from shroud.base.errors import InputError
from shroud.analysis.sweep import run_sweeps
from shroud.base.markdown import markdown_table, seconds
from shroud.core.plotting import figure, save
from shroud.core.results import HBResult, SweepResult
from shroud.core.verdict import with_rounding
from shroud.base.tables import write_records

OPTIONS = {"gaps_um": [600.0, 100.0, 50.0], "small_gap_um": 1.0, "preloads_N": [0.0, 10.0, 50.0],
           "rpm_from": 6000.0, "rpm_to": 14000.0, "td_rpm_count": 17, "harmonics": 7, "samples": 256,
           "match": 0.01, "checkpoint_rpms": [8000.0, 12000.0], "checkpoint_cases": ["gap 100 um"]}
LINE, POINTS, CHECK = "reduced", "fe-reduced", "fe"


def check(scene) -> None:
    o = scene.options
    labels = [c.label for c in fam.cases(scene.params, o)]
    if any(c not in labels for c in o["checkpoint_cases"]):
        raise InputError("options.checkpoint_cases", f"{o['checkpoint_cases']!r}; allowed: labels among {labels}")
    if any(not o["rpm_from"] <= r <= o["rpm_to"] for r in o["checkpoint_rpms"]):
        raise InputError("options.checkpoint_rpms", f"{o['checkpoint_rpms']!r}; allowed: speeds within "
                                                    f"rpm_from..rpm_to ({o['rpm_from']:g}..{o['rpm_to']:g} r/min)")


def full_solid_checkpoints(cases, solids, o) -> list[dict]:
    """The full solid's state from every state of the reduced solid's branch at each checkpoint speed.

    Speeds outermost: the cases at one speed share one condensation of the solid.
    """
    out = []
    for rpm in o["checkpoint_rpms"]:
        for c, solid in zip(cases, solids):
            if c.label not in o["checkpoint_cases"]:
                continue
            for X, stable in starts_at(solid, rpm):
                cp = checkpoint(c.params, CHECK, rpm, harmonics=solid.harmonics, samples=solid.samples, start=X)
                row = {"case": c.label, "reduced_branch_stable": stable, **cp.to_json(),
                       "difference": (cp.start_amplitude_v_L / cp.amplitude_v_L - 1
                                      if cp.start_amplitude_v_L is not None else None)}
                out.append(_rounded(row, cp))
    return out


def _rounded(row: dict, cp: Checkpoint) -> dict:
    """The checkpoint's row with its ``difference`` (-2.7e-5, a ratio of two amplitudes less 1, so it keeps
    few of their digits) declared rounding where both are converged to Newton's tolerance: held to twice it."""
    if row["difference"] is None or not cp.converged or cp.short:
        return row
    return with_rounding(row, "the difference of two amplitudes each solved to Newton's tolerance: held to "
                              "twice the tolerance", difference=2.0 * cp.tolerance)


def conclusions(cases, branches: dict, peaks: dict, checks: list[dict]) -> dict:
    """Per case: the beam's and the reduced solid's resonance (on points not shown unstable, with errors and
    stability: comparisons._hb.resonance_of), the same measured at twice the harmonics (``peaks``:
    comparisons._peaks.converged_peak) and whether the two are the same (a Verdict on the peaks: the paper's
    "good agreement" of its beam and FE model, Fig. 7); per full-solid checkpoint its stability next to the
    reduced solid's branch there (True, False, None: undecided or not computed)."""
    out = {}
    for k, c in enumerate(cases):
        beam, solid = resonance_of(branches[LINE][k]), resonance_of(branches[POINTS][k])
        pair = {"beam": peaks[LINE][k], "solid": peaks[POINTS][k]}
        out[c.label] = {"beam": beam, "solid": solid, "peaks": pair,
                        "same_resonance": same_peak(pair["beam"], pair["solid"], ("beam", "reduced solid")).to_json(),
                        "checkpoints": [{"rpm": p["rpm"], "stable": p["stable"],
                                         "reduced_branch_stable": p["reduced_branch_stable"]}
                                        for p in checks if p["case"] == c.label]}
    return out


@dataclass(frozen=True)
class HBFig7Result:
    """The beam's and the reduced solid's branches per case, the reduced solid's sweeps with every point named
    by the state it landed on, the full-solid checkpoints, and the one basis' error against per-speed ones."""

    cases: list[fam.Case]                      # comparisons._families.cases
    branches: dict[str, list[HBResult]]        # LINE / POINTS -> branch per case
    sweeps: list[SweepResult]                  # the reduced solid's time-domain sweep per case
    points: list[dict]                         # the sweep points named (comparisons._hb.named_points)
    checks: list[dict]                         # :func:`full_solid_checkpoints`
    peaks: dict[str, list[dict]]               # LINE / POINTS -> resonance at 2 H per case (_peaks.converged_peak)
    in_time: dict[str, list[list[dict]]]       # LINE / POINTS -> per case: bifurcations checked in time (_in_time)
    basis_error: list[dict]                    # reference_fe.frequency.basis_error
    per_speed_bases_s: float                   # building the time domain's per-speed bases
    peaks_s: float                             # locating the resonances at 2 H
    in_time_s: float                           # the bifurcations' checks in time

    def rows(self) -> list[dict]:
        """Per case: both resonances and their difference, folds, sweep points on a stable branch, costs."""
        rows = []
        for k, c in enumerate(self.cases):
            line, solid, sw = self.branches[LINE][k], self.branches[POINTS][k], self.sweeps[k]
            mine = [p for p in self.points if p["case"] == c.label]
            a_l, a_s = line.resonance["amplitude"], solid.resonance["amplitude"]
            rows.append({"case": c.label, "beam_resonance": line.resonance, "solid_resonance": solid.resonance,
                         "resonance_difference": abs(a_l / a_s - 1),
                         "solid_folds_rpm": [float(b["rpm"]) for b in solid.bifurcations if b["kind"] == "fold"],
                         "beam_folds_rpm": [float(b["rpm"]) for b in line.bifurcations if b["kind"] == "fold"],
                         "td_on_stable": sum(on_stable(p["branch"]) for p in mine), "td_points": len(mine),
                         "beam_hb_s": line.elapsed_s, "solid_hb_s": solid.elapsed_s, "solid_td_cpu_s": sw.cpu_s,
                         "complete": line.complete and solid.complete})
        return rows

    def cost_s(self) -> dict:
        rows, checks = self.rows(), self.checks
        return {"beam_hb_s": sum(r["beam_hb_s"] for r in rows), "solid_hb_s": sum(r["solid_hb_s"] for r in rows),
                "solid_td_cpu_s": sum(r["solid_td_cpu_s"] for r in rows), "per_speed_bases_s": self.per_speed_bases_s,
                "full_solid_condensation_s": sum(p["linear_s"] for p in checks),
                "full_solid_newton_s": sum(p["start_s"] + p["newton_s"] for p in checks),
                "full_solid_stability_s": sum(p["stability_s"] for p in checks),
                "peaks_s": self.peaks_s, "in_time_s": self.in_time_s}

    def conclusions(self) -> dict:
        return conclusions(self.cases, self.branches, self.peaks, self.checks)

    def to_json(self) -> dict:
        return {"conclusions": self.conclusions(), "cases": self.rows(),
                "branches": {c.label: {LINE: self.branches[LINE][k].to_json(),
                                       POINTS: self.branches[POINTS][k].to_json()} for k, c in enumerate(self.cases)},
                "time_domain_points": self.points, "basis_error": self.basis_error, "cost_s": self.cost_s(),
                "full_solid_checkpoints": self.checks,
                "bifurcations_in_time": {c.label: {m: self.in_time[m][k] for m in (LINE, POINTS)}
                                         for k, c in enumerate(self.cases)}}


def compute(scene) -> HBFig7Result:
    """Both models' branches per case, the reduced solid's sweeps on per-speed bases (each point read against
    its branch), the full-solid checkpoints, and the one basis' error against the per-speed ones."""
    from reference_fe.frequency import basis_error
    from reference_fe.system import reduced_operators
    params, o = scene.params, scene.options
    cases = fam.cases(params, o)
    td_rpms = np.linspace(o["rpm_from"], o["rpm_to"], int(o["td_rpm_count"]))
    t0 = time.perf_counter()
    for rpm in td_rpms:                                   # per-speed bases of the time domain (cached)
        reduced_operators(params, float(rpm))
    build_s = time.perf_counter() - t0
    errors = basis_error(params, td_rpms[:: max(1, len(td_rpms) // 4)])
    hb_kw = dict(harmonics=int(o["harmonics"]), samples=int(o["samples"]))
    branches = {m: [run_hb(c.params, m, o["rpm_from"], o["rpm_to"], **hb_kw) for c in cases] for m in (LINE, POINTS)}
    sweeps = run_sweeps([c.params for c in cases], POINTS, td_rpms)
    checks = full_solid_checkpoints(cases, branches[POINTS], o)
    points = [pt for c, solid, sw in zip(cases, branches[POINTS], sweeps)
              for pt in named_points(sw, partial(states_at, solid, c.params, POINTS, multipliers=False), o["match"],
                                     case=c.label)]
    t0 = time.perf_counter()
    peaks = {m: [converged_peak(b, c.params, m) for c, b in zip(cases, branches[m])] for m in (LINE, POINTS)}
    peaks_s = time.perf_counter() - t0
    in_time = {m: [bifurcations_in_time(b, c.params, m) for c, b in zip(cases, branches[m])] for m in (LINE, POINTS)}
    return HBFig7Result(cases=cases, branches=branches, sweeps=sweeps, points=points, checks=checks,
                        peaks=peaks, in_time=in_time, basis_error=errors, per_speed_bases_s=build_s,
                        peaks_s=peaks_s, in_time_s=time.perf_counter() - t0 - peaks_s)


def plot(result: HBFig7Result, scene, out: Path) -> list[str]:
    """Both panels (gaps; the small gap and preloads): beam thick, reduced solid thin, its sweep as circles,
    the full-solid checkpoints as diamonds; the named sweep points and the checkpoints as CSV."""
    fig, axes = figure(1, 2, width=10.0, height=4.2)
    for k, c in enumerate(result.cases):
        ax = axes[0][0 if c.kind == "gap" else 1]
        colour = f"C{k % 10}"
        line, solid, sw = result.branches[LINE][k], result.branches[POINTS][k], result.sweeps[k]
        line.plot(ax, label=f"{c.label} beam", colour=colour, linewidth=2.0, alpha=0.6)
        solid.plot(ax, label=f"{c.label} solid (reduced)", colour=colour, linewidth=0.8)
        ax.plot(sw.rpm, sw.amplitude_v_L * 1e3, "o", ms=3.5, mfc="none", color=colour)
        mine = [p for p in result.checks if p["case"] == c.label and p["converged"]]
        for stable, fill, word in ((True, colour, "stable"), (False, "none", "unstable"),
                                   (None, "0.85", "undecided")):
            these = [p for p in mine if p["stable"] is stable]
            if these:
                ax.plot([p["rpm"] for p in these], [p["amplitude_v_L"] * 1e3 for p in these], "D", ms=6,
                        color=colour, mfc=fill, mec="k", label=f"{c.label} full solid (HB checkpoints, {word})")
    for ax, title in zip(axes[0], ("(a) initial gaps", "(b) small gap and initial preloads")):
        ax.set_title(f"{title}\n(beam thick, solid thin, o solid TD, \u25c6/\u25c7 full solid HB stable/unstable;"
                     " dotted: undecided)",
                     fontsize=9)
        ax.legend(fontsize=6, ncol=2)
    save(fig, out / "hb_fig7.png")
    write_records(out / "td_points_by_branch.csv", result.points)
    write_records(out / "full_solid_checkpoints.csv",
                  [{k: p[k] for k in ("case", "rpm", "amplitude_v_L", "amplitude_w_L", "start_amplitude_v_L",
                                      "difference", "converged", "iterations", "stable", "reduced_branch_stable",
                                      "linear_s", "newton_s", "stability_s")}
                   for p in result.checks])
    return ["hb_fig7.png"]


def report(result: HBFig7Result, scene, files: list[str]) -> str:
    params, o = scene.params, scene.options
    rows, cost, concl, errors = result.rows(), result.cost_s(), result.conclusions(), result.basis_error
    lines = [f"# {scene.title}\n",
             f"Harmonic balance H = {o['harmonics']}, {o['samples']} samples, {o['rpm_from']:g}-{o['rpm_to']:g} r/min; "
             f"the reduced solid on one basis built at {params.speed.rpm:g} r/min. Against the per-speed bases: "
             f"frequencies within {max(e['frequency_error'] for e in errors):.2e}, linear tip response within "
             f"{max(e['response_error'] for e in errors):.2e} (at {', '.join(f'{e['rpm']:.0f}' for e in errors)} r/min).\n",
             f"Cost: HB beam {seconds(cost['beam_hb_s'])}, HB solid {seconds(cost['solid_hb_s'])}; the solid's time "
             f"domain {seconds(cost['solid_td_cpu_s'])} CPU for {int(o['td_rpm_count'])} speeds per curve (plus "
             f"{seconds(cost['per_speed_bases_s'])} for its per-speed bases); the resonances at twice the harmonics "
             f"{seconds(cost['peaks_s'])}, the bifurcations checked in time {seconds(cost['in_time_s'])}.\n",
             markdown_table(["case", "beam resonance (r/min, um)", "solid resonance (r/min, um)", "difference (%)",
                             "beam folds (r/min)", "solid folds (r/min)", "solid TD points on a stable solid branch"],
                            [(r["case"], f"{r['beam_resonance']['rpm']:.0f}, {r['beam_resonance']['amplitude'] * 1e6:.2f}",
                              f"{r['solid_resonance']['rpm']:.0f}, {r['solid_resonance']['amplitude'] * 1e6:.2f}",
                              100 * r["resonance_difference"],
                              ", ".join(f"{x:.0f}" for x in r["beam_folds_rpm"]) or "none",
                              ", ".join(f"{x:.0f}" for x in r["solid_folds_rpm"]) or "none",
                              f"{r['td_on_stable']}/{r['td_points']}") for r in rows]),
             "", "Same resonance (beam against reduced solid, relative amplitude difference of the resonances "
                 "at twice the harmonics): " + "; ".join(
                 f"{label}: {verdict_text(c['same_resonance'], 100, ' %')}" for label, c in concl.items()) + ". "
             + notes_line([(f"{m} {c.label}", result.branches[m][k]) for m in (LINE, POINTS)
                           for k, c in enumerate(result.cases)]),
             "", in_time_line([(f"{m} {c.label}", result.in_time[m][k]) for m in (LINE, POINTS)
                               for k, c in enumerate(result.cases)]),
             "", *[f"![{f}]({f})" for f in files], "", *checkpoint_report(result.checks, cost)]
    return "\n".join(lines) + "\n"


run = study(compute, plot, report)


def checkpoint_report(checks: list[dict], cost: dict) -> list[str]:
    """The report's section on the full-solid checkpoints."""
    if not checks:
        return []
    worst = max((abs(p["difference"]) for p in checks if p["difference"] is not None), default=float("nan"))
    c = checks[0]
    return ["## Full-solid checkpoints\n",
            f"The full solid ({c['dofs']} DOF) condensed exactly on its {c['condensed_on']} contact coordinates "
            f"per harmonic (H = {c['harmonics']}), its Newton started from each state of the reduced solid's "
            f"branch at the speed: the reduced solid's states within {100 * worst:.3f} % of the full solid's "
            f"(v_L). Cost: condensation {seconds(cost['full_solid_condensation_s'])} (once per speed, shared by "
            f"the cases there), Newton {seconds(cost['full_solid_newton_s'])} (with the reduced start), "
            f"stability {seconds(cost['full_solid_stability_s'])}. Stability: the Floquet multipliers of the full "
            "solid's own orbit (its contact states along the period), the perturbations projected on the reduced "
            "solid's basis and on one with twice its modes; the largest |multiplier| on each is listed, the "
            "verdict is the larger basis'.\n",
            markdown_table(["case", "rpm", "reduced solid (um)", "full solid (um)", "difference (%)",
                            "reduced branch", "full solid", "largest |multiplier| by basis (DOF)",
                            "Newton iterations", "condensation (s)", "Newton (s)", "stability (s)"],
                           [(p["case"], f"{p['rpm']:.0f}",
                             f"{p['start_amplitude_v_L'] * 1e6:.3f}" if p["start_amplitude_v_L"] else "-",
                             f"{p['amplitude_v_L'] * 1e6:.3f}" + _newton_note(p),
                             f"{100 * p['difference']:.3f}" if p["difference"] is not None else "-",
                             _word(p["reduced_branch_stable"]), _word(p["stable"]),
                             ", ".join(f"{d}: {m:.4f}" for d, m in p["largest_multiplier"].items()) or "-",
                             p["iterations"], f"{p['linear_s']:.1f}", f"{p['start_s'] + p['newton_s']:.1f}",
                             f"{p['stability_s']:.1f}")
                            for p in checks])]


def _newton_note(p: dict) -> str:
    """What a checkpoint's Newton reached, where short of what was asked (Checkpoint.converged, .short)."""
    if not p["converged"]:
        return " (not converged)"
    return f" (residual {p['residual']:.1e}: short of the tolerance asked)" if p["short"] else ""


def _word(stable: bool | None) -> str:
    return "-" if stable is None else "stable" if stable else "unstable"
