"""Fig. 8 and Table 3 of the paper: four models of the shroud impact and friction (and Fig. 10: the shell).

At 10000 r/min, N0 = 0, kn = kt = 1e7 N/m, alpha = 15 deg, mu = 0.3 (the
scene), each model runs ``time.periods`` excitation periods from rest:

* "reduced": the beam model reduced to nr = 6 free-interface modes,
* "full": the beam model, 5 N = 30 DOF,
* "fe-reduced": the solid FE model reduced to fe.cms_modes normal modes plus
  the residual attachment modes of its contact nodes and load,
* "fe": the solid FE model, one contact element per contact-face node;
* "shell", "shell-reduced": the shell FE model and its reduction (paper
  Fig. 10, scenes/fig10.toml), any of them in ``options.models``.

Figures as the paper's: impact force, friction force, hysteresis loop
(friction force against the face's tangential displacement w_s) and contact
state of each side, and the shroud displacements v_L, w_L. Agreement is
measured against ``options.reference`` over the last ``window_periods``
periods (NRMSE and peak error of each signal, share of time in each state),
and for the two reduced/full pairs, whose targets are 1 % (beam) and 2 %
(solid) NRMSE. Table 3 is the cost of each run beside the paper's, after a
short warm-up run that compiles the integrator kernel (its time is reported
apart: a fresh process pays it once, whichever model runs first).

For the solid models, the contact-state map: per contact-face node,
the share of the final window spent separate / stick / slip, drawn on the
two shroud faces (reference_fe.contact_map, drawn by comparisons._pictures).

Each model's settling is measured (the change of its tip amplitudes between
the last window and the one before, shroud.analysis.sweep.amplitude_change),
and the report says what the run's settings cannot resolve: unsettled
models, models left out (the reduced solid standing in for the full one), a
solid mesh other than the default. :func:`conclusions` turns the returned
numbers into what the report concludes.

The study is compute (:func:`compute` -> :class:`Fig8Result`) -> plot -> report.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from pathlib import Path

from comparisons import convergence
from comparisons._study import study
from shroud.analysis.agreement import SIGNALS, Agreement, agreement, signals_of
from comparisons._bands import CHEAPER, TIMING_NOISE, cost_versus, versus
from comparisons.paper import PAPER_SECONDS, TABLE3_SECONDS
from shroud.analysis import api
from shroud.core import registry
from shroud.core.states import STATE_NAMES
from shroud.core.verdict import BandVerdict, RatioVerdict, Verdict
from shroud.base.cache import builds
from shroud.base.errors import InputError, RunDiverged
from shroud.base.log import info, warn
from shroud.core.plotting import MODEL_COLOURS, figure, save
from shroud.base.markdown import markdown_table, seconds
from shroud.core.signals import STEADY_PERIODS
from shroud.analysis.sweep import Settling, amplitude_change
from shroud.analysis.transient import simulate
from shroud.base.tables import write_records
from shroud.params import FE

OPTIONS = {
    "models": ["reduced", "full", "extended", "fe-reduced", "fe"],
    "reference": "fe",          # what every model is measured against
    "window_periods": 10,       # the steady window of the metrics
    "plot_periods": 2,          # periods shown in the time panels
}

FIGURE = "fig8.png"      # paper Fig. 8 (a)-(j)
# (model, its full model, NRMSE target)
PAIRS = (("reduced", "full", 0.01), ("fe-reduced", "fe", 0.02), ("shell-reduced", "shell", 0.02))
LABELS = {"reduced": "reduced beam (nr modes)", "full": "full beam (5N DOF)",
          "fe-reduced": "reduced solid FE", "fe": "full solid FE",
          "extended": "extended beam (torsion, rigid shroud; nr modes)",
          "shell": "full shell FE", "shell-reduced": "reduced shell FE"}
# The unreduced models solid, the reductions dashed above them (each its own dash), so that a reduction
# that lies on its full model shows as dashes on its line instead of vanishing under it.
DASHES = {"full": dict(ls="-", zorder=2), "fe": dict(ls="-", zorder=2),
          "reduced": dict(ls=(0, (5, 3)), zorder=3), "fe-reduced": dict(ls=(0, (2, 2)), zorder=3),
          "extended": dict(ls=(0, (6, 2, 1, 2)), zorder=3), "shell": dict(ls="-", zorder=2),
          "shell-reduced": dict(ls=(0, (3, 1, 1, 1)), zorder=3)}
# Bands of the conclusions. Amplitudes within 0.5 % are the same (a settled amplitude is known to the
# settling tolerance, 0.2 %); a model is closer to the reference than another when its worst NRMSE is
# below 1/1.5 of the other's; cost in the band of comparisons._bands; contact-state shares within
# 0.02 of the window are the same.
SAME_AMPLITUDE = 0.005
CLOSER = 1.5
SAME_SHARE = 0.02
# Paper Fig. 8(d, h): States 1-3 are separation, slip, stick.
PAPER_STATE = {STATE_NAMES.index("separate"): 1, STATE_NAMES.index("slip"): 2, STATE_NAMES.index("stick"): 3}


def check(scene) -> None:
    o = scene.options
    unknown = [m for m in o["models"] if m not in registry.names("transient")]
    if unknown or not o["models"]:
        raise InputError("options.models", f"{o['models']!r}; allowed: a list from {', '.join(registry.names("transient"))}")
    if o["reference"] not in o["models"]:
        raise InputError("options.reference", f"{o['reference']!r} is not among options.models")
    if not 1 <= o["window_periods"] <= scene.params.time.periods:
        raise InputError("options.window_periods", f"{o['window_periods']!r}; allowed: 1 .. time.periods")
    if not 1 <= o["plot_periods"] <= scene.params.time.periods:
        raise InputError("options.plot_periods", f"{o['plot_periods']!r}; allowed: 1 .. time.periods")


def run_models(params, models, out: Path) -> dict[str, dict]:
    """Build and integrate each model; a diverging model is reported, not fatal."""
    runs = {}
    for model in models:
        with builds() as built:                  # artefacts built on disk in this build (a cold build)
            system = api.build_system(params, model)
        cache_s = sum(dt for _, dt in built)
        csv_path = out / f"transient_{model}.csv"
        try:
            result = simulate(system, params, csv_path=csv_path)
        except RunDiverged as exc:
            warn(str(exc))
            runs[model] = {"diverged": str(exc), "dofs": system.dofs, "build_s": system.build_s,
                           "cache_build_s": cache_s}
            continue
        info(f"{model}: {system.dofs} DOF, built in {system.build_s:.2f} s, "
             f"{result.steps} steps in {result.elapsed_s:.2f} s")
        runs[model] = {"result": result, "dofs": system.dofs, "build_s": system.build_s, "cache_build_s": cache_s,
                       "run_s": result.elapsed_s, "t": result.trajectory.t,
                       "signals": signals_of(result.trajectory),
                       "amplitude_change": amplitude_change(result.trajectory, params.time.steps_per_period,
                                                            STEADY_PERIODS)}
    return runs


@dataclass(frozen=True)
class Fig8Result:
    """Every model's run, its agreement with the reference and within the reduced/full pairs, the costs,
    and for the solids the contact-state maps."""

    rpm: float
    periods: int
    steps_per_period: int
    period: float                  # the excitation period, s
    reference: str                 # the model every other one is measured against
    runs: dict[str, dict]          # model -> run (run_models: the result, or why it diverged; DOF, times)
    compile_s: float               # the kernels' compilation before the runs (kept out of Table 3), s
    versus_ref: dict[str, Agreement]
    pairs: dict[str, dict]         # "small vs big" -> agreement, target, met
    maps: dict[str, dict]          # solid model -> its contact-state map's summary (contact_maps)
    faces: list | None             # the shroud faces the maps lie on (reference_fe.contact_map.FaceGeometry)

    @property
    def ok(self) -> dict[str, dict]:
        """The runs that completed."""
        return {m: r for m, r in self.runs.items() if "result" in r}

    @property
    def table3(self) -> list[dict]:
        return [{"model": m, "dofs": r["dofs"], "build_s": r["build_s"], "run_s": r.get("run_s"),
                 "total_s": r["build_s"] + r.get("run_s", math.nan), "cache_build_s": r["cache_build_s"],
                 "warm_total_s": r["build_s"] - r["cache_build_s"] + r.get("run_s", math.nan),
                 "paper_s": PAPER_SECONDS.get(m),
                 "status": "diverged" if "diverged" in r else "complete"} for m, r in self.runs.items()]

    @property
    def states(self) -> dict[str, dict]:
        return {m: r["result"].state_fraction for m, r in self.ok.items()}

    def to_json(self) -> dict:
        ok, runs = self.ok, self.runs
        change = {m: r["amplitude_change"] for m, r in ok.items()}
        results = {
            "rpm": self.rpm, "periods": self.periods,
            "steps_per_period": self.steps_per_period, "reference": self.reference,
            "table3": self.table3, "compile_s": self.compile_s, "paper_table3_s": TABLE3_SECONDS,
            "amplitude": {m: r["result"].amplitude for m, r in ok.items()},
            "peak": {m: r["result"].peak for m, r in ok.items()},
            "state_fraction": self.states, "period": {m: r["result"].period for m, r in ok.items()},
            "versus_reference": {m: a.to_json() for m, a in self.versus_ref.items()},
            "pairs": self.pairs, "diverged": {m: r["diverged"] for m, r in runs.items() if "diverged" in r},
            "figures": [FIGURE] + [m["png"] for m in self.maps.values()],
            "contact_map": self.maps,
            "amplitude_change": {m: c if math.isfinite(c) else None for m, c in change.items()},
            "settled": {m: c <= Settling.tolerance if math.isfinite(c) else None for m, c in change.items()},
        }
        results["conclusions"] = conclusions(results)
        return results


def compute(scene, out: Path) -> Fig8Result:
    """Every model's run (time series into ``out``), each against the reference and its full model; the
    solids' contact-state maps."""
    check(scene)
    params, o = scene.params, scene.options
    period = 2 * math.pi / (params.load.ke * params.speed.omega)
    compile_s = api.compile_kernels(params)
    info(f"kernels compiled in {compile_s:.2f} s (kept out of Table 3)")
    runs = run_models(params, o["models"], out)
    ok = {m: r for m, r in runs.items() if "result" in r}
    ref = ok.get(o["reference"])
    versus_ref: dict[str, Agreement] = {}
    if ref is not None:
        for m, r in ok.items():
            if m != o["reference"]:
                versus_ref[m] = agreement(r["t"], r["signals"], ref["t"], ref["signals"], period,
                                          o["window_periods"])
    pairs = {}
    for small, big, target in PAIRS:
        if small in ok and big in ok:
            fit = agreement(ok[small]["t"], ok[small]["signals"], ok[big]["t"], ok[big]["signals"],
                            period, o["window_periods"])
            pairs[f"{small} vs {big}"] = {**fit.to_json(), "target": target, "met": fit.worst_nrmse <= target}
    faces, maps = contact_maps(ok, params)
    return Fig8Result(rpm=params.speed.rpm, periods=params.time.periods, steps_per_period=params.time.steps_per_period,
                      period=period, reference=o["reference"], runs=runs, compile_s=compile_s, versus_ref=versus_ref,
                      pairs=pairs, maps=maps, faces=faces)


