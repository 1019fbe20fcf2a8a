"""Two models' resonances compared where the branch points alone leave it open (issue 33; hb_fig4, hb_fig7).

A branch's resonance (HBResult.resonance) is its largest amplitude on the
points not shown unstable, uncertain by the amplitude's change at twice the
harmonics plus how far the top may rise between the points around it. Both
can be made small by measuring: the top is located on the branch with twice
the harmonics (2 H) by golden-section search between the branch points
around it (Newton at each trial speed, from the branch's own harmonics), and
its error is then its change at 4 H there plus the rise of the parabola
through the last bracket above its best point. A branch still rising at
the range's end has its resonance beyond the range: what is inside is its
response there, read at 2 H with the same error plus Newton's accepted
residual (hb.ACCEPT), and the verdict says so. Kept apart from
comparisons._hb so that only the studies that ask it name it among their
sources.
"""

from __future__ import annotations

import math

import numpy as np

from comparisons._hb import SAME_RESONANCE, relative_error
from shroud.core.verdict import Verdict

GOLDEN_STEPS = 14          # the bracket (two branch steps) shrinks to 0.618^14 = 1.2e-3 of itself
GOLDEN = (math.sqrt(5.0) - 1.0) / 2.0
NEWTON_ITERATIONS, TOLERANCE = 50, 1e-10    # as shroud.core.harmonic_balance.newton (accepted at hb.ACCEPT)


def converged_peak(branch, params, model: str) -> dict:
    """The resonance of ``branch`` (an HBResult of ``model`` on ``params``) measured at 2 H: rpm (r/min) with
    its ``rpm_error`` (half the last bracket's span), amplitude_m with ``amplitude_error_m`` (its change at
    4 H plus the rise of the parabola through the last bracket; at a range's end Newton's accepted residual
    instead of the rise), ``stable`` (the branch's there), ``where``: "inside" (the top, located), "range
    end" (the branch still rising at its last or first point: the resonance lies beyond the range), or "not
    refined" (a stability change beside the top, or Newton failing on the search: the branch's own
    resonance, comparisons._hb.resonance_of, is kept), or "branch stopped" (the continuation stopped short
    of the range at its largest point, ``stopped`` why: its amplitude, error infinite), the harmonics used
    and the Newton solves it took.

    The search runs along the branch, not in speed, so a top at a fold is found as one elsewhere: each
    trial point is the 2 H state on the hyperplane normal to the chord between the branch points either
    side of the top, through a point of that chord (pseudo-arclength's bordered Newton, unknowns scaled
    by the top's largest coefficient and its speed)."""
    from comparisons._hb import resonance_of
    from shroud.analysis.hb import SpeedModel, model_at_speed, refined_point, residual_in_speed
    from shroud.analysis.transient import contact_law_for
    from shroud.core import harmonic_balance as hb
    kept = np.flatnonzero([s is not False for s in branch.stable])
    i = int(kept[np.argmax(branch.amplitude_v_L[kept])])
    last = len(branch.rpm) - 1
    speeds = SpeedModel(model_at_speed(params, model), branch.harmonics).refined()
    basis = hb.fourier(speeds.H, max(branch.samples, 4 * speeds.H + 1))
    law = contact_law_for(speeds.system(float(branch.rpm[i])), params.contact)
    residual = residual_in_speed(speeds, law, basis)
    nx = branch.X.shape[1] // (2 * branch.harmonics + 1)

    def padded(j: int) -> np.ndarray:
        """Branch point j as (2 H harmonics, rpm)."""
        X = np.zeros((basis.nh, nx))
        X[:2 * branch.harmonics + 1] = branch.X[j].reshape(-1, nx)
        return np.r_[X.ravel(), branch.rpm[j]]

    scale = np.r_[np.full(basis.nh * nx, np.abs(branch.X[i]).max()), branch.rpm[i]]
    solves = 0

    def solve(y0: np.ndarray, normal: np.ndarray):
        """(amplitude m, (2 H harmonics, rpm)) of the 2 H state on the hyperplane through ``y0`` normal to
        ``normal`` (scaled unknowns): Newton on [R; normal . (y - y0) / scale] = 0; (nan, None) where it fails."""
        nonlocal solves
        solves += 1
        y = y0.copy()
        for k in range(NEWTON_ITERATIONS + 1):
            R, J, d_rpm = residual(y[:-1], y[-1])
            lin = speeds.linear(y[-1])[0]
            relative = np.linalg.norm(R) / np.linalg.norm(lin.Fr)
            if relative <= TOLERANCE or (k == NEWTON_ITERATIONS and relative <= hb.ACCEPT):
                tip = lin.tip(y[:-1].reshape(basis.nh, nx), residual.last[2].contact.Lam)
                return float(hb.amplitude_over_period(tip)[0]), y
            A = np.block([[J, d_rpm()[:, None]], [normal[None, :] / scale]])
            y = y + np.linalg.solve(A, -np.r_[R, normal @ ((y - y0) / scale)])
            if not np.all(np.isfinite(y)):
                break
        return math.nan, None

    def entry(rpm, rpm_error, amplitude, error, where):
        return {"rpm": float(rpm), "rpm_error": float(rpm_error), "amplitude_m": float(amplitude),
                "amplitude_error_m": float(error), "stable": branch.stable[i], "where": where,
                "harmonics": speeds.H, "solves": solves}

    def error_at_4h(y: np.ndarray, amplitude: float) -> float:
        fine = refined_point(speeds, law, basis, y[:-1], float(y[-1]))
        return math.inf if fine is None else abs(fine[0] - amplitude)

    if i == last and not branch.complete:                # the continuation stopped at the top
        own = resonance_of(branch)
        return {"rpm": own["rpm"], "rpm_error": own["rpm_error"], "amplitude_m": own["amplitude_m"],
                "amplitude_error_m": math.inf, "stable": own["stable"], "where": "branch stopped",
                "harmonics": branch.harmonics, "solves": 0, "stopped": branch.stopped}
    if i in (0, last):                                   # still rising at the range's end: solved at its speed
        y0 = padded(i)
        amplitude, y = solve(y0, np.r_[np.zeros(basis.nh * nx), 1.0])
        if y is not None:
            return entry(y[-1], 0.0, amplitude, error_at_4h(y, amplitude) + hb.ACCEPT * amplitude, "range end")
    elif branch.stable[i - 1] is not False and branch.stable[i + 1] is not False:   # no stability change beside
        a, b = padded(i - 1), padded(i + 1)
        normal = (b - a) / scale
        normal /= np.linalg.norm(normal)
        lo, hi = 0.0, 1.0
        c, d = hi - GOLDEN * (hi - lo), lo + GOLDEN * (hi - lo)
        f = {t: solve(a + t * (b - a), normal) for t in (lo, c, d, hi)}
        for _ in range(GOLDEN_STEPS):
            if not all(math.isfinite(v[0]) for v in f.values()):
                break
            if f[c][0] >= f[d][0]:
                hi, d = d, c
                c = hi - GOLDEN * (hi - lo)
            else:
                lo, c = c, d
                d = lo + GOLDEN * (hi - lo)
            f = {t: f[t] if t in f else solve(a + t * (b - a), normal) for t in (lo, c, d, hi)}
        if all(math.isfinite(v[0]) for v in f.values()):
            three = (lo, c, d) if f[c][0] >= f[d][0] else (c, d, hi)
            amplitude, y = f[three[1]]
            rise = _parabola_top(np.array(three), np.array([f[t][0] for t in three])) - amplitude
            return entry(y[-1], abs(f[hi][1][-1] - f[lo][1][-1]) / 2, amplitude,
                         error_at_4h(y, amplitude) + max(rise, 0.0), "inside")
    own = resonance_of(branch)
    return {"rpm": own["rpm"], "rpm_error": own["rpm_error"], "amplitude_m": own["amplitude_m"],
            "amplitude_error_m": own["amplitude_error_m"], "stable": own["stable"], "where": "not refined",
            "harmonics": branch.harmonics, "solves": solves}


