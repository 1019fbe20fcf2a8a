"""Fig. 11: amplitude-frequency responses over initial gap and initial normal preload.

Paper (Sect. 3.1, mu 0.3, alpha 30 deg, kt 5e6 N/m): the resonance of v_L
sits near 8500 r/min at a 0.6 mm gap (2 f_r close to the first frequency,
284.2 Hz); smaller gaps or larger preloads raise the resonant speed and
flatten the peak; among preloads one minimizes the resonant amplitude.

The study is compute (:func:`compute` -> :class:`GapPreloadResult`) -> plot -> report.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
import scipy.linalg

from comparisons import _families as fam
from comparisons import paper
from comparisons._study import study
from shroud.analysis.api import build_system
from shroud.analysis.transient import contact_law_for
from shroud.core.newmark import stuck_stiffness
from shroud.base.markdown import markdown_table, seconds
from shroud.core.verdict import Verdict

OPTIONS = dict(fam.FAMILY_OPTIONS)


def stuck_first_frequency(params, model: str, rpm: float) -> tuple[float, float]:
    """First natural frequency (Hz) of the blade free and with both shroud contacts stuck (undamped,
    contact springs kn, kt added): the two limits a preload moves the resonance between."""
    p = params.updated({"speed.rpm": rpm})
    system = build_system(p, model)
    law = contact_law_for(system, p.contact)
    W = np.asarray(system.contact.W, float)
    K, M = np.asarray(system.K, float), np.asarray(system.M, float)
    free = scipy.linalg.eigh(K, M, eigvals_only=True, subset_by_index=[0, 0])[0]
    stuck = scipy.linalg.eigh(K + W.T @ stuck_stiffness(law) @ W, M, eigvals_only=True, subset_by_index=[0, 0])[0]
    return float(np.sqrt(free) / (2 * np.pi)), float(np.sqrt(stuck) / (2 * np.pi))


def rises(ordered: list[dict], step_rpm: float) -> Verdict:
    """Whether the resonant speed rises along ``ordered`` (gaps closing): the smallest step from one gap
    to the next against -step/2. Speeds are read on the grid, within half a step each: a step down of one
    grid step or an equal reading may hide a rise, so it is not decided; a rise of a step or more is one."""
    steps = [b["resonance_rpm"] - a["resonance_rpm"] for a, b in zip(ordered, ordered[1:])]
    return Verdict.of(min(steps, default=float("nan")), -0.5 * step_rpm, 0.5 * step_rpm, below=False,
                      above=True, unit="r/min", reason="resonant speeds read on the speed grid, within half a "
                                                       "step each")


@dataclass(frozen=True)
class GapPreloadResult:
    """The curves over the gap and preload cases, their resonances, and the first frequency's two limits."""

    family: dict                   # variant -> [(case, SweepResult)] (one variant: the scene's mu)
    rows: list[dict]               # resonance per case (comparisons._families.resonance_table)
    step_rpm: float                # the speed grid's step
    first_frequency_hz: tuple[float, float]   # at the top speed: free, both contacts stuck

    @property
    def gaps(self) -> list[dict]:
        """The gap cases' resonances, the largest gap first (gaps closing)."""
        return sorted((r for r in self.rows if r["kind"] == "gap"), key=lambda r: -r["value"])

    @property
    def rising(self) -> Verdict:
        return rises(self.gaps, self.step_rpm)

    @property
    def optimum(self) -> tuple[float, float]:
        return fam.optimal_preload(self.rows, next(iter(self.family)))

    @property
    def every_preload_beyond(self) -> bool:
        return all(r["beyond_range"] for r in self.rows if r["kind"] == "preload" and r["value"] > 0)

    def to_json(self) -> dict:
        rows, (n_opt, a_opt), (f_free, f_stuck) = self.rows, self.optimum, self.first_frequency_hz
        return {"resonances": rows, "curves": fam.curves_json(self.family),
                "conclusions": {"resonances": {r["case"]: {"rpm": r["resonance_rpm"], "beyond_range": r["beyond_range"]}
                                               for r in rows},
                                "resonant_speed_rises_as_gap_closes": self.rising,
                                "every_preload_beyond_range": self.every_preload_beyond},
                "optimal_preload_N": n_opt, "optimal_resonant_amplitude_m": a_opt,
                "resonant_speed_rises_as_gap_closes": self.rising,
                "first_frequency_hz_at_top_speed": {"free": f_free, "stuck": f_stuck}}


