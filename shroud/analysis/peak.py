"""The resonance peak followed in the initial normal preload N0 (peak tracking; paper Figs. 11b, 13c-d, 17c-d).

At a preload N0 the resonance of the speed branch (shroud.analysis.hb) is
where the tip amplitude a = (max - min)/2 of v_L over one period stops
growing with the speed. That point is followed in N0 by pseudo-arclength
continuation (shroud.core.continuation) of the extended system

    R(X, rpm; N0) = 0                                        (harmonic balance, paper Eq. 9)
    g(rpm; N0) = [a(rpm (1 + e)) - a(rpm (1 - e))] / (2 e) = 0   (the peak condition)

in the unknowns (X, rpm) with the parameter N0, so the resonant amplitude
and the resonant speed come out as curves over N0, and the optimal preload
(the smallest resonant amplitude, paper Fig. 11b) is read off one curve.

The peak condition is the slope of the chord of the speed branch over
+-e of the speed (a(rpm (1 +- e)) are the branch's own points there,
solved by Newton from X), not the branch's local slope da/drpm. The law is
sampled at a finite number of instants, so the branch a(rpm) is continuous
but its slope jumps wherever a contact switch crosses a sample: along the
20 N branch of the Fig. 11 contact (512 samples) the local log-slope
d ln a / d ln rpm from the branch tangent scatters by up to ~0.03 about
its trend, which near the top changes by ~0.1 per 120 r/min: a zero of
the local slope need not exist, the slope may jump across it. The chord slope is
continuous, and its zero is the top of the peak to second order in e
(exactly for a parabolic top); with e = 0.5 % the tracked amplitudes lie
within 0.06 % of the largest amplitudes of speed branches solved at the
same preloads (0-300 N, hb_optimal_preload).

Jacobian: dR/dX analytic (the core's, through the law), dR/drpm the
forward difference of the linear part (shroud.analysis.hb.residual_in_speed),
dR/dN0 a forward difference of the law (the system itself does not depend
on N0); the extra scalar row by forward differences in rpm and N0 (g does
not depend on X). Units: SI (m, N), speeds in r/min.
"""

from __future__ import annotations

import dataclasses
import time
from dataclasses import dataclass

import numpy as np

from shroud.analysis.hb import (DEFAULT_HARMONICS, SpeedModel, check_inputs, model_at_speed, point_details,
                                residual_in_speed, run_hb)
from shroud.analysis.transient import contact_law_for
from shroud.base.errors import InputError
from shroud.core import harmonic_balance as hb
from shroud.core.contact import N0 as N0_COLUMN
from shroud.core.contact import ContactLaw
from shroud.core.continuation import continue_branch
from shroud.params import Parameters

CHORD = 5e-3               # half-span e of the chord (share of the speed) in the peak condition
STEP = 1e-6                # relative step of the forward differences in rpm and N0


@dataclass(frozen=True)
class PeakCurve:
    """The resonance over preload: points in continuation order (N0 in N, rpm in r/min, amplitudes in m)."""

    model: str
    harmonics: int
    samples: int
    n0: np.ndarray
    rpm: np.ndarray
    amplitude_v_L: np.ndarray
    stable: np.ndarray          # object: True, False or None (within the multipliers' error) per point
    complete: bool
    stopped: str | None
    elapsed_s: float
    X: np.ndarray
    amplitude_error: np.ndarray | None = None   # per point: the amplitude's change at 2 H, m (nan: not taken)

    def __post_init__(self):      # one spelling of the three verdicts: True, False, None (undecided)
        object.__setattr__(self, "stable", np.array([None if v is None else bool(v) for v in self.stable], object))

    @property
    def optimum(self) -> dict:
        """The optimal preload: the smallest resonant amplitude over the curve's points not shown unstable,
        {"N0" (N), "rpm", "amplitude" (m), "stable" (True, or None: undecided), "bracket" (its neighbours' N0,
        N), "at_end" (the smallest is the curve's first or last point: the optimum is there or beyond),
        "unstable_minimum" (the smallest on unstable points where smaller, {"N0", "rpm", "amplitude"}; else
        None)}. Where every point is unstable, N0, rpm and amplitude are nan."""
        shown_unstable = np.array([v is False for v in self.stable], bool)
        kept, other = np.flatnonzero(~shown_unstable), np.flatnonzero(shown_unstable)
        lowest = None
        if other.size:
            j = int(other[np.argmin(self.amplitude_v_L[other])])
            lowest = {"N0": float(self.n0[j]), "rpm": float(self.rpm[j]), "amplitude": float(self.amplitude_v_L[j])}
        if not kept.size:
            nan = float("nan")
            return {"N0": nan, "rpm": nan, "amplitude": nan, "amplitude_error": nan, "stable": None,
                    "bracket": [nan, nan], "at_end": True,
                    "unstable_minimum": lowest}
        i = int(kept[np.argmin(self.amplitude_v_L[kept])])
        smaller = lowest is not None and lowest["amplitude"] < float(self.amplitude_v_L[i])
        error = float("inf") if self.amplitude_error is None else float(self.amplitude_error[i])
        return {"N0": float(self.n0[i]), "rpm": float(self.rpm[i]), "amplitude": float(self.amplitude_v_L[i]),
                "amplitude_error": error if np.isfinite(error) else float("inf"), "stable": self.stable[i],
                "bracket": [float(self.n0[max(i - 1, 0)]), float(self.n0[min(i + 1, len(self.n0) - 1)])],
                "at_end": bool(i in (0, len(self.n0) - 1)), "unstable_minimum": lowest if smaller else None}

    def index(self, n0: float) -> int | None:
        """Index of the curve's point at exactly ``n0`` (one of the ``at`` preloads of :func:`track_peak`),
        the last if the curve passes it more than once, or None."""
        hit = np.flatnonzero(np.isclose(self.n0, n0, rtol=0.0, atol=1e-9 * (1.0 + abs(n0))))
        return int(hit[-1]) if hit.size else None

    def at(self, n0: float) -> dict[str, float] | None:
        """The curve's point at exactly ``n0`` (:meth:`index`), or None."""
        i = self.index(n0)
        if i is None:
            return None
        return {"N0": float(self.n0[i]), "rpm": float(self.rpm[i]), "amplitude": float(self.amplitude_v_L[i]),
                "stable": self.stable[i]}

    def to_json(self) -> dict:
        return {"model": self.model, "method": "hb peak tracking", "harmonics": self.harmonics,
                "samples": self.samples, "N0": [float(x) for x in self.n0], "rpm": [float(r) for r in self.rpm],
                "amplitude_v_L": [float(a) for a in self.amplitude_v_L], "stable": list(self.stable),
                "optimum": self.optimum, "complete": self.complete, "stopped": self.stopped,
                "elapsed_s": round(self.elapsed_s, 6)}