def plot(result: Fig8Result, scene, out: Path) -> list[str]:
    """Paper Fig. 8 (fig8.png), the contact-state maps (PNG and per-node CSV); Table 3, the agreement and
    the state shares as CSV."""
    o = scene.options
    write_records(out / "table3.csv", result.table3)
    write_records(out / "agreement.csv", [
        {"model": m, "versus": o["reference"], "signal": s, "nrmse": a.nrmse[s], "peak_error": a.peak_error[s]}
        for m, a in result.versus_ref.items() for s in SIGNALS])
    write_records(out / "state_fractions.csv", [
        {"model": m, "side": side, **fr} for m, st in result.states.items() for side, fr in st.items()])
    figures = _figures(result.ok, scene.params, o, result.period, out)
    return [p.name for p in figures] + _contact_map_pictures(result, out)


def report(result: Fig8Result, scene, files: list[str]) -> str:
    return _report(scene, result.runs, result.table3, result.compile_s, result.versus_ref, result.pairs,
                   result.states, result.maps, result.to_json())


run = study(compute, plot, report, writes=True)


def _state_order(shares: dict[str, float]) -> str:
    """The states by falling share, "=" between shares within SAME_SHARE: "separate > slip > stick"."""
    ranked = sorted(STATE_NAMES, key=lambda k: -shares[k])
    text = ranked[0]
    for a, b in zip(ranked, ranked[1:]):
        text += (" = " if shares[a] - shares[b] <= SAME_SHARE else " > ") + b
    return text


