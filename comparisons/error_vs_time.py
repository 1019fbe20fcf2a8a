"""Error against run time: every model at several fidelities on the Fig. 8 case.

Each point is one transient (the scene's speed, contact and number of
periods) of one model at one fidelity: the beam model's kept modes nr and
shape functions N, the solid's element size and degree, the reduced solid's
kept modes, the shell's element size and the reduced shell's kept modes
(docs/shell.md), and the time step. Its error is the worst NRMSE of the six Fig. 8
signals (N1, N2, Ff1, Ff2, v_L, w_L) against the full solid FE model at the
finest setting, over the last ``window_periods`` periods; its cost is the
wall time of building the model plus integrating it, measured one way for
every point: warm. Each point's model is built once untimed first (so a mesh
or reduction basis cached on disk is built, or read, there and only there),
then built again and integrated under the clock; the first build's time is
listed apart (``first_build_s``), counted once, never on the cost axis. (A
basis built in the run beside one read from the disk cache made the quick
front's cost axis mix 2.7 s cold with 0.13 s warm.) The Pareto front is
the set of points no other point beats in both error and time. The
reference is not one of the points (its error is 0 by definition): a point
with the reference's own settings is left out.

Beside them, the steady response by harmonic balance (shroud.analysis.hb,
with its Floquet stability) of each dense model, the frequency-domain
answer to the same question: a second picture puts every point's error in
the steady amplitudes of v_L and w_L (against the reference's over its
last periods) against its cost, time-domain runs and harmonic-balance
points side by side.

The study is compute (:func:`compute` -> :class:`ErrorVsTime`) -> plot -> report.
"""

from __future__ import annotations

import csv
import math
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from shroud.analysis.agreement import agreement, signals_of
from comparisons._study import study
from comparisons._bands import CHEAPER, TIMING_NOISE, cost_versus, versus
from shroud.analysis import api
from shroud.analysis.hb import checkpoint
from shroud.core import registry
from shroud.base.errors import InputError, RunDiverged
from shroud.base.log import info, warn
from shroud.core.plotting import MODEL_COLOURS, figure, save
from shroud.base.markdown import markdown_table, seconds
from shroud.analysis.transient import simulate
from shroud.core.signals import amplitude
from shroud.core.verdict import RatioVerdict, timing
from shroud.base.outputs import open_replacing

OPTIONS = {
    "reduced_nr": [2, 4, 6, 10],          # beam model, kept modes (at reduced.N)
    "beam_N": [4, 6, 8],                  # full beam model, shape functions per field
    "fe_mesh_sizes": [0.0035],            # solid, element size (m) ...
    "fe_orders": [1, 2],                  # ... and degree
    "cms_modes": [6, 12, 24, 48],         # reduced solid, kept normal modes
    "steps_per_period": [64, 128, 256],   # time step, for each of step_models at its scene fidelity
    "step_models": ["reduced", "fe-reduced"],
    "extended_nr": [6, 10],               # the extended beam (torsion, rigid shroud), kept modes
    "shell_mesh_sizes": [0.004],          # shell, element size (m)
    "shell_cms_modes": [12, 24],          # reduced shell, kept normal modes
    "window_periods": 10,
    "hb_models": ["reduced", "full", "extended", "fe-reduced"],   # harmonic balance at the scene's fidelity
    "hb_harmonics": 15,
}


@dataclass(frozen=True)
class Point:
    model: str
    setting: str
    overrides: tuple[str, ...]


