"""Figs. 14-15: P1 motion at mu = 0.1 and P10 motion at mu = 0.5, 25500 r/min.

Paper (Sect. 3.2): with a small gap or a preload, the response at 25500 r/min
is period-one at mu 0.1 and period-ten at mu 0.5 (the impact repeats every
ten excitation periods; friction shares that period). The paper does not
state the gap or preload of Figs. 14-15; this study runs every case in
``cases`` and reports the period found for each. It then maps the period
over the band where the paper sees P10 (Fig. 12(f): mu 0.5, preloads,
22500-26000 r/min): every speed of ``search_rpms`` for small gaps and
preloads, with ``search_periods`` periods per run so transients have died.
Each map case's P1 branch is then continued by harmonic balance with its
Floquet multipliers (:func:`hb_case`), so that where P1 is lost, and
through which multiplier (-1: period doubling; a complex pair:
Neimark-Sacker, n ~ 2 pi / arg mu), is predicted and read against the
periods the runs found (:func:`reading`).

The study is compute (:func:`compute` -> :class:`PeriodicityResult`) ->
plot (:func:`plot`) -> report (:func:`report`). The waveforms shown for each
mu are those of the case whose run found the longest period (a response
with no period up to P10 ranks above all): chosen by what the runs found,
never by the paper's expected answer.
"""

from __future__ import annotations

import csv
import dataclasses
import math
import os
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from comparisons import paper
from comparisons._hb import starts_at
from shroud.analysis.api import build_system
from shroud.analysis.hb import SpeedModel, check_inputs, checkpoint, model_at_speed, point_details, run_hb
from shroud.analysis.sweep import Settling, run_sweeps
from shroud.analysis.transient import contact_law_for, simulate
from shroud.base.markdown import markdown_table, seconds
from shroud.core import floquet, signals
from shroud.core import harmonic_balance as hb
from shroud.core.plotting import figure, save
from shroud.core.results import HBResult, SweepResult, TransientResult
from shroud.base.outputs import open_replacing, write_text
from shroud.core.verdict import Verdict

OPTIONS = {"mu_values": [0.1, 0.5], "gaps_um": [1.0], "preloads_N": [10.0, 25.0, 50.0],
           "plot_periods": 20,
           "search_mu": paper.P10_MU, "search_rpm_from": paper.P10_BAND_RPM[0],
           "search_rpm_to": paper.P10_BAND_RPM[1], "search_rpm_count": 15,
           "search_gaps_um": [0.5, 1.0, 2.0, 5.0, 10.0],
           "search_preloads_N": [1.0, 2.0, 5.0, 10.0, 15.0, 20.0, 25.0, 35.0, 50.0, 100.0],
           "search_periods": 600,
           # (mu, gap in um, r/min): P10 points the family sweeps (friction scene) found outside the band
           "confirm_points": [[0.5, 10.0, 12500.0], [0.3, 10.0, 21250.0]],
           # the P1 branch of every map case by harmonic balance, continued from hb_rpm_from (below the band,
           # where the start is easy) to the band's end, with its Floquet multipliers (shroud.analysis.hb)
           "hb": True, "hb_rpm_from": 20000.0, "harmonics": 10, "samples": 512,
           "match": 0.01,        # a time-domain P1 point is on an HB state within this relative amplitude
           # a point without P1 is read against a P1 state only within this relative amplitude: 1.5 times the
           # farthest measured, 9.8 % (this scene's quick map: gap 1 um, mu 0.5, 23375 r/min, no period, beside
           # its Neimark-Sacker P1 state); the 8 non-P1 points of the 1 um gap sweep at mu 0.3 lie 0.7-6.1 %
           # from theirs (docs/hb-stability.md)
           "near": 0.15,
           # where a time-domain point is on no state of the branch: Newton from these multiples of the
           # contact-free linear solution at that speed finds the coexisting P1 states the branch misses
           "hb_seeds": [2.0, 3.0, 5.0, 8.0, 12.0, 20.0],
           # a P1 time-domain point HB does not confirm is run again this long: is it a P1 orbit, or a small
           # torus around an unstable P1 state that the period detector's tolerance calls P1?
           "probe_periods": 1500}


MIN_SEEDED_POINTS = 30   # points a seeded branch has at least over its range (as run_hb's MIN_POINTS)
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
class HBState:
    """One P1 state by harmonic balance at one speed of the map: its v_L amplitude (m), Floquet verdict (True,
    False, None: within ``error``, the largest |multiplier|'s own, of 1), the largest |multiplier|, how that multiplier lies (``kind``: "fold" real > 0, "period-doubling" real < 0,
    "Neimark-Sacker" a complex pair, whose angle gives ``n`` = 2 pi / |arg|) and where Newton started:
    "branch" (the continued branch's crossing of the speed) or "seeded" (a multiple of the linear solution)."""

    amplitude: float
    stable: bool | None
    largest: float
    kind: str
    n: float | None
    source: str
    X: np.ndarray | None = field(default=None, repr=False, compare=False)   # harmonic coefficients
    error: float = floquet.MULTIPLIER_FLOOR

    def describe(self) -> str:
        how = {"fold": "real > 0", "period-doubling": "real < 0",
               "Neimark-Sacker": f"complex pair, n ~ {self.n:.1f}" if self.n else "complex pair"}[self.kind]
        word = {True: "stable", False: "unstable", None: "undecided"}[self.stable]
        return (f"{self.amplitude * 1e6:.2f} um {word} ({self.source}; "
                f"|mu| {self.largest:.3f} +- {self.error:.3f}, {how})")


