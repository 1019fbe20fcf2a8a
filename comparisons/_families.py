"""Families of amplitude-frequency curves over gap and preload (paper Figs. 11-13, 16-17).

One study = one contact parameter varied (none, mu, or the stiffness ratio
xi = kt/kn) over two panels of cases: initial gaps, and a 1 um gap followed
by initial normal preloads (the paper's (a)/(b) panels). Every curve is a
speed sweep of the reduced model; the resonance (speed and amplitude of the
largest steady-state v_L amplitude) is read off each curve. Every point runs
until it has settled (shroud.analysis.sweep.Settling); points that have not
are marked in the figures and counted in the tables.
"""

from __future__ import annotations

import csv
import dataclasses
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from shroud.params import Parameters
from shroud.core.plotting import figure, save
from shroud.analysis.sweep import PLATEAU, SETTLING_OPTIONS, Settling, run_sweeps, steady_resonance
from shroud.core.results import SweepResult
from shroud.base.tables import write_records
from shroud.core.verdict import Verdict
from shroud.base.outputs import open_replacing

FAMILY_OPTIONS = {
    "gaps_um": [600.0, 300.0, 100.0, 50.0, 10.0],
    "small_gap_um": 1.0,
    "preloads_N": [10.0, 25.0, 50.0, 100.0, 200.0],
    "rpm_from": 4000.0, "rpm_to": 30000.0, "rpm_count": 66,
    "model": "reduced",
    **SETTLING_OPTIONS,
}


@dataclass(frozen=True)
class Case:
    label: str
    kind: str          # "gap" | "preload"
    value: float       # gap in um, or N0 in N
    params: Parameters


def cases(base: Parameters, options: dict) -> list[Case]:
    """The gap panel, then the 1 um gap and the preload panel."""
    out = [Case(f"gap {g:g} um", "gap", g, base.updated({"contact.gap": g * 1e-6}))
           for g in options["gaps_um"]]
    g = options["small_gap_um"]
    out.append(Case(f"gap {g:g} um", "preload", -base.contact.kn * g * 1e-6,
                    base.updated({"contact.gap": g * 1e-6})))
    out += [Case(f"N0 {n:g} N", "preload", n, base.updated({"contact.N0": n}))
            for n in options["preloads_N"]]
    return out


def rpms(options: dict) -> np.ndarray:
    return np.linspace(options["rpm_from"], options["rpm_to"], int(options["rpm_count"]))


def run_family(variants: dict[str, Parameters], options: dict) -> dict[str, list[tuple[Case, SweepResult]]]:
    """Every case of every variant, swept in one parallel map."""
    all_cases = [(name, c) for name, base in variants.items() for c in cases(base, options)]
    results = run_sweeps([c.params for _, c in all_cases], options["model"], rpms(options),
                         settling=Settling.from_options(options))
    out: dict[str, list] = {name: [] for name in variants}
    for (name, c), r in zip(all_cases, results):
        out[name].append((c, r))
    return out


def resonance_table(family: dict[str, list[tuple[Case, SweepResult]]]) -> list[dict]:
    """Resonance of every curve (shroud.analysis.sweep.steady_resonance: settled points only, the end
    of a flat top); ``beyond_range`` when it sits on the last speed (the resonance lies at or above the
    swept range, and its speed and amplitude are lower bounds)."""
    rows = []
    for name, curves in family.items():
        for c, r in curves:
            res = steady_resonance(r)
            rows.append({"variant": name, "case": c.label, "kind": c.kind, "value": c.value,
                         "resonance_rpm": res["rpm"],
                         "beyond_range": bool(res["rpm"] >= r.rpm[-1]),
                         "resonance_amplitude_m": res["amplitude"],
                         "unsettled_speeds": int(sum(not x for x in r.settled)),
                         "periods_seen": sorted({p for p in r.period if p}),
                         "unperiodic_speeds": int(sum(p is None for p in r.period)),
                         "cpu_s": r.cpu_s})
    return rows


def every_other(sweep: SweepResult, start: int) -> SweepResult:
    """The sweep read on every other speed from ``start`` (0 or 1): its grid's step doubled."""
    cut = slice(start, None, 2)
    return dataclasses.replace(sweep, rpm=sweep.rpm[cut], amplitude_v_L=sweep.amplitude_v_L[cut],
                               amplitude_w_L=sweep.amplitude_w_L[cut], period=sweep.period[cut],
                               slip_fraction=sweep.slip_fraction[cut], settled=tuple(sweep.settled)[cut])


