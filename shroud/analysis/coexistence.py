"""Where two models' amplitude curves differ: model error, or coexisting steady states?

Near the resonance of a gap case the blade can have two steady states at
one speed (impact makes the response multivalued); runs from rest may land
on different ones in two models whose transients differ only slightly.
Where two curves differ by more than ``coexist_threshold`` of the larger
amplitude, both models are restarted from the same physical initial states
(the static deflection under the aerodynamic load scaled to tip deflections
of ``coexist_starts`` times the larger amplitude, shroud.analysis.sweep.coexisting_states)
and the sets of steady amplitudes they reach are compared. Only settled runs
count as steady states (shroud.analysis.sweep.Settling); where one model or
both reach none, the row says so instead of comparing. Used by the Fig. 4
(reduced against full beam) and Fig. 7 (beam against reduced solid) studies.
"""

from __future__ import annotations

import numpy as np

from shroud.base.markdown import markdown_table
from shroud.analysis.sweep import SETTLING_OPTIONS, Settling, coexisting_states
from shroud.core.verdict import NOT_DECIDED, Verdict

OPTIONS = {"coexist_threshold": 0.05, "coexist_starts": [-1.0, -0.5, 0.0, 0.5, 1.0], **SETTLING_OPTIONS}


def coexistence(cases, sweeps, rpms, opts, models: tuple[str, str]) -> list[dict]:
    """Speeds where the curves of ``models`` differ: the steady states each model reaches from the same starts.

    ``cases``: (label, parameters) per curve; ``sweeps[model][i]``: the
    SweepResult of case i.
    """
    first, second = models
    settling = Settling.from_options(opts)
    rows = []
    for i, (label, params) in enumerate(cases):
        a, b = sweeps[first][i].amplitude_v_L, sweeps[second][i].amplitude_v_L
        for k in np.flatnonzero(np.abs(a - b) > opts["coexist_threshold"] * np.maximum(a, b)):
            starts = [c * max(a[k], b[k]) for c in opts["coexist_starts"]]
            runs = {m: coexisting_states(params, m, float(rpms[k]), starts, settling=settling) for m in models}
            found = {m: r.amplitudes for m, r in runs.items()}
            none = [m for m in models if not found[m]]
            difference = matched_difference(found[first], found[second])
            matched = state_match(difference, settling.tolerance)
            shared = not none and matched.answer is True
            same = shared and len(found[first]) == len(found[second])
            rows.append({"case": label, "rpm": float(rpms[k]), "from_rest_m": {first: float(a[k]), second: float(b[k])},
                         "from_rest_settled": {first: sweeps[first][i].settled[k], second: sweeps[second][i].settled[k]},
                         "states_m": found, "unsettled_runs": {m: r.unsettled for m, r in runs.items()},
                         "no_steady_state": none, "shared_states": shared, "same_states": same,
                         "verdict": "no steady state" if none else "same" if same else "shared" if shared
                         else NOT_DECIDED if matched.answer == NOT_DECIDED else "different",
                         "largest_state_difference": difference, "states_match": matched})
    return rows


SAME = 0.01        # two steady amplitudes within 1 % are one state


def state_match(difference: float, tolerance: float) -> Verdict:
    """Whether every state of one model is one of the other's: their largest matched difference against SAME;
    each settled amplitude is known to the settling ``tolerance``, so two of them to twice it (the margin).
    A model with no steady state matches nothing (an infinite difference decides nothing)."""
    return Verdict.of(difference, SAME, 2 * tolerance, below=True, above=False,
                      reason="two settled amplitudes, each known to the settling tolerance")


def matched_difference(xs: list[float], ys: list[float]) -> float:
    """Largest relative distance from a state of the list with fewer states to the nearest state of the other.

    A model with no steady state matches nothing: the difference is infinite, never 0.

    >>> matched_difference([30.05e-6, 62.41e-6], [30.06e-6, 62.38e-6]) < SAME
    True
    >>> matched_difference([], [40e-6]), matched_difference([], [])
    (inf, inf)
    """
    if not xs or not ys:
        return float("inf")
    few, many = (xs, ys) if len(xs) <= len(ys) else (ys, xs)
    return max(min(abs(x - y) / abs(y) for y in many) for x in few)


def summary(rows: list[dict]) -> str:
    """One phrase for a report's comparison table ("" when the curves nowhere differ)."""
    if not rows:
        return ""
    same = [r for r in rows if r["same_states"]]
    shared = sum(r["shared_states"] and not r["same_states"] for r in rows)
    none = sum(bool(r["no_steady_state"]) for r in rows)
    text = (f"; at {len(same)} of {len(rows)} differing speeds both models have the same coexisting steady states"
            f" (largest difference {100 * max(r['largest_state_difference'] for r in same):.2f} %)" if same else
            f"; at none of {len(rows)} differing speeds do both models have the same steady states")
    return (text + (f", at {shared} more every state of one model is also one of the other's" if shared else "")
            + (f", at {none} one model or both reach no settled steady state from the common starts, so "
               "nothing is compared there" if none else ""))


def section(rows: list[dict], opts, models: tuple[str, str], names: tuple[str, str]) -> list[str]:
    """The report section: per differing speed, the states reached from rest and from the common starts."""
    if not rows:
        return [f"\nNo speed where the curves differ by more than {100 * opts['coexist_threshold']:g} %.\n"]
    def um(xs, unsettled):
        text = ", ".join(f"{1e6 * x:.2f}" for x in xs) or "none"
        return text + (f" ({unsettled} not settled)" if unsettled else "")

    def rest(r, m):
        return f"{1e6 * r['from_rest_m'][m]:.4g}" + ("" if r["from_rest_settled"][m] else " (not settled)")

    first, second = models
    return [f"\n## Speeds where the curves differ by more than {100 * opts['coexist_threshold']:g} %\n",
            "Both models restarted from the same physical initial states (static deflection under the "
            "aerodynamic load, tip deflection " + ", ".join(f"{c:g}" for c in opts["coexist_starts"]) +
            " times the larger amplitude); the distinct steady amplitudes each reaches:\n",
            markdown_table(["case", "speed (r/min)", f"from rest: {names[0]} (um)", f"from rest: {names[1]} (um)",
                            f"steady states {names[0]} (um)", f"steady states {names[1]} (um)", "states",
                            "largest difference to the nearest state of the other model"],
                           [(r["case"], r["rpm"], rest(r, first), rest(r, second),
                             um(r["states_m"][first], r["unsettled_runs"][first]),
                             um(r["states_m"][second], r["unsettled_runs"][second]), r["verdict"],
                             "-" if r["no_steady_state"] else f"{100 * r['largest_state_difference']:.2f} %")
                            for r in rows]),
            f"\nStates within {100 * SAME:g} % count as one. *Same*: both models have the same coexisting "
            "steady states, and the two runs from rest fall into different ones (their transients differ "
            "by the models' small differences, enough to cross a basin boundary): the difference of the "
            "curves is not a model error. *Shared*: every state of the model with fewer states is also a "
            "state of the other, which has one more from these starts (a branch whose basin the first "
            "model's starts missed, or that it lacks). *Different*: the models' steady states differ by "
            "the amount shown. *Not decided*: the largest difference lies within twice the settling "
            f"tolerance ({200 * Settling.from_options(opts).tolerance:.2g} %, two settled amplitudes) of "
            f"{100 * SAME:g} %. *No steady state*: from these starts one model or both never settled (runs "
            "listed as not settled), so nothing can be compared there.\n"]