@dataclass(frozen=True)
class HBCase:
    """The P1 branch of one map case with its stability, and every P1 state found at the map's speeds."""

    label: str
    branch: HBResult
    states: list[list[HBState]]               # per map speed
    branch_s: float                           # run_hb: continuation with the multipliers of every point
    states_s: float                           # the states at the map's speeds, the seeded branches
    seeded: list[HBResult] = ()               # branches continued from seeded states (coexisting P1 branches)

    def stretches(self) -> list[dict]:
        """Unstable stretches of the continued branch and of the seeded ones (:func:`unstable_stretches`)."""
        out = [dict(s, branch="continued") for s in unstable_stretches(self.branch)]
        for br in self.seeded:
            out += [dict(s, branch="seeded") for s in unstable_stretches(br)]
        return out


@dataclass(frozen=True)
class PeriodicityResult:
    runs: list[CaseRun]
    map_rpm: np.ndarray
    period_map: list[tuple[str, SweepResult]]
    confirmed: list[Confirmation]
    hb_cases: list[HBCase] = ()
    band: tuple[float, float] = (0.0, 0.0)
    match: float = 0.01
    near: float = 0.15
    search_mu: float = paper.P10_MU
    probes: list[dict] = ()

    def readings(self) -> list[dict]:
        """Every map point read against the HB states at its speed (:func:`reading`)."""
        by_label = dict(self.period_map)
        return [dict(case=c.label, rpm=float(r), **reading(per, amp, sts, self.match, self.near))
                for c in self.hb_cases
                for r, per, amp, sts in zip(self.map_rpm, by_label[c.label].period,
                                            by_label[c.label].amplitude_v_L, c.states)]

    def p1_verdict(self) -> Verdict:
        """Whether HB's stability predicts the map's P1 points (:func:`p1_share`)."""
        p1 = [r for r in self.readings() if r["period"] == 1]
        return p1_share(sum(r["verdict"] == "agree" for r in p1), sum(r["verdict"] == "marginal" for r in p1),
                        len(p1), self.match)

    def hb_conclusions(self) -> dict:
        """The prediction against the time domain, as data."""
        rows = self.readings()
        non_p1 = [r for r in rows if r["period"] != 1]
        p1 = [r for r in rows if r["period"] == 1]
        kinds = sorted({k for c in self.hb_cases for k in unstable_kinds(c, self.band)})
        agree_non_p1 = sum(r["verdict"] == "agree" for r in non_p1)
        agree_p1 = sum(r["verdict"] == "agree" for r in p1)
        return {"every_td_non_p1_on_unstable_p1": bool(non_p1) and agree_non_p1 == len(non_p1),
                "td_p1_on_stable_p1_at_least_95pct": self.p1_verdict().to_json(),
                "period_doubling_in_band": "period-doubling" in kinds,
                "p1_unstable_in_band": {f"mu {self.search_mu:g}, {c.label}": bool(unstable_kinds(c, self.band))
                                        for c in self.hb_cases},
                "instability_kinds_in_band": kinds,
                "td_non_p1": len(non_p1),
                "td_non_p1_on_unstable_p1": agree_non_p1,
                "td_non_p1_without_stable_p1_at_speed": sum(not r["stable_at_speed"] for r in non_p1),
                "td_p1": len(p1),
                "td_p1_on_stable_p1": agree_p1,
                "td_p1_where_hb_has_no_stable_p1": sum(not r["stable_at_speed"] for r in p1),
                "disagreements": sum(r["verdict"] == "disagree" for r in rows),
                "marginal": sum(r["verdict"] == "marginal" for r in rows)}

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
                "p10_in_band": any(p == 10 for _, sw in self.period_map for p in sw.period),
                **({"hb": self.hb_conclusions()} if self.hb_cases else {})}

    def to_json(self) -> dict:
        return {"conclusions": self.conclusions(),
                "periods": {f"mu {r.mu:g}, {r.label}": r.result.period for r in self.runs},
                "shown": {f"{mu:g}": r.label for mu, r in self.shown().items()},
                "rows": [dict(zip(CASE_KEYS, (r.mu, r.label, r.result.period, r.result.amplitude["v_L"] * 1e3,
                                              r.result.peak["N1"], r.result.peak["Ff1"], r.result.elapsed_s)))
                         for r in self.runs],
                "confirmed": [c.row for c in self.confirmed],
                "period_map": {"rpm": [float(r) for r in self.map_rpm],
                               "cases": {label: {"period": list(sw.period),
                                                 "amplitude_v_L_m": [float(a) for a in sw.amplitude_v_L]}
                                         for label, sw in self.period_map}},
                "hb": {"readings": self.readings(),
                       "cases": {c.label: {"branch": c.branch.to_json(), "seeded": [b.to_json() for b in c.seeded],
                                           "unstable": c.stretches(), "branch_s": c.branch_s,
                                           "states_s": c.states_s} for c in self.hb_cases},
                       "probes": list(self.probes), "cost_s": self.costs()}}

    def costs(self) -> dict:
        """Harmonic balance (wall, one process) against the map's time domain (summed CPU of its runs)."""
        return {"hb_branches": sum(c.branch_s for c in self.hb_cases),
                "hb_states": sum(c.states_s for c in self.hb_cases),
                "td_map_cpu": sum(sw.cpu_s for _, sw in self.period_map),
                "td_map_wall": sum(sw.elapsed_s for _, sw in self.period_map)}