def conclusions(results: dict) -> dict:
    """What the report concludes, as data, from the numbers ``run`` returns (a results.json gives them).

    Every comparison is a verdict (shroud.core.verdict) with its number, band and margin; the margins are
    measured: a run's settling (its tip amplitudes' change between the last two windows, ``amplitude_change``)
    for amplitudes and NRMSE, the state shares' step (one time step of the window) for slip, the timing noise
    of identical runs (comparisons._bands.TIMING_NOISE) for cost.

    * pairs_met: each reduced model's worst NRMSE against its full model below its target;
    * settled: each model's tip amplitudes settled (change over the last window <= Settling.tolerance);
    * closer_to_reference: for two models (canonical order), "closer", "farther" or "as close" (worst
      NRMSE against the reference within a factor CLOSER), and closest_to_reference: the models tied
      for the smallest worst NRMSE;
    * amplitude_vs_reference: each model's v_L, w_L amplitude "larger", "smaller" or "the same"
      (within SAME_AMPLITUDE) than the reference's;
    * slip_vs_reference: its slip share (mean of the sides) "more", "less" or "the same" (SAME_SHARE);
    * state_order: its states by falling share (mean of the sides);
    * cost: for two models, "cheaper", "costlier" or "comparable" (warm total time, build + run without
      the artefacts built on disk in this run, within a factor CHEAPER).
    """
    ref = results["reference"]
    # the default models' order first (the pairs' names), then any other the scene runs (fig10's shells)
    order = [m for m in OPTIONS["models"] if m in results["amplitude"]]
    order += [m for m in results["amplitude"] if m not in order]
    worst = {m: v["worst_nrmse"] for m, v in results["versus_reference"].items()}
    total = {r["model"]: r.get("warm_total_s", r["total_s"]) for r in results["table3"] if r["status"] == "complete"}
    slip = {m: (st["side1"]["slip"] + st["side2"]["slip"]) / 2 for m, st in results["state_fraction"].items()}
    change = results["amplitude_change"]
    best = min(worst.values(), default=math.inf)
    pairs = [(a, b) for i, a in enumerate(order) for b in order[i + 1:]]
    share_step = 1.0 / (results["steps_per_period"] * min(STEADY_PERIODS, results["periods"]))

    def settling(*models) -> tuple[float, str]:
        """The relative margin of numbers read on these runs' last window: their largest settling change."""
        known = [change.get(m) for m in models]
        if any(c is None for c in known):
            return math.inf, "a run too short to measure its settling: nothing is decided"
        return max(known), (f"the runs' tip amplitudes change by up to {100 * max(known):.2g} % between the "
                            "last two windows (settling)")

    def amplitude(m: str, s: str) -> RatioVerdict:
        margin, why = settling(m, ref)
        return versus(results["amplitude"][m][s], results["amplitude"][ref][s], 1 + SAME_AMPLITUDE, 1 + margin,
                      ("larger", "smaller", "the same"), why)

    # An NRMSE is an RMS difference over a signal's range: a settling change of the amplitudes by a share
    # c moves it by up to about c (absolute), which is the margin of an NRMSE and, over the smaller of
    # two, of their ratio.
    def closer(a: str, b: str) -> RatioVerdict:
        margin, why = settling(a, b, ref)
        return versus(worst[a], worst[b], CLOSER, 1 + margin / min(worst[a], worst[b]),
                      ("farther", "closer", "as close"), why)

    def pair(name: str, fit: dict) -> Verdict:
        margin, why = settling(*name.split(" vs "))
        return Verdict.of(fit["worst_nrmse"], fit["target"], margin, below=True, above=False,
                          reason=f"NRMSE target; {why}")

    def share(m: str, s: float) -> BandVerdict:
        settled = math.isfinite(settling(m, ref)[0])
        return BandVerdict(s - slip[ref], SAME_SHARE, share_step if settled else math.inf, above="more",
                           below="less", between="the same",
                           reason="a share is counted in time steps of the window: its resolution is one step"
                           if settled else "a run too short to measure its settling: nothing is decided")

    return {
        "pairs_met": {k: pair(k, v) for k, v in results["pairs"].items()},
        "settled": {m: Verdict.of(c if c is not None else math.nan, Settling.tolerance, 0.0, below=True,
                                  above=False, reason="the change between the last two windows is measured, "
                                  "not estimated") for m, c in change.items()},
        "closest_to_reference": sorted(m for m, w in worst.items() if w <= CLOSER * best),
        "closer_to_reference": {f"{a} vs {b}": closer(a, b) for a, b in pairs if a in worst and b in worst},
        "amplitude_vs_reference": {m: {s: amplitude(m, s) for s in ("v_L", "w_L")}
                                   for m in results["amplitude"] if m != ref and ref in slip},
        "slip_vs_reference": {m: share(m, s) for m, s in slip.items() if m != ref and ref in slip},
        "state_order": {m: _state_order({k: (st["side1"][k] + st["side2"][k]) / 2 for k in STATE_NAMES})
                        for m, st in results["state_fraction"].items()},
        "cost": {f"{a} vs {b}": cost_versus(total[a], total[b])
                 for a, b in pairs if a in total and b in total},
    }


