"""Figs. 14-15: P1 motion at mu = 0.1 and P10 motion at mu = 0.5, 25500 r/min.

Paper (Sect. 3.2): with a small gap or a preload, the response at 25500 r/min
is period-one at mu 0.1 and period-ten at mu 0.5 (the impact repeats every
ten excitation periods; friction shares that period). The paper does not
state the gap or preload of Figs. 14-15; this study runs every case in
``cases`` and reports the period found for each. It then maps the period
over the band where the paper sees P10 (Fig. 12(f): mu 0.5, preloads,
22500-26000 r/min): every speed of ``search_rpms`` for small gaps and
preloads, with ``search_periods`` periods per run so transients have died.

The study is compute (:func:`compute` -> :class:`PeriodicityResult`) ->
plot (:func:`plot`) -> report (:func:`report`). The waveforms shown for each
mu are those of the case whose run found the longest period (a response
with no period up to P10 ranks above all): chosen by what the runs found,
never by the paper's expected answer.
"""

from __future__ import annotations

import csv
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from comparisons import paper
from shroud.analysis.api import build_system
from shroud.analysis.sweep import Settling, run_sweeps
from shroud.analysis.transient import simulate
from shroud.base.markdown import markdown_table, seconds
from shroud.core import signals
from shroud.core.plotting import figure, save
from shroud.core.results import SweepResult, TransientResult

OPTIONS = {"mu_values": [0.1, 0.5], "gaps_um": [1.0], "preloads_N": [10.0, 25.0, 50.0],
           "plot_periods": 20,
           "search_mu": paper.P10_MU, "search_rpm_from": paper.P10_BAND_RPM[0],
           "search_rpm_to": paper.P10_BAND_RPM[1], "search_rpm_count": 15,
           "search_gaps_um": [0.5, 1.0, 2.0, 5.0, 10.0],
           "search_preloads_N": [1.0, 2.0, 5.0, 10.0, 15.0, 20.0, 25.0, 35.0, 50.0, 100.0],
           "search_periods": 600,
           # (mu, gap in um, r/min): P10 points the family sweeps (friction scene) found outside the band
           "confirm_points": [[0.5, 10.0, 12500.0], [0.3, 10.0, 21250.0]]}


NO_PERIOD_RANK = 99      # a response without a period up to P10 outranks every periodic one


@dataclass(frozen=True)
class CaseRun:
    """One run at the scene's speed: its friction coefficient, case label and result."""

    mu: float
    label: str
    result: TransientResult


@dataclass(frozen=True)
class Confirmation:
    """A long run at a point where the family sweeps found a long period."""

    row: dict
    result: TransientResult


@dataclass(frozen=True)
class PeriodicityResult:
    runs: list[CaseRun]
    map_rpm: np.ndarray
    period_map: list[tuple[str, SweepResult]]
    confirmed: list[Confirmation]

    def shown(self) -> dict[float, CaseRun]:
        """Per mu, the run whose waveforms the figures show (:func:`waveform_case`)."""
        by_mu: dict[float, list[CaseRun]] = {}
        for r in self.runs:
            by_mu.setdefault(r.mu, []).append(r)
        return {mu: waveform_case(runs) for mu, runs in sorted(by_mu.items())}

    def conclusions(self) -> dict:
        """What the report concludes, as data: the period of every case at the scene's speed, whether
        P10 appears there and anywhere on the band's map."""
        return {"periods": {f"mu {r.mu:g}, {r.label}": r.result.period for r in self.runs},
                "p10_at_scene_speed": any(r.result.period == 10 for r in self.runs),
                "p10_in_band": any(p == 10 for _, sw in self.period_map for p in sw.period)}

    def to_json(self) -> dict:
        return {"conclusions": self.conclusions(),
                "periods": {f"mu {r.mu:g}, {r.label}": r.result.period for r in self.runs},
                "shown": {f"{mu:g}": r.label for mu, r in self.shown().items()},
                "rows": [list(row) for row in _case_rows(self.runs)],
                "confirmed": [c.row for c in self.confirmed],
                "period_map": {"rpm": [float(r) for r in self.map_rpm],
                               "cases": {label: {"period": list(sw.period),
                                                 "amplitude_v_L_m": [float(a) for a in sw.amplitude_v_L]}
                                         for label, sw in self.period_map}}}