def _parabola_top(xs: np.ndarray, ys: np.ndarray) -> float:
    """The top of the parabola through three points (xs, ys) whose middle one is the highest (m)."""
    a, b, c = np.polyfit(xs - xs[1], ys, 2)
    return float(c - b * b / (4 * a)) if a < 0 else float(ys[1])


def same_peak(a: dict, b: dict, names: tuple[str, str]) -> Verdict:
    """Whether two :func:`converged_peak` amplitudes are the same (within comparisons._hb.SAME_RESONANCE,
    margin their relative errors summed); the reason says where each was read."""
    value = abs(a["amplitude_m"] / b["amplitude_m"] - 1) if b["amplitude_m"] > 0 else math.nan
    how = [f"{100 * SAME_RESONANCE:g} %: the match within which the studies put a time-domain point on a branch; "
           "each resonance located on its branch at twice its harmonics, margin its change at four times them "
           "plus the rise of the parabola through its last bracket"]
    ends = [n for n, p in zip(names, (a, b)) if p["where"] == "range end"]
    if ends:
        how.append(f"{' and '.join(ends)} still rising at {max(p['rpm'] for p in (a, b) if p['where'] == 'range end'):.0f}"
                   " r/min, the range's end: the resonance lies beyond the range, the largest response inside it "
                   "compared (margin with Newton's accepted residual)")
    for n, p in zip(names, (a, b)):
        if p["where"] == "branch stopped":
            how.append(f"{n}'s branch stopped at its largest point, {p['rpm']:.0f} r/min, short of the range "
                       f"({p['stopped']}): deciding it takes a continuation that passes there")
        if p["where"] == "not refined":
            how.append(f"{n}'s top lies beside a stability change: its branch points' own errors "
                       "(deciding it would take locating that bifurcation at twice the harmonics, multipliers at each trial)")
    return Verdict.of(value, SAME_RESONANCE, relative_error(a) + relative_error(b), below="same",
                      above="different", reason=f"{names[0]} against {names[1]}: " + "; ".join(how))