def _figures(ok: dict, params, o, period: float, out: Path) -> list[Path]:
    """Paper Fig. 8 (a)-(j): each side's N, F_f, loop and state; v_L and w_L."""
    fig, axes = figure(5, 2, width=7.5, height=12.0)
    spp = params.time.steps_per_period
    for model, r in ok.items():
        t, s = r["t"], r["signals"]
        tr = r["result"].trajectory
        shown = slice(len(t) - 1 - o["plot_periods"] * spp, None)
        loop = slice(len(t) - 1 - spp, None)
        tt = (t[shown] - t[shown][0]) / period
        style = dict(color=MODEL_COLOURS[model], label=LABELS[model], lw=1.0 if model != "fe" else 1.6,
                     **DASHES[model])
        for col, side in enumerate((1, 2)):
            axes[0, col].plot(tt, s[f"N{side}"][shown], **style)
            axes[1, col].plot(tt, s[f"Ff{side}"][shown], **style)
            axes[2, col].plot(1e6 * tr.tangential[loop, side - 1], s[f"Ff{side}"][loop], **style)
            axes[3, col].step(tt, [PAPER_STATE[int(x)] for x in tr.state[shown, side - 1]], where="post", **style)
        axes[4, 0].plot(tt, 1e6 * s["v_L"][shown], **style)
        axes[4, 1].plot(tt, 1e6 * s["w_L"][shown], **style)
    titles = [["(a) impact force N1, side 1", "(e) impact force N2, side 2"],
              ["(b) friction force Ff1, side 1", "(f) friction force Ff2, side 2"],
              ["(c) hysteresis loop, side 1 (last period)", "(g) hysteresis loop, side 2 (last period)"],
              ["(d) contact state, side 1", "(h) contact state, side 2"],
              ["(i) v_L (flexural)", "(j) w_L (swing)"]]
    ylabels = ["N (N)", "Ff (N)", "Ff (N)", "state", "displacement (um)"]
    for i in range(5):
        for j in range(2):
            ax = axes[i, j]
            ax.set_title(titles[i][j])
            ax.set_ylabel(ylabels[i])
            ax.set_xlabel("w_s (um)" if i == 2 else "t / T_e (last periods)")
            if i == 3:
                ax.set_yticks([1, 2, 3], ["1 separate", "2 slip", "3 stick"])
    if ok:      # one legend above the panels: inside one it hid the peaks of (a)
        fig.legend(*axes[0, 0].get_legend_handles_labels(), loc="upper center", ncol=3, frameon=False)
    return [save(fig, out / FIGURE, top=0.95 if ok else 1.0)]


