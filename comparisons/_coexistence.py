"""Where two models' amplitude curves differ: model error, or coexisting steady states?

Near the resonance of a gap case the blade can have two steady states at
one speed (impact makes the response multivalued); runs from rest may land
on different ones in two models whose transients differ only slightly.
Where two curves differ by more than ``coexist_threshold`` of the larger
amplitude, both models are restarted from the same physical initial states
(the static deflection under the aerodynamic load scaled to tip deflections
of ``coexist_starts`` times the larger amplitude, shroud.analysis.sweep.coexisting_states)
and the sets of steady amplitudes they reach are compared. Used by the
Fig. 4 (reduced against full beam) and Fig. 7 (beam against reduced solid)
studies.
"""

from __future__ import annotations

import math

import numpy as np

from shroud.base.markdown import markdown_table
from shroud.analysis.sweep import coexisting_states

OPTIONS = {"coexist_threshold": 0.05, "coexist_starts": [-1.0, -0.5, 0.0, 0.5, 1.0]}


def coexistence(cases, sweeps, rpms, opts, models: tuple[str, str]) -> list[dict]:
    """Speeds where the curves of ``models`` differ: the steady states each model reaches from the same starts.

    ``cases``: (label, parameters) per curve; ``sweeps[model][i]``: the
    SweepResult of case i.
    """
    first, second = models
    rows = []
    for i, (label, params) in enumerate(cases):
        a, b = sweeps[first][i].amplitude_v_L, sweeps[second][i].amplitude_v_L
        for k in np.flatnonzero(np.abs(a - b) > opts["coexist_threshold"] * np.maximum(a, b)):
            starts = [c * max(a[k], b[k]) for c in opts["coexist_starts"]]
            found = {m: coexisting_states(params, m, float(rpms[k]), starts) for m in models}
            difference = matched_difference(found[first], found[second])
            shared = difference <= SAME
            rows.append({"case": label, "rpm": float(rpms[k]), "from_rest_m": {first: float(a[k]), second: float(b[k])},
                         "states_m": found, "shared_states": shared,
                         "same_states": shared and len(found[first]) == len(found[second]),
                         "largest_state_difference": difference})
    return rows


SAME = 0.01        # two steady amplitudes within 1 % are one state


def matched_difference(xs: list[float], ys: list[float]) -> float:
    """Largest relative distance from a state of the list with fewer states to the nearest state of the other.

    A model that reached no steady state (every run diverged or none
    settled) shares nothing with the other: the difference is infinite, so
    the states are never called the same or shared.

    >>> matched_difference([30e-6, 62e-6], [30.1e-6, 62e-6]) < SAME
    True
    >>> matched_difference([], [30e-6]), matched_difference([], [])
    (inf, inf)
    """
    if not xs or not ys:
        return math.inf
    few, many = (xs, ys) if len(xs) <= len(ys) else (ys, xs)
    return max(min(abs(x - y) / abs(y) for y in many) for x in few)


def summary(rows: list[dict]) -> str:
    """One phrase for a report's comparison table ("" when the curves nowhere differ)."""
    if not rows:
        return ""
    same = [r for r in rows if r["same_states"]]
    shared = sum(r["shared_states"] and not r["same_states"] for r in rows)
    unsettled = sum(not all(r["states_m"].values()) for r in rows)
    text = (f"; at {len(same)} of {len(rows)} differing speeds both models have the same coexisting steady states"
            f" (largest difference {100 * max(r['largest_state_difference'] for r in same):.2f} %)" if same else
            f"; at none of {len(rows)} differing speeds do both models have the same steady states")
    return (text + (f", at {shared} more every state of one model is also one of the other's" if shared else "")
            + (f", at {unsettled} a model reached no steady state from the common starts" if unsettled else ""))


def _difference_text(row: dict, models: tuple[str, str], names: tuple[str, str]) -> str:
    unsettled = [n for m, n in zip(models, names) if not row["states_m"][m]]
    if unsettled:
        return "no steady state reached by " + " and ".join(unsettled)
    return f"{100 * row['largest_state_difference']:.2f} %"


def section(rows: list[dict], opts, models: tuple[str, str], names: tuple[str, str]) -> list[str]:
    """The report section: per differing speed, the states reached from rest and from the common starts."""
    if not rows:
        return [f"\nNo speed where the curves differ by more than {100 * opts['coexist_threshold']:g} %.\n"]
    um = lambda xs: ", ".join(f"{1e6 * x:.2f}" for x in xs)  # noqa: E731
    first, second = models
    return [f"\n## Speeds where the curves differ by more than {100 * opts['coexist_threshold']:g} %\n",
            "Both models restarted from the same physical initial states (static deflection under the "
            "aerodynamic load, tip deflection " + ", ".join(f"{c:g}" for c in opts["coexist_starts"]) +
            " times the larger amplitude); the distinct steady amplitudes each reaches:\n",
            markdown_table(["case", "speed (r/min)", f"from rest: {names[0]} (um)", f"from rest: {names[1]} (um)",
                            f"steady states {names[0]} (um)", f"steady states {names[1]} (um)", "states",
                            "largest difference to the nearest state of the other model"],
                           [(r["case"], r["rpm"], 1e6 * r["from_rest_m"][first], 1e6 * r["from_rest_m"][second],
                             um(r["states_m"][first]), um(r["states_m"][second]),
                             "same" if r["same_states"] else "shared" if r["shared_states"] else "different",
                             _difference_text(r, models, names)) for r in rows]),
            f"\nStates within {100 * SAME:g} % count as one. *Same*: both models have the same coexisting "
            "steady states, and the two runs from rest fall into different ones (their transients differ "
            "by the models' small differences, enough to cross a basin boundary): the difference of the "
            "curves is not a model error. *Shared*: every state of the model with fewer states is also a "
            "state of the other, which has one more from these starts (a branch whose basin the first "
            "model's starts missed, or that it lacks). *Different*: the models' steady states differ by "
            "the amount shown, or one of them reached no steady state from these starts.\n"]