def waveform_case(runs: list[CaseRun]) -> CaseRun:
    """The run with the longest period found (no period up to P10 ranks highest; ties: the first)."""
    return max(runs, key=lambda r: r.result.period or NO_PERIOD_RANK)


def _case_rows(runs: list[CaseRun]) -> list[tuple]:
    return [(r.mu, r.label, f"P{r.result.period}" if r.result.period else "none up to P10",
             r.result.amplitude["v_L"] * 1e3, r.result.peak["N1"], r.result.peak["Ff1"],
             seconds(r.result.elapsed_s)) for r in runs]


def confirm(params, points, periods: int) -> list[Confirmation]:
    """Long runs at given (mu, gap, speed) points: the period over the last 30 and the last 100 periods."""
    out = []
    for mu, gap_um, rpm in points:
        p = params.updated({"contact.mu": mu, "contact.gap": gap_um * 1e-6, "speed.rpm": rpm,
                            "time.periods": int(periods)})
        res = simulate(build_system(p, "reduced"), p)
        tr, spp = res.trajectory, p.time.steps_per_period
        x = tr.tip[:, 0]
        out.append(Confirmation(row={
            "mu": mu, "gap_um": gap_um, "rpm": rpm, "period_30": res.period,
            "period_100": signals.detect_period(x, spp, max_period=20, window=100),
            "amplitude_v_L_m": res.amplitude["v_L"],
            # how strong the subharmonic is: spread of the once-per-period samples
            "poincare_spread_m": float(np.ptp(signals.poincare(signals.last_periods(x, spp, 30), spp))),
            # share of the excitation periods with an impact: 1 for impacts every period,
            # 0.1 for the paper's P10 (one impact every ten periods)
            "impact_periods_fraction": float(np.mean(np.any(
                (signals.last_periods(tr.normal.max(axis=1), spp, 30)[1:] > 0).reshape(30, spp), axis=1))),
            "time_s": res.elapsed_s}, result=res))
    return out


def period_map(params, opts) -> tuple[np.ndarray, list[tuple[str, SweepResult]]]:
    """Period (and amplitude) at every speed of the P10 band for every small gap and preload."""
    base = params.updated({"contact.mu": opts["search_mu"], "time.periods": int(opts["search_periods"])})
    cases = [(f"gap {g:g} um", base.updated({"contact.gap": g * 1e-6})) for g in opts["search_gaps_um"]]
    cases += [(f"N0 {n:g} N", base.updated({"contact.N0": n})) for n in opts["search_preloads_N"]]
    rpms = np.linspace(opts["search_rpm_from"], opts["search_rpm_to"], int(opts["search_rpm_count"]))
    # exactly search_periods per run, as the report says (no extension until the amplitude settles)
    sweeps = run_sweeps([p for _, p in cases], "reduced", rpms,
                        settling=Settling(max_periods=int(opts["search_periods"])))
    return rpms, [(label, sw) for (label, _), sw in zip(cases, sweeps)]


def compute(scene, out: Path) -> PeriodicityResult:
    """Every case at the scene's speed (time series into ``out``), the period map, the long runs."""
    params, opts = scene.params, scene.options
    cases = [(f"gap {g:g} um", {"contact.gap": g * 1e-6}) for g in opts["gaps_um"]]
    cases += [(f"N0 {n:g} N", {"contact.N0": n}) for n in opts["preloads_N"]]
    runs = []
    for mu in opts["mu_values"]:
        for label, change in cases:
            p = params.updated({**change, "contact.mu": mu})
            res = simulate(build_system(p, "reduced"), p, csv_path=out / f"mu{mu:g}_{label.replace(' ', '')}.csv")
            runs.append(CaseRun(mu=mu, label=label, result=res))
    rpms, search = period_map(params, opts)
    confirmed = confirm(params, opts["confirm_points"], opts["search_periods"]) if opts["confirm_points"] else []
    return PeriodicityResult(runs=runs, map_rpm=rpms, period_map=search, confirmed=confirmed)