def _solid_runs(ok: dict) -> dict:
    """The solid models' trajectories that hold node-wise contact shares."""
    return {m: r["result"].trajectory for m, r in ok.items()
            if m in ("fe-reduced", "fe") and r["result"].trajectory.element_share is not None}


def contact_maps(ok: dict, params) -> tuple[list | None, dict[str, dict]]:
    """Per solid model: the node-wise state shares on the shroud faces, summarized (the faces, the summaries;
    ``draw_s`` the time to summarize them, the picture is drawn by :func:`plot`)."""
    solid = _solid_runs(ok)
    if not solid:
        return None, {}
    from reference_fe.contact_map import face_geometry, summarize
    faces = face_geometry(params)
    window = min(STEADY_PERIODS, params.time.periods)
    maps = {}
    for model, tr in solid.items():
        t0 = time.perf_counter()
        maps[model] = {"png": f"contact_map_{model}.png", "csv": f"contact_map_{model}.csv", "window_periods": window,
                       **summarize(faces, tr.element_share, tr.element_peak_normal),
                       "draw_s": time.perf_counter() - t0}
    return faces, maps


def _contact_map_pictures(result: Fig8Result, out: Path) -> list[str]:
    """Per solid model: its contact-state map (PNG) and the per-node shares (CSV)."""
    if not result.maps:
        return []
    from comparisons._pictures import contact_map_picture
    from reference_fe.contact_map import split_by_side
    faces, names = result.faces, []
    for model, tr in _solid_runs(result.ok).items():
        window = result.maps[model]["window_periods"]
        png = contact_map_picture(out / f"contact_map_{model}.png", faces, split_by_side(faces, tr.element_share),
                                  f"{LABELS[model]}, last {window} periods")
        rows = []
        for face, share, peak in zip(faces, split_by_side(faces, tr.element_share),
                                     split_by_side(faces, tr.element_peak_normal)):
            for j in range(face.nodes.shape[0]):
                rows.append({"side": face.side, "x_m": face.nodes[j, 0], "y_m": face.nodes[j, 1],
                             "z_m": face.nodes[j, 2], "area_share": face.weight[j],
                             **{name: share[j, c] for c, name in enumerate(STATE_NAMES)},
                             "peak_normal_N": peak[j]})
        write_records(out / f"contact_map_{model}.csv", rows)
        names.append(png.name)
    return names