P1_SHARE = 0.95   # HB's stability predicts the map's P1 points: all but one in twenty on a stable P1 state


def p1_share(agree: int, marginal: int, points: int, match: float) -> Verdict:
    """The share of the map's P1 points on a stable P1 state of HB (within ``match``) against P1_SHARE. A
    marginal point (its nearest state's |multiplier| within its error of 1) may go either way: the share lies
    between agree / points and (agree + marginal) / points, the value its middle and the margin half its width
    (NaN without P1 points: nothing to decide)."""
    low, high = (agree / points, (agree + marginal) / points) if points else (math.nan, math.nan)
    return Verdict.of(0.5 * (low + high), threshold=P1_SHARE, margin=0.5 * (high - low) if points else 0.0,
                      below=False, above=True,
                      reason=f"share of the {points} P1 time-domain points on a stable HB P1 state within "
                             f"{100 * match:g} % against {P1_SHARE:g} (all but one in twenty), margin half the "
                             f"share of the {marginal} points whose nearest state's stability is undecided")


def waveform_case(runs: list[CaseRun]) -> CaseRun:
    """The run with the longest period found (no period up to P10 ranks highest; ties: the first)."""
    return max(runs, key=lambda r: r.result.period or NO_PERIOD_RANK)


# One case's run in results.json: numbers, the run time under a timing key (shroud compare skips it);
# the report's and the CSV's rows (_case_rows) are the same, worded.
CASE_KEYS = ("mu", "case", "period", "amplitude_v_L_mm", "peak_N1", "peak_Ff1", "elapsed_s")


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


def map_cases(params, opts) -> list[tuple[str, object]]:
    """(label, parameters) of every case of the period map: mu = search_mu, each small gap and preload."""
    base = params.updated({"contact.mu": opts["search_mu"], "time.periods": int(opts["search_periods"])})
    cases = [(f"gap {g:g} um", base.updated({"contact.gap": g * 1e-6})) for g in opts["search_gaps_um"]]
    return cases + [(f"N0 {n:g} N", base.updated({"contact.N0": n})) for n in opts["search_preloads_N"]]


def period_map(params, opts) -> tuple[np.ndarray, list[tuple[str, SweepResult]]]:
    """Period (and amplitude) at every speed of the P10 band for every small gap and preload."""
    cases = map_cases(params, opts)
    rpms = np.linspace(opts["search_rpm_from"], opts["search_rpm_to"], int(opts["search_rpm_count"]))
    # exactly search_periods per run, as the report says (no extension until the amplitude settles)
    sweeps = run_sweeps([p for _, p in cases], "reduced", rpms,
                        settling=Settling(max_periods=int(opts["search_periods"])))
    return rpms, [(label, sw) for (label, _), sw in zip(cases, sweeps)]


class _Orbits:
    """One case's model over speed with its contact law and Fourier basis: P1 states and their multipliers."""

    def __init__(self, params, harmonics: int, samples: int, rpm: float):
        self.params, self.H, self.n = params, harmonics, check_inputs(harmonics, samples, 0.5 * rpm, rpm)
        self.speeds = SpeedModel(model_at_speed(params, "reduced"), harmonics)
        self.law = contact_law_for(self.speeds.at(rpm)[0], params.contact)
        self.basis = hb.fourier(harmonics, self.n)

    def details(self, X: np.ndarray, rpm: float) -> dict:
        return point_details(self.speeds, self.law, self.basis, X, rpm)

    def state(self, X0: np.ndarray, rpm: float, source: str) -> HBState | None:
        """The P1 state Newton reaches from ``X0`` at exactly ``rpm`` (shroud.analysis.hb.checkpoint, not
        started again from elsewhere), or None; its multipliers in full, for the kind of their crossing."""
        sol = checkpoint(self.params, "reduced", rpm, harmonics=self.H, samples=self.n, start=X0, retry=False,
                         multipliers=False)
        if not sol.converged:
            return None
        d = self.details(sol.X, rpm)
        kind, n = floquet.crossing(d["multipliers"])
        return HBState(amplitude=d["amplitude_v_L"], stable=d["stable"], largest=float(np.abs(d["multipliers"]).max()),
                       kind=kind, n=n, source=source, X=sol.X, error=float(d["multiplier_error"]))

    def branch_from(self, X: np.ndarray, rpm_from: float, rpm_to: float, points: int) -> HBResult:
        """The branch through the state ``X`` at ``rpm_from``, continued to ``rpm_to`` as run_hb continues,
        with the multipliers of every point."""
        return run_hb(self.params, "reduced", rpm_from, rpm_to, harmonics=self.H, samples=self.n, min_points=points,
                      start=X)

    def linear(self, rpm: float) -> np.ndarray:
        return hb.linear_solution(self.speeds.at(rpm)[1])


