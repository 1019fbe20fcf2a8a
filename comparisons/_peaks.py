"""Two models' resonances compared where the branch points alone leave it open (issue 33; hb_fig4, hb_fig7).

A branch's resonance (HBResult.resonance) is its largest amplitude on the
points not shown unstable, uncertain by the amplitude's change at twice the
harmonics plus how far the top may rise between the points around it. Both
are made small by measuring: the top is located by golden-section search in
speed between the branch points around it, each trial solved at twice the
branch's harmonics (2 H; at H where Newton at 2 H fails), and its error is
then its change at twice those harmonics there plus the rise of the
parabola through the last bracket above its best point. A branch still
rising at the range's end has its resonance beyond the range: what is
inside is its response there, read at 2 H with the same error plus
Newton's accepted residual (hb.ACCEPT), and the verdict says so. Kept apart
from comparisons._hb so that only the studies that ask it name it among
their sources.
"""

from __future__ import annotations

import math

import numpy as np

from comparisons._hb import SAME_RESONANCE, relative_error
from shroud.core.verdict import Verdict

GOLDEN_STEPS = 14          # the bracket (two branch steps) shrinks to 0.618^14 = 1.2e-3 of itself
GOLDEN = (math.sqrt(5.0) - 1.0) / 2.0


def converged_peak(branch, params, model: str) -> dict:
    """The resonance of ``branch`` (an HBResult of ``model`` on ``params``) measured at 2 H, or at H where
    Newton at 2 H fails on the search: rpm (r/min) with its ``rpm_error`` (half the last bracket),
    amplitude_m with ``amplitude_error_m`` (its change at twice the harmonics used, or at H where Newton at
    2 H fails at the top the change the branch measured at its top point, plus the rise of the parabola
    through the last bracket's three best points; at a range's end Newton's accepted residual
    instead of the rise), ``stable`` (the branch's there), ``where``: "inside" (the top, located), "range
    end" (the branch still rising at its last or first point: the resonance lies beyond the range), "not
    refined" (``why``: a fold or a stability change beside the top, or Newton failing (``why`` also says
    where the search fell back to H); the branch's own
    resonance, comparisons._hb.resonance_of, is kept) or "branch stopped" (the continuation stopped short
    of the range at its largest point, ``why`` its words: error infinite), the harmonics used and the
    Newton solves it took.

    The search runs in speed between the branch points either side of the top, each trial the state at
    that speed by Newton from the nearest trial's (else from the branch's harmonics interpolated there):
    with 2 H the branch moves by its truncation, so a trial is taken at a speed, not at a place on the
    H branch (a hyperplane normal to the branch's chord met the 1 um gap's 2 H branch 400 r/min away)."""
    from comparisons._hb import resonance_of
    from shroud.analysis.hb import SpeedModel, model_at_speed, refined_point
    from shroud.analysis.transient import contact_law_for
    from shroud.core import harmonic_balance as hb
    kept = np.flatnonzero([s is not False for s in branch.stable])
    i = int(kept[np.argmax(branch.amplitude_v_L[kept])])
    last, r = len(branch.rpm) - 1, branch.rpm
    coarse = SpeedModel(model_at_speed(params, model), branch.harmonics)
    law = contact_law_for(coarse.system(float(r[i])), params.contact)
    nx = branch.X.shape[1] // (2 * branch.harmonics + 1)
    solves = 0

    def search(speeds: SpeedModel, samples: int) -> dict | None:
        """The top at ``speeds``' harmonics (None where Newton fails on it)."""
        basis = hb.fourier(speeds.H, samples)
        solved: dict[float, tuple[float, np.ndarray]] = {}     # rpm -> (amplitude m, harmonics)

        def at(rpm: float, X: np.ndarray) -> float:
            """The state's amplitude at ``rpm`` (m; nan where Newton fails from every start), kept in ``solved``;
            ``X`` the branch's harmonics at H there."""
            nonlocal solves
            padded = np.zeros((basis.nh, nx))
            padded[:2 * branch.harmonics + 1] = X.reshape(-1, nx)
            near = min(solved, key=lambda q: abs(q - rpm), default=None)
            lin = speeds.linear(rpm)[0]
            for start in ([] if near is None else [solved[near][1]]) + [padded.ravel()]:
                solves += 1
                sol = hb.newton(start, lin, law, basis)
                if sol.converged:
                    tip = lin.tip(sol.X.reshape(basis.nh, nx), sol.balance.contact.Lam)
                    solved[rpm] = (float(hb.amplitude_over_period(tip)[0]), sol.X)
                    return solved[rpm][0]
            return math.nan

        def on_branch(rpm: float) -> float:
            j = i - 1 if (rpm - r[i]) * (r[i - 1] - r[i]) > 0 else i + 1
            t = (rpm - r[i]) / (r[j] - r[i])
            return at(rpm, (1 - t) * branch.X[i] + t * branch.X[j])

        def entry(rpm: float, rpm_error: float, rise: float, where: str) -> dict:
            amplitude, X = solved[rpm]
            fine = refined_point(speeds, law, basis, X, rpm)
            if fine is not None:
                change = abs(fine[0] - amplitude)
            else:                # the branch's own, at its top point (its 2 H state followed along the branch)
                change = branch.amplitude_error[i] if speeds.H == branch.harmonics else math.inf
            error = (change if math.isfinite(change) else math.inf) + rise
            return {"rpm": float(rpm), "rpm_error": float(rpm_error), "amplitude_m": amplitude,
                    "amplitude_error_m": float(error), "stable": branch.stable[i], "where": where,
                    "why": None if speeds.H > branch.harmonics else
                    ("Newton at twice the branch's harmonics failed on the search: its truncation stays the "
                     "branch's (deciding it takes the branch followed at twice the harmonics)"),
                    "harmonics": speeds.H, "solves": solves}

        if i in (0, last):                               # still rising at the range's end: read at that speed
            if math.isfinite(at(float(r[i]), branch.X[i])):
                return entry(float(r[i]), 0.0, hb.ACCEPT * solved[float(r[i])][0], "range end")
            return None
        lo, hi = sorted((float(r[i - 1]), float(r[i + 1])))
        c, d = hi - GOLDEN * (hi - lo), lo + GOLDEN * (hi - lo)
        for x in (c, d, lo, hi):
            on_branch(x)
        for _ in range(GOLDEN_STEPS):
            if not all(math.isfinite(solved.get(x, (math.nan,))[0]) for x in (lo, c, d, hi)):
                return None
            if solved[c][0] >= solved[d][0]:
                hi, d = d, c
                c = hi - GOLDEN * (hi - lo)
                on_branch(c)
            else:
                lo, c = c, d
                d = lo + GOLDEN * (hi - lo)
                on_branch(d)
        if not all(math.isfinite(solved.get(x, (math.nan,))[0]) for x in (lo, c, d, hi)):
            return None
        three = (lo, c, d) if solved[c][0] >= solved[d][0] else (c, d, hi)
        rise = _parabola_top(np.array(three), np.array([solved[x][0] for x in three])) - solved[three[1]][0]
        return entry(three[1], (hi - lo) / 2, max(rise, 0.0), "inside")

    why = None
    if i == last and not branch.complete:
        why = f"its continuation stopped there: {branch.stopped}"
    elif i not in (0, last) and (r[i - 1] - r[i]) * (r[i + 1] - r[i]) >= 0:
        why = "the top lies at a fold (deciding it would take locating the fold)"
    elif i not in (0, last) and (branch.stable[i - 1] is False or branch.stable[i + 1] is False):
        why = ("the top lies beside a stability change (deciding it would take locating that bifurcation, "
               "multipliers at each trial)")
    else:
        fine = coarse.refined()
        for speeds, samples in ((fine, max(branch.samples, 4 * fine.H + 1)), (coarse, branch.samples)):
            found = search(speeds, samples)
            if found is not None:
                return found
        why = "Newton failed at a trial speed at H and at 2 H"
    own = resonance_of(branch)
    stopped = i == last and not branch.complete
    return {"rpm": own["rpm"], "rpm_error": own["rpm_error"], "amplitude_m": own["amplitude_m"],
            "amplitude_error_m": math.inf if stopped else own["amplitude_error_m"], "stable": own["stable"],
            "where": "branch stopped" if stopped else "not refined", "why": why,
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
           f"each resonance solved at {a['harmonics']} and {b['harmonics']} harmonics and located on its branch, "
           "margin its change at twice them plus the rise of the parabola through its last bracket"]
    ends = [(n, p["rpm"]) for n, p in zip(names, (a, b)) if p["where"] == "range end"]
    if ends:
        how.append(f"{' and '.join(n for n, _ in ends)} still rising at {ends[0][1]:.0f} r/min, the range's end: "
                   "the resonance lies beyond the range, the largest response inside it compared (margin with "
                   "Newton's accepted residual)")
    for n, p in zip(names, (a, b)):
        if p["where"] in ("branch stopped", "not refined"):
            how.append(f"{n}'s resonance at {p['rpm']:.0f} r/min not measured again: {p['why']}; its branch "
                       "points' own errors")
        elif p["why"]:
            how.append(f"{n}: {p['why']}")
    return Verdict.of(value, SAME_RESONANCE, relative_error(a) + relative_error(b), below="same",
                      above="different", reason=f"{names[0]} against {names[1]}: " + "; ".join(how))
