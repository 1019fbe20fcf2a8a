"""Fig. 11b's "optimal preload" by harmonic balance: the resonance followed in the preload, over an extended range.

The paper reads an optimal initial normal preload off five from-rest
sweeps whose resonances lie at or beyond the swept range (Fig. 11b; per
coefficient of friction and stiffness ratio in Figs. 13c-d and 17c-d: the
resonant speed and amplitude over N0). Here the resonance itself is
followed in N0 (shroud.analysis.peak: pseudo-arclength continuation of the
harmonic balance with the peak condition), so the resonant amplitude and
the resonant speed come out as curves over the preload, free to move in
speed beyond any swept range, and the optimal preload is the curve's
minimum. The speed branches of a few preloads (shroud.analysis.hb, their
largest amplitude: the brute-force answer) are drawn with the curve and
overlaid on it as markers, with their difference from it. Where the curve
turns flat the shroud stays stuck through the resonance: from there the
preload (and the coefficient of friction) no longer matters.

The study is compute (:func:`compute` -> :class:`PreloadResonance`) -> plot -> report; :func:`track` is the
computation alone, for the studies that follow the resonance per variant (comparisons.hb_friction).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from comparisons._study import study
from shroud.analysis.hb import run_hb
from shroud.analysis.peak import PeakCurve, track_peak
from shroud.base.errors import InputError
from shroud.base.markdown import markdown_table, seconds
from shroud.base.tables import write_records
from shroud.core.plotting import figure, save
from shroud.core.results import HBResult
from shroud.core.verdict import NOT_DECIDED, Verdict

OPTIONS = {"preloads_N": [0.0, 10.0, 20.0, 50.0, 100.0, 200.0, 300.0],   # brute-force speed branches (markers)
           "n0_from": 0.0, "n0_to": 300.0,          # the tracked curve, N
           "rpm_from": 4000.0, "rpm_to": 60000.0,   # the speed branches; the first peak must lie inside
           "harmonics": 10, "samples": 512, "model": "reduced",
           "branch_points": 200,                    # at least this many points per speed branch
           "track_points": 40}                      # at least this many points on the tracked curve
AGREE = 0.01            # tracked and brute-force resonant amplitudes agree within this share
AGREE_REASON = ("1 %: the match used throughout; margin: the brute-force peak's own error (its change at twice "
                "the harmonics plus its rise between branch points) at the worst preload")
STUCK = 1e-6            # the curve is flat (stuck through the resonance) where it changes less than this share


def check(scene) -> None:
    o = scene.options
    if not o["n0_from"] < o["n0_to"]:
        raise InputError("options.n0_to", f"{o['n0_to']:g} N: allowed: above options.n0_from ({o['n0_from']:g} N)")
    if not 0 < o["rpm_from"] < o["rpm_to"]:
        raise InputError("options.rpm_to", f"{o['rpm_from']:g} .. {o['rpm_to']:g}: allowed: 0 < rpm_from < rpm_to")
    outside = [n for n in o["preloads_N"] if not o["n0_from"] <= n <= o["n0_to"]]
    if outside:
        raise InputError("options.preloads_N", f"{outside} lie outside the tracked range "
                                               f"{o['n0_from']:g}-{o['n0_to']:g} N; allowed: preloads inside it")
    for key in ("branch_points", "track_points"):
        if o[key] < 3:
            raise InputError(f"options.{key}", f"{o[key]}: allowed: an integer >= 3")


@dataclass(frozen=True)
class PreloadResonance:
    """The tracked resonance over N0 and the brute-force speed branches of some preloads."""

    curve: PeakCurve
    branches: dict[float, HBResult]          # N0 -> speed branch
    rpm_to: float                            # the speed branches' last speed, r/min

    def rows(self, rpm_to: float) -> list[dict]:
        """Per brute-force preload: the branch's largest amplitude against the tracked curve's point there."""
        out = []
        for n0, br in self.branches.items():
            res, point = br.resonance, self.curve.at(n0)
            top = res["unstable_peak"] or res       # the tracked peak is the branch's top, stable or not
            out.append({"N0": n0, "branch_rpm": top["rpm"], "branch_amplitude_m": top["amplitude"],
                        "branch_top_stable": top["stable"], "branch_amplitude_error_m": top["amplitude_error"],
                        "branch_peak_at_range_end": bool(res["rpm"] >= rpm_to - 1e-6),
                        "tracked_rpm": point["rpm"] if point else None,
                        "tracked_amplitude_m": point["amplitude"] if point else None,
                        "tracked_stable": point["stable"] if point else None,
                        "difference": abs(point["amplitude"] / top["amplitude"] - 1) if point else None,
                        "branch_s": br.elapsed_s})
        return out

    @property
    def stuck_from_N0(self) -> float | None:
        """The preload from which the resonance no longer changes (stuck through it), or None."""
        a = self.curve.amplitude_v_L
        flat = np.abs(a / a[-1] - 1) <= STUCK
        if len(a) < 2 or not flat[-2]:
            return None
        i = len(a) - 1
        while i > 0 and flat[i - 1]:
            i -= 1
        return float(self.curve.n0[i])

    def conclusions(self) -> dict:
        """What the report concludes, as data: the optimal preload (N, with its bracket), its resonant
        amplitude and speed, whether it lies inside the curve, whether the resonant speed rises with the
        preload, where the shroud stays stuck through the resonance, whether the brute-force peaks agree."""
        best = self.curve.optimum
        rows = [r for r in self.rows(float("inf")) if r["difference"] is not None]
        worst = max(rows, key=lambda r: r["difference"], default=None)
        agrees = Verdict.of(worst["difference"] if worst else float("nan"), AGREE,
                            worst["branch_amplitude_error_m"] / worst["branch_amplitude_m"] if worst else 0.0,
                            True, False, AGREE_REASON)
        return {"optimal_preload_N": best["N0"], "optimal_bracket_N": best["bracket"],
                "optimal_stable": best["stable"], "optimal_amplitude_error_m": best["amplitude_error"],
                "optimal_amplitude_m": best["amplitude"], "optimal_rpm": best["rpm"],
                "optimum_inside": not best["at_end"],
                "resonant_speed_rises_with_preload": bool(np.all(np.diff(self.curve.rpm) > -1.0)),
                "stuck_from_N0": self.stuck_from_N0,
                "brute_force_agrees": agrees.answer, "brute_force_agrees_verdict": agrees.to_json(),
                "complete": self.curve.complete}

    def to_json(self) -> dict:
        rows = self.rows(self.rpm_to)
        return {"conclusions": self.conclusions(), "peak_curve": self.curve.to_json(), "resonances": rows,
                "branches": {f"N0 {n0:g} N": br.to_json() for n0, br in self.branches.items()},
                "cost_s": {"peak_tracking": self.curve.elapsed_s, "speed_branches": sum(r["branch_s"] for r in rows)}}


def track(params, opts: dict, branches: dict[float, HBResult] | None = None) -> PreloadResonance:
    """The tracked curve from ``opts["n0_from"]`` to ``opts["n0_to"]`` with a point at every brute-force
    preload, and the brute-force speed branches (``branches``, N0 -> branch, where already computed)."""
    preloads = list(branches) if branches is not None else [float(n) for n in opts["preloads_N"]]
    curve = track_peak(params, opts["model"], opts["n0_from"], opts["n0_to"], opts["rpm_from"], opts["rpm_to"],
                       harmonics=int(opts["harmonics"]), samples=int(opts["samples"]),
                       at=tuple(preloads), min_points=int(opts["track_points"]))
    if branches is None:
        branches = {n0: run_hb(params.updated({"contact.N0": n0}), opts["model"], opts["rpm_from"],
                               opts["rpm_to"], harmonics=int(opts["harmonics"]), samples=int(opts["samples"]),
                               min_points=int(opts["branch_points"])) for n0 in preloads}
    return PreloadResonance(curve=curve, branches=branches, rpm_to=float(opts["rpm_to"]))


def compute(scene) -> PreloadResonance:
    """The scene's resonance tracked over N0 and the speed branches of ``preloads_N`` (:func:`track`)."""
    return track(scene.params, scene.options)