def hb_case(label: str, params, rpm_from: float, rpm_to: float, td: SweepResult, opts) -> HBCase:
    """The P1 branch from ``rpm_from`` to ``rpm_to`` and the P1 states at the time domain's speeds.

    At each speed of ``td`` the branch's crossings are converged there; where the time-domain point lies
    on none of them as a stable state within ``match`` (every non-P1 point, and P1 points on a coexisting
    state the branch misses), Newton is also started from ``hb_seeds`` multiples of the contact-free
    linear solution. The distinct states so found at the lowest such speed are continued to ``rpm_to``
    (coexisting branches), and their crossings join the states at every later speed.
    """
    H, n = int(opts["harmonics"]), int(opts["samples"])
    branch = run_hb(params, "reduced", rpm_from, rpm_to, harmonics=H, samples=n)
    t0 = time.perf_counter()
    orbits = _Orbits(params, H, n, rpm_from)
    seeded: list[HBResult] = []
    states = []
    for rpm, amp in zip(td.rpm, td.amplitude_v_L):
        found: list[HBState] = []

        def add(st):
            if st and all(abs(st.amplitude / o.amplitude - 1) > 1e-4 for o in found):
                found.append(st)
        for X, _ in starts_at(branch, rpm):
            add(orbits.state(X, rpm, "branch"))
        for other in seeded:
            for X, _ in starts_at(other, rpm):
                add(orbits.state(X, rpm, "seeded branch"))
        if not any(st.stable and abs(st.amplitude / amp - 1) <= opts["match"] for st in found):
            lin, known = orbits.linear(rpm), len(found)
            for c in opts["hb_seeds"]:
                add(orbits.state(c * lin, rpm, "seeded"))
            if not seeded and rpm < rpm_to:
                seeded = [orbits.branch_from(st.X, float(rpm), rpm_to, MIN_SEEDED_POINTS) for st in found[known:]]
        states.append(sorted(found, key=lambda st: st.amplitude))
    return HBCase(label=label, branch=branch, states=states, branch_s=branch.elapsed_s,
                  states_s=time.perf_counter() - t0, seeded=seeded)


def unstable_kinds(case: HBCase, band: tuple[float, float]) -> list[str]:
    """Kinds of the largest multiplier at the continued branch's unstable points inside ``band`` (r/min)."""
    return sorted({k for (k, _), r, s in zip(case.branch.critical, case.branch.rpm, case.branch.stable)
                   if s is False and band[0] <= r <= band[1]})


def unstable_stretches(branch: HBResult) -> list[dict]:
    """Contiguous unstable stretches of a branch (points shown unstable, beyond their multipliers' error):
    from / to (r/min, halfway to the neighbours), the kinds of their largest multipliers, the range of
    n = 2 pi / |arg mu| of complex ones, the largest |mu|."""
    out, i, m, kinds = [], 0, len(branch.rpm), branch.critical
    while i < m:
        if branch.stable[i] is not False:
            i += 1
            continue
        j = i
        while j + 1 < m and branch.stable[j + 1] is False:
            j += 1
        r = branch.rpm
        ns = [k[1] for k in kinds[i:j + 1] if k[1] is not None]
        out.append({"from_rpm": float(r[i] if i == 0 else 0.5 * (r[i - 1] + r[i])),
                    "to_rpm": float(r[j] if j == m - 1 else 0.5 * (r[j] + r[j + 1])),
                    "kinds": sorted({k[0] for k in kinds[i:j + 1]}),
                    "n_range": [min(ns), max(ns)] if ns else None,
                    "largest_multiplier": float(branch.max_multiplier[i:j + 1].max())})
        i = j + 1
    return out


