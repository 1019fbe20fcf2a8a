"""Fig. 11 by harmonic balance: every steady-state branch over speed, with its stability, for gaps and preloads.

The paper's Fig. 11 (a: initial gaps, b: a 1 um gap and initial normal
preloads) is a set of from-rest time-domain sweeps. Here each curve is a
harmonic-balance branch followed by continuation (shroud.analysis.hb):
stable stretches solid, unstable dashed, folds (o), period doublings (s)
and Neimark-Sacker points (^) marked. The time-domain sweep of the same
cases is overlaid as dots, and each of its points is named by the branch it
landed on: a stable P1 branch (the lower or upper one where several
coexist), or none (a run still drifting, or a P3/P5/... state the P1
curves cannot hold; the Neimark-Sacker and period-doubling marks say
where those begin). The resonance of each case (largest P1 amplitude on
the branch's points not shown unstable) and the optimal preload are read off the
branches; both methods' costs are reported side by side.

With ``seed_from_sweep`` the study also finds the branches the continuation
from ``rpm_from`` misses (isolated loops, stretches beyond a corner it
stepped over) from its own time-domain sweep: each P1 point of the sweep not
on a stable stretch of the continued branch seeds one
(shroud.analysis.hb.run_hb_family; the seed's state is the run's own, from
rest over ``time.periods``, as the sweep ran it), and the points are named by
every branch found. The conclusions say how many branches each case has and
from which seeds.

The study is compute (:func:`compute` -> :class:`HBGapPreloadResult`) -> plot -> report.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import partial
from pathlib import Path

import numpy as np

from comparisons._hb import (landed_on, named_points, notes_line, on_stable, resonance_of, rises, states_at,
                             states_on, verdict_text)
from comparisons._in_time import bifurcations_in_time, in_time_line
from comparisons._study import study
from shroud.analysis.hb import HBFamily, run_hb, run_hb_family
from shroud.analysis.sweep import run_sweeps
from shroud.base.markdown import markdown_table, seconds
from shroud.core.plotting import figure, save
from shroud.core.results import HBResult, SweepResult
from shroud.base.tables import write_records

OPTIONS = {
    "gaps_um": [600.0, 300.0, 100.0, 50.0, 10.0],
    "small_gap_um": 1.0,
    "preloads_N": [10.0, 25.0, 50.0, 100.0, 200.0],
    "rpm_from": 4000.0, "rpm_to": 30000.0,
    "td_rpm_count": 53,            # speeds of the overlaid time-domain sweep
    "harmonics": 10, "samples": 512,
    "model": "reduced",
    "match": 0.01,                 # a time-domain point is on a branch within this relative difference
    "seed_from_sweep": False,      # continue a branch through each P1 point of the sweep the first one misses
}


def cases(params, opts) -> list[tuple[str, str, float, object]]:
    """(label, kind, value, params): the gap panel, then the small gap and the preload panel."""
    out = [(f"gap {g:g} um", "gap", g, params.updated({"contact.gap": g * 1e-6})) for g in opts["gaps_um"]]
    g = opts["small_gap_um"]
    out.append((f"gap {g:g} um", "preload", -params.contact.kn * g * 1e-6,
                params.updated({"contact.gap": g * 1e-6})))
    out += [(f"N0 {n:g} N", "preload", n, params.updated({"contact.N0": n})) for n in opts["preloads_N"]]
    return out


def seeded(params, opts, sweep, branch):
    """The family of ``branch`` (the one continued from rpm_from) grown from the sweep's P1 points it does not
    hold on a stable stretch: their speeds are the seeds, their states the runs' own (the scene's periods)."""
    seeds = [r for r, a, per in zip(sweep.rpm, sweep.amplitude_v_L, sweep.period)
             if per == 1 and not on_stable(landed_on(states_at(branch, params, opts["model"], r), a, per,
                                                     opts["match"]))]
    return run_hb_family(params, opts["model"], opts["rpm_from"], opts["rpm_to"], seeds,
                         harmonics=int(opts["harmonics"]), samples=int(opts["samples"]),
                         periods=params.time.periods, match=opts["match"], continued=branch)


def branches_found(family) -> dict:
    """How many branches a case has and the seeds they came from (data for the conclusions)."""
    return {"branches": len(family.branches), "seeds_rpm": [s.rpm for s in family.seeds],
            "new_branches_from_rpm": [s.rpm for s in family.seeds if s.outcome == "new branch"],
            "seed_outcomes": [s.to_json() for s in family.seeds]}


def seeds_text(found: dict | None) -> str:
    """The report's sentence on the branches found (seed_from_sweep), or on their not being sought."""
    if found is None:
        return ("Branches: the one continued from the range's first speed per case (seed_from_sweep off: "
                "branches it misses are not sought).")
    return ("Branches (the continued one, then one through each P1 point of the time-domain sweep it does not "
            "hold on a stable stretch): " + "; ".join(
                f"{label} {f['branches']}" + (f" (new from {', '.join(f'{r:.0f}' for r in f['new_branches_from_rpm'])}"
                                               " r/min)" if f["new_branches_from_rpm"] else "")
                + (f", {len(f['seeds_rpm'])} seeds" if f["seeds_rpm"] else "") for label, f in found.items()) + ".")