def check(scene) -> None:
    o = scene.options
    if not o["fe_mesh_sizes"] or not o["fe_orders"] or any(k not in (1, 2) for k in o["fe_orders"]):
        raise InputError("options.fe_orders", f"{o['fe_orders']!r}; allowed: a non-empty list of 1 and 2")
    if any(nr > 5 * scene.params.reduced.N or nr < 1 for nr in o["reduced_nr"]):
        raise InputError("options.reduced_nr", f"{o['reduced_nr']!r}; allowed: 1 .. 5 reduced.N")
    if any(nr > 6 * scene.params.reduced.N or nr < 1 for nr in o["extended_nr"]):
        raise InputError("options.extended_nr", f"{o['extended_nr']!r}; allowed: 1 .. 6 reduced.N")
    if any(m not in registry.names("transient") for m in o["step_models"]):
        raise InputError("options.step_models", f"allowed: models from {', '.join(registry.names("transient"))}")
    if not 1 <= o["window_periods"] <= scene.params.time.periods:
        raise InputError("options.window_periods", "allowed: 1 .. time.periods")
    hb_models = set(registry.names("transient")) - {"fe"}      # the full solid has checkpoints, not these
    if any(m not in hb_models for m in o["hb_models"]):
        raise InputError("options.hb_models", f"{o['hb_models']!r}; allowed: models from {', '.join(sorted(hb_models))}")
    if not isinstance(o["hb_harmonics"], int) or o["hb_harmonics"] < 1:
        raise InputError("options.hb_harmonics", f"{o['hb_harmonics']!r}; allowed: an integer >= 1")
    if any(h <= 0 for h in o["shell_mesh_sizes"]):
        raise InputError("options.shell_mesh_sizes", f"{o['shell_mesh_sizes']!r}; allowed: sizes > 0 m")
    for key in ("steps_per_period", "cms_modes", "beam_N", "shell_cms_modes"):
        if any(v < 1 for v in o[key]):
            raise InputError(f"options.{key}", f"{o[key]!r}; allowed: positive integers")


def reference_point(o) -> Point:
    h, order, spp = min(o["fe_mesh_sizes"]), max(o["fe_orders"]), max(o["steps_per_period"])
    return Point("fe", f"h = {1e3 * h:g} mm, P{order}, {spp} steps/period (reference)",
                 (f"fe.mesh_size={h}", f"fe.order={order}", f"time.steps_per_period={spp}"))


def points(o) -> list[Point]:
    pts = [Point("reduced", f"nr = {nr}", (f"reduced.nr={nr}",)) for nr in o["reduced_nr"]]
    pts += [Point("full", f"N = {n} ({5 * n} DOF)", (f"reduced.N={n}",)) for n in o["beam_N"]]
    pts += [Point("fe", f"h = {1e3 * h:g} mm, P{k}", (f"fe.mesh_size={h}", f"fe.order={k}"))
            for h in o["fe_mesh_sizes"] for k in o["fe_orders"]]
    pts += [Point("fe-reduced", f"{k} modes", (f"fe.cms_modes={k}",)) for k in o["cms_modes"]]
    pts += [Point(m, f"{s} steps/period", (f"time.steps_per_period={s}",))
            for m in o["step_models"] for s in o["steps_per_period"]]
    pts += [Point("extended", f"nr = {nr}", (f"reduced.nr={nr}",)) for nr in o["extended_nr"]]
    pts += [Point("shell", f"h = {1e3 * h:g} mm", (f"shell.mesh_size={h}",)) for h in o["shell_mesh_sizes"]]
    pts += [Point("shell-reduced", f"{k} modes", (f"shell.cms_modes={k}",)) for k in o["shell_cms_modes"]]
    return pts


def pareto(times: np.ndarray, errors: np.ndarray) -> np.ndarray:
    """Mask of the points that no other point beats in both time and error."""
    front = np.zeros(times.size, bool)
    best = math.inf
    for i in np.lexsort((errors, times)):
        if errors[i] < best:
            front[i], best = True, errors[i]
    return front


def steady_amplitudes(trajectory, steps_per_period: int) -> tuple[float, float]:
    """(v_L, w_L) steady amplitudes (m) of a transient over its last periods."""
    return tuple(amplitude(trajectory.tip[:, j], steps_per_period) for j in (0, 1))


def amplitude_error(a: tuple[float, float], ref: tuple[float, float]) -> float:
    """The larger relative error of the two steady amplitudes."""
    return max(abs(x / r - 1.0) for x, r in zip(a, ref))


def hb_point(params, model: str, harmonics: int) -> dict:
    """The steady state of ``model`` at the scene's speed by harmonic balance with its stability, and its cost
    measured warm as every time-domain point's (a first, untimed solve builds what it caches)."""
    t0 = time.perf_counter()
    checkpoint(params, model, params.speed.rpm, harmonics=harmonics)
    first = time.perf_counter() - t0
    t0 = time.perf_counter()
    sol = checkpoint(params, model, params.speed.rpm, harmonics=harmonics)
    return {"model": model, "setting": f"harmonic balance, H = {harmonics}", "time_s": time.perf_counter() - t0,
            "first_build_s": first,
            "amplitudes": (sol.amplitude_v_L, sol.amplitude_w_L), "converged": sol.converged,
            "stable": sol.stable, "spectral_tail": sol.spectral_tail}