def plot(result: PeriodicityResult, scene, out: Path) -> list[Path]:
    """Waveforms and spectra of the shown runs; the long runs with their once-per-period samples."""
    params, opts = scene.params, scene.options
    spp = params.time.steps_per_period
    shown = list(result.shown().items())[:2]
    n = opts["plot_periods"] * spp
    fig, axes = figure(3, 2, width=9.0)
    for col, (mu, run) in enumerate(shown):
        tr, res = run.result.trajectory, run.result
        for row, (x, name) in enumerate(((tr.tip[:, 0] * 1e3, "v_L (mm)"), (tr.friction[:, 0], "F_f1 (N)"),
                                         (tr.normal[:, 0], "N_1 (N)"))):
            ax = axes[row][col]
            ax.plot(tr.t[-n:], x[-n:], lw=0.8)
            ax.set_xlabel("t (s)")
            ax.set_ylabel(name)
        axes[0][col].set_title(f"mu = {mu:g}, {run.label}: "
                               + (f"P{res.period}" if res.period else "no period up to P10"))
    paths = [save(fig, out / "waveforms.png")]
    fig, axes = figure(3, 2, width=9.0)
    f_e = params.load.ke * params.speed.rpm / 60.0
    for col, (mu, run) in enumerate(shown):
        tr = run.result.trajectory
        for row, (x, name) in enumerate(((tr.tip[:, 0], "v_L (m)"), (tr.friction[:, 0], "F_f1 (N)"),
                                         (tr.normal[:, 0], "N_1 (N)"))):
            f, a = signals.spectrum(x, tr.dt, spp, periods=opts["plot_periods"])
            ax = axes[row][col]
            ax.plot(f / f_e, a, lw=0.8)
            ax.set_xlim(0, 4)
            ax.set_xlabel("frequency / f_e")
            ax.set_ylabel(f"|{name}|")
        axes[0][col].set_title(f"spectra, mu = {mu:g}, {run.label}")
    paths.append(save(fig, out / "spectra.png"))
    if result.confirmed:
        fig, axes = figure(len(result.confirmed), 1, width=9.0, height=2.4 * len(result.confirmed) + 0.4)
        for ax, c in zip((a[0] for a in axes), result.confirmed):
            tr, r = c.result.trajectory, c.row
            x, n30 = tr.tip[:, 0], 30 * spp
            ax.plot(tr.t[-n30 - 1:], x[-n30 - 1:] * 1e3, lw=0.7)
            ax.plot(tr.t[-n30 - 1::spp], x[-n30 - 1::spp] * 1e3, "o", ms=3, label="once per excitation period")
            ax.set_title(f"mu = {r['mu']:g}, gap {r['gap_um']:g} um, {r['rpm']:g} r/min: "
                         + (f"P{r['period_30']}" if r["period_30"] else "no period up to P10"))
            ax.set_xlabel("t (s)")
            ax.set_ylabel("v_L (mm)")
            ax.legend()
        paths.append(save(fig, out / "confirmed_periods.png"))
    return paths