def plot_over_preload(ax_amplitude, ax_speed, result: PreloadResonance, label: str, colour) -> None:
    """The tracked resonant amplitude (mm) and speed (r/min) over N0 (lines: solid stable, dashed
    unstable), the brute-force branches' peaks as markers, the optimum as a star."""
    c = result.curve
    for ax, y in ((ax_amplitude, c.amplitude_v_L * 1e3), (ax_speed, c.rpm)):
        ax.plot(c.n0, np.where(c.stable, y, np.nan), "-", color=colour, label=label)
        if not c.stable.all():
            ax.plot(c.n0, np.where(c.stable, np.nan, y), "--", color=colour)
    n0 = list(result.branches)
    ax_amplitude.plot(n0, [b.resonance["amplitude"] * 1e3 for b in result.branches.values()], "o", color=colour,
                      mfc="none", ms=5)
    ax_speed.plot(n0, [b.resonance["rpm"] for b in result.branches.values()], "o", color=colour, mfc="none", ms=5)
    best = c.optimum
    ax_amplitude.plot(best["N0"], best["amplitude"] * 1e3, "*", color=colour, ms=10)
    ax_amplitude.set_ylabel("resonant amplitude of v_L (mm)")
    ax_speed.set_ylabel("resonant speed (r/min)")
    for ax in (ax_amplitude, ax_speed):
        ax.set_xlabel("initial preload N0 (N)")