def _conclusion_lines(results: dict) -> list[str]:
    """The conclusions (:func:`conclusions`) in words, each verdict with its number, band and margin."""
    found, ref = results["conclusions"], results["reference"]
    if not found["closest_to_reference"]:
        return []
    lines = ["\n## What the comparison concludes\n",
             f"- Closest to the {LABELS[ref]} (worst NRMSE, within a factor {CLOSER:g} counts as a tie): "
             + ", ".join(f"{LABELS[m]} ({results['versus_reference'][m]['worst_nrmse']:.2g})"
                         for m in found["closest_to_reference"]) + "."]
    lines += [f"- {pair}: {v.sentence()}." for pair, v in found["closer_to_reference"].items()]
    lines.append(f"- Tip amplitudes v_L, w_L against the {LABELS[ref]} (within {100 * SAME_AMPLITUDE:g} % the "
                 "same):")
    lines += [f"  - {LABELS[m]}: v_L {v['v_L'].sentence()}; w_L {v['w_L'].sentence()}."
              for m, v in found["amplitude_vs_reference"].items()]
    lines.append(f"- Slip share against the {LABELS[ref]} (mean of the sides, within {SAME_SHARE:g} the same): "
                 + "; ".join(f"{LABELS[m]} {v.sentence()}" for m, v in found["slip_vs_reference"].items())
                 + ". States by share: " + "; ".join(f"{LABELS[m]} {v}" for m, v in found["state_order"].items())
                 + ".")
    total = {r["model"]: r.get("warm_total_s", r["total_s"]) for r in results["table3"] if r["status"] == "complete"}
    ranked = sorted(total, key=total.get)
    chain = LABELS[ranked[0]]
    for a, b in zip(ranked, ranked[1:]):
        verdict = found["cost"].get(f"{a} vs {b}", found["cost"].get(f"{b} vs {a}"))
        chain += {"comparable": " ~ ", "cheaper": " < ", "costlier": " < "}.get(verdict.answer, " ? ") + LABELS[b]
    lines.append(f"- Cost (build + run, warm: artefacts built on disk in this run left out, Table 3 lists them; "
                 f"within a factor {CHEAPER:g} comparable, ~; within the timing noise "
                 f"x{TIMING_NOISE:g} of that edge not decided, ?): {chain}.")
    lines += [f"  - {pair}: {v.sentence()}." for pair, v in found["cost"].items()]
    return lines