@dataclass(frozen=True)
class HBGapPreloadResult:
    """Every case's branch (and with ``seed_from_sweep`` the branches seeded from its sweep), its from-rest
    sweep, and every sweep point named by the state it landed on."""

    cases: list[tuple[str, str, float, object]]     # (label, kind, value, params): :func:`cases`
    branches: list[HBResult]                        # the branch continued from rpm_from, per case
    sweeps: list[SweepResult]                       # the time-domain sweep per case
    families: list[HBFamily] | None                 # seed_from_sweep: every branch found per case, else None
    points: list[dict]                              # the sweep points named (comparisons._hb.named_points)
    rpm_range: tuple[float, float]                  # rpm_from, rpm_to
    in_time: list[list[list[dict]]]                 # per case, per branch found: bifurcations checked in time

    def found(self, i: int) -> list[HBResult]:
        """Every branch of case i: the continued one first."""
        return self.families[i].branches if self.families else [self.branches[i]]

    def rows(self) -> list[dict]:
        """Per case: both methods' resonances, the sweep points on a stable branch, stability changes, costs."""
        rows = []
        for i, ((label, kind, value, _), br, sw) in enumerate(zip(self.cases, self.branches, self.sweeps)):
            mine = [p for p in self.points if p["case"] == label]
            rows.append({"case": label, "kind": kind, "value": value,
                         "hb_resonance_rpm": br.resonance["rpm"], "hb_resonance_amplitude_m": br.resonance["amplitude"],
                         "td_resonance_rpm": sw.resonance["rpm"], "td_resonance_amplitude_m": sw.resonance["amplitude"],
                         "td_points_on_a_stable_branch": sum(on_stable(p["branch"]) for p in mine),
                         "td_points": len(mine),
                         "stability_changes": [dict(b, rpm=float(b["rpm"]), amplitude=float(b["amplitude"]))
                                               for b in br.bifurcations],
                         "hb_points": len(br.rpm), "hb_complete": br.complete, "hb_stopped": br.stopped,
                         "hb_s": br.elapsed_s + (self.families[i].elapsed_s if self.families else 0.0),
                         "hb_branches": len(self.found(i)), "td_cpu_s": sw.cpu_s, "td_wall_s": sw.elapsed_s,
                         "spectral_tail": br.spectral_tail})
        return rows

    def best(self) -> dict | None:
        """The row of the preload with the smallest resonant amplitude among those peaking inside the range."""
        lo, hi = self.rpm_range
        pre = [r for r in self.rows() if r["kind"] == "preload" and r["value"] >= 0
               and lo < r["hb_resonance_rpm"] < hi]
        return min(pre, key=lambda r: r["hb_resonance_amplitude_m"]) if pre else None

    def conclusions(self) -> dict:
        return conclusions(self.cases, self.branches, self.best(), self.families)

    def to_json(self) -> dict:
        rows, best = self.rows(), self.best()
        curves = {}
        for i, ((label, _, _, _), br) in enumerate(zip(self.cases, self.branches)):
            curves[label] = br.to_json()
            if self.families:
                curves[label]["seeded_branches"] = [b.to_json() for b in self.found(i)[1:]]
        return {"conclusions": self.conclusions(), "cases": rows, "branches": curves,
                "time_domain_points": self.points, "optimal_preload_N": best["value"] if best else None,
                "bifurcations_in_time": {label: self.in_time[i] for i, (label, _, _, _) in enumerate(self.cases)},
                "cost_s": {"harmonic_balance_wall": sum(r["hb_s"] for r in rows),
                           "time_domain_cpu": sum(r["td_cpu_s"] for r in rows)}}