def optimum_text(best: dict) -> str:
    return (f"N0 = {best['N0']:.1f} N (between the curve's points {best['bracket'][0]:.1f} and "
            f"{best['bracket'][1]:.1f} N), {best['amplitude'] * 1e3:.4g} mm at {best['rpm']:.0f} r/min")


def plot(result: PreloadResonance, scene, out: Path) -> list[str]:
    """(a) the speed branches with the tracked resonance, (b) its amplitude and (c) its speed over N0; the
    branch peaks and the tracked curve as CSV."""
    curve = result.curve
    fig, axes = figure(1, 3, width=13.0, height=4.2)
    for i, (n0, br) in enumerate(result.branches.items()):
        br.plot(axes[0][0], label=f"N0 {n0:g} N", colour=f"C{i % 10}")
    axes[0][0].plot(curve.rpm, curve.amplitude_v_L * 1e3, "k-", lw=1.5, label="resonance over N0")
    axes[0][0].set_title("(a) speed branches and the tracked resonance")
    axes[0][0].legend(ncol=2)
    plot_over_preload(axes[0][1], axes[0][2], result, "tracked", "k")
    axes[0][1].set_title("(b) resonant amplitude (o: branch peaks, *: optimum)")
    axes[0][2].set_title("(c) resonant speed (o: branch peaks)")
    save(fig, out / "hb_optimal_preload.png")
    write_records(out / "resonances.csv", result.rows(result.rpm_to))
    write_records(out / "peak_curve.csv", [{"N0": float(n), "rpm": float(r), "amplitude_v_L_m": float(a),
                                            "stable": bool(s)} for n, r, a, s in
                                           zip(curve.n0, curve.rpm, curve.amplitude_v_L, curve.stable)])
    return ["hb_optimal_preload.png"]


def report(result: PreloadResonance, scene, files: list[str]) -> str:
    opts = scene.options
    curve, rows = result.curve, result.rows(result.rpm_to)
    concl = result.conclusions()
    branch_s = sum(r["branch_s"] for r in rows)
    stuck = concl["stuck_from_N0"]
    lines = [f"# {scene.title}\n",
             f"Model {opts['model']}, harmonic balance H = {opts['harmonics']} ({opts['samples']} samples). "
             f"The resonance is followed in N0 from {opts['n0_from']:g} to {opts['n0_to']:g} N ({len(curve.n0)} "
             f"points, {seconds(curve.elapsed_s)}, its first speed branch included); the speed branches of "
             f"{len(rows)} preloads over {opts['rpm_from']:g}-{opts['rpm_to']:g} r/min, the brute-force answer, "
             f"took {seconds(branch_s)}.\n",
             (f"Optimal preload: {optimum_text(curve.optimum)}." if concl["optimum_inside"] else
              f"The smallest resonant amplitude lies at the end of the tracked range (N0 = {curve.optimum['N0']:g} N): "
              "the optimum is there or beyond it."),
             "",
             "The resonant speed " + ("rises with the preload all along the curve" if
                                      concl["resonant_speed_rises_with_preload"] else "does not rise monotonically")
             + f", from {curve.rpm[0]:.0f} r/min at {curve.n0[0]:g} N to {curve.rpm[-1]:.0f} r/min at "
               f"{curve.n0[-1]:g} N.",
             (f"From N0 = {stuck:.1f} N on the resonance no longer changes ({curve.amplitude_v_L[-1] * 1e3:.4g} mm at "
              f"{curve.rpm[-1]:.0f} r/min): the shroud stays stuck through it, and neither the preload nor the "
              "coefficient of friction matters any more." if stuck is not None else
              "The shroud still slips at the resonance at the end of the tracked range."),
             "",
             f"Tracked curve against the speed branches' largest amplitudes (agreement within {100 * AGREE:g} %: "
             f"{ {True: 'yes', False: 'no'}.get(concl['brute_force_agrees'], NOT_DECIDED)}, margin "
             f"{100 * concl['brute_force_agrees_verdict']['margin']:.3g} %):\n",
             markdown_table(["N0 (N)", "branch peak (r/min)", "branch peak (mm)", "tracked (r/min)", "tracked (mm)",
                             "difference (%)", "stable at the peak", "branch cost"],
                            [(f"{r['N0']:g}", ("at the range's end " if r["branch_peak_at_range_end"] else "")
                              + f"{r['branch_rpm']:.0f}", r["branch_amplitude_m"] * 1e3,
                              f"{r['tracked_rpm']:.0f}", r["tracked_amplitude_m"] * 1e3, 100 * r["difference"],
                              "yes" if r["tracked_stable"] else "no", seconds(r["branch_s"])) for r in rows]),
             "",
             "" if curve.complete else f"The tracked curve is incomplete: {curve.stopped}.\n",
             *[f"![{f}]({f})" for f in files]]
    return "\n".join(lines) + "\n"


run = study(compute, plot, report)