def reading(period, amplitude: float, states: list[HBState], match: float, near: float) -> dict:
    """A time-domain point (period, amplitude m) read against the P1 states HB finds at its speed.

    The state it is read against is the nearest in amplitude (log ratio). A P1 point agrees when a stable
    state lies within ``match``; it is "marginal" when only states of undecided stability (|multiplier|
    within its own error of 1) do. A point without P1 (any other period, or none up to P10) is read only
    against a state within ``near`` of it: it agrees when that state is unstable (the run could not stay
    on it), is marginal when undecided; with no P1 state within ``near`` the verdict is "no P1 state
    nearby" (an unstable state far away explains nothing).
    """
    out = {"period": period, "amplitude_m": float(amplitude), "states": [st.describe() for st in states],
           "stable_at_speed": any(st.stable is True for st in states)}
    if not states or not np.isfinite(amplitude) or amplitude <= 0:
        return {**out, "verdict": "no HB state", "nearest": None, "why": "no P1 state found at this speed"}
    closest = min(states, key=lambda st: abs(np.log(st.amplitude / amplitude)))
    out["nearest"] = closest.describe()
    out["kind"], out["n"] = (closest.kind, closest.n) if closest.stable is not True else ("", None)
    if period == 1:
        within = [st for st in states if abs(st.amplitude / amplitude - 1) <= match]
        on = [st for st in within if st.stable is True]
        if on:
            return {**out, "verdict": "agree", "why": f"on the stable P1 state {on[0].describe()}"}
        verdict = "marginal" if any(st.stable is None for st in within) else "disagree"
        return {**out, "verdict": verdict,
                "why": f"P1 run on no stable HB state within {100 * match:g} %; nearest {closest.describe()}"}
    if abs(closest.amplitude / amplitude - 1) > near:
        return {**out, "verdict": "no P1 state nearby",
                "why": f"no P1 state within {100 * near:g} %; nearest {closest.describe()}"}
    if closest.stable is False:
        return {**out, "verdict": "agree", "why": f"nearest P1 state unstable: {closest.describe()}"}
    verdict = "marginal" if closest.stable is None else "disagree"
    return {**out, "verdict": verdict, "why": f"nearest P1 state {'undecided' if verdict == 'marginal' else 'stable'}: "
                                              f"{closest.describe()}"}


def probe(params, opts, readings: list[dict]) -> list[dict]:
    """Long runs at the P1 time-domain points HB does not confirm: the spread of the once-per-period samples
    of v_L over the last 100 and the last 400 periods against the period detector's tolerance
    (shroud.core.signals.detect_period: 2e-3 of the peak-to-peak range). A spread that persists (the same
    over 100 and 400 periods) is a torus, not a P1 orbit, whatever the detector calls it."""
    cases, out = dict(map_cases(params, opts)), []
    for r in readings:
        if r["period"] != 1 or r["verdict"] == "agree":
            continue
        p = cases[r["case"]].updated({"speed.rpm": r["rpm"], "time.periods": int(opts["probe_periods"])})
        res = simulate(build_system(p, "reduced"), p)
        x, spp = res.trajectory.tip[:, 0], p.time.steps_per_period
        spread = {w: float(np.ptp(signals.poincare(signals.last_periods(x, spp, w), spp))) for w in (100, 400)}
        out.append({"case": r["case"], "rpm": r["rpm"], "period": res.period, "amplitude_m": res.amplitude["v_L"],
                    "spread_100_m": spread[100], "spread_400_m": spread[400],
                    "tolerance_m": 2e-3 * float(np.ptp(signals.last_periods(x, spp, 30))),
                    "time_s": res.elapsed_s})
    return out


def hb_map(params, opts, search: list[tuple[str, SweepResult]]) -> list[HBCase]:
    """:func:`hb_case` for every case of the period map (its parameters as :func:`period_map` builds them)."""
    cases = dict(map_cases(params, opts))
    return [hb_case(label, cases[label], float(opts["hb_rpm_from"]), float(opts["search_rpm_to"]), sw, opts)
            for label, sw in search]


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
    hb_cases = hb_map(params, opts, search) if opts["hb"] else []
    confirmed = confirm(params, opts["confirm_points"], opts["search_periods"]) if opts["confirm_points"] else []
    result = PeriodicityResult(runs=runs, map_rpm=rpms, period_map=search, confirmed=confirmed, hb_cases=hb_cases,
                               band=(float(opts["search_rpm_from"]), float(opts["search_rpm_to"])),
                               match=float(opts["match"]), near=float(opts["near"]),
                               search_mu=float(opts["search_mu"]))
    return dataclasses.replace(result, probes=probe(params, opts, result.readings())) if hb_cases else result


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


KIND_MARKS = {"Neimark-Sacker": ("^", "tab:red"), "period-doubling": ("s", "tab:blue"), "fold": ("o", "tab:gray")}
VERDICT_COLOURS = {"agree": "#9fd89f", "predicted": "#8ecae6", "disagree": "#f08080", "marginal": "#f5d76e",
                   "no HB state": "#cccccc", "no P1 state nearby": "#e0e0e0"}
MULTIPLIER_AXIS_TOP = 1.5    # the |multiplier| panels stop here (saddle branches reach 2-4)


def _period_text(period) -> str:
    return f"P{period}" if period else "none"


def shown_hb_cases(result: PeriodicityResult) -> list[HBCase]:
    """The map cases drawn with their branches: those with an unstable P1 stretch or a time-domain point
    without P1, then the first case without either (for contrast)."""
    by_label = dict(result.period_map)
    busy = [c for c in result.hb_cases if c.stretches() or any(p != 1 for p in by_label[c.label].period)]
    calm = [c for c in result.hb_cases if c not in busy][:1]
    return busy + calm