def _limits(scene, results: dict) -> list[str]:
    """What this run's settings cannot resolve, from its settings and its measured settling."""
    p, o = scene.params, scene.options
    window, tol = STEADY_PERIODS, Settling.tolerance
    change = results["amplitude_change"]
    lines = ["## What these settings resolve and what they cannot\n"]
    unknown = [m for m, c in change.items() if c is None]
    unsettled = {m: c for m, c in change.items() if c is not None and c > tol}
    if unknown:
        lines.append(f"- {p.time.periods} periods are fewer than two windows of {window}: whether "
                     f"{', '.join(LABELS[m] for m in unknown)} settled cannot be told; their amplitudes, "
                     "agreement and contact shares may be those of the start-up transient.")
    if unsettled:
        lines.append(f"- Not shown settled after {p.time.periods} periods: the tip amplitudes over the last "
                     f"{window} periods differ from those over the {window} before by "
                     + ", ".join(f"{100 * c:.2g} % ({LABELS[m]})" for m, c in unsettled.items())
                     + f", more than {100 * tol:g} %: their amplitudes, agreement and contact shares may be those "
                     "of the start-up transient (or the window before still held it); more periods "
                     "(time.periods) tell.")
    settled = [m for m, c in change.items() if c is not None and c <= tol]
    if settled:
        lines.append(f"- Settled after {p.time.periods} periods: {', '.join(LABELS[m] for m in settled)} "
                     f"(tip amplitudes change by at most {100 * max(change[m] for m in settled):.2g} % "
                     f"between the last {window} periods and the {window} before; settled below "
                     f"{100 * tol:g} %): more periods would not move their amplitudes, agreement or "
                     "contact shares by more than that.")
    missing = [m for m in ("reduced", "full", "fe-reduced", "fe") if m not in o["models"]]
    if missing:
        checks = [f"{small} vs {big}" for small, big, _ in PAIRS if small in missing or big in missing]
        lines.append(f"- Not run here: {', '.join(LABELS[m] for m in missing)}: no Table 3 row"
                     + (", no contact map" if {"fe", "fe-reduced"} & set(missing) else "")
                     + (f", no pair check ({', '.join(checks)})" if checks else "") + ".")
    if o["reference"] != "fe" and "fe" in missing:
        lines.append(f"- The reference is the {LABELS[o['reference']]}, not the full solid FE: every "
                     "comparison with the reference is one with the full solid only as far as the "
                     "reference follows it (the fe-reduced vs fe pair of scenes/fig8.toml).")
    solids = [m for m in o["models"] if m in ("fe", "fe-reduced")]
    default = FE()
    mesh = (p.fe.cell, p.fe.mesh_size, p.fe.order)
    if solids and mesh != (default.cell, default.mesh_size, default.order):
        lines.append(f"- The solid mesh ({p.fe.cell}, {p.fe.mesh_size:g} m, order {p.fe.order}) is not the "
                     f"default ({default.cell}, {default.mesh_size:g} m, order {default.order}, the mesh "
                     "scenes/convergence.toml chose): its frequencies, and the solid's response, differ from "
                     "the default solid's by an amount this run does not measure.")
    elif solids:
        lines.append(f"- The solid is the default mesh ({p.fe.cell}, {p.fe.mesh_size:g} m, order {p.fe.order}), "
                     f"chosen by scenes/convergence.toml to hold its first {convergence.OPTIONS['n_modes']} "
                     f"frequencies within {convergence.OPTIONS['tolerance_pct']:g} % of the mesh-converged values.")
    lines.append(f"- {p.time.steps_per_period} steps per excitation period (dt = {p.time_step:.3g} s): a "
                 f"contact event is located to within dt, the state shares are counted in steps of "
                 f"1/{p.time.steps_per_period} of a period; the stability scene measures what coarser steps cost.")
    return lines


