"""Figs. 12-13 by harmonic balance: the coefficient of friction over gaps and preloads.

Per value of mu (paper: 0.1, 0.3, 0.5) every case of Fig. 11 (initial gaps;
a 1 um gap and initial preloads) is a harmonic-balance branch over speed
with its stability (shroud.analysis.hb; stable solid, unstable dashed,
stability changes marked), over a speed range extended beyond the paper's
so that the preloads' resonances lie inside it. The resonant speed and
amplitude over the gap (Fig. 13a-b) are read off the branches (largest P1
amplitude on the points not shown unstable); over the preload (Fig. 13c-d) they are the
resonance followed in N0 from touching (N0 = 0) on (shroud.analysis.peak),
with the branches' peaks as markers (the 1 um gap: its branch's peak). Where the time-domain sweep is run
(``time_domain``) its points are overlaid and named by the HB state they
landed on (comparisons._hb). The conclusions are the paper's (Sect. 3.2):
mu hardly matters at gaps >= 100 um; with a 1 um gap or a preload the
resonant speed rises with mu; the optimal preload falls as mu grows while
the smallest resonant amplitude stays nearly the same; once the shroud
stays stuck through the resonance mu no longer matters; and (Sect. 3.1)
the resonant speed rises as the gap closes.

The study is compute (:func:`compute` -> :class:`HBFamilyResult`; :func:`compute_variants` for any varied
contact parameter, comparisons.hb_stiffness_ratio) -> plot -> report.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import partial
from pathlib import Path

import numpy as np

from comparisons import hb_optimal_preload as peak
from comparisons._hb import named_points, notes_line, on_stable, rises, states_at, verdict_text
from comparisons._study import study
from comparisons.hb_gap_preload import cases as fig11_cases
from shroud.analysis.hb import SpeedModel, model_at_speed, run_hb
from shroud.analysis.transient import contact_law_for
from shroud.analysis.sweep import run_sweeps
from shroud.base.errors import InputError
from shroud.base.markdown import markdown_table, seconds
from shroud.base.tables import write_records
from shroud.core import harmonic_balance as hb
from shroud.core.plotting import figure, save
from shroud.core.results import HBResult, SweepResult
from shroud.core.verdict import NOT_DECIDED, Verdict

OPTIONS = {
    "values": [0.1, 0.3, 0.5],
    "gaps_um": [600.0, 300.0, 100.0, 50.0, 10.0],
    "small_gap_um": 1.0,
    "preloads_N": [10.0, 25.0, 50.0, 100.0, 200.0],
    "n0_to": 300.0,                  # the resonance is followed in N0 from 0 up to this preload, N
    "rpm_from": 4000.0, "rpm_to": 60000.0,
    "harmonics": 10, "samples": 512, "model": "reduced",
    "branch_points": 60, "track_points": 40,
    "time_domain": True,             # overlay the from-rest time-domain sweep
    "td_rpm_to": 30000.0,            # ... over rpm_from..td_rpm_to (the paper's range)
    "td_rpm_count": 27,
    "match": 0.01,                   # a time-domain point is on a branch within this relative difference
}
NO_EFFECT = 0.05        # resonances spread by less than this share across the variants: (almost) no effect
NEARLY_SAME = 0.10      # optimal preloads or smallest resonant amplitudes spread by less than this share: the same
LARGE_GAP_UM = 100.0
STARTS = 3              # branch points before a top tried as the 2 H branch's start (measured_resonance)
NO_EFFECT_REASON = ("5 %: 'hardly affects' as the paper reads it off its curves (Sect. 3.2); margin: the spread's "
                    "own error, from the two extreme resonances' errors (amplitude: its change at twice the "
                    "harmonics plus its rise between branch points, and where Newton at twice the harmonics "
                    "failed at the top's own speed (a fold just past it) the top's change against the top of the "
                    "branch followed at twice the harmonics around it plus both tops' rises between their "
                    "points; speed: half the branch steps around the peak)")
NEARLY_SAME_REASON = ("10 %: 'nearly the same' / 'unaffected' as the paper reads them (Sects. 3.2-3.3); margin: "
                      "the spread's own error, from the two extremes' errors (optimal preload: half its bracket of "
                      "tracked points; amplitude: its change at twice the harmonics)")


def check(scene) -> None:
    o = scene.options
    if len(o["values"]) < 2:
        raise InputError("options.values", f"{o['values']}: allowed: at least two values to compare")
    if not 0 < o["rpm_from"] < o["rpm_to"]:
        raise InputError("options.rpm_to", f"{o['rpm_from']:g} .. {o['rpm_to']:g}: allowed: 0 < rpm_from < rpm_to")
    if max(o["preloads_N"], default=0.0) > o["n0_to"]:
        raise InputError("options.n0_to", f"{o['n0_to']:g} N: allowed: at least the largest preload "
                                          f"({max(o['preloads_N']):g} N)")
    if o["time_domain"] and not o["rpm_from"] < o["td_rpm_to"] <= o["rpm_to"]:
        raise InputError("options.td_rpm_to", f"{o['td_rpm_to']:g}: allowed: in (rpm_from, rpm_to]")


def peak_covered(branch: HBResult) -> bool:
    """Whether a branch holds its resonance: it is complete, or it stopped (the corrector failed) only after
    coming down from its largest amplitude to below half of it (a branch with no point holds nothing)."""
    if branch.amplitude_v_L.size == 0:
        return False
    i = int(np.argmax(branch.amplitude_v_L))
    return bool(branch.complete or (i < len(branch.rpm) - 1
                                    and branch.amplitude_v_L[-1] < 0.5 * branch.amplitude_v_L[i]))


@dataclass(frozen=True)
class Variant:
    """One value of the varied parameter: its branches (gap and preload cases), the tracked resonance over
    N0, and the time-domain sweeps (or None)."""

    name: str
    cases: list[tuple[str, str, float, object]]      # (label, kind, value, params) as comparisons.hb_gap_preload
    branches: list[HBResult]
    resonances: list[dict]      # per case its branch's resonance (HBResult.resonance; gaps: :func:`measured_resonance`)
    preload: peak.PreloadResonance
    sweeps: list[SweepResult] | None

    def gap_rows(self) -> list[dict]:
        """Resonance of every gap branch (Fig. 13a-b): largest P1 amplitude on its points not shown unstable
        (HBResult.resonance), with its errors (:func:`measured_resonance`) and stability."""
        return [{"variant": self.name, "case": label, "gap_um": value, "rpm": r["rpm"], "amplitude_m": r["amplitude"],
                 "rpm_error": r["rpm_error"], "amplitude_error_m": r["amplitude_error"], "stable": r["stable"],
                 "covered": peak_covered(br), "hb_s": br.elapsed_s}
                for (label, kind, value, _), br, r in zip(self.cases, self.branches, self.resonances) if kind == "gap"]

    def preload_rows(self) -> list[dict]:
        """Resonance at the small gap (its branch's peak; ``covered`` False when the branch stopped short of it)
        and at every preload (the tracked curve's point there) (Fig. 13c-d)."""
        out = []
        for (label, kind, value, _), br in zip(self.cases, self.branches):
            if kind != "preload":
                continue
            point = self.preload.curve.at(value)
            row = {"variant": self.name, "case": label, "N0": value, "branch_rpm": br.resonance["rpm"],
                   "branch_amplitude_m": br.resonance["amplitude"]}
            if point:
                out.append({**row, "rpm": point["rpm"], "amplitude_m": point["amplitude"], "source": "tracked",
                            "covered": True})
            elif value < 0:
                out.append({**row, "rpm": br.resonance["rpm"], "amplitude_m": br.resonance["amplitude"],
                            "source": "branch", "covered": peak_covered(br)})
            else:                      # a preload the tracked curve stopped short of: no resonance to hold
                out.append({**row, "rpm": math.nan, "amplitude_m": math.nan, "source": "not tracked",
                            "covered": False})
        return out


def compute_variant(name: str, params, opts: dict) -> Variant:
    cs = fig11_cases(params, opts)
    branches = [run_hb(p, opts["model"], opts["rpm_from"], opts["rpm_to"], harmonics=int(opts["harmonics"]),
                       samples=int(opts["samples"]), min_points=int(opts["branch_points"])) for _, _, _, p in cs]
    preload = peak.track(params, {**opts, "n0_from": 0.0},
                         {value: br for (_, kind, value, _), br in zip(cs, branches)
                          if kind == "preload" and value >= 0})
    resonances = [measured_resonance(br, p, opts) if kind == "gap" else br.resonance
                  for (_, kind, _, p), br in zip(cs, branches)]
    sweeps = (run_sweeps([p for _, _, _, p in cs], opts["model"],
                         np.linspace(opts["rpm_from"], opts["td_rpm_to"], int(opts["td_rpm_count"])))
              if opts["time_domain"] else None)
    return Variant(name=name, cases=cs, branches=branches, resonances=resonances, preload=preload, sweeps=sweeps)


def top_rise(amplitude: np.ndarray, i: int) -> float:
    """How far the top of a branch may rise above its largest point ``i`` (m) between its two neighbours: a
    quarter of its drop to the lower one (a parabolic top, HBResult.resonance); inf at the branch's end (the
    top may lie beyond it)."""
    if not 0 < i < len(amplitude) - 1:
        return math.inf
    return max(0.25 * (amplitude[i] - min(amplitude[i - 1], amplitude[i + 1])), 0.0)


def top_change_error(coarse: np.ndarray, i: int, fine: np.ndarray) -> float:
    """The error (m) of the resonant amplitude read at the top point ``i`` of a branch at H (amplitudes
    ``coarse``) where its change at 2 H could not be taken at that speed, from ``fine``, the amplitudes of the
    branch followed at 2 H around that top: the two tops' change, |max fine - coarse[i]|, plus how far either
    top may rise between its points (:func:`top_rise`; inf where either lies at its branch's end). With the
    resonance taken as the 2 H top (as the change at 2 H takes it everywhere), this bounds the H point's
    distance to it: |coarse[i] - top_2H| <= |coarse[i] - max fine| + rise_2H; the H top's own rise is added as
    the branch points' error elsewhere adds it."""
    j = int(np.argmax(fine))
    return float(abs(fine[j] - coarse[i]) + top_rise(coarse, i) + top_rise(fine, j))


def measured_resonance(branch: HBResult, params, opts: dict) -> dict:
    """``branch.resonance``, its amplitude error measured where the branch could not take it: where Newton at
    2 H failed at the top point's own speed. Near a fold the 2 H branch folds at another speed, and no 2 H
    state may lie at the top's (hb_stiffness_ratio, gap 300 um, xi 0.2: at H the top 400.67 um at 9517 r/min
    and the fold at 9551; at 2 H the top 400.54 um at 9477 and the fold at 9508). There the branch is followed
    at 2 H from the nearest of its STARTS points before the top (and below it in speed) where Newton at 2 H
    converges, over the speeds of its points up to one past the top and as far again (the scene's
    ``branch_points`` points over that window, no stability: the amplitudes only), and the error is
    :func:`top_change_error`. A top at the branch's end, or one whose 2 H start or window finds no 2 H top
    inside, keeps its infinite error."""
    r = branch.resonance
    kept = np.flatnonzero([s is not False for s in branch.stable])
    if math.isfinite(r["amplitude_error"]) or kept.size == 0:
        return r
    i = int(kept[np.argmax(branch.amplitude_v_L[kept])])
    rpm, H = branch.rpm, branch.harmonics
    if not 0 < i < len(rpm) - 1 or math.isfinite(r["truncation_error"]):
        return r
    fine = SpeedModel(model_at_speed(params, opts["model"]), H).refined()
    basis = hb.fourier(fine.H, max(branch.samples, 4 * fine.H + 1))
    law = contact_law_for(fine.system(float(rpm[i])), params.contact)
    nx = branch.X.shape[1] // (2 * H + 1)
    for j in (j for j in range(i - 1, max(i - 1 - STARTS, -1), -1) if rpm[j] < rpm[i]):
        X0 = np.zeros((basis.nh, nx))
        X0[:2 * H + 1] = branch.X[j].reshape(-1, nx)
        sol = hb.newton(X0.ravel(), fine.linear(float(rpm[j]))[0], law, basis)
        if sol.converged:
            top = float(rpm[j:i + 2].max())
            twice = run_hb(params, opts["model"], float(rpm[j]), 2 * top - float(rpm[j]), harmonics=fine.H,
                           samples=basis.samples, start=sol.X, stability=False, min_points=int(opts["branch_points"]))
            return {**r, "amplitude_error": top_change_error(branch.amplitude_v_L, i, twice.amplitude_v_L)}
    return r


def spread(values: list[float]) -> float:
    """(max - min) / max of positive values."""
    return (max(values) - min(values)) / max(values)


def spread_verdict(values: list[float], errors: list[float], threshold: float, below, above,
                   reason: str) -> Verdict:
    """:func:`spread` of ``values`` against ``threshold``, its margin from the errors of the largest and the
    smallest value: d[(max - min) / max] = (e_min + e_max min / max) / max, the errors adding (inf: unknown)."""
    hi, lo = int(np.argmax(values)), int(np.argmin(values))
    margin = (errors[lo] + errors[hi] * values[lo] / values[hi]) / values[hi]
    return Verdict.of(spread(values), threshold, margin if np.isfinite(margin) else float("inf"), below, above, reason)


def both(a: Verdict, b: Verdict):
    """The answer of two yes/no verdicts together: True when both are, False when either is, else not decided."""
    answers = (a.answer, b.answer)
    return False if False in answers else True if answers == (True, True) else NOT_DECIDED


def trend(values: list[float], tolerance: float = 1e-3) -> int:
    """+1 when the last value is larger than the first by more than ``tolerance`` (share), -1 when smaller, 0 else."""
    d = (values[-1] - values[0]) / max(abs(values[0]), 1e-300)
    return int(d > tolerance) - int(d < -tolerance)


def conclusions(variants: list[Variant]) -> dict:
    """The paper's checks as data. Trends run from the first variant to the last (+1 rising, -1 falling,
    0 equal within 0.1 %): per preload case the resonant speed and amplitude; per variant whether the
    resonant speed rises as the gap closes; the spread across variants at gaps >= 100 um; per variant the
    optimal preload (N) and from which preload the shroud stays stuck through the resonance; the trend of
    the optimal preload (0 where the optimal preloads spread by less than NEARLY_SAME: unaffected) and the
    spread of the smallest resonant amplitudes; whether the stuck resonance
    is the same for every variant."""
    gaps = [[r for r in v.gap_rows() if r["covered"]] for v in variants]     # branches stopped short: out
    pre = [v.preload_rows() for v in variants]
    kept = [i for i in range(len(pre[0])) if all(rows[i]["covered"] for rows in pre)]   # branches stopped short: out
    shared = set.intersection(*({r["gap_um"] for r in rows if r["gap_um"] >= LARGE_GAP_UM} for rows in gaps))
    large = [[r for r in sorted(rows, key=lambda r: r["gap_um"]) if r["gap_um"] in shared] for rows in gaps]

    def widest(value: str, error: str) -> Verdict:
        """The spread verdict of the shared large gap whose values spread most."""
        found = [spread_verdict([rows[i][value] for rows in large], [rows[i][error] for rows in large], NO_EFFECT,
                                True, False, NO_EFFECT_REASON) for i in range(len(shared))]
        return max(found, key=lambda v: v.value, default=Verdict.of(0.0, NO_EFFECT, 0.0, True, False,
                                                                    NO_EFFECT_REASON))
    amp_v, rpm_v = widest("amplitude_m", "amplitude_error_m"), widest("rpm", "rpm_error")
    touching = [{"rpm": float(v.preload.curve.rpm[0]), "rpm_error": 0.0} for v in variants]   # tracked: exact
    closing = [rises(sorted(rows, key=lambda r: -r["gap_um"]) + [end], "gaps closing down to touching (N0 = 0)")
               for rows, end in zip(gaps, touching)]
    opt = [v.preload.curve.optimum for v in variants]
    stuck = [v.preload.stuck_from_N0 for v in variants]
    ends = [float(v.preload.curve.amplitude_v_L[-1]) for v in variants]
    preload_v = spread_verdict([o["N0"] for o in opt], [0.5 * (o["bracket"][1] - o["bracket"][0]) for o in opt],
                               NEARLY_SAME, True, False, NEARLY_SAME_REASON)
    minimum_v = spread_verdict([o["amplitude"] for o in opt], [o["amplitude_error"] for o in opt], NEARLY_SAME,
                               True, False, NEARLY_SAME_REASON)
    out = {
        "resonant_speed_rises_as_gap_closes": {v.name: r.answer for v, r in zip(variants, closing)},
        "resonant_speed_rises_as_gap_closes_verdict": {v.name: r.to_json() for v, r in zip(variants, closing)},
        "large_gaps": {"amplitude_spread": amp_v.value, "speed_spread": rpm_v.value, "no_effect": both(amp_v, rpm_v),
                       "amplitude_spread_verdict": amp_v.to_json(), "speed_spread_verdict": rpm_v.to_json()},
        "preload_cases": {pre[0][i]["case"]: {"speed_trend": trend([rows[i]["rpm"] for rows in pre]),
                                              "amplitude_trend": trend([rows[i]["amplitude_m"] for rows in pre])}
                          for i in kept},
        "preload_cases_left_out": [pre[0][i]["case"] for i in range(len(pre[0])) if i not in kept],
        "optimal_preload_N": {v.name: o["N0"] for v, o in zip(variants, opt)},
        "optimal_bracket_N": {v.name: o["bracket"] for v, o in zip(variants, opt)},
        "optimal_stable": {v.name: o["stable"] for v, o in zip(variants, opt)},
        "optimum_inside": {v.name: not o["at_end"] for v, o in zip(variants, opt)},
        "optimal_preload_spread": preload_v.value,
        "optimal_preload_unaffected": preload_v.answer,
        "optimal_preload_unaffected_verdict": preload_v.to_json(),
        "optimal_preload_trend": ({True: 0, False: trend([o["N0"] for o in opt])}.get(preload_v.answer, NOT_DECIDED)),
        "minimum_amplitude_spread": minimum_v.value,
        "minimum_amplitude_nearly_same": minimum_v.answer,
        "minimum_amplitude_nearly_same_verdict": minimum_v.to_json(),
        "stuck_from_N0": {v.name: s for v, s in zip(variants, stuck)},
        "stuck_resonance_same": bool(all(s is not None for s in stuck) and spread(ends) < 1e-4),
        "peak_tracking_complete": bool(all(v.preload.curve.complete for v in variants)),
    }
    return out


@dataclass(frozen=True)
class HBFamilyResult:
    """The variants of one contact parameter, every time-domain point named by the state it landed on, and a
    study's own data computed from the variants (``explanation``, or None)."""

    describe: str                    # the varied parameter, as the report names it
    variants: list[Variant]
    points: list[dict]               # the sweep points named (comparisons._hb.named_points)
    explanation: list[dict] | None = None

    def conclusions(self) -> dict:
        return conclusions(self.variants)

    def to_json(self) -> dict:
        return {"conclusions": self.conclusions(),
                **({"explanation": self.explanation} if self.explanation is not None else {}),
                "variants": {v.name: {"gaps": v.gap_rows(), "preloads": v.preload_rows(),
                                      "peak_curve": v.preload.curve.to_json(),
                                      "branches": {c[0]: b.to_json() for c, b in zip(v.cases, v.branches)}}
                             for v in self.variants},
                "time_domain_points": self.points,
                "cost_s": {v.name: {"branches": sum(b.elapsed_s for b in v.branches),
                                    "peak_tracking": v.preload.curve.elapsed_s,
                                    "time_domain_cpu": sum(s.cpu_s for s in v.sweeps) if v.sweeps else None}
                           for v in self.variants}}


def _trend_word(t, up: str = "rises", down: str = "falls") -> str:
    return {1: up, -1: down, 0: "stays the same"}.get(t, NOT_DECIDED)


def _answer_word(answer, yes: str = "yes", no: str = "no") -> str:
    """A verdict's answer (True, False or not decided) in words."""
    return yes if answer is True else no if answer is False else NOT_DECIDED


def plot(result: HBFamilyResult, scene, out: Path) -> list[str]:
    """Fig. 12/16 (branches per variant: gaps, then the small gap and preloads) and Fig. 13/17 (resonant
    speed and amplitude over gap and preload); the named sweep points and the resonances as CSV."""
    variants = result.variants
    fig, axes = figure(len(variants), 2, width=11.0, height=3.2 * len(variants) + 0.4)
    for i, v in enumerate(variants):
        for k, ((label, kind, _, _), br) in enumerate(zip(v.cases, v.branches)):
            ax = axes[i][0 if kind == "gap" else 1]
            br.plot(ax, label=label, colour=f"C{k % 10}")
            if v.sweeps is not None:
                sw = v.sweeps[k]
                ax.plot(sw.rpm, sw.amplitude_v_L * 1e3, ".", color=f"C{k % 10}", ms=4)
        c = v.preload.curve
        axes[i][1].plot(c.rpm, c.amplitude_v_L * 1e3, "k-", lw=1.2, label="resonance over N0")
        small = next(label for label, kind, _, _ in v.cases if kind == "preload")
        for j, what in enumerate(("initial gaps", f"{small} and preloads")):
            axes[i][j].set_title(f"{v.name}: {what}" + (" (HB stable -, unstable --, undecided :x; time domain .)"
                                                         if v.sweeps else ""))
            axes[i][j].legend(ncol=2, fontsize=7)
    files = [save(fig, out / "hb_branches.png").name]
    fig, axes = figure(2, 2, width=10.0, height=7.0)
    for i, v in enumerate(variants):
        colour = f"C{i}"
        rows = [r for r in v.gap_rows() if r["covered"]]      # a branch that stopped short holds no resonance
        axes[0][0].plot([r["gap_um"] for r in rows], [r["rpm"] for r in rows], "o-", color=colour, label=v.name)
        axes[1][0].plot([r["gap_um"] for r in rows], [r["amplitude_m"] * 1e3 for r in rows], "o-", color=colour,
                        label=v.name)
        peak.plot_over_preload(axes[1][1], axes[0][1], v.preload, v.name, colour)
    for ax, title in ((axes[0][0], "(a) resonant speed over the gap"), (axes[1][0], "(b) resonant amplitude "
                      "over the gap"), (axes[0][1], "(c) resonant speed over N0 (o: branch peaks)"),
                      (axes[1][1], "(d) resonant amplitude over N0 (*: optimum)")):
        ax.set_title(title)
        ax.legend()
    for ax in (axes[0][0], axes[1][0]):
        ax.set_xscale("log")
        ax.set_xlabel("initial gap (um)")
    axes[0][0].set_ylabel("resonant speed (r/min)")
    axes[1][0].set_ylabel("resonant amplitude of v_L (mm)")
    files.append(save(fig, out / "resonance_characteristics.png").name)
    write_records(out / "td_points_by_branch.csv", result.points)
    write_records(out / "resonances_over_gap.csv", [r for v in variants for r in v.gap_rows()])
    write_records(out / "resonances_over_preload.csv", [r for v in variants for r in v.preload_rows()])
    return files


def time_domain_points(variants: list[Variant], opts: dict) -> list[dict]:
    """Every time-domain point with the HB state it landed on."""
    return [pt for v in variants for (label, _, _, p), br, sw in zip(v.cases, v.branches, v.sweeps or [])
            for pt in named_points(sw, partial(states_at, br, p, opts["model"]), opts["match"], variant=v.name,
                                   case=label)]


def report(result: HBFamilyResult, scene, files: list[str]) -> str:
    opts, variants, points, describe = scene.options, result.variants, result.points, result.describe
    concl = result.conclusions()
    hb_s = {v.name: sum(b.elapsed_s for b in v.branches) for v in variants}
    track_s = {v.name: v.preload.curve.elapsed_s for v in variants}
    td_s = {v.name: sum(s.cpu_s for s in v.sweeps) for v in variants if v.sweeps is not None}
    pre = concl["preload_cases"]
    speed_up = [c for c, t in pre.items() if t["speed_trend"] == 1]
    amp_down = [c for c, t in pre.items() if t["amplitude_trend"] == -1]
    names = [v.name for v in variants]
    stuck = concl["stuck_from_N0"]
    lg = concl["large_gaps"]
    off = [p for p in points if not on_stable(p["branch"])]
    lines = [
        f"# {scene.title}\n",
        f"Model {opts['model']}; harmonic balance H = {opts['harmonics']}, {opts['samples']} samples, branches "
        f"{opts['rpm_from']:g}-{opts['rpm_to']:g} r/min with Floquet stability; the resonance followed in N0 from "
        f"0 to {opts['n0_to']:g} N"
        + (f"; time domain {opts['td_rpm_count']} speeds {opts['rpm_from']:g}-{opts['td_rpm_to']:g} r/min x "
           f"{scene.params.time.periods} periods from rest (dots)" if opts["time_domain"] else "") + ".\n",
        "Cost per variant: " + "; ".join(
            f"{n}: branches {seconds(hb_s[n])}, peak tracking {seconds(track_s[n])}"
            + (f", time domain {seconds(td_s[n])} CPU" if n in td_s else "") for n in names) + ".\n",
        "| paper | here |", "|---|---|",
        f"| gaps >= {LARGE_GAP_UM:g} um: {describe} has (almost) no effect on the resonant speed and amplitude | "
        f"{_answer_word(lg['no_effect'])}: spread across the variants, speed "
        f"{verdict_text(lg['speed_spread_verdict'], 100, ' %')}, amplitude "
        f"{verdict_text(lg['amplitude_spread_verdict'], 100, ' %')} |",
        "| the resonant speed rises as the gap closes (down to touching, N0 = 0) | " + "; ".join(
            f"{n}: {_answer_word(ok)} (smallest rise "
            f"{verdict_text(concl['resonant_speed_rises_as_gap_closes_verdict'][n], unit=' r/min')})"
            for n, ok in concl["resonant_speed_rises_as_gap_closes"].items()) + " |",
        f"| 1 um gap or a preload: the resonant speed as {describe} grows | " + "; ".join(
            f"{c}: {_trend_word(t['speed_trend'])}" for c, t in pre.items()) + " |",
        f"| ... the resonant amplitude as {describe} grows | " + "; ".join(
            f"{c}: {_trend_word(t['amplitude_trend'])}" for c, t in pre.items()) + " |",
        "| optimal preload (tracked resonance's minimum) | " + "; ".join(
            f"{n}: " + (f"{concl['optimal_preload_N'][n]:.1f} N" if concl["optimum_inside"][n] else
                        f"at the end ({concl['optimal_preload_N'][n]:g} N)") for n in names)
        + f": it {_trend_word(concl['optimal_preload_trend'])} as {describe} grows; spread across the variants "
          f"{100 * concl['optimal_preload_spread']:.1f} % ("
          f"{_answer_word(concl['optimal_preload_unaffected'], 'unaffected', 'affected')}: "
          f"{verdict_text(concl['optimal_preload_unaffected_verdict'], 100, ' %')}) |",
        f"| smallest resonant amplitude | spread {100 * concl['minimum_amplitude_spread']:.1f} % across the variants "
        f"({_answer_word(concl['minimum_amplitude_nearly_same'], 'nearly the same', 'not the same')}: "
        f"{verdict_text(concl['minimum_amplitude_nearly_same_verdict'], 100, ' %')}) |",
        "| stuck through the resonance (the resonance no longer changes with N0) from | " + "; ".join(
            f"{n}: " + (f"{s:.1f} N" if s is not None else f"not within {opts['n0_to']:g} N") for n, s in stuck.items())
        + ("; there every variant has the same resonance" if concl["stuck_resonance_same"] else "") + " |",
        "",
        f"Preload cases where the resonant speed rises with {describe}: {len(speed_up)} of {len(pre)}; where the "
        f"resonant amplitude falls: {len(amp_down)} of {len(pre)}."
        + (f" Left out of these trends: {', '.join(concl['preload_cases_left_out'])} (a branch stopped short of "
           "its peak, below)." if concl["preload_cases_left_out"] else "") + "\n",
        markdown_table(["variant", "case", "resonant speed (r/min)", "resonant amplitude (mm)", "source"],
                       [(r["variant"], r["case"], f"{r['rpm']:.0f}" if np.isfinite(r["rpm"]) else None,
                         r["amplitude_m"] * 1e3 if np.isfinite(r["amplitude_m"]) else None,
                         "branch peak" + ("" if r["covered"] else " (the branch stopped short of it: left out)"))
                        for v in variants for r in v.gap_rows()]
                       + [(r["variant"], r["case"], f"{r['rpm']:.0f}", r["amplitude_m"] * 1e3,
                           f"tracked (branch peak {r['branch_amplitude_m'] * 1e3:.4g} mm at {r['branch_rpm']:.0f})"
                           if r["source"] == "tracked" else
                           "branch peak" + ("" if r["covered"] else " (the branch stopped short of it: left out)"))
                          for v in variants for r in v.preload_rows()]),
    ]
    if points:
        lines += ["", f"Time-domain points not on a stable P1 branch within {100 * opts['match']:g} %: {len(off)} of "
                  f"{len(points)} (each named in td_points_by_branch.csv by the state it landed on)."]
    if not (concl["peak_tracking_complete"] and all(b.complete for v in variants for b in v.branches)):
        lines += ["", "Incomplete: " + "; ".join(
            [f"{v.name} peak tracking: {v.preload.curve.stopped}" for v in variants if not v.preload.curve.complete]
            + [f"{v.name} {c[0]}: {b.stopped}" for v in variants for c, b in zip(v.cases, v.branches)
               if not b.complete])]
    branch_notes = notes_line([(f"{v.name} {c[0]}", b) for v in variants for c, b in zip(v.cases, v.branches)])
    if branch_notes:
        lines += ["", branch_notes]
    lines += ["", *[f"![{f}]({f})" for f in files]]
    return "\n".join(lines) + "\n"


def compute_variants(scene, variants: dict, describe: str, explain=None) -> HBFamilyResult:
    """The variants (name -> Parameters) of one contact parameter, their time-domain points named;
    ``explain(variants) -> list[dict]``: a study's own data from them (its ``explanation``)."""
    opts = scene.options
    done = [compute_variant(name, p, opts) for name, p in variants.items()]
    return HBFamilyResult(describe=describe, variants=done, points=time_domain_points(done, opts),
                          explanation=explain(done) if explain is not None else None)


def compute(scene) -> HBFamilyResult:
    """The coefficient of friction's variants (mu over ``values``)."""
    variants = {f"mu {v:g}": scene.params.updated({"contact.mu": v}) for v in scene.options["values"]}
    return compute_variants(scene, variants, "mu")


run = study(compute, plot, report)
