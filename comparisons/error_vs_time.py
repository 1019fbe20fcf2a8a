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

Verdicts that decide (issue 33). Orderings ("error of <finer> against
<coarser>": smaller, larger or the same) and "beats" were ratios of errors
read with a dead band of zero width and a fixed margin x1.5, so two errors
within x1.5 of each other (every converged ladder: N = 8 against N = 6,
ratio 0.9998) could never be decided. Now:

* "The same" is a band of x1.5 (SAME_ERROR): fig8's "as close" (a model is
  closer to the reference than another when its worst NRMSE is below 1/1.5
  of the other's), so one word means one thing in both studies. "Beats" is
  the band of width 1. A verdict is decided where the interval in which the
  true errors' ratio lies is on one side of an edge (:func:`error_margin`);
  an undecided one names in its reason the measurement that would decide it.
* What a verdict asks sets what its errors are measured against. Runs that
  all share the reference's time step (the ladders of modes, shape
  functions, kept modes; every "beats") ask which model is nearer the solid,
  both integrated alike: the truth is the reference's model at that step, and
  their errors are computed exactly (margin 0, as fig3's reduction error,
  both runs on one time grid). A step ladder asks what the step does: its
  truth is the reference's model integrated exactly in time, from which the
  reference lies a distance e; by the triangle inequality each measured
  error lies within e of its true one (the worst NRMSE is a norm of the
  difference on the reference's ranges, :func:`distance`). e is measured in
  the study on the scene's step ladder of the reduced solid, the model with
  the reference's mesh, degree, contact and integrator (:class:`StepError`):
  the changes from each rung to the next finer, the finest at the
  reference's steps, shrink by q per halving, and what is still to come sums
  to at most the last change x max(1, q / (1 - q)). (Measured once beside the
  full scene: the reduced solid's change from 128 to 256 steps per period
  0.00407, the P2 solid's own 0.00409.) Two rungs of one model are also held
  by their own difference: the worst NRMSE d of one run against the other
  bounds the difference of their true errors exactly (|T_b - T_a| <= d), which
  narrows the interval where a step moves the signals far less than the
  error both carry.
* Costs of harmonic balance against the time domain are median CPU times
  (time.process_time: a loaded machine lengthens the wall time by the waits
  for a core, the CPU time much less) of ``cost_repeats`` samples each, a
  sample repeating a call of milliseconds until it has taken SAMPLE_CPU_S,
  the margin the two measured spreads multiplied (:func:`cost_verdict`):
  decided only where every sample of one against every sample of the other
  takes the same side of the band's edge. They stay timings (unit
  TIME_RATIO): shroud compare and the quick-against-full test skip them.

The study is compute (:func:`compute` -> :class:`ErrorVsTime`) -> plot -> report.
"""

from __future__ import annotations

import csv
import math
import time
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from shroud.analysis.agreement import FLAT_SHARE, QUANTITIES, SIGNALS, agreement, signals_of, window
from comparisons._study import study
from comparisons._bands import CHEAPER, TIMING_NOISE, versus
from shroud.analysis import api
from shroud.analysis.hb import checkpoint
from shroud.core import registry
from shroud.base.errors import InputError, RunDiverged
from shroud.base.log import info, warn
from shroud.core.plotting import MODEL_COLOURS, figure, save
from shroud.base.markdown import markdown_table, seconds
from shroud.analysis.transient import simulate
from shroud.core.signals import amplitude
from shroud.core.verdict import NOT_DECIDED, TIME_RATIO, RatioVerdict, timing
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
    "cost_repeats": 5,                    # CPU-time samples that give a cost verdict its medians and spreads
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
    if not isinstance(o["cost_repeats"], int) or o["cost_repeats"] < 2:
        raise InputError("options.cost_repeats", f"{o['cost_repeats']!r}; allowed: an integer >= 2")
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


SAMPLE_CPU_S = 0.2   # a timed sample runs the call until it has taken this much CPU time (timeit's autorange)


def repeated(run, repeats: int) -> tuple[object, list[float], list[float]]:
    """(the last result, wall times (s), CPU times (s)) per call, from ``repeats`` samples of ``run``.

    CPU time (time.process_time) is what a cost verdict reads: on a machine shared with other jobs the wall
    time also counts the time the process waited for a core, the CPU time much less. A call of a few
    milliseconds is one tick of the scheduler's noise, so each sample runs it ``loops`` times, as many as
    first take SAMPLE_CPU_S of CPU time (doubling from 1), and divides."""
    loops, walls, cpus, result = 1, [], [], None
    while len(cpus) < repeats:
        w0, c0 = time.perf_counter(), time.process_time()
        for _ in range(loops):
            result = run()
        wall, cpu = time.perf_counter() - w0, time.process_time() - c0
        if not cpus and cpu < SAMPLE_CPU_S:        # calibrating: the sample is too short to count
            loops *= 2
            continue
        walls.append(wall / loops)
        cpus.append(cpu / loops)
    return result, walls, cpus


def spread(times: list[float]) -> float:
    """How far the repeats lie from their median, as a factor >= 1: max(largest / median, median / smallest)."""
    median = float(np.median(times))
    return max(max(times) / median, median / min(times))


def hb_point(params, model: str, harmonics: int, repeats: int) -> dict:
    """The steady state of ``model`` at the scene's speed by harmonic balance with its stability, and its cost
    measured warm as every time-domain point's (a first, untimed solve builds what it caches), then in
    ``repeats`` samples (:func:`repeated`): the median wall time (the figure's axis), the median CPU time and
    its spread (the cost verdict); beside it the same of the model's time-domain run at the scene's fidelity
    (build + integration, as a point's cost)."""
    t0 = time.perf_counter()
    checkpoint(params, model, params.speed.rpm, harmonics=harmonics)
    first = time.perf_counter() - t0
    sol, walls, cpus = repeated(lambda: checkpoint(params, model, params.speed.rpm, harmonics=harmonics), repeats)
    _, _, td_cpus = repeated(lambda: simulate(api.build_system(params, model), params), repeats)
    return {"model": model, "setting": f"harmonic balance, H = {harmonics}", "time_s": float(np.median(walls)),
            "first_build_s": first, "cpu_s": float(np.median(cpus)), "cpu_spread": timing(spread(cpus)),
            "time_domain_cpu_s": float(np.median(td_cpus)), "time_domain_cpu_spread": timing(spread(td_cpus)),
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
    reference_error: StepError     # how far the reference lies from its own time-exact solution
    rows: list[dict]               # one per point: DOF, warm time, worst NRMSE, amplitude error, on the front
    front: np.ndarray              # on the error-against-time front, per row
    hb_rows: list[dict]            # one per harmonic-balance point
    conclusions: dict              # conclusions() | hb_conclusions()

    def to_json(self) -> dict:
        rows = self.rows
        return {"reference": {"setting": self.reference.setting, "dofs": self.reference_dofs,
                              "time_s": self.reference_s, "amplitudes": self.reference_amplitudes,
                              "error": self.reference_error.to_json()},
                # which points are on the front is decided by run times: declared so (shroud compare skips it)
                "points": [{k: v for k, v in r.items() if k != "pareto"} for r in rows],
                "pareto": timing([f"{r['model']} {r['setting']}" for r in rows if r["pareto"]]),
                "harmonic_balance": self.hb_rows, "conclusions": self.conclusions}


def on_window(t: np.ndarray, signals: dict, t_ref: np.ndarray, period: float, periods: int) -> np.ndarray:
    """The six compared signals (agreement.SIGNALS) of a run on the reference's last ``periods`` periods,
    interpolated on its time grid as shroud.analysis.agreement reads them: shape (6, samples)."""
    tw = t_ref[window(t_ref, period, periods)]
    return np.array([np.interp(tw, t, signals[name]) for name in SIGNALS])


def spans(reference: np.ndarray) -> np.ndarray:
    """The range each NRMSE divides by: the reference signal's own, at least FLAT_SHARE of the largest of its
    quantity (shroud.analysis.agreement's rule on the reference alone: the two are one where the runs' ranges
    do not lift the floor above a signal's range, as on the Fig. 8 case, whose faces all touch)."""
    ptp = dict(zip(SIGNALS, np.ptp(reference, axis=1)))
    floor = {name: FLAT_SHARE * max(ptp[n] for n in group) for group in QUANTITIES for name in group}
    return np.array([max(ptp[name], floor[name]) for name in SIGNALS])


def distance(x: np.ndarray, y: np.ndarray, ranges: np.ndarray) -> float:
    """The worst NRMSE of ``x`` against ``y`` on the ranges ``ranges``: max over signals of RMS(x - y) / range.

    A norm of the difference (a maximum of weighted RMS norms), so the triangle inequality holds exactly:
    |d(a, r) - d(b, r)| <= d(a, b) for any runs a, b and reference r on one grid.
    """
    return float(np.max(np.sqrt(np.mean((x - y) ** 2, axis=1)) / ranges))


@dataclass(frozen=True)
class StepError:
    """How far the reference lies from the time-exact solution of its own model, in the worst-NRMSE norm.

    Measured on the scene's step ladder of the model that shares the reference's mesh, degree, contact and
    integrator (the reduced solid): ``changes`` are the worst NRMSEs of each rung against the next finer one,
    the finest at the reference's own steps per period. If the changes shrink by ``q`` per halving from there
    on, the reference's distance from the step-free solution is at most the sum of the changes still to come,
    change q / (1 - q); ``error`` takes it, and at least the last change (order >= 1 at any q <= 1/2).
    None measured (fewer than three rungs, a rung that diverged, q >= 1): inf, and nothing is decided on it.

    It is the margin of a comparison whose runs are not all at the reference's own step
    (``reference_steps`` per period), the step ladders: their question is the step's, and its truth the
    time-exact solution. Runs that all share the reference's step are compared against the reference's model
    at that step, their error the model's (modes, shape functions, mesh), not the step's, and computed exactly:
    margin 0 (as fig3's reduction error, both runs on one time grid); :meth:`resolution`.
    """

    model: str
    reference_steps: int
    steps_per_period: tuple[int, ...]
    changes: tuple[float, ...]

    def resolution(self, *steps: int) -> tuple[float, str]:
        """(margin of each error, why) for a comparison of runs at ``steps`` steps per period."""
        if all(s == self.reference_steps for s in steps):
            return 0.0, (f"every run at the reference's {self.reference_steps} steps/period: the error asked is "
                         "the model's against the solid at that step, computed exactly (margin 0, as fig3's)")
        return self.error, self.reason

    @property
    def error(self) -> float:
        if len(self.changes) < 2 or not self.changes[-2] > 0:
            return math.inf
        q = self.changes[-1] / self.changes[-2]
        return self.changes[-1] * max(1.0, q / (1.0 - q)) if q < 1.0 else math.inf

    @property
    def reason(self) -> str:
        if not math.isfinite(self.error):
            return (f"the reference's own step error is not measured (the {self.model} step ladder "
                    f"{list(self.steps_per_period)} steps/period gives changes {[f'{c:.2g}' for c in self.changes]})")
        return (f"each error lies within the reference's own step error {self.error:.2g} of its true one "
                f"(triangle inequality; step error from the {self.model} runs at "
                f"{'/'.join(map(str, self.steps_per_period))} steps/period, changes "
                f"{' / '.join(f'{c:.2g}' for c in self.changes)})")

    def to_json(self) -> dict:
        return {"value": self.error, "model": self.model, "reference_steps_per_period": self.reference_steps,
                "steps_per_period": list(self.steps_per_period),
                "changes": list(self.changes)}


STEP_LADDER_MODEL = "fe-reduced"    # the step model whose ladder measures the reference's step error


def reference_error(signals: dict[str, np.ndarray], ranges: np.ndarray, o, reference_spp: int) -> StepError:
    """The reference's own step error from the reduced solid's runs at the scene's steps per period up to the
    reference's (``signals`` by point name, on the reference's window)."""
    ladder = [s for s in sorted(o["steps_per_period"]) if s <= reference_spp]
    runs = [signals.get(f"{STEP_LADDER_MODEL} {s} steps/period") for s in ladder]
    if (STEP_LADDER_MODEL not in o["step_models"] or not ladder or ladder[-1] != reference_spp
            or any(run is None for run in runs)):
        return StepError(STEP_LADDER_MODEL, reference_spp, tuple(ladder), ())
    return StepError(STEP_LADDER_MODEL, reference_spp, tuple(ladder),
                     tuple(distance(a, b, ranges) for a, b in zip(runs, runs[1:])))


def compute(scene) -> ErrorVsTime:
    """The reference run, then every point (warm) against it; the reference's own step error; the
    harmonic-balance points."""
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
    ref_window = on_window(t_ref, s_ref, t_ref, period, o["window_periods"])
    info(f"reference {ref_point.setting}: {ref_dofs} DOF, {ref_s:.1f} s")
    rows, runs, signals = [], [], {}
    for pt in points(o):
        if pt.model == ref_point.model and set(pt.overrides) <= set(ref_point.overrides):
            continue                                              # the reference itself: not a point
        run_of = (pt.model, params.with_overrides(list(pt.overrides)))
        twin = next((r for key, r in runs if key == run_of), None)
        if twin is not None:                                      # e.g. the scene's own step: one run, one point
            twin["setting"] += f" (= {pt.setting})"
            twin["names"].append(f"{pt.model} {pt.setting}")
            signals[f"{pt.model} {pt.setting}"] = signals[twin["names"][0]]
            continue
        try:
            result, dofs, cost, first = measure(params, pt)
        except RunDiverged as exc:
            warn(f"{pt.model} {pt.setting}: {exc}")
            continue
        run_signals = signals_of(result.trajectory)
        fit = agreement(result.trajectory.t, run_signals, t_ref, s_ref, period, o["window_periods"])
        signals[f"{pt.model} {pt.setting}"] = on_window(result.trajectory.t, run_signals, t_ref, period,
                                                         o["window_periods"])
        spp = params.with_overrides(list(pt.overrides)).time.steps_per_period
        rows.append({"model": pt.model, "setting": pt.setting, "dofs": dofs, "steps_per_period": spp,
                     "time_s": cost, "first_build_s": first,
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
    ranges = spans(ref_window)
    ref_error = reference_error(signals, ranges, o, ref_spp)
    info(f"reference's own step error: {ref_error.error:.3g} ({ref_error.reason})")
    hb_rows = []
    for model in o["hb_models"]:
        h = hb_point(params, model, o["hb_harmonics"], o["cost_repeats"])
        h["amplitude_error"] = amplitude_error(h["amplitudes"], ref_amp)
        hb_rows.append(h)
        info(f"{model} harmonic balance: {h['time_s']:.2f} s, amplitude error {h['amplitude_error']:.3g}")
    spread_of = lambda a, b: distance(signals[a], signals[b], ranges)             # noqa: E731
    return ErrorVsTime(reference=ref_point, reference_dofs=ref_dofs, reference_s=ref_s, reference_amplitudes=ref_amp,
                       reference_error=ref_error, rows=rows, front=front, hb_rows=hb_rows,
                       conclusions=conclusions(rows, scene, ref_error, spread_of) | hb_conclusions(hb_rows))


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
    return (_report(scene, result.reference, result.reference_dofs, result.reference_s, result.reference_error,
                    result.rows, fig_name, result.conclusions)
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


def hb_conclusions(hb_rows: list[dict]) -> dict:
    """Per model: how its harmonic-balance point's cost compares with its time-domain run's at the scene's
    fidelity (:func:`cost_verdict`). Their amplitude errors are reported, not ranked: the reference shares the
    time-domain runs' step error, which moves their difference by as much as it is (quick 128 against full 256
    steps per period turned the extended beam's from "smaller" into "about the same")."""
    return {f"cost of harmonic balance of {h['model']} against its time-domain run":
            cost_verdict(h["cpu_s"], h["cpu_spread"]["value"], h["time_domain_cpu_s"],
                         h["time_domain_cpu_spread"]["value"]) for h in hb_rows}


def cost_verdict(cpu_a: float, spread_a: float, cpu_b: float, spread_b: float) -> RatioVerdict:
    """How the median CPU time ``cpu_a`` of samples of identical calls compares with ``cpu_b``: "costlier", "cheaper" or
    "comparable" (band comparisons._bands.CHEAPER), the margin the product of the two spreads (:func:`spread`):
    decided only where every sample of one against every sample of the other takes the same side."""
    noise = spread_a * spread_b
    reason = (f"CPU times per call, medians of samples, spreads x{spread_a:.3g} and x{spread_b:.3g}: decided where "
              "every sample of one against every sample of the other takes the same side")
    verdict = versus(cpu_a, cpu_b, CHEAPER, noise, ("costlier", "cheaper", "comparable"), reason, TIME_RATIO)
    return _deciding(verdict, "samples on a quieter machine, whose CPU times spread less")


SAME_ERROR = 1.5  # errors within this factor of each other are "the same" (fig8's CLOSER: "as close")
UNRESOLVED = ("a reference of smaller step error: the P2 solid at twice its steps per period, with the reduced "
              "solid's step ladder extended to it")


def _deciding(verdict: RatioVerdict, what: str) -> RatioVerdict:
    """The verdict, its reason naming the measurement that would decide it where it is not decided (and, for
    an unbounded margin, why it is unbounded)."""
    if verdict.answer != NOT_DECIDED:
        return verdict
    unbounded = ("; unbounded: an error no larger than the reference's own, whose true value could vanish"
                 if not math.isfinite(verdict.noise) else "")
    return replace(verdict, reason=f"{verdict.reason}{unbounded}; to decide: {what}")


def error_margin(error_a: float, error_b: float, resolution: float, band: float, spread: float = math.inf) -> float:
    """The margin (a factor) of the ratio error_b / error_a against a band of x``band``: how far the true ratio
    may lie from the measured one towards the band's edges.

    Each measured error lies within ``resolution`` (the reference's own error, :class:`StepError`) of its
    true one, and the two true errors within ``spread`` (the worst NRMSE of one run against the other,
    :func:`distance`) of each other: the true ratio lies in [low, high] =
    [max((b - e) / (a + e), 1 - spread / (a - e)), min((b + e) / (a - e), 1 + spread / (a - e))]
    (no upper bound where a <= e: the true error a could vanish; a lower bound 0 or less: b could). The margin
    is the factor from the measured ratio to the end of that interval that faces an edge: to ``high`` where
    the whole interval lies below 1 / band, to ``low`` where it lies above band, else to the farther end.

    >>> round(error_margin(0.1, 0.05, 0.01, band=1.5), 4)     # [0.36, 0.67]: straddles 1/1.5, the farther end
    1.375
    >>> round(error_margin(0.1, 0.03, 0.01, band=1.5), 4)     # [0.18, 0.44]: below, its upper end faces the edge
    1.4815
    >>> round(error_margin(0.12, 0.1199, 0.01, band=1.5, spread=0.001), 4)   # the runs' own difference bounds it
    1.0099
    """
    a, b, e = error_a, error_b, resolution
    low = max((b - e) / (a + e), 1.0 - spread / (a - e) if a > e else -math.inf)
    high = min((b + e) / (a - e), 1.0 + spread / (a - e)) if a > e else math.inf
    ratio = b / a
    if high < 1.0 / band:
        return high / ratio
    if low > band:
        return ratio / low
    return max(high / ratio, ratio / low) if low > 0 else math.inf


def ordering(error_a: float, error_b: float, resolution: tuple[float, str], spread: float = math.inf) -> RatioVerdict:
    """How the second (finer) run's error compares with the first's: "smaller", "larger", or "the same" within
    a factor SAME_ERROR; not decided where the true errors' ratio (:func:`error_margin`: ``resolution`` the
    margin of each error and why, :meth:`StepError.resolution`; the runs' own difference ``spread``)
    straddles an edge of that band."""
    e, why = resolution
    noise = error_margin(error_a, error_b, e, SAME_ERROR, spread)
    reason = (f"within x{SAME_ERROR:g} the same (fig8's 'as close'); {why}"
              + (f"; the two runs differ by {spread:.2g} (worst NRMSE of one against the other), which bounds "
                 "their true errors' difference" if e > 0 and math.isfinite(spread) else ""))
    return _deciding(versus(error_b, error_a, SAME_ERROR, noise, ("larger", "smaller", "the same"), reason),
                     UNRESOLVED)


def beats(error: float, best: float, resolution: tuple[float, str]) -> RatioVerdict:
    """Whether ``error`` is below ``best`` (True/False), not decided where the true errors' ratio
    (:func:`error_margin`, ``resolution`` the margin of each error and why) straddles 1."""
    e, why = resolution
    return _deciding(versus(error, best, 1.0, error_margin(best, error, e, 1.0), (False, True, True), why),
                     UNRESOLVED)


def conclusions(rows: list[dict], scene, reference: StepError, spread_of) -> dict:
    """What the report concludes, as data (verdicts, shroud.core.verdict): whether the scene's reduced solid
    beats every beam and each solid every beam (:func:`beats`), and for every two fidelities of one model
    differing in one setting, how the finer one's error compares (:func:`ordering`; ``spread_of(a, b)`` the
    worst NRMSE of point a against point b, by name). The shell (docs/shell.md) is held to the same: whether
    the scene's reduced shell and each full shell beat every beam. Each is read with the margin
    ``reference.resolution`` gives its runs' steps per period."""
    p, o = scene.params, scene.options
    named = {name: r for r in rows for name in r["names"]}
    beams = [r for r in rows if r["model"] in ("reduced", "full")]
    best = min(beams, key=lambda r: r["error"]) if beams else None

    def beats_beams(r: dict) -> RatioVerdict:
        return beats(r["error"], best["error"], reference.resolution(r["steps_per_period"],
                                                                     *(b["steps_per_period"] for b in beams)))

    out = {}
    solid = named.get(f"fe-reduced {p.fe.cms_modes} modes")
    if best and solid is not None:
        out[f"reduced solid ({p.fe.cms_modes} modes) beats every beam"] = beats_beams(solid)
    shell = named.get(f"shell-reduced {p.shell.cms_modes} modes")
    if best and shell is not None:
        out[f"reduced shell ({p.shell.cms_modes} modes) beats every beam"] = beats_beams(shell)
    for r in rows:
        if r["model"] == "fe" and best:
            out[f"solid {r['setting']} beats the best beam"] = beats_beams(r)
        if r["model"] == "shell" and best:
            out[f"shell {r['setting']} beats the best beam"] = beats_beams(r)
    ladders = [[f"reduced nr = {n}" for n in sorted(o["reduced_nr"])],
               [f"full N = {n} ({5 * n} DOF)" for n in sorted(o["beam_N"])],
               [f"fe-reduced {k} modes" for k in sorted(o["cms_modes"])],
               [f"shell-reduced {k} modes" for k in sorted(o["shell_cms_modes"])],
               *[[f"{m} {s} steps/period" for s in sorted(o["steps_per_period"])] for m in o["step_models"]]]
    for ladder in ladders:
        for i, a in enumerate(ladder):
            for b in ladder[i + 1:]:
                if a in named and b in named:
                    ra, rb = named[a], named[b]
                    out[f"error of {b} against {a}"] = ordering(
                        ra["error"], rb["error"], reference.resolution(ra["steps_per_period"], rb["steps_per_period"]),
                        spread_of(a, b))
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


def _report(scene, ref_point, ref_dofs, ref_s, ref_error, rows, fig_name, found) -> str:
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
        "\nThe reference is not a point of its own front (its error is 0 by definition). Its own distance from "
        f"the time-exact solution of its model, measured: {ref_error.error:.3g} ({ref_error.reason}). Errors "
        f"within x{SAME_ERROR:g} of each other are the same (fig8's 'as close'); an ordering or a 'beats' is "
        "decided where the true errors' ratio lies on one side of its band's edge, each error within the "
        "reference's step error of its true one and, for two fidelities of one model, the two true errors within "
        "the runs' own difference (worst NRMSE of one against the other) of each other (error_margin). Costs of "
        f"harmonic balance against the time domain: median CPU times of {scene.options['cost_repeats']} samples "
        f"each (repeated), comparable within x{CHEAPER:g}, decided where every sample of one against every "
        "sample of the other takes the same side:\n",
        *[f"- {k}: {v.sentence()}" for k, v in found.items()], "",
        _shell_sentence(rows),
        "What these settings cannot resolve: a step's error below the reference's own (above); the "
        "reference's mesh error, which no run here measures (one mesh, "
        f"{ref_point.setting.replace(' (reference)', '')}: every error is against the solid on that mesh); "
        f"and with {p.time.periods} periods "
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
                      f"{seconds(h['cpu_s'])} (x{h['cpu_spread']['value']:.2f})",
                      f"{seconds(h['time_domain_cpu_s'])} (x{h['time_domain_cpu_spread']['value']:.2f})"))
    lines.append(markdown_table(("model", "HB time (warm)", "HB amplitude error", "stable", "force tail above H",
                                 "time-domain time (warm)", "time-domain amplitude error", "HB CPU (spread)",
                                 "time-domain CPU (spread)"), table))
    lines.append(f"\nCPU times per call: medians of {scene.options['cost_repeats']} samples each, a sample "
                 f"repeating a warm call until it has taken {SAMPLE_CPU_S:g} s of CPU (the time-domain run at the "
                 "scene's fidelity, build + integration), with how far the samples lie from their median; the "
                 "cost verdicts above read them.")
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