def plot_hb(result: PeriodicityResult, scene, out: Path) -> list[Path]:
    """Per shown case: the P1 branches with the time-domain points (left) and the largest |multiplier| along
    them (right); then the whole map, each point coloured by how it reads against HB."""
    by_label = dict(result.period_map)
    cases = shown_hb_cases(result)
    lo, hi = result.band
    fig, axes = figure(len(cases), 2, width=11.0, height=2.9 * len(cases) + 0.6)
    for row, c in zip(axes, cases):
        ax, axm = row
        sw = by_label[c.label]
        for ax_ in (ax, axm):
            ax_.axvspan(lo, hi, color="0.93", zorder=0)
        c.branch.plot(ax, label="HB P1 branch, continued from below (stable -, unstable --, undecided :x)",
                      colour="k", scale=1e6, lw=1.0)
        for k, br in enumerate(c.seeded):
            br.plot(ax, label="HB P1 branch through a seeded state" if k == 0 else None, colour="tab:purple",
                    scale=1e6, lw=1.0)
        p1 = np.array([p == 1 for p in sw.period])
        ax.plot(sw.rpm[p1], sw.amplitude_v_L[p1] * 1e6, "o", color="tab:green", ms=4, label="time domain: P1")
        if (~p1).any():
            ax.plot(sw.rpm[~p1], sw.amplitude_v_L[~p1] * 1e6, "X", color="tab:red", ms=6,
                    label="time domain: not P1 (label: period found)")
        for r, a, p in zip(sw.rpm, sw.amplitude_v_L, sw.period):
            if p != 1:
                ax.annotate(_period_text(p), (r, a * 1e6), textcoords="offset points", xytext=(0, 6),
                            ha="center", fontsize=7, color="tab:red")
        ax.set_ylabel("amplitude of v_L (um)")
        ax.set_title(f"mu = {result.search_mu:g}, {c.label}: amplitude (band shaded)")
        ax.legend(fontsize=6, loc="best")
        for br, colour in [(c.branch, "k")] + [(b, "tab:purple") for b in c.seeded]:
            axm.plot(br.rpm, br.max_multiplier, "-", color=colour, lw=0.9)
            for kind, (mark, col) in KIND_MARKS.items():
                sel = [i for i, ((kd, _), s) in enumerate(zip(br.critical, br.stable)) if kd == kind and s is False]
                if sel:
                    axm.plot(br.rpm[sel], br.max_multiplier[sel], mark, color=col, ms=4, mfc="none",
                             label=f"unstable: {kind}" + (" (real > 1)" if kind == "fold" else ""))
            undecided = np.flatnonzero(br.uncertain)
            if undecided.size:
                axm.plot(br.rpm[undecided], br.max_multiplier[undecided], "o", color="goldenrod", ms=4, mfc="none",
                         label="undecided: |mu| within its error of 1")
        axm.axhline(1.0, color="0.3", lw=0.8)
        for y in (1 - floquet.MULTIPLIER_FLOOR, 1 + floquet.MULTIPLIER_FLOOR):
            axm.axhline(y, color="0.5", lw=0.6, ls=":")
        top = max([float(b.max_multiplier.max()) for b in (c.branch, *c.seeded) if len(b.rpm)] or [1.0])
        if top > MULTIPLIER_AXIS_TOP:
            axm.set_ylim(top=MULTIPLIER_AXIS_TOP)
            axm.text(0.99, 0.97, f"off scale: up to {top:.2f}", transform=axm.transAxes, ha="right", va="top",
                     fontsize=7)
        ns = [s["n_range"] for s in c.stretches() if s["n_range"]]
        axm.set_title("largest |Floquet multiplier| (1 +- its least error dotted)"
                      + (f"; NS pair: n ~ {min(n[0] for n in ns):.1f}-{max(n[1] for n in ns):.1f}" if ns else ""))
        axm.set_xlabel("speed (r/min)")
        axm.set_ylabel("|mu| max")
        handles, labels = axm.get_legend_handles_labels()
        if handles:
            uniq = dict(zip(labels, handles))
            axm.legend(uniq.values(), uniq.keys(), fontsize=6, loc="best")
    paths = [save(fig, out / "hb_branches.png")]
    labels = [c.label for c in result.hb_cases]
    readings = result.readings()
    fig, axes = figure(1, 1, width=max(6.0, 0.62 * len(result.map_rpm) + 2.2), height=0.36 * len(labels) + 1.6)
    ax = axes[0][0]
    from matplotlib.colors import to_rgb
    grid = np.ones((len(labels), len(result.map_rpm), 3))
    for r in readings:
        i, j = labels.index(r["case"]), int(np.argmin(np.abs(result.map_rpm - r["rpm"])))
        colour = "predicted" if r["verdict"] == "agree" and r["period"] != 1 else r["verdict"]
        grid[i, j] = to_rgb(VERDICT_COLOURS[colour])
        ax.text(j, i, _period_text(r["period"]) + ("*" if not r["stable_at_speed"] else ""), ha="center",
                va="center", fontsize=7)
    ax.imshow(grid, aspect="auto")
    ax.grid(False)
    ax.set_xticks(range(len(result.map_rpm)), [f"{r:.0f}" for r in result.map_rpm], rotation=60, fontsize=7)
    ax.set_yticks(range(len(labels)), labels, fontsize=7)
    ax.set_xlabel("speed (r/min)")
    ax.set_title(f"mu = {result.search_mu:g}: period found by the time domain (text; * HB has no stable P1 at "
                 "that speed)\ngreen: P1 on a stable HB P1 state; blue: no P1, HB's nearest P1 state unstable;\n"
                 "red: HB disagrees; yellow: |mu| within its error of 1; light grey: no P1 state nearby",
                 fontsize=8)
    paths.append(save(fig, out / "period_map_vs_hb.png"))
    return paths