def measure(params, point: Point, warm: bool = True):
    """(result, DOF, time of build + integration (s), time of the untimed first build (s)).

    ``warm``: the model is built once before the clock starts, so what it caches on disk or in the
    process is in place for the timed build; otherwise (the reference, which is not a point) the one build
    is timed as it comes and the first build's time is 0.
    """
    p = params.with_overrides(list(point.overrides))
    first = 0.0
    if warm:
        t0 = time.perf_counter()
        api.build_system(p, point.model)
        first = time.perf_counter() - t0
    t0 = time.perf_counter()
    system = api.build_system(p, point.model)
    result = simulate(system, p)
    return result, system.dofs, time.perf_counter() - t0, first


@dataclass(frozen=True)
class ErrorVsTime:
    """Every point's error against the reference and its warm cost, the front, the HB points, the verdicts."""

    reference: Point
    reference_dofs: int
    reference_s: float             # the reference's build + integration, s (cold: it is not a point)
    reference_amplitudes: tuple[float, float]   # its steady v_L, w_L amplitudes, m
    rows: list[dict]               # one per point: DOF, warm time, worst NRMSE, amplitude error, on the front
    front: np.ndarray              # on the error-against-time front, per row
    hb_rows: list[dict]            # one per harmonic-balance point
    conclusions: dict              # conclusions() | hb_conclusions()

    def to_json(self) -> dict:
        rows = self.rows
        return {"reference": {"setting": self.reference.setting, "dofs": self.reference_dofs,
                              "time_s": self.reference_s, "amplitudes": self.reference_amplitudes},
                # which points are on the front is decided by run times: declared so (shroud compare skips it)
                "points": [{k: v for k, v in r.items() if k != "pareto"} for r in rows],
                "pareto": timing([f"{r['model']} {r['setting']}" for r in rows if r["pareto"]]),
                "harmonic_balance": self.hb_rows, "conclusions": self.conclusions}


def compute(scene) -> ErrorVsTime:
    """The reference run, then every point (warm) against it; the harmonic-balance points."""
    check(scene)
    params, o = scene.params, scene.options
    period = 2 * math.pi / (params.load.ke * params.speed.omega)
    # compile first (and build each model's cached parts) so that no point pays for it
    api.compile_kernels(params, [pt.model for pt in points(o) if pt.model != "fe"])
    ref_point = reference_point(o)
    ref, ref_dofs, ref_s, _ = measure(params, ref_point, warm=False)
    t_ref, s_ref = ref.trajectory.t, signals_of(ref.trajectory)
    ref_spp = params.with_overrides(list(ref_point.overrides)).time.steps_per_period
    ref_amp = steady_amplitudes(ref.trajectory, ref_spp)
    info(f"reference {ref_point.setting}: {ref_dofs} DOF, {ref_s:.1f} s")
    rows, runs = [], []
    for pt in points(o):
        if pt.model == ref_point.model and set(pt.overrides) <= set(ref_point.overrides):
            continue                                              # the reference itself: not a point
        run_of = (pt.model, params.with_overrides(list(pt.overrides)))
        twin = next((r for key, r in runs if key == run_of), None)
        if twin is not None:                                      # e.g. the scene's own step: one run, one point
            twin["setting"] += f" (= {pt.setting})"
            twin["names"].append(f"{pt.model} {pt.setting}")
            continue
        try:
            result, dofs, cost, first = measure(params, pt)
        except RunDiverged as exc:
            warn(f"{pt.model} {pt.setting}: {exc}")
            continue
        fit = agreement(result.trajectory.t, signals_of(result.trajectory), t_ref, s_ref, period,
                        o["window_periods"])
        spp = params.with_overrides(list(pt.overrides)).time.steps_per_period
        rows.append({"model": pt.model, "setting": pt.setting, "dofs": dofs, "time_s": cost, "first_build_s": first,
                     "error": fit.worst_nrmse, **{f"nrmse_{k}": v for k, v in fit.nrmse.items()},
                     "amplitude_error": amplitude_error(steady_amplitudes(result.trajectory, spp), ref_amp),
                     "names": [f"{pt.model} {pt.setting}"]})
        runs.append((run_of, rows[-1]))
        info(f"{pt.model} {pt.setting}: {dofs} DOF, {cost:.2f} s, worst NRMSE {fit.worst_nrmse:.3g}")
    times = np.array([r["time_s"] for r in rows])
    errors = np.array([r["error"] for r in rows])
    front = pareto(times, errors)
    for r, f in zip(rows, front):
        r["pareto"] = bool(f)
    hb_rows = []
    for model in o["hb_models"]:
        h = hb_point(params, model, o["hb_harmonics"])
        h["amplitude_error"] = amplitude_error(h["amplitudes"], ref_amp)
        hb_rows.append(h)
        info(f"{model} harmonic balance: {h['time_s']:.2f} s, amplitude error {h['amplitude_error']:.3g}")
    return ErrorVsTime(reference=ref_point, reference_dofs=ref_dofs, reference_s=ref_s, reference_amplitudes=ref_amp,
                       rows=rows, front=front, hb_rows=hb_rows,
                       conclusions=conclusions(rows, scene) | hb_conclusions(rows, hb_rows, scene))