def report(result: PeriodicityResult, scene) -> str:
    params, opts = scene.params, scene.options
    rpms, search, confirmed = result.map_rpm, result.period_map, [c.row for c in result.confirmed]
    seen = sorted({p for _, sw in search for p in sw.period if p})
    p10_at = [(label, rpms[k]) for label, sw in search for k, p in enumerate(sw.period) if p == 10]
    p1 = [r.label for r in result.runs if r.mu == min(opts["mu_values"]) and r.result.period == 1]
    p10 = [r.label for r in result.runs if r.mu == max(opts["mu_values"]) and r.result.period == 10]
    shown = ", ".join(f"mu = {mu:g}: {r.label}" for mu, r in result.shown().items())
    lines = [f"# {scene.title}\n",
             f"{params.speed.rpm:g} r/min, {params.time.periods} periods, period read from one sample per "
             f"excitation period over the last 30 periods.\n",
             "| paper | here |", "|---|---|",
             f"| P1 at mu = {min(opts['mu_values']):g} | P1 in: {', '.join(p1) or 'none of the cases'} |",
             f"| P10 at mu = {max(opts['mu_values']):g} | P10 in: {', '.join(p10) or 'none of the cases'} |", "",
             markdown_table(["mu", "case", "period", "amplitude v_L (mm)", "peak N1 (N)", "peak Ff1 (N)", "time"],
                            _case_rows(result.runs)),
             f"Waveforms and spectra below: for each mu the case with the longest period found ({shown}).\n",
             "![waveforms.png](waveforms.png)", "![spectra.png](spectra.png)",
             f"\n## Period over the P10 band: mu = {opts['search_mu']:g}, {len(rpms)} speeds "
             f"{rpms[0]:g}-{rpms[-1]:g} r/min, {opts['search_periods']} periods per run\n",
             f"Periods found: {', '.join(f'P{p}' for p in seen) or 'none'}; P10 at: "
             + (", ".join(f"{c} {r:.0f} r/min" for c, r in p10_at) or "no case and speed") +
             f". '-': no period up to P10 (quasi-periodic or chaotic) over the last 30 periods. Summed run "
             f"time {seconds(sum(sw.cpu_s for _, sw in search))}. With {len(rpms)} speeds and {len(search)} "
             "cases the map can miss periods that live in narrow speed bands"
             + (" (this is the quick version: the full scene's finer map is the reference for which periods "
                "occur)" if scene.quick else "") + ".\n",
             markdown_table(["case", *[f"{r:.0f}" for r in rpms]],
                            [(label, *[f"P{p}" if p else "-" for p in sw.period]) for label, sw in search])]
    if confirmed:
        lines += [f"\n## Periods at points found by the family sweeps, {opts['search_periods']} periods per run\n",
                  markdown_table(["mu", "gap (um)", "speed (r/min)", "period (last 30)",
                                  "period (last 100, up to P20)", "amplitude v_L (mm)",
                                  "spread of once-per-period samples (mm)", "periods with an impact", "time"],
                                 [(r["mu"], r["gap_um"], r["rpm"], f"P{r['period_30']}" if r["period_30"] else "-",
                                   f"P{r['period_100']}" if r["period_100"] else "-", 1e3 * r["amplitude_v_L_m"],
                                   1e3 * r["poincare_spread_m"], f"{100 * r['impact_periods_fraction']:.0f} %",
                                   seconds(r["time_s"])) for r in confirmed]),
                  "\nThe paper's P10 has one impact every ten excitation periods; a P10 with an impact in every "
                  "period is a weak ten-period modulation of a P1-like motion.\n",
                  "![confirmed_periods.png](confirmed_periods.png)"]
    return "\n".join(lines) + "\n"


def write_csv(result: PeriodicityResult, out: Path) -> None:
    with open(out / "periods.csv", "w", newline="") as fh:
        csv.writer(fh).writerows([("mu", "case", "period", "amplitude_v_L_mm", "peak_N1", "peak_Ff1", "time"),
                                  *_case_rows(result.runs)])
    with open(out / "period_map.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["case", "rpm", "period", "amplitude_v_L_m"])
        for label, sw in result.period_map:
            for k, r in enumerate(result.map_rpm):
                w.writerow([label, r, sw.period[k] or "", sw.amplitude_v_L[k]])


def run(scene, out: Path) -> dict:
    result = compute(scene, out)
    write_csv(result, out)
    plot(result, scene, out)
    (out / "report.md").write_text(report(result, scene))
    return result.to_json()