def law_with_preload(law: ContactLaw, n0: float) -> ContactLaw:
    """``law`` with the side's initial normal preload set to ``n0`` (N; < 0 a gap), shared by the weights."""
    props = law.props.copy()
    props[:, N0_COLUMN] = law.weight * n0
    return dataclasses.replace(law, props=props)


class PeakSystem:
    """The extended system [R; g] in y = (X, c rpm) with the parameter N0 (c = x_scale / rpm at the start)."""

    def __init__(self, speeds: SpeedModel, law: ContactLaw, basis: hb.Fourier, x_scale: float, rpm_scale: float,
                 n0_scale: float, chord: float = CHORD):
        self.speeds, self.law, self.basis, self.chord = speeds, law, basis, chord
        self.c, self.x_scale, self.n0_scale = x_scale / rpm_scale, x_scale, n0_scale
        self._ends: dict[int, np.ndarray] = {}     # the last solution at each end of the chord: Newton's start

    def amplitude(self, X0: np.ndarray, rpm: float, law: ContactLaw, end: int) -> float:
        """a of the branch's point at ``rpm`` (Newton from the last solution at this ``end`` of the chord,
        else from ``X0``), m; nan if Newton fails from both."""
        lin = self.speeds.linear(rpm)[0]
        for start in (self._ends.get(end), X0):
            if start is not None:
                X, b, _, ok, _, _ = hb.newton(start, lin, law, self.basis)
                if ok:
                    self._ends[end] = X
                    return float(hb.amplitude_over_period(lin.tip(X.reshape(self.basis.nh, lin.nx),
                                                                  b.contact.Lam))[0])
        return float("nan")

    def slope(self, X: np.ndarray, rpm: float, law: ContactLaw) -> float:
        """g: the chord slope of a over +-chord of the speed, in units of x_scale (per unit relative speed)."""
        e = self.chord
        return ((self.amplitude(X, rpm * (1 + e), law, +1) - self.amplitude(X, rpm * (1 - e), law, -1))
                / (2 * e * self.x_scale))

    def __call__(self, y: np.ndarray, n0: float):
        """(G, dG/dy, () -> dG/dN0) at y = (X, c rpm) and the preload ``n0`` (shroud.core.continuation's form)."""
        X, rpm = y[:-1], y[-1] / self.c
        if not (np.all(np.isfinite(y)) and rpm > 0 and np.isfinite(n0)):     # a diverged corrector step
            return np.full(y.size, np.nan), np.eye(y.size), lambda: np.zeros(y.size)
        law = law_with_preload(self.law, n0)
        R, J, d_rpm = residual_in_speed(self.speeds, law, self.basis)(X, rpm)
        g = self.slope(X, rpm, law)
        h = STEP * rpm
        g_rpm = (self.slope(X, rpm + h, law) - g) / h
        n = J.shape[0]
        Jy = np.zeros((n + 1, n + 1))
        Jy[:n, :n], Jy[:n, n], Jy[n, n] = J, d_rpm() / self.c, g_rpm / self.c

        def d_n0():
            hn = STEP * self.n0_scale
            shifted = law_with_preload(self.law, n0 + hn)
            lin, L, F = self.speeds.linear(rpm)
            Rn = hb.balance(X, lin, shifted, self.basis, L, F.reshape(self.basis.nh, lin.nx), jacobian=False).R
            return np.r_[(Rn - R) / hn, (self.slope(X, rpm, shifted) - g) / hn]
        return np.r_[R, g], Jy, d_n0