def plot(result: ErrorVsTime, scene, out: Path) -> list[str]:
    """Error against run time with its front, amplitude error against run time (HB points too); the CSV."""
    rows = result.rows
    with open_replacing(out / "error_vs_time.csv") as fh:
        w = csv.DictWriter(fh, fieldnames=[k for k in rows[0] if k != "names"], extrasaction="ignore")
        w.writeheader()
        w.writerows(rows)
    return [_figure(rows, result.front, result.reference, out),
            _amplitude_figure(rows, result.hb_rows, result.reference, out)]


def report(result: ErrorVsTime, scene, files: list[str]) -> str:
    fig_name, amp_name = files
    return (_report(scene, result.reference, result.reference_dofs, result.reference_s, result.rows, fig_name,
                    result.conclusions)
            + _hb_report(scene, result.rows, result.hb_rows, result.reference_amplitudes, amp_name))


run = study(compute, plot, report)


def scene_point(rows: list[dict], model: str, scene) -> dict | None:
    """The time-domain run of ``model`` at the scene's own fidelity (the one its HB point shares)."""
    p = scene.params
    own = {"reduced": f"reduced nr = {p.reduced.nr}", "extended": f"extended nr = {p.reduced.nr}",
           "full": f"full N = {p.reduced.N} ({5 * p.reduced.N} DOF)",
           "fe-reduced": f"fe-reduced {p.fe.cms_modes} modes",
           "shell-reduced": f"shell-reduced {p.shell.cms_modes} modes"}.get(model)
    return next((r for r in rows if own in r["names"]), None)


def hb_conclusions(rows: list[dict], hb_rows: list[dict], scene) -> dict:
    """Per model: how its harmonic-balance point's cost compares with its time-domain run's at the same
    fidelity, both measured warm (comparisons._bands.cost_versus: "cheaper", "costlier", "comparable", not
    decided within the timing noise of identical runs). Their amplitude errors are reported, not ranked: the
    reference shares the time-domain runs' step error, which moves their difference by as much as it is
    (quick 128 against full 256 steps per period turned the extended beam's from "smaller" into "about the
    same")."""
    out = {}
    for h in hb_rows:
        td = scene_point(rows, h["model"], scene)
        if td is None:
            continue
        out[f"cost of harmonic balance of {h['model']} against its time-domain run"] = cost_versus(h["time_s"],
                                                                                                   td["time_s"])
    return out


CLEARLY = 1.5     # errors within this factor of each other are not told apart (the margin of ERROR_REASON)
ERROR_REASON = ("errors move by up to x1.5 with the reference's own step error and the window (quick 128 "
                "against full 256 steps per period moved the extended beam's by that)")