def grid_margin(family, measure) -> float:
    """How far a number read off the curves' resonances moves with the speed grid: the largest change of
    ``measure(resonance_table(...))`` when every curve is read on every other speed (even, odd). Doubling
    the step over-states the error of the grid actually swept, so this is a safe margin; a change common to
    the variants (a peak that every variant's grid misses alike) cancels in a spread, as it should.

    >>> import numpy as np
    >>> rpm = np.arange(5.0)
    >>> peak = SweepResult("m", rpm, np.array([1.0, 2.0, 4.0, 2.0, 1.0]), rpm, (1,) * 5, rpm, 1, 0.0, 0.0,
    ...                    (True,) * 5)
    >>> one = {"a": [(Case("gap 1 um", "gap", 1.0, None), peak)]}
    >>> grid_margin(one, lambda rows: rows[0]["resonance_amplitude_m"])    # odd speeds read 2, not 4
    2.0
    """
    full = measure(resonance_table(family))
    halves = [measure(resonance_table({n: [(c, every_other(r, k)) for c, r in curves]
                                       for n, curves in family.items()})) for k in (0, 1)]
    return max((abs(h - full) for h in halves if np.isfinite(h)), default=float("nan"))


def same_speed(rpm_a: float, rpm_b: float, step_rpm: float) -> Verdict:
    """Whether two curves read on one speed grid resonate at the same speed (True/False).

    Each resonant speed is a grid speed within half a step of the true one: readings one step apart may
    be one speed read twice, or two speeds a step apart, so that difference is not decided; equal
    readings are the same speed, readings two or more steps apart are not.
    """
    return Verdict.of(abs(rpm_a - rpm_b), step_rpm, 0.5 * step_rpm, below=True, above=False, unit="r/min",
                      reason="each resonant speed read on the speed grid, within half a step of the true one")


def speed_text(row: dict) -> str:
    """Resonant speed as the reports print it: '>= 30000' when beyond the swept range."""
    return (">= " if row["beyond_range"] else "") + f"{row['resonance_rpm']:.0f}"


def curve_differences(family, kind: str, min_value: float | None = None,
                      threshold: float = 0.05) -> tuple[float, list[dict]]:
    """Pointwise differences between the variants' curves of each case of ``kind`` (value >= ``min_value``),
    relative to the case's largest amplitude: (largest difference at the speeds below ``threshold``,
    the speeds at or above it with every variant's amplitude). Near a jump the blade has coexisting
    steady states, and variants run from rest may sit on different ones there (see the Fig. 4 study)."""
    small, jumps = 0.0, []
    names = list(family)
    for i, (c, r) in enumerate(family[names[0]]):
        if c.kind != kind or (min_value is not None and c.value < min_value):
            continue
        amps = np.array([family[n][i][1].amplitude_v_L for n in names])
        diff = (np.nanmax(amps, axis=0) - np.nanmin(amps, axis=0)) / np.nanmax(amps)
        below = diff < threshold
        small = max(small, float(np.max(diff[below], initial=0.0)))
        jumps += [{"case": c.label, "rpm": float(r.rpm[k]), "difference": float(diff[k]),
                   "amplitude_m": {n: float(a) for n, a in zip(names, amps[:, k])}}
                  for k in np.flatnonzero(~below)]
    return small, jumps


def optimal_preload(rows: list[dict], variant: str) -> tuple[float, float]:
    """(N0, resonant amplitude) of the preload with the smallest resonant amplitude."""
    pre = [r for r in rows if r["variant"] == variant and r["kind"] == "preload" and r["value"] >= 0]
    best = min(pre, key=lambda r: r["resonance_amplitude_m"])
    return best["value"], best["resonance_amplitude_m"]


# Caption of the figures below: how coinciding curves stay visible.
WIDEST_FIRST = ("Curves of a panel are drawn widest first: where two coincide (a blade stuck all period "
                "responds alike whatever its preload, friction or stiffness ratio), the later one runs "
                "inside the earlier one.")


def widest_first(k: int, count: int) -> float:
    """Line width (pt) of the k-th of ``count`` curves of a panel: each later one 0.9 pt thinner, the last 1 pt."""
    return 1.0 + 0.9 * (count - 1 - k)