def report_hb(result: PeriodicityResult, scene) -> list[str]:
    """The report's section on the harmonic-balance prediction."""
    opts = scene.options
    c = result.hb_conclusions()
    cost = result.costs()
    readings = result.readings()
    by_label = dict(result.period_map)
    lo, hi = result.band
    locked = [r for r in readings if r["period"] not in (1, None) and r.get("n")]
    other = [r for r in readings if r["verdict"] != "agree"]
    rows = []
    for case in result.hb_cases:
        sw = by_label[case.label]
        st = [s for s in case.stretches() if s["to_rpm"] >= lo and s["from_rpm"] <= hi]
        rows.append((case.label,
                     "; ".join(f"{s['from_rpm']:.0f}-{s['to_rpm']:.0f} {'/'.join(s['kinds'])}"
                               + (f" (n {s['n_range'][0]:.1f}-{s['n_range'][1]:.1f})" if s["n_range"] else "")
                               + f", |mu| <= {s['largest_multiplier']:.3f}"
                               + (" [seeded branch]" if s["branch"] == "seeded" else "") for s in st) or "stable",
                     ", ".join(f"{r:.0f} {_period_text(p)}" for r, p in zip(sw.rpm, sw.period) if p != 1) or "-",
                     f"{sum(r['verdict'] == 'agree' for r in readings if r['case'] == case.label)}/{len(sw.rpm)}",
                     seconds(case.branch_s), seconds(case.states_s), seconds(sw.cpu_s)))
    pct = (lambda a, b: f"{a}/{b} ({100 * a / b:.0f} %)" if b else "none")
    lines = ["\n## Prediction by harmonic balance: where P1 loses stability, and how\n",
             f"For every case of the map, the P1 branch (reduced beam, H = {opts['harmonics']}, {opts['samples']} "
             f"samples per period, this scene's contact) is continued from {opts['hb_rpm_from']:g} r/min (below "
             f"the band, where the start is easy) to {hi:g} r/min with the Floquet multipliers of every point "
             "(shroud.analysis.hb.run_hb). Where the largest multiplier leaves the unit circle, its position says "
             "what replaces P1: through -1 (period doubling) P2, then P4 ...; a complex pair mu = |mu| e^(i theta) "
             "(Neimark-Sacker) a quasi-periodic motion, or a P-n locked near n ~ 2 pi / theta; through +1 a fold "
             "(a jump to another state). At each speed of the map the branch's crossings are solved there; where a "
             f"time-domain point lies on none of them as a stable state within {100 * result.match:g} %, Newton is "
             f"also started from {', '.join(f'{x:g}' for x in opts['hb_seeds'])} times the contact-free linear "
             "solution, and the states so found at the first such speed are continued over the band too "
             "(coexisting branches, 'seeded'). Each time-domain point is read against the P1 state nearest to "
             "it in amplitude: a P1 point agrees when a stable state lies within the match, a point without P1 "
             f"when its nearest state is unstable and within {100 * result.near:g} % of it (else: no P1 state "
             "nearby). A state whose largest |multiplier| lies within its own error of 1 (sampling, harmonic "
             "truncation) is undecided, and a point read against it marginal.\n",
             "| what | measured |", "|---|---|",
             f"| time-domain points without P1 whose nearest HB P1 state is unstable | "
             f"{pct(c['td_non_p1_on_unstable_p1'], c['td_non_p1'])} |",
             f"| ... at speeds where HB has no stable P1 state at all | "
             f"{pct(c['td_non_p1_without_stable_p1_at_speed'], c['td_non_p1'])} |",
             f"| time-domain P1 points on a stable HB P1 state within {100 * result.match:g} % | "
             f"{pct(c['td_p1_on_stable_p1'], c['td_p1'])} |",
             f"| time-domain P1 points at speeds where HB has no stable P1 state | "
             f"{c['td_p1_where_hb_has_no_stable_p1']} |",
             f"| how the continued P1 branches lose stability in the band | "
             f"{', '.join(c['instability_kinds_in_band']) or 'they do not'} |",
             f"| cost: HB branches / states at the map's speeds and seeded branches / time-domain map | "
             f"{seconds(cost['hb_branches'])} / {seconds(cost['hb_states'])} wall (one process) / "
             f"{seconds(cost['td_map_cpu'])} CPU ({seconds(cost['td_map_wall'])} wall on "
             f"{os.cpu_count()} cores) |", "",
             f"`td_p1_on_stable_p1_at_least_95pct`: {result.p1_verdict().sentence()}.", "",
             markdown_table(["case", "HB: unstable P1 (r/min, kind of the largest multiplier)",
                             "time domain: speeds without P1", "points agreeing", "HB branch", "HB states",
                             "time domain (CPU)"], rows), "",
             "![hb_branches.png](hb_branches.png)", "",
             "Left: amplitude over speed, the continued branch black, branches through seeded states purple "
             "(stable solid, unstable dashed; o fold, s period doubling, ^ Neimark-Sacker marks), time-domain "
             "points green (P1) or red crosses labelled with the period found ('none': no period up to P10). "
             "Right: the largest |multiplier| along each branch, unstable points marked by kind.\n",
             "Kinds: 'Neimark-Sacker' a complex pair outside the unit circle; 'period-doubling' a real multiplier "
             "below -1; 'fold' a real multiplier above +1 (a stretch between two folds, the saddle between "
             "coexisting states). Stretches are bounded halfway between the branch points around them.\n",
             "![period_map_vs_hb.png](period_map_vs_hb.png)", ""]
    if locked:
        lines += ["Periods the time domain found where HB has a Neimark-Sacker pair (n ~ 2 pi / theta of the "
                  "nearest P1 state's pair): a locked P-n need not have n equal to 2 pi / theta (it locks to a "
                  "nearby rational rotation), but the two should be close.\n",
                  markdown_table(["case", "speed (r/min)", "time domain", "HB n ~ 2 pi / theta", "|mu|"],
                                 [(r["case"], f"{r['rpm']:.0f}", _period_text(r["period"]), f"{r['n']:.1f}",
                                   r["nearest"].split("|mu| ")[1].split(",")[0]) for r in locked]), ""]
    if other:
        lines += [f"Points where HB and the time domain disagree ({len(other)}):\n",
                  markdown_table(["case", "speed (r/min)", "time domain", "amplitude (um)", "verdict",
                                  "P1 states HB finds at that speed"],
                                 [(r["case"], f"{r['rpm']:.0f}", _period_text(r["period"]), r["amplitude_m"] * 1e6,
                                   r["verdict"], "; ".join(r["states"]) or "none") for r in other]), ""]
    if result.probes:
        torus = [p for p in result.probes if p["spread_400_m"] > 0 and p["spread_100_m"] >= 0.5 * p["spread_400_m"]]
        lines += [f"The P1 points HB does not confirm, run again for {opts['probe_periods']} periods: the spread "
                  "of the once-per-period samples of v_L over the last 100 and the last 400 periods, against the "
                  "period detector's tolerance (2e-3 of the peak-to-peak range, compared between samples p "
                  "periods apart).\n",
                  markdown_table(["case", "speed (r/min)", "period found", "amplitude (um)",
                                  "spread, last 100 (um)", "spread, last 400 (um)", "detector tolerance (um)",
                                  "time"],
                                 [(p["case"], f"{p['rpm']:.0f}", _period_text(p["period"]), p["amplitude_m"] * 1e6,
                                   p["spread_100_m"] * 1e6, p["spread_400_m"] * 1e6, p["tolerance_m"] * 1e6,
                                   seconds(p["time_s"])) for p in result.probes]), "",
                  (f"{len(torus)} of {len(result.probes)} keep their spread from 100 to 400 periods: not a P1 "
                   "orbit still settling but a small torus around the unstable P1 state (the Neimark-Sacker "
                   "pair's), whose samples move less from one period to the next than the detector's tolerance, "
                   "so the time domain calls it P1. There HB is right and the period map's P1 is the "
                   "detector's reading." if torus else
                   "None keeps a spread: these are P1 orbits HB calls unstable (see the multipliers above)."), ""]
    return lines


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
    if result.hb_cases:
        lines += report_hb(result, scene)
    return "\n".join(lines) + "\n"