def ordering(error_a: float, error_b: float) -> RatioVerdict:
    """How the second error compares with the first: "smaller" or "larger", not decided within a factor
    CLEARLY (differences the reference's own error and the window can shift)."""
    return versus(error_b, error_a, 1.0, CLEARLY, ("larger", "smaller", "the same"), ERROR_REASON)


def beats(error: float, best: float) -> RatioVerdict:
    """Whether ``error`` is below ``best`` (True/False), not decided within a factor CLEARLY."""
    return versus(error, best, 1.0, CLEARLY, (False, True, True), ERROR_REASON)


def conclusions(rows: list[dict], scene) -> dict:
    """What the report concludes, as data (verdicts, shroud.core.verdict): whether the scene's reduced solid
    beats every beam and each solid every beam (:func:`beats`), and for every two fidelities of one model
    differing in one setting, how the finer one's error compares (:func:`ordering`). The shell (docs/shell.md)
    is held to the same: whether the scene's reduced shell and each full shell beat every beam."""
    p, o = scene.params, scene.options
    err = {name: r["error"] for r in rows for name in r["names"]}
    beams = [r["error"] for r in rows if r["model"] in ("reduced", "full")]
    solid = err.get(f"fe-reduced {p.fe.cms_modes} modes")
    out = {}
    if beams and solid is not None:
        out[f"reduced solid ({p.fe.cms_modes} modes) beats every beam"] = beats(solid, min(beams))
    shell = err.get(f"shell-reduced {p.shell.cms_modes} modes")
    if beams and shell is not None:
        out[f"reduced shell ({p.shell.cms_modes} modes) beats every beam"] = beats(shell, min(beams))
    for r in rows:
        if r["model"] == "fe" and beams:
            out[f"solid {r['setting']} beats the best beam"] = beats(r["error"], min(beams))
        if r["model"] == "shell" and beams:
            out[f"shell {r['setting']} beats the best beam"] = beats(r["error"], min(beams))
    ladders = [[f"reduced nr = {n}" for n in sorted(o["reduced_nr"])],
               [f"full N = {n} ({5 * n} DOF)" for n in sorted(o["beam_N"])],
               [f"fe-reduced {k} modes" for k in sorted(o["cms_modes"])],
               [f"shell-reduced {k} modes" for k in sorted(o["shell_cms_modes"])],
               *[[f"{m} {s} steps/period" for s in sorted(o["steps_per_period"])] for m in o["step_models"]]]
    for ladder in ladders:
        for i, a in enumerate(ladder):
            for b in ladder[i + 1:]:
                if a in err and b in err:
                    out[f"error of {b} against {a}"] = ordering(err[a], err[b])
    return out


LABEL_OFFSETS = [(5, 5), (5, -11), (-14, 5), (-14, -11), (5, 15), (-14, 15), (5, -21), (-14, -21),
                 (16, -3), (-24, -3), (16, 12), (-24, 12), (16, -18), (-24, -18), (5, 25), (5, -31)]  # points


def place_labels(ax, xy: list[tuple[float, float]], texts: list[str], fontsize: float = 7) -> None:
    """Annotate each point with its text at the first offset (LABEL_OFFSETS) whose box overlaps no label
    placed before and no marker (the last offset when none is free); a thin leader line joins labels
    set further off. Call after the layout is final."""
    renderer = ax.figure.canvas.get_renderer()
    markers = [ax.transData.transform(p) for p in xy]
    taken = []

    def put(text, x, y, dx, dy):
        far = abs(dx) > 10 or abs(dy) > 12
        return ax.annotate(text, (x, y), xytext=(dx, dy), textcoords="offset points", fontsize=fontsize,
                           zorder=5, arrowprops={"arrowstyle": "-", "lw": 0.4, "color": "0.5"} if far else None)

    for (x, y), text in zip(xy, texts):
        for dx, dy in LABEL_OFFSETS:
            a = put(text, x, y, dx, dy)
            box = a.get_window_extent(renderer).padded(2)
            if not any(box.overlaps(b) for b in taken) and not any(box.contains(*m) for m in markers):
                break
            a.remove()
        else:
            box = put(text, x, y, dx, dy).get_window_extent(renderer)
        taken.append(box)


