"""Reading time-domain points against harmonic-balance branches (shared by the hb_* studies)."""

from __future__ import annotations

import math

import numpy as np

from shroud.core.verdict import NOT_DECIDED, Verdict

SAME_RESONANCE = 0.01     # two models' resonant amplitudes this close (relative): the same resonance
SAME_REASON = ("1 %: the match within which the studies put a time-domain point on a branch; margin: each "
               "resonance's change at twice the harmonics plus its rise between branch points")


def crossings(branch, rpm: float, stable: bool | None) -> list[float]:
    """Amplitudes (m) where stretches of ``branch`` with the given stability (True, False, or None:
    undecided, HBResult.stable) cross ``rpm`` (interpolated)."""
    out = []
    for i in range(len(branch.rpm) - 1):
        r0, r1 = branch.rpm[i], branch.rpm[i + 1]
        if (r0 != r1 and min(r0, r1) <= rpm <= max(r0, r1) and branch.stable[i] is stable
                and branch.stable[i + 1] is stable):
            t = (rpm - r0) / (r1 - r0)
            out.append(float((1 - t) * branch.amplitude_v_L[i] + t * branch.amplitude_v_L[i + 1]))
    return sorted(out)


def states_at(branch, params, model: str, rpm: float, multipliers: bool = True) -> list[tuple[float, bool | None]]:
    """Every P1 state of ``branch`` at ``rpm``: (amplitude m, stable: True, False or None where undecided),
    solved there by harmonic balance.

    Each crossing of the branch with the speed is interpolated and then
    converged at exactly that speed (Newton from the interpolated
    coefficients), so a sparse stretch of the branch reads as exactly as a dense one.
    ``multipliers=False`` takes the stability of the two branch points around
    the crossing instead of computing the state's own (large models).
    """
    from shroud.analysis.hb import checkpoint
    out = []
    for X, stable in starts_at(branch, rpm):
        sol = checkpoint(params, model, rpm, harmonics=branch.harmonics, samples=branch.samples, start=X,
                         retry=False, multipliers=multipliers)
        if sol.converged:
            out.append((sol.amplitude_v_L, sol.stable if multipliers else stable))
    return out


def states_on(branches, params, model: str, rpm: float) -> list[tuple[float, bool | None]]:
    """Every P1 state at ``rpm`` of every branch of one case (:func:`states_at` of each)."""
    return [s for b in branches for s in states_at(b, params, model, rpm)]


def starts_at(branch, rpm: float) -> list[tuple[np.ndarray, bool]]:
    """Every crossing of ``branch`` with ``rpm``: its coefficients interpolated there, and whether the two
    branch points around it are both stable (True, not undecided)."""
    out = []
    for i in range(len(branch.rpm) - 1):
        r0, r1 = branch.rpm[i], branch.rpm[i + 1]
        if r0 != r1 and min(r0, r1) <= rpm <= max(r0, r1):
            t = (rpm - r0) / (r1 - r0)
            out.append(((1 - t) * branch.X[i] + t * branch.X[i + 1],
                        branch.stable[i] is True and branch.stable[i + 1] is True))
    return out


def landed_on(states: list[tuple[float, bool | None]], amplitude: float, period, match: float) -> str:
    """Name of the P1 state (from :func:`states_at`) a time-domain point landed on: a stable one, else one
    of undecided stability (its |multiplier| within its error of 1), else why none."""
    if not np.isfinite(amplitude):
        return "diverged"
    stable = sorted(a for a, s in states if s is True)
    names = (["lower stable", "upper stable"] if len(stable) == 2 else
             [f"stable {i + 1} of {len(stable)}" for i in range(len(stable))] if len(stable) > 2 else
             ["stable"])
    if stable:
        i = int(np.argmin([abs(a / amplitude - 1) for a in stable]))
        if abs(stable[i] / amplitude - 1) <= match:
            return names[i]
    if period == 1 and any(s is None and abs(a / amplitude - 1) <= match for a, s in states):
        return "undecided P1 state (|multiplier| within its error of 1)"
    if period is None:
        return "no steady state within the run (no period detected: still drifting, or quasi-periodic)"
    if period != 1:
        return f"P{period} (no P1 branch holds it)"
    if any(s is False for _, s in states) and not stable:
        return "beside an unstable P1 branch"
    return "off the P1 branches"


def named_points(sweep, states, match: float, **labels) -> list[dict]:
    """Every point of a time-domain ``sweep`` with the P1 state it landed on (:func:`landed_on`; ``states(rpm)``
    gives the states there, :func:`states_at`): ``labels`` (case, model, ...), rpm, amplitude_m, period, branch."""
    return [{**labels, "rpm": float(r), "amplitude_m": float(a), "period": per,
             "branch": landed_on(states(r), a, per, match)}
            for r, a, per in zip(sweep.rpm, sweep.amplitude_v_L, sweep.period)]


def on_stable(name: str) -> bool:
    """Whether a name from :func:`landed_on` is a stable P1 branch."""
    return name.endswith("stable") or name.startswith("stable")