def conclusions(cs, branches, best: dict | None, families=None) -> dict:
    """What the study concludes, as data: every case's resonance (on points not shown unstable, with its
    errors and stability: comparisons._hb.resonance_of); whether the resonant speed rises as the gap closes
    (the gaps from the largest down to the small gap: a Verdict, paper Sect. 3.1); the optimal preload read
    off the branches (N0, N, with its resonance's stability; None when no preload peaks inside the range);
    with ``families`` (seed_from_sweep) how many branches each case has and from which seeds."""
    res = {label: resonance_of(br) for (label, _, _, _), br in zip(cs, branches)}
    closing = [res[label] for label, kind, value, _ in sorted(cs, key=lambda c: -abs(c[2]) if c[1] == "gap" else 0.0)
               if kind == "gap" or value < 0]
    out = {"resonances": res,
           "resonant_speed_rises_as_gap_closes": rises(closing, "gaps closing down to the small gap").to_json(),
           "optimal_preload": None if best is None else {"N0": best["value"], "stable": res[best["case"]]["stable"]}}
    if families is not None:
        out["branches_found"] = {label: branches_found(f) for (label, _, _, _), f in zip(cs, families)}
    return out


def compute(scene) -> HBGapPreloadResult:
    """Every case's branch by continuation, its from-rest sweep (with ``seed_from_sweep``: the branches seeded
    from it), and every sweep point read against the branches found."""
    opts, params = scene.options, scene.params
    cs = cases(params, opts)
    branches = [run_hb(p, opts["model"], opts["rpm_from"], opts["rpm_to"], harmonics=int(opts["harmonics"]),
                       samples=int(opts["samples"])) for _, _, _, p in cs]
    rpms = np.linspace(opts["rpm_from"], opts["rpm_to"], int(opts["td_rpm_count"]))
    sweeps = run_sweeps([p for _, _, _, p in cs], opts["model"], rpms)
    families = ([seeded(p, opts, sw, br) for (_, _, _, p), sw, br in zip(cs, sweeps, branches)]
                if opts["seed_from_sweep"] else None)
    found = [families[i].branches if families else [br] for i, br in enumerate(branches)]
    points = [pt for (label, _, _, p), sw, brs in zip(cs, sweeps, found)
              for pt in named_points(sw, partial(states_on, brs, p, opts["model"]), opts["match"], case=label)]
    in_time = [[bifurcations_in_time(b, p, opts["model"]) for b in brs] for (_, _, _, p), brs in zip(cs, found)]
    return HBGapPreloadResult(cases=cs, branches=branches, sweeps=sweeps, families=families, points=points,
                              rpm_range=(float(opts["rpm_from"]), float(opts["rpm_to"])), in_time=in_time)


def plot(result: HBGapPreloadResult, scene, out: Path) -> list[str]:
    """Both panels (gaps; the small gap and preloads): every branch found, the sweep as dots; the named
    sweep points as CSV."""
    fig, axes = figure(1, 2, width=10.0, height=4.2)
    in_panel = [kind for _, kind, _, _ in result.cases]
    for i, ((label, kind, _, _), br, sw) in enumerate(zip(result.cases, result.branches, result.sweeps)):
        ax = axes[0][0 if kind == "gap" else 1]
        colour = f"C{i % 10}"
        # widest first: a curve that lies on an earlier one (the preloaded blade stuck alike at 25 and
        # 100 N) shows as a line within a line; dashes mean unstable here, so they cannot tell them apart
        br.plot(ax, label=label, colour=colour, linewidth=1.0 + 0.9 * in_panel[i + 1:].count(kind))
        for extra in result.found(i)[1:]:
            extra.plot(ax, colour=colour, linewidth=1.0)
        ax.plot(sw.rpm, sw.amplitude_v_L * 1e3, ".", color=colour, ms=4)
    for j, title in enumerate(("(a) initial gaps", "(b) 1 um gap and initial preloads")):
        ax = axes[0][j]
        ax.set_title(f"{title}: HB stable -, unstable --, undecided :x; time domain .")
        ax.legend(ncol=2)
    save(fig, out / "hb_fig11.png")
    write_records(out / "td_points_by_branch.csv", result.points)
    return ["hb_fig11.png"]