def _figure(rows, front, ref_point, out: Path) -> str:
    fig, axes = figure(1, 2, width=9.0, height=4.4)
    ax, key = axes[0]
    ax.get_gridspec().set_width_ratios([2.3, 1])
    for model in dict.fromkeys(r["model"] for r in rows):
        sel = [(i, r) for i, r in enumerate(rows) if r["model"] == model]
        ax.loglog([r["time_s"] for _, r in sel], [r["error"] for _, r in sel], "o", mfc="none", ms=6,
                  color=MODEL_COLOURS[model], label=model, zorder=2)
        on = [r for i, r in sel if front[i]]
        ax.loglog([r["time_s"] for r in on], [r["error"] for r in on], "o", ms=6, color=MODEL_COLOURS[model],
                  zorder=4)
    order = np.argsort([r["time_s"] for r in rows])
    fr = [rows[i] for i in order if front[i]]
    ax.step([r["time_s"] for r in fr], [r["error"] for r in fr], where="post", color="k", lw=1.0,
            label="Pareto front (filled points)", zorder=3)
    ax.set_xlabel("run time, warm: build + integration (s; cached parts built before the clock)")
    ax.set_ylabel("worst NRMSE against the reference")
    ax.set_title(f"reference: full solid FE, {ref_point.setting.replace(' (reference)', '')}", fontsize=8)
    ax.margins(0.15)
    ax.legend(loc="lower left", fontsize=7)
    key.axis("off")
    key.text(0.0, 1.0, "\n".join(f"{i + 1:>2}  {r['model']}: {r['setting']}" for i, r in enumerate(rows)),
             fontsize=7, va="top", family="monospace", transform=key.transAxes)
    fig.tight_layout()
    place_labels(ax, [(r["time_s"], r["error"]) for r in rows], [str(i + 1) for i in range(len(rows))])
    return save(fig, out / "error_vs_time.png").name


def _report(scene, ref_point, ref_dofs, ref_s, rows, fig_name, found) -> str:
    p = scene.params
    return "\n".join([
        f"# {scene.title}\n",
        f"Fig. 8 case at {p.speed.rpm:g} r/min, {p.time.periods} periods; reference: full solid FE, "
        f"{ref_point.setting}, {ref_dofs} DOF, {seconds(ref_s)} (one build, as it came: not a point). Error: "
        "worst NRMSE of N1, N2, Ff1, Ff2, v_L, w_L over the last periods. Time: build + integration on this "
        "machine, measured warm for every point: each model is built once before the clock starts, so a mesh "
        "or reduction basis cached on disk is built (or read) there, counted once in the column 'first "
        f"build' and never on the cost axis. Run times of identical runs differ by up to x{TIMING_NOISE:g} "
        "(comparisons._bands).\n",
        f"![error against run time]({fig_name})\n",
        markdown_table(("#", "model", "setting", "DOF", "time (warm)", "first build", "worst NRMSE", "NRMSE v_L",
                        "Pareto"),
                       [(i + 1, r["model"], r["setting"], r["dofs"], seconds(r["time_s"]),
                         seconds(r["first_build_s"]), r["error"], r["nrmse_v_L"], "yes" if r["pareto"] else "")
                        for i, r in enumerate(rows)]),
        "\nThe reference is not a point of its own front (its error is 0 by definition). Comparisons "
        f"(errors within a factor {CLEARLY:g} of each other not decided, run times within {CHEAPER:g}x "
        f"comparable and within the timing noise x{TIMING_NOISE:g} of that edge not decided):\n",
        *[f"- {k}: {v.sentence()}" for k, v in found.items()], "",
        _shell_sentence(rows),
        f"What these settings cannot resolve: errors below the reference's own time-step and mesh error "
        f"(it is one mesh, {ref_point.setting.replace(' (reference)', '')}), and with {p.time.periods} periods "
        f"the window of the last {scene.options['window_periods']} periods "
        + ("still holds the start-up transient, so errors measure the transient as much as the steady response."
           if p.time.periods < 2 * scene.options["window_periods"] else "lies after the start-up transient.") + "\n",
        "\nData: `error_vs_time.csv`.\n"])