def write_csv(result: PeriodicityResult, out: Path) -> None:
    with open_replacing(out / "periods.csv") as fh:
        csv.writer(fh).writerows([("mu", "case", "period", "amplitude_v_L_mm", "peak_N1", "peak_Ff1", "time"),
                                  *_case_rows(result.runs)])
    with open_replacing(out / "period_map.csv") as fh:
        w = csv.writer(fh)
        w.writerow(["case", "rpm", "period", "amplitude_v_L_m"])
        for label, sw in result.period_map:
            for k, r in enumerate(result.map_rpm):
                w.writerow([label, r, sw.period[k] or "", sw.amplitude_v_L[k]])
    if result.hb_cases:
        with open_replacing(out / "hb_readings.csv") as fh:
            w = csv.writer(fh)
            w.writerow(["case", "rpm", "td_period", "td_amplitude_v_L_m", "verdict", "hb_stable_p1_at_speed",
                        "nearest_hb_state", "hb_states"])
            for r in result.readings():
                w.writerow([r["case"], r["rpm"], r["period"] or "", r["amplitude_m"], r["verdict"],
                            int(r["stable_at_speed"]), r["nearest"] or "", "; ".join(r["states"])])


def run(scene, out: Path) -> dict:
    result = compute(scene, out)
    write_csv(result, out)
    plot(result, scene, out)
    if result.hb_cases:
        plot_hb(result, scene, out)
    write_text(out / "report.md", report(result, scene))
    return result.to_json()