def track_peak(params: Parameters, model: str, n0_from: float, n0_to: float, rpm_from: float, rpm_to: float,
               harmonics: int = DEFAULT_HARMONICS, samples: int | None = None, at: tuple[float, ...] = (),
               min_points: int = 40, chord: float = CHORD, refine: int = 20) -> PeakCurve:
    """The resonance of ``model`` followed in N0 from ``n0_from`` to ``n0_to`` (N).

    The first peak is the largest amplitude of the speed branch at
    ``n0_from`` over ``rpm_from``-``rpm_to`` r/min (it must lie inside that
    range); from there the peak is free to move in speed. The curve has a
    point at exactly each preload of ``at`` (within the range) and at least
    ``min_points`` points (bounds the step in N0). The stretch between the
    smallest resonant amplitude's two neighbours is followed again in
    ``refine`` steps (the minimum may be a sharp V: where the shroud begins
    to stick through the resonance). An incomplete curve (the corrector
    stopped converging) is returned so far, with where and why.
    """
    t0 = time.perf_counter()
    if not n0_from < n0_to:
        raise InputError("n0_to", f"{n0_from:g} .. {n0_to:g} N: allowed: n0_from < n0_to")
    n = check_inputs(harmonics, samples, rpm_from, rpm_to)
    first = run_hb(params.updated({"contact.N0": n0_from}), model, rpm_from, rpm_to, harmonics, n,
                   min_points=min_points)
    i = int(np.argmax(first.amplitude_v_L))
    if not 0 < i < len(first.rpm) - 1:
        raise InputError("rpm_to", f"the speed branch at N0 = {n0_from:g} N peaks at the end of "
                                   f"{rpm_from:g}-{rpm_to:g} r/min ({first.rpm[i]:.0f}); allowed: a range "
                                   "that holds the peak")
    basis = hb.fourier(harmonics, n)
    speeds = SpeedModel(model_at_speed(params, model), harmonics)
    system, _, _, _ = speeds.at(float(first.rpm[i]))
    law = contact_law_for(system, params.contact)
    x_scale = float(np.abs(first.X[i]).max())
    n0_scale = max(abs(n0_from), abs(n0_to))
    extended = PeakSystem(speeds, law, basis, x_scale, float(first.rpm[i]), n0_scale, chord)
    marks = {float(a) for a in at if n0_from < a < n0_to}

    def follow(y, p, end, dp_max) -> tuple[list, str | None]:
        """Points (y, N0, details) from (y, p) to ``end`` through every mark between; (points, why stopped)."""
        out: list[tuple[np.ndarray, float, dict]] = []

        def keep(y, n0):
            if out and n0 == out[-1][1]:       # a segment's start is the previous segment's end
                return
            X, rpm = y[:-1], y[-1] / extended.c
            out.append((y, n0, point_details(speeds, law_with_preload(law, n0), basis, X, rpm)))

        for stop in sorted({m for m in marks if p < m < end} | {float(end)}):
            branch = continue_branch(extended, y, p, stop, x_scale, ds=0.05, ds_max=0.3, dp_max=dp_max,
                                     p_scale=n0_scale, on_point=keep, forward=True)
            if not branch.complete or not branch.p or branch.p[-1] < stop:
                return out, branch.stopped or f"the corrector did not reach N0 = {stop:g} N"
            y, p = branch.x[-1], branch.p[-1]
        return out, None

    points, stopped = follow(np.r_[first.X[i], extended.c * first.rpm[i]], float(n0_from), n0_to,
                             (n0_to - n0_from) / (min_points - 1))
    k = int(np.argmin([pt[2]["amplitude_v_L"] for pt in points])) if points else 0
    if stopped is None and refine > 0 and 0 < k < len(points) - 1:     # the optimum, between its neighbours
        lo, hi = points[k - 1], points[k + 1]
        finer, why = follow(lo[0], lo[1], hi[1], (hi[1] - lo[1]) / refine)
        if why is None:
            points = points[:k - 1] + finer + points[k + 2:]
    ys = np.array([pt[0] for pt in points])
    return PeakCurve(model=model, harmonics=harmonics, samples=n, n0=np.array([pt[1] for pt in points]),
                     rpm=ys[:, -1] / extended.c, amplitude_v_L=np.array([pt[2]["amplitude_v_L"] for pt in points]),
                     stable=np.array([pt[2]["stable"] for pt in points], object), complete=stopped is None,
                     stopped=stopped, elapsed_s=time.perf_counter() - t0, X=ys[:, :-1],
                     amplitude_error=np.array([pt[2]["amplitude_error"] for pt in points]))