def report(result: HBGapPreloadResult, scene, files: list[str]) -> str:
    opts, params = scene.options, scene.params
    rows, best, concl, points = result.rows(), result.best(), result.conclusions(), result.points
    hb_total, td_total = sum(r["hb_s"] for r in rows), sum(r["td_cpu_s"] for r in rows)
    off = [p for p in points if not on_stable(p["branch"])]
    lines = [f"# {scene.title}\n",
             f"Model {opts['model']}; harmonic balance H = {opts['harmonics']}, {opts['samples']} samples per "
             f"period, continuation from {opts['rpm_from']:g} to {opts['rpm_to']:g} r/min with the Floquet "
             f"multipliers of every point; time domain {int(opts['td_rpm_count'])} speeds x {params.time.periods} "
             "periods from rest.\n",
             f"Cost: harmonic balance {seconds(hb_total)} wall for all branches (one process) against "
             f"{seconds(td_total)} CPU for the time-domain sweeps.\n",
             markdown_table(["case", "HB resonance (r/min)", "HB amplitude (mm)", "TD resonance (r/min)",
                             "TD amplitude (mm)", "TD points on a stable HB branch", "stability changes",
                             "HB cost", "TD cost (CPU)"],
                            [(r["case"], f"{r['hb_resonance_rpm']:.0f}", r["hb_resonance_amplitude_m"] * 1e3,
                              f"{r['td_resonance_rpm']:.0f}", r["td_resonance_amplitude_m"] * 1e3,
                              f"{r['td_points_on_a_stable_branch']}/{r['td_points']}",
                              ", ".join(f"{b['kind']} {b['rpm']:.0f}" for b in r["stability_changes"]) or "none",
                              seconds(r["hb_s"]), seconds(r["td_cpu_s"])) for r in rows]),
             "",
             (f"Optimal preload over {opts['rpm_from']:g}-{opts['rpm_to']:g} r/min (smallest resonant amplitude on "
              f"the branches): N0 = {best['value']:g} N, {best['hb_resonance_amplitude_m'] * 1e3:.4f} mm at "
              f"{best['hb_resonance_rpm']:.0f} r/min." if best else
              f"No preload has its resonance inside {opts['rpm_from']:g}-{opts['rpm_to']:g} r/min (every peak is at "
              "the range's end): no optimal preload can be read off here (see the hb_optimal_preload study)."),
             "",
             f"Time-domain points not on a stable P1 branch within {100 * opts['match']:g} %: {len(off)} of "
             f"{len(points)}" + (":\n" if off else "."),
             *(markdown_table(["case", "rpm", "amplitude (mm)", "period", "landed on"],
                              [(p["case"], f"{p['rpm']:.0f}", p["amplitude_m"] * 1e3, p["period"] or "-",
                                p["branch"]) for p in off]).splitlines() if off else []),
             "", seeds_text(concl.get("branches_found")),
             "", "Resonant speed rises as the gap closes (its smallest rise from one gap to the next): "
             + verdict_text(concl["resonant_speed_rises_as_gap_closes"], unit=" r/min") + ". "
             + notes_line([(label, br) for (label, _, _, _), br in zip(result.cases, result.branches)]),
             "", in_time_line([(f"{label} branch {j + 1}", checked)
                               for (label, _, _, _), per in zip(result.cases, result.in_time)
                               for j, checked in enumerate(per)]),
             "", *[f"![{f}]({f})" for f in files], "",
             "Each panel's curves are drawn widest first: where two coincide (a preloaded blade stuck all "
             "period responds alike at every preload), the later one runs inside the earlier one."]
    return "\n".join(lines) + "\n"


run = study(compute, plot, report)