def compute(scene) -> GapPreloadResult:
    """The scene's blade swept over the gap and preload cases; the first frequency free and stuck at the top speed."""
    opts = scene.options
    family = fam.run_family({f"mu {scene.params.contact.mu:g}": scene.params}, opts)
    grid = fam.rpms(opts)
    return GapPreloadResult(family=family, rows=fam.resonance_table(family), step_rpm=float(grid[1] - grid[0]),
                            first_frequency_hz=stuck_first_frequency(scene.params, opts["model"], opts["rpm_to"]))


def plot(result: GapPreloadResult, scene, out: Path) -> list[str]:
    """The families' figures and CSV (comparisons._families.write_outputs)."""
    return fam.write_outputs(out, result.family, result.rows, scene.title)


def report(result: GapPreloadResult, scene, files: list[str]) -> str:
    opts, rows, ordered = scene.options, result.rows, result.gaps
    at_06 = next((r for r in ordered if abs(r["value"] * 1e-6 - paper.FIG11_GAP_M) < 1e-12), None)
    n_opt, a_opt = result.optimum
    cpu = sum(r["cpu_s"] for r in rows)
    f_free, f_stuck = result.first_frequency_hz
    f_e = scene.params.load.ke * opts["rpm_to"] / 60.0
    lines = [f"# {scene.title}\n",
             f"Reduced model (nr = {scene.params.reduced.nr}), at least {scene.params.time.periods} periods per speed, "
             f"{len(fam.rpms(opts))} speeds per curve; runs' summed time {seconds(cpu)}.\n",
             "| paper (Sect. 3.1) | here |", "|---|---|",
             f"| resonance near {paper.FIG11_RESONANCE_RPM:g} r/min at {paper.FIG11_GAP_M * 1e3:g} mm gap | "
             f"{at_06['resonance_rpm']:.0f} r/min, {at_06['resonance_amplitude_m'] * 1e3:.3f} mm |" if at_06 else
             f"| resonance near {paper.FIG11_RESONANCE_RPM:g} r/min at {paper.FIG11_GAP_M * 1e3:g} mm gap | "
             "(that gap is not in gaps_um) |",
             f"| resonant speed rises as the gap closes | {result.rising.sentence()}: "
             + ", ".join(f"{r['value']:g} um -> {fam.speed_text(r)}" for r in ordered) + " |",
             f"| an optimal preload minimizes the resonant amplitude | N0 = {n_opt:g} N "
             f"({a_opt * 1e3:.4f} mm)" + (" -- but every preload's resonance lies at or beyond the last swept "
                                         "speed, so this is the smallest amplitude at that speed, not an optimum"
                                         if result.every_preload_beyond else "") + " |", "",
             f"At {opts['rpm_to']:g} r/min the first frequency is {f_free:.0f} Hz free and {f_stuck:.0f} Hz with "
             f"both contacts stuck (kn = {scene.params.contact.kn:.3g}, kt = {scene.params.contact.kt:.3g} N/m), "
             f"against the excitation {f_e:.0f} Hz (ke = {scene.params.load.ke}): with the shroud kept stuck the "
             f"resonance needs at least {60 * f_stuck / scene.params.load.ke:.0f} r/min (the frequency still rises "
             "with speed), beyond the swept range.\n",
             markdown_table(["case", "resonant speed (r/min)", "resonant amplitude (mm)", "periods seen", "cpu"],
                            [(r["case"], fam.speed_text(r), r["resonance_amplitude_m"] * 1e3,
                              ",".join(f"P{p}" for p in r["periods_seen"]), seconds(r["cpu_s"])) for r in rows]),
             fam.settling_text(rows, opts),
             *[f"![{f}]({f})" for f in files], "", fam.WIDEST_FIRST]
    return "\n".join(lines) + "\n"


run = study(compute, plot, report)