def write_outputs(out: Path, family, rows: list[dict], title: str) -> list[str]:
    """Amplitude-frequency panels per variant, resonance characteristics, and the CSVs."""
    names = list(family)
    fig, axes = figure(len(names), 2, width=8.0, height=2.6 * len(names) + 0.6)
    for i, name in enumerate(names):
        for j, kind in enumerate(("gap", "preload")):
            ax = axes[i][j]
            shown = [(c, r) for c, r in family[name] if c.kind == kind]
            for k, (c, r) in enumerate(shown):
                ax.plot(r.rpm, r.amplitude_v_L * 1e3, label=c.label, lw=widest_first(k, len(shown)))
                bad = ~np.array(r.settled, bool)
                if bad.any():
                    ax.plot(r.rpm[bad], r.amplitude_v_L[bad] * 1e3, "x", color="k",
                            label=None if "not settled" in ax.get_legend_handles_labels()[1] else "not settled")
            ax.set_xlabel("speed (r/min)")
            ax.set_ylabel("amplitude of v_L (mm)")
            ax.set_title(f"{name}: {'initial gaps' if kind == 'gap' else 'small gap and preloads'}")
            ax.legend(ncol=2)
    files = [save(fig, out / "amplitude_frequency.png").name]
    fig, axes = figure(2, 2, width=8.0)
    for k, name in enumerate(names):
        lw = widest_first(k, len(names))
        style = dict(marker="o", lw=lw, ms=2.0 + 2.0 * lw, label=name)
        for j, kind in enumerate(("gap", "preload")):
            sel = [r for r in rows if r["variant"] == name and r["kind"] == kind and
                   (kind == "gap" or r["value"] >= 0)]
            x = [r["value"] for r in sel]
            axes[0][j].plot(x, [r["resonance_rpm"] for r in sel], **style)
            axes[1][j].plot(x, [r["resonance_amplitude_m"] * 1e3 for r in sel], **style)
    for j, xl in enumerate(("initial gap (um)", "initial preload N0 (N)")):
        axes[0][j].set_ylabel("resonant speed (r/min)")
        axes[1][j].set_ylabel("resonant amplitude (mm)")
        for i in range(2):
            axes[i][j].set_xlabel(xl)
            axes[i][j].legend()
    axes[0][0].set_xscale("log")
    axes[1][0].set_xscale("log")
    files.append(save(fig, out / "resonance_characteristics.png").name)
    with open_replacing(out / "amplitude_frequency.csv") as fh:
        w = csv.writer(fh)
        w.writerow(["variant", "case", "rpm", "amplitude_v_L_m", "amplitude_w_L_m", "period", "settled"])
        for name in names:
            for c, r in family[name]:
                for k in range(len(r.rpm)):
                    w.writerow([name, c.label, r.rpm[k], r.amplitude_v_L[k], r.amplitude_w_L[k],
                                r.period[k] or "", int(r.settled[k])])
    write_records(out / "resonances.csv", rows)
    return files


def settling_text(rows: list[dict], options: dict) -> str:
    """The report's paragraph on settling and on what the sweep's settings cannot resolve."""
    unsettled = [f"{r['variant']} {r['case']}: {r['unsettled_speeds']}" for r in rows if r["unsettled_speeds"]]
    step = (options["rpm_to"] - options["rpm_from"]) / (int(options["rpm_count"]) - 1)
    return (Settling.from_options(options).describe() + " Resonance: the largest settled amplitude, or "
            f"where the top is flat (within {100 * PLATEAU:g} % of it over a band of speeds, an impacting branch) "
            "the highest speed on it, where the branch ends. Speeds not settled per curve: "
            + (", ".join(unsettled) or "none") + ".\n\n"
            f"What these settings cannot resolve: {grid_limits(step)}.\n")


def grid_limits(step_rpm: float) -> str:
    """What a sweep's speed grid of step ``step_rpm`` (r/min) cannot resolve, for a report."""
    return (f"resonant speeds closer than the speed step ({step_rpm:.0f} r/min; a peak between two speeds is "
            "read at the nearer one), the amplitude of such a peak (the grid's largest lies below it) and "
            "amplitude jumps narrower than one step")


def curves_json(family) -> dict:
    return {name: {c.label: r.to_json() for c, r in curves} for name, curves in family.items()}