def _shell_sentence(rows) -> str:
    """Where the shell's points sit: their error and warm time beside the reduced solid's, and on the front or not."""
    shells = [r for r in rows if r["model"] in ("shell", "shell-reduced")]
    if not shells:
        return ""
    solids = [r for r in rows if r["model"] == "fe-reduced"]
    best = min(solids, key=lambda r: r["error"]) if solids else None
    return ("Where the shell sits: " + "; ".join(
        f"{r['model']} {r['setting']} ({r['dofs']} DOF) error {r['error']:.3g} in {seconds(r['time_s'])}, "
        + ("on the front" if r["pareto"] else "off the front") for r in shells)
        + (f" (the reduced solid's best: {best['setting']}, error {best['error']:.3g} in {seconds(best['time_s'])})"
           if best else "")
        + ". The shell's error against the solid reference holds the two formulations' own difference (its "
        "frequencies sit 0.2-0.9 % below the solid's, docs/shell.md), which no shell setting removes.\n")


def _amplitude_figure(rows, hb_rows, ref_point, out: Path) -> str:
    fig, axes = figure(1, 1, width=7.0, height=4.4)
    ax = axes[0, 0]
    for model in dict.fromkeys([r["model"] for r in rows] + [h["model"] for h in hb_rows]):
        td = [r for r in rows if r["model"] == model]
        if td:
            ax.loglog([r["time_s"] for r in td], [r["amplitude_error"] for r in td], "o", mfc="none", ms=6,
                      color=MODEL_COLOURS[model], label=f"{model}, time domain")
        for h in (h for h in hb_rows if h["model"] == model):
            ax.loglog(h["time_s"], h["amplitude_error"], "D", ms=7, color=MODEL_COLOURS[model],
                      label=f"{model}, harmonic balance")
    ax.set_xlabel("run time, warm: build + solution (s; cached parts built before the clock)")
    ax.set_ylabel("error of the steady amplitudes of v_L, w_L")
    ax.set_title(f"steady amplitudes against the full solid FE, {ref_point.setting.replace(' (reference)', '')}",
                 fontsize=8)
    ax.margins(0.15)
    ax.legend(fontsize=7, loc="best", ncol=2)
    fig.tight_layout()
    return save(fig, out / "amplitude_error_vs_time.png").name


def _hb_report(scene, rows, hb_rows, ref_amp, fig_name) -> str:
    lines = ["\n## Steady response: time domain and harmonic balance\n",
             f"The reference's steady amplitudes over its last periods: v_L {ref_amp[0] * 1e6:.4g} um, "
             f"w_L {ref_amp[1] * 1e6:.4g} um. Harmonic balance finds the periodic steady state directly (no "
             f"start-up transient, with its Floquet stability); its cost is the model's system at the speed and "
             f"the Newton solve. Below, each model's harmonic-balance point beside its time-domain run at the "
             f"same fidelity ({scene.params.time.periods} periods from rest).\n",
             f"![amplitude error against run time]({fig_name})\n"]
    table = []
    for h in hb_rows:
        td = scene_point(rows, h["model"], scene)
        table.append((h["model"], seconds(h["time_s"]), h["amplitude_error"],
                      "yes" if h["stable"] else "no", f"{h['spectral_tail']:.2g}",
                      seconds(td["time_s"]) if td else "-", td["amplitude_error"] if td else "-",
                      f"{td['time_s'] / h['time_s']:.1f}x" if td else "-"))
    lines.append(markdown_table(("model", "HB time (warm)", "HB amplitude error", "stable", "force tail above H",
                                 "time-domain time (warm)", "time-domain amplitude error", "HB faster by"), table))
    spp = max(scene.options["steps_per_period"])
    lines.append("\nThe amplitude error of a time-domain run also holds what is left of its start-up "
                 "transient; the harmonic-balance point's holds the truncation at H harmonics (the contact "
                 "forces' spectral tail above H is listed). The reference is itself a time-domain run at "
                 f"{spp} steps per period, and a time-domain point at that step shares its time-discretization "
                 "error, which the harmonic balance (the periodic solution of the semi-discrete equations) "
                 "does not have: errors of the order of the reference's own step error do not say which "
                 "answer is nearer the exact one. A single speed is the time domain's best case: harmonic "
                 "balance pays off over a speed range (continuation reuses each point; "
                 "`benchmarks/bench_hb.py`).\n")
    return "\n".join(lines)