def _report(scene, runs, table3, compile_s, versus_ref, pairs, states, maps, results) -> str:
    p = scene.params
    lines = [f"# {scene.title}\n",
             f"{p.speed.rpm:g} r/min, N0 = {p.contact.N0:g} N, kn = {p.contact.kn:g} N/m, "
             f"kt = {p.contact.kt:g} N/m, alpha = {p.contact.alpha_deg:g} deg, mu = {p.contact.mu:g}; "
             f"{p.time.periods} excitation periods at {p.time.steps_per_period} steps each "
             f"(dt = {p.time_step:.4g} s), {p.time.contact} contact; solid mesh "
             f"{p.fe.mesh_size:g} m, order {p.fe.order}, {p.fe.cms_modes} kept modes.\n",
             "## Table 3: run times\n",
             "Ours on this machine (2 cores); the paper's on an i7-6700 (ANSYS for the FE models). "
             "Build: matrices, reduction basis (cached on disk after the first run), damping. "
             "Run: the time integration, steady cost: the integrator kernel was compiled before, "
             f"by a one-period reduced-beam run that took {seconds(compile_s)} (numba compilation, or "
             "loading its disk cache; paid once per process, not per model). 'Built on disk': the part of "
             "the build that made cache entries (mesh, reduction basis) in this run, counted once: a "
             "later run reads them. The cost verdicts compare warm totals (total without it), so every "
             "model's cost is measured one way.\n",
             markdown_table(("model", "DOF", "build", "built on disk", "run", "total", "warm total", "paper",
                             "status"),
                            [(LABELS[r["model"]], r["dofs"], seconds(r["build_s"]), seconds(r["cache_build_s"]),
                              seconds(r["run_s"]), seconds(r["total_s"]) if math.isfinite(r["total_s"]) else "-",
                              seconds(r["warm_total_s"]) if math.isfinite(r["warm_total_s"]) else "-",
                              seconds(r["paper_s"]), r["status"]) for r in table3]),
             "\n![Fig. 8](fig8.png)\n",
             "Full models solid, reductions dashed and drawn above them: where a reduction lies on its "
             "full model, its dashes run along that line.\n",
             "## Agreement over the last periods\n"]
    if pairs:
        lines.append("Reduced model against its own full model (worst NRMSE over the six signals):\n")
        lines.append(markdown_table(("pair", "worst NRMSE", "target", "met"),
                                    [(k, v["worst_nrmse"], v["target"], "yes" if v["met"] else "no")
                                     for k, v in pairs.items()]))
    if versus_ref:
        ref = scene.options["reference"]
        lines.append(f"\nEach model against the {LABELS[ref]} (NRMSE / peak error):\n")
        lines.append(markdown_table(("model",) + SIGNALS,
                                    [(LABELS[m],) + tuple(f"{a.nrmse[s]:.3g} / {a.peak_error[s]:.3g}"
                                                          for s in SIGNALS) for m, a in versus_ref.items()]))
    lines.append("\nShare of the window in each contact state (separate / stick / slip):\n")
    lines.append(markdown_table(("model", "side 1", "side 2"),
                                [(LABELS[m], *(" / ".join(f"{st[side][k]:.2f}" for k in STATE_NAMES)
                                               for side in ("side1", "side2"))) for m, st in states.items()]))
    lines += _conclusion_lines(results)
    for m, c in maps.items():
        lines.append(f"\n## Contact-state map, {LABELS[m]}\n")
        lines.append(f"Each contact-face node is one contact element; colour: its share of the last "
                     f"{c['window_periods']} periods spent separate, stick and slip. Area-weighted mean "
                     "share of the face (node range in brackets) and the largest nodal normal force; "
                     f"summarized in {seconds(c['draw_s'])}.\n")
        lines.append(markdown_table(
            ("side", "nodes") + STATE_NAMES + ("peak nodal N (N)",),
            [(side[-1], c[side]["nodes"],
              *(f"{c[side]['area_weighted_share'][k]:.3f} ({c[side]['node_share_min'][k]:.2f}-"
                f"{c[side]['node_share_max'][k]:.2f})" for k in STATE_NAMES),
              f"{c[side]['peak_normal_max_N']:.3g}") for side in ("side1", "side2")]))
        lines.append(f"\n![contact-state map, {LABELS[m]}]({c['png']})\n")
    diverged = {m: r["diverged"] for m, r in runs.items() if "diverged" in r}
    for m, why in diverged.items():
        lines.append(f"\n**{LABELS[m]} diverged**: {why}\n")
    lines.append("")
    lines += _limits(scene, results)
    lines.append("\nTime series of each model: `transient_<model>.csv`; tables: `table3.csv`, "
                 "`agreement.csv`, `state_fractions.csv`, per-node contact maps `contact_map_<model>.csv`.\n")
    return "\n".join(lines)