def resonance_of(branch) -> dict:
    """A branch's resonance as conclusions hold it (HBResult.resonance: on the points not shown unstable):
    rpm (r/min) and amplitude_m with their errors (amplitude_error_m: truncation plus the rise between
    points, null at a branch's end; truncation_error_m: the amplitude's change at twice the harmonics there
    alone), its stability (True, or None: undecided), and the larger unstable peak beside it (rpm,
    amplitude_m) or None."""
    r = branch.resonance
    other = r["unstable_peak"]
    return {"rpm": r["rpm"], "rpm_error": r["rpm_error"], "amplitude_m": r["amplitude"],
            "amplitude_error_m": r["amplitude_error"], "truncation_error_m": r["truncation_error"],
            "stable": r["stable"],
            "unstable_peak": None if other is None else {"rpm": other["rpm"], "amplitude_m": other["amplitude"]}}


def relative_error(resonance: dict) -> float:
    """The relative error of a :func:`resonance_of` amplitude (inf where unknown)."""
    a, e = resonance["amplitude_m"], resonance["amplitude_error_m"]
    return e / a if a > 0 and math.isfinite(e) else math.inf


def same_resonance(a: dict, b: dict, names: tuple[str, str]) -> Verdict:
    """Whether two :func:`resonance_of` amplitudes are the same (within SAME_RESONANCE, margin their
    relative errors summed)."""
    value = abs(a["amplitude_m"] / b["amplitude_m"] - 1) if b["amplitude_m"] > 0 else math.nan
    return Verdict.of(value, SAME_RESONANCE, relative_error(a) + relative_error(b), below="same", above="different",
                      reason=f"{names[0]} against {names[1]}: {SAME_REASON}")


def rises(resonances: list[dict], what: str) -> Verdict:
    """Whether the resonant speed of successive :func:`resonance_of` entries rises: the smallest step from
    one to the next (r/min) against 0, margin that pair's speed errors summed."""
    steps = [(b["rpm"] - a["rpm"], a["rpm_error"] + b["rpm_error"]) for a, b in zip(resonances, resonances[1:])]
    value, margin = min(steps, default=(math.nan, 0.0))
    return Verdict.of(value, 0.0, margin, below=False, above=True, unit="r/min",
                      reason=f"{what}: the smallest rise of the resonant speed from one case to the next, against "
                             "0 within the two peaks' speed errors (half the branch steps around each)")


def bifurcations_in_time(branch, params, model: str) -> list[dict]:
    """Every bifurcation of ``branch`` checked in time: the branch points on both sides of each
    (shroud.analysis.hb.bifurcation_points) started in the project's integrator for 100 periods
    (shroud.analysis.hb.check_in_time). Per point: rpm, amplitude_m, the branch's ``stable`` there, the
    run's answer ("stays", "leaves" or not decided) with its two verdicts (shroud.core.period_map.InTime,
    JSON) and ``contradicts``: the
    branch calls it unstable and the integrator stays, or stable and the integrator leaves. A model the
    integrator cannot be started on (shroud.analysis.hb.startable) gives an empty list."""
    from shroud.analysis.hb import SpeedModel, bifurcation_points, check_in_time, model_at_speed, startable
    points = bifurcation_points(branch)
    if not points or not startable(*SpeedModel(model_at_speed(params, model), branch.harmonics).at(
            float(branch.rpm[points[0]]))[:2]):
        return []
    out = []
    for i, check in zip(points, check_in_time(params, model, branch, points)):
        answer, stable = check.answer, branch.stable[i]
        out.append({"rpm": float(branch.rpm[i]), "amplitude_m": float(branch.amplitude_v_L[i]), "stable": stable,
                    "in_time": check.to_json(),
                    "contradicts": (stable is False and answer == "stays") or (stable is True and answer == "leaves")})
    return out


def in_time_line(checked: list[tuple[str, list[dict]]]) -> str:
    """One sentence of :func:`bifurcations_in_time` over named branches: how many points the integrator
    confirmed and which it contradicts."""
    points = [(name, p) for name, ps in checked for p in ps]
    if not points:
        return "No bifurcation to check in time."
    bad = [f"{name} {p['rpm']:.0f} r/min ({'stable' if p['stable'] else 'unstable'}, {p['in_time']['answer']})"
           for name, p in points if p["contradicts"]]
    undecided = sum(p["in_time"]["answer"] == NOT_DECIDED for _, p in points)
    return (f"Bifurcations checked in time (the integrator started on the points either side, 100 periods): "
            f"{len(points)} points, {len(points) - len(bad) - undecided} confirmed, {undecided} not decided, "
            f"contradicted at {len(bad)}" + (": " + "; ".join(bad) if bad else "") + ".")


def notes_line(named: list[tuple[str, object]]) -> str:
    """One sentence of what named branches say about their own trust (HBResult.notes: incomplete, kinks
    stepped over, a tail target missed, points of undecided stability); empty when none says anything."""
    notes = [f"{name}: {'; '.join(br.notes())}" for name, br in named if br.notes()]
    return ("Branch notes: " + " | ".join(notes) + ".") if notes else ""


def verdict_text(v: dict, scale: float = 1.0, unit: str = "") -> str:
    """A verdict's JSON (shroud.core.verdict) in words: answer (value against threshold +- margin), the
    numbers times ``scale`` in ``unit``."""
    def num(x):
        return "-" if x is None or not math.isfinite(x) else f"{scale * x:.3g}"
    return f"{v['answer']} ({num(v['value'])} against {num(v['threshold'])} +- {num(v['margin'])}{unit})"
