"""The tuned ring against fixed neighbours for the Fig. 11 contact: sector HB, its stability, the ring in time.

The paper holds both neighbours of its blade fixed (Sect. 2; Fig. 11:
alpha 30 deg, kt 5e6 N/m, mu 0.3, initial gaps and preloads). On a tuned
ring of N blades under engine order ke the forced response may be a
travelling wave, U_{j+1,h} = exp(i h phi) U_{j,h}, phi = 2 pi ke / N
(docs/ring.md), which one sector carries by harmonic balance
(shroud.analysis.ring_hb). Per case (``gaps_um``, then ``preloads_N``) and ring size
(``blades``) the study draws

* the fixed-neighbour blade's HB branch with its stability
  (shroud.analysis.hb.run_hb, what shroud.api.continuation runs, with the
  branch's samples) and the sector's HB branch over the same speeds
  (shroud.analysis.ring_hb.run_ring_hb) with its stability against every
  nodal diameter (the ring's monodromy by the wave's symmetry, its error
  the largest of floquet's floor, the change at half the samples and at
  2 H), both at ``branch_harmonics``. The ring's stability is taken at
  ``branch_stability_points`` points (per ring size) spread over a longer branch, at both ends of
  every stretch crossing a time point's speed (there the branch is held to the wave's own verdict) and
  between neighbours whose verdicts differ until they are adjacent
  (ring_hb.located_changes): every point not evaluated lies between two
  evaluated ones with one verdict, which it is drawn with. A branch the
  continuation cannot carry across the range is drawn as far as it goes
  and its stop reported;
* at each of ``td_rpms`` the whole ring in time from rest
  (shroud.api.transient; E scattered by ``symmetry_break``, 1e-4, so that a
  wave unstable in another nodal diameter can be left: a perfectly
  symmetric start excites only the wave's own, docs/ring.md), each blade's
  settled amplitude;
* there, the sector's wave solved at that speed and, for the ring sizes in
  ``stability_blades``, its stability against every nodal diameter
  (ring_hb.stability_verdict: the whole ring's monodromy at 2 H against 1,
  its margin the change from H, at least floquet's floor 0.02; the
  monodromy from g / N of the period by the wave's symmetry makes 48
  blades a few seconds a point); where it is not decided, the same verdict
  THRESHOLD_STEP either side: decided and different there, the wave sits
  at its stability threshold. Such a wave is judged apart
  (``stability_threshold_bracketed``: every undecided settled wave
  bracketed?) and left out of ``hb_stable_where_on_wave``, whose reason
  names it; an undecided wave not bracketed stays in both.

Each time point is named: on the travelling wave (blade 0 P1, settled, the
blades' spread within ``wave_spread``), where the sector's HB must agree
within ``agree`` (0.5 %) and be stable; or off it, where the report says
what explains it: the wave is unstable, or a coexisting branch of the
sector (more than one wave at that speed), or what is missing (no wave
reached, stability not computed); the dominant nodal diameter of the
blades' spread says what the ring lands on.
docs/ring-tuned.md has the measurements.

The study is compute (:func:`compute` -> :class:`RingTunedComparison`) -> plot -> report.
"""

from __future__ import annotations

import csv
import math
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from comparisons._hb import crossings
from comparisons._study import study
from shroud.api import transient
from shroud.analysis.hb import run_hb
from shroud.analysis.ring_hb import run_ring_hb, sector_at, stability_verdict
from shroud.base.errors import InputError, RunDiverged
from shroud.base.markdown import markdown_table
from shroud.base.outputs import open_replacing
from shroud.core import floquet, signals
from shroud.core.plotting import figure, plain_log, save
from shroud.core.verdict import NOT_DECIDED, Verdict

OPTIONS = {
    "gaps_um": [1.0, 100.0],           # Fig. 11b's small gap and Fig. 11a's 0.1 mm
    "preloads_N": [],                  # Fig. 11b's preloads (N0 per interface, touching), cases after the gaps
    "blades": [12, 24, 48],
    "rpm_from": 6000.0, "rpm_to": 14000.0,
    "td_rpms": [8000.0, 10000.0, 12000.0],
    "harmonics": 20,                   # the waves' at the time points (the impacts need H = 20: docs/ring.md)
    "branch_harmonics": 10,            # the branches' (at H = 20 the 1 um gap's first point fails)
    "stability_harmonics": 20,         # the stability verdict at 2 x this against this
    "stability_blades": [12, 24, 48],  # ring sizes whose waves get the stability verdict
    "branch_stability_points": [0, 40, 12],   # per ring size of blades: the sector branch's stability at
                                              # this many spread points, then where it changes (0: every point)
    "symmetry_break": 1e-4,            # std of E's scatter in the time runs
    "wave_spread": 0.005,              # (max - min) / mean of the blades' amplitudes on a travelling wave
    "agree": 0.005,                    # the issue's: the sector's HB within 0.5 % of the ring in time
    "model": "reduced",
}
SETTLED = 1e-3       # relative change of every blade's amplitude between the last two windows of STEADY_PERIODS
STEP_SPREAD = 1e-3   # the blades' spread the time step alone makes on a wave (0.075 % measured, 24 blades, docs/ring.md)
# r/min either side of a wave whose stability is not decided, where its stability is computed again: decided
# and different on the two sides, the wave sits at its stability threshold (1 um, 12 blades, 12000 r/min:
# stable at 11800, unstable at 12200; docs/ring-tuned.md "At the threshold")
THRESHOLD_STEP = 200.0
THRESHOLD_VERDICT = "stability_threshold_bracketed"    # the conclusion on the settled waves at a threshold


def check(scene) -> None:
    o = scene.options
    if any(n < 2 for n in o["blades"]) or not o["blades"]:
        raise InputError("options.blades", f"{o['blades']!r}; allowed: ring sizes >= 2")
    if not 0 < o["rpm_from"] < o["rpm_to"] or not o["td_rpms"] or min(o["td_rpms"]) <= 0:
        raise InputError("options.rpm_from", "allowed: 0 < rpm_from < rpm_to and time-domain speeds > 0 r/min")
    if any(g < 0 for g in o["gaps_um"]) or not (o["gaps_um"] or o["preloads_N"]):
        raise InputError("options.gaps_um", f"{o['gaps_um']!r}; allowed: gaps >= 0 um (or preloads, at least one "
                                            "case)")
    if len(o["branch_stability_points"]) != len(o["blades"]) or min(o["branch_stability_points"]) < 0:
        raise InputError("options.branch_stability_points", f"{o['branch_stability_points']!r}; allowed: one "
                                                            "count >= 0 per ring size of options.blades")
    if any(n <= 0 for n in o["preloads_N"]):
        raise InputError("options.preloads_N", f"{o['preloads_N']!r}; allowed: preloads > 0 N")


@dataclass(frozen=True)
class RingPoint:
    """The ring in time at one speed and the sector's wave there."""

    blades: int
    rpm: float
    amplitudes: list[float]            # every blade's settled v_L amplitude, m
    period: int | None                 # blade 0's detected period (None: none up to 10)
    drift: float                       # largest relative change of a blade's amplitude between the last windows
    wave: float | None                 # the sector's wave solved at rpm (from the linear start), m; None: not reached
    coexisting: list[float]            # the sector branch's waves at rpm (interpolated), m
    stability: Verdict | None          # of the wave at rpm; None: not computed (ring size not in stability_blades,
                                       # or no wave at H or 2 H)
    wave_spread: float                 # the blades' spread below which the ring is on a travelling wave
    stability_tried: bool              # the ring size is one of stability_blades
    branch_stable: object = None       # the sector branch's verdict at rpm on the stretch nearest the wave
                                       # (True, False, 'not decided'; None: no branch or no stretch there)
    beside: dict = field(default_factory=dict)   # rpm -> the wave's stability (Verdict; None: not reached) at
                                                 # rpm -+ THRESHOLD_STEP, where its own is not decided

    def threshold_bracket(self) -> Verdict | None:
        """Whether the wave, its stability not decided at rpm, sits at a stability threshold bracketed
        THRESHOLD_STEP either side: each side's largest |multiplier| as x = (|mu| - 1) / its margin (beyond +-1:
        decided), read as the smaller |x| of the two, signed + where the sides lie on opposite sides of 1
        (stable on one, unstable on the other: the threshold between them) and - where on the same; against
        0, margin 1 (a side within its own margin decides nothing; NaN where a side's wave is not reached or
        the sides were not computed). None where the wave's stability is decided or not computed (nothing to
        bracket)."""
        if self.stability is None or self.stability.answer != NOT_DECIDED:
            return None
        sides = [v for _, v in sorted(self.beside.items())]
        x = [math.nan if v is None else (v.value - v.threshold) / v.margin for v in sides]
        b = (math.copysign(min(map(abs, x)), -x[0] * x[1]) if len(x) == 2 and not any(map(math.isnan, x))
             else math.nan)
        return Verdict.of(b, threshold=0.0, margin=1.0, below=False, above=True, unit="margins",
                          reason=f"its stability {THRESHOLD_STEP:g} r/min either side "
                                 f"({self.side_words()}) as (|mu| - 1) / margin, the smaller of the two signed + "
                                 "where stable on one side and unstable on the other, - where alike; against 0, "
                                 "margin 1: a side within its own margin decides nothing")

    def at_threshold(self) -> bool:
        """Whether the wave's stability, not decided at rpm, is decided on both sides THRESHOLD_STEP away and
        differs (threshold_bracket yes): the wave sits at its stability threshold (the physics', not the
        method's)."""
        b = self.threshold_bracket()
        return b is not None and b.answer is True

    def side_words(self) -> str:
        """The wave's stability THRESHOLD_STEP either side in words ('stable (0.915 +- 0.02) at 11800 r/min,
        ...'; 'not computed' where it was not)."""
        return ", ".join(f"{'not reached' if v is None else _stable_word(v)} at {r:g} r/min"
                         for r, v in sorted(self.beside.items())) or "not computed"

    @property
    def spread(self) -> float:
        a = np.asarray(self.amplitudes)
        return float(np.ptp(a) / a.mean())

    def on_wave(self) -> Verdict | bool:
        """Whether the ring settled on a travelling wave: False where blade 0 is not P1 or its amplitudes still
        drift; else the blades' spread against ``wave_spread`` (margin the step's own spread on a wave)."""
        if self.period != 1 or self.drift >= SETTLED:
            return False
        return Verdict.of(self.spread, threshold=self.wave_spread, margin=STEP_SPREAD, below=True, above=False,
                          reason="the blades' amplitude spread (max - min) / mean against the wave's 0 (threshold "
                                 f"{self.wave_spread:g}; margin the Newmark step's own spread on a wave, "
                                 f"{STEP_SPREAD:g})")

    @property
    def on(self):
        """on_wave's answer: True, False or 'not decided'."""
        v = self.on_wave()
        return v if isinstance(v, bool) else v.answer

    @property
    def pattern_nd(self) -> int | None:
        """The nodal diameter whose Fourier component around the ring dominates the blades' amplitude spread
        (None on a wave, where no pattern is meant): what the ring lands on when it leaves the wave."""
        a = np.asarray(self.amplitudes)
        if self.on is True:
            return None
        return int(np.argmax(np.abs(np.fft.rfft(a - a.mean()))[1:]) + 1)

    def difference(self) -> float | None:
        """The largest |blade / wave - 1| against the nearest wave the HB has at rpm."""
        waves = [w for w in [self.wave, *self.coexisting] if w is not None]
        if not waves:
            return None
        a = np.asarray(self.amplitudes)
        return min(float(np.abs(a / w - 1).max()) for w in waves)

    def agreement(self, agree: float) -> Verdict | None:
        d = self.difference()
        if d is None:
            return None
        return Verdict.of(d, threshold=agree, margin=STEP_SPREAD, below=True, above=False,
                          reason=f"largest |blade / wave - 1| against {agree:g}, margin the Newmark step's own "
                                 f"effect on the amplitudes ({STEP_SPREAD:g})")

    def explanation(self) -> str:
        """What the HB says of a ring that left the wave (or of one on it: 'stable wave' when it should)."""
        s = None if self.stability is None else self.stability.answer
        if s is None:
            s = "not reached" if self.stability_tried else "not computed"
        if self.on is True:
            return {True: "stable wave", False: "on an unstable wave", "not reached": "stability not reached at 2 H",
                    "not computed": "stability not computed"}.get(
                s, "at the stability threshold" if self.at_threshold() else "stability not decided")
        if s is False:
            return "wave unstable"
        if len(self.coexisting) > 1:
            return "coexisting branch"
        if self.wave is None:
            return "no wave reached"
        return {"not computed": "stability not computed", "not reached": "stability not reached at 2 H",
                NOT_DECIDED: "stability not decided"}.get(s, "unexplained")

    def key(self) -> str:
        return f"{self.blades} blades, {self.rpm:g} r/min"

    def to_json(self, agree: float) -> dict:
        v = self.agreement(agree)
        return {"blades": self.blades, "rpm": self.rpm, "amplitudes_m": self.amplitudes, "period": self.period,
                "drift": self.drift, "spread": self.spread, "spread_nodal_diameter": self.pattern_nd,
                "on_wave": self.on if isinstance(self.on_wave(), bool) else self.on_wave().to_json(),
                "wave_m": self.wave, "coexisting_waves_m": self.coexisting,
                "stable": None if self.stability is None else self.stability.to_json(),
                "stable_beside": {f"{r:g}": _json(v) for r, v in sorted(self.beside.items())},
                "branch_stable": self.branch_stable,
                "agreement": None if v is None else v.to_json(), "explanation": self.explanation()}


@dataclass(frozen=True)
class RingCase:
    """One Fig. 11 case: the fixed-neighbour branch, the sector branches, the ring's time points."""

    label: str
    gap_um: float                       # 0 for a preloaded case
    fixed: object                       # HBResult of the blade between fixed neighbours
    sectors: dict[int, object | None]   # N -> the sector's HBResult (None: no wave reached at rpm_from)
    failures: dict[int, str]            # N -> why the sector's branch was not continued
    points: list[RingPoint] = field(default_factory=list)
    preload_N: float = 0.0              # N0 per interface of a preloaded case (0 for a gap)
    costs: dict[int, dict] = field(default_factory=dict)   # N -> the sector branch's cpu_s, wall_s, points,
                                                           # evaluated (points with the ring's stability)


@dataclass(frozen=True)
class RingTunedComparison:
    cases: list[RingCase]
    agree: float

    def points(self):
        return [(c, p) for c in self.cases for p in c.points]

    def agreement(self, points) -> Verdict | None:
        """The sector's HB against the ring in time over ``points`` on a travelling wave: the largest
        |blade / wave - 1| against ``agree``, margin the Newmark step's own effect; None without such a point."""
        diffs = [(p.difference(), p) for p in points if p.on is True and p.difference() is not None]
        if not diffs:
            return None
        worst, at = max(diffs, key=lambda d: d[0])
        return Verdict.of(worst, threshold=self.agree, margin=STEP_SPREAD, below=True, above=False,
                          reason=f"largest |blade / wave - 1| over {len(diffs)} points on a travelling wave (at "
                                 f"{at.key()}) against {self.agree:g}, the issue's 0.5 %; margin the Newmark "
                                 f"step's own spread of the blades on a wave ({STEP_SPREAD:g})")

    def settled_waves(self) -> list:
        """(case, point) of every wave the ring in time settled on whose stability was computed."""
        return [(c, p) for c, p in self.points() if p.on is True and p.stability is not None]

    def stable_where_on_wave(self) -> Verdict | None:
        """The HB's stability of the waves the ring in time settled on, except those at a bracketed stability
        threshold (RingPoint.at_threshold: judged by :meth:`threshold_bracketed`, named in the reason), read at
        the least stable one (a decided unstable before an undecided before a stable one; within each, the
        largest |multiplier|); one not decided says what its stability THRESHOLD_STEP either side shows."""
        at = [(c, p) for c, p in self.settled_waves() if p.at_threshold()]
        on = [(c, p) for c, p in self.settled_waves() if not p.at_threshold()]
        if not on:
            return None
        rank = {False: 0, NOT_DECIDED: 1, True: 2}
        c, p = min(on, key=lambda cp: (rank[cp[1].stability.answer], -cp[1].stability.value))
        v = p.stability
        beside = f"; not shown at a threshold ({p.side_words()})" if p.threshold_bracket() is not None else ""
        left = (f"; {len(at)} left to `{THRESHOLD_VERDICT}`, at a bracketed stability threshold: "
                + "; ".join(f"{a.label}, {q.key()}" for a, q in at)) if at else ""
        return Verdict.of(v.value, threshold=v.threshold, margin=v.margin, below=True, above=False,
                          reason=f"the least stable of the {len(on)} waves the ring in time settled on whose "
                                 f"stability is not at a bracketed threshold ({c.label}, {p.key()}): "
                                 f"{v.reason}{beside}{left}")

    def threshold_bracketed(self) -> Verdict | None:
        """Whether every wave the ring in time settled on whose stability is not decided sits at a stability
        threshold bracketed THRESHOLD_STEP either side (RingPoint.threshold_bracket), read at the least
        bracketed one; None where no settled wave's stability is undecided (nothing to bracket)."""
        open_ = [(c, p, b) for c, p in self.settled_waves() if (b := p.threshold_bracket()) is not None]
        if not open_:
            return None
        c, p, b = min(open_, key=lambda t: t[2].value if math.isfinite(t[2].value) else 0.0)
        named = {True: [], False: []}
        for a, q, w in open_:
            named[w.answer is True].append(f"{a.label}, {q.key()}")
        left = (f"; bracketed, at the wave's stability threshold and left out of `hb_stable_where_on_wave`: "
                f"{'; '.join(named[True])} (deciding such a wave's own stability needs its multiplier known within "
                f"its distance from 1, below floquet's floor {floquet.MULTIPLIER_FLOOR:g} and the monodromy's "
                "sampling of the contact states, or a time point off the threshold)") if named[True] else ""
        kept = f"; kept in `hb_stable_where_on_wave`: {'; '.join(named[False])}" if named[False] else ""
        return Verdict.of(b.value, threshold=b.threshold, margin=b.margin, below=False, above=True, unit=b.unit,
                          reason=f"the least bracketed of the {len(open_)} settled waves whose stability is not "
                                 f"decided ({c.label}, {p.key()}): {b.reason}{left}{kept}")

    def departures_explained(self) -> Verdict | None:
        """Whether the HB explains every departure from the wave (an unstable wave or a coexisting branch): the
        count of departures it does not explain against 0.5, margin the count whose explanation waits on a
        stability not decided, not reached or not computed (each could go either way)."""
        off = [p for _, p in self.points() if p.on is False]
        if not off:
            return None
        open_ = [p for p in off if p.explanation() in OPEN_EXPLANATIONS]
        unexplained = [p for p in off if p.explanation() not in ("wave unstable", "coexisting branch")]
        return Verdict.of(len(unexplained), threshold=0.5, margin=len(open_), below=True, above=False,
                          unit="points", reason=f"departures from the wave the HB does not explain, of {len(off)}; "
                                                f"margin the {len(open_)} whose wave's stability is not decided, "
                                                "not reached or not computed")

    def branch_against_points(self) -> Verdict | None:
        """Whether the sector branch's stability (H = branch_harmonics) equals the wave's own (2 H of the time
        points) wherever both are decided: the count that differ against 0.5; margin 0, both verdicts being
        decided beyond their own margins. None where no point has both decided."""
        both = [(p.stability.answer, p.branch_stable) for _, p in self.points()
                if p.stability is not None and p.stability.answer in (True, False) and p.branch_stable in (True, False)]
        if not both:
            return None
        return Verdict.of(sum(a != b for a, b in both), threshold=0.5, margin=0.0, below=True, above=False,
                          unit="points", reason=f"points whose branch verdict differs from the wave's own, of the "
                                                f"{len(both)} where both are decided")

    def fixed_neighbours_for_ring(self) -> Verdict | None:
        """Whether the blade between fixed neighbours (the paper's model) stands in for the tuned ring where the
        ring settles on a wave: the largest |ring's mean blade / the fixed-neighbour blade's nearest stable HB
        state - 1| against ``agree``; margin the HB's own measured difference from the ring in time there (at
        least the Newmark step's). None where no such point has a stable fixed-neighbour state."""
        pairs = []
        for c, p in self.points():
            fixed = crossings(c.fixed, p.rpm, True)
            if p.on is True and fixed:
                mean = float(np.mean(p.amplitudes))
                pairs.append((min(abs(mean / a - 1) for a in fixed), c, p))
        if not pairs:
            return None
        worst, c, p = max(pairs, key=lambda t: t[0])
        hb = self.agreement([q for _, q in self.points()])
        return Verdict.of(worst, threshold=self.agree, margin=max(STEP_SPREAD, hb.value if hb else 0.0),
                          below=True, above=False,
                          reason=f"largest |ring / fixed-neighbour blade - 1| over {len(pairs)} points on a wave "
                                 f"(at {c.label}, {p.key()}) against {self.agree:g}; margin the sector HB's largest "
                                 "difference from the ring in time on a wave (the HB's own error here)")

    def verdicts(self) -> dict[str, Verdict | None]:
        return {"hb_agrees_where_on_wave": self.agreement([p for _, p in self.points()]),
                "hb_stable_where_on_wave": self.stable_where_on_wave(),
                THRESHOLD_VERDICT: self.threshold_bracketed(),
                "departures_explained": self.departures_explained(),
                "branch_agrees_with_points": self.branch_against_points(),
                "fixed_neighbours_stand_in_for_ring": self.fixed_neighbours_for_ring()}

    def agreement_by_speed(self) -> dict[str, Verdict | None]:
        """:meth:`agreement` at each time-domain speed."""
        speeds = sorted({p.rpm for _, p in self.points()})
        return {f"{r:g} r/min": self.agreement([p for _, p in self.points() if p.rpm == r]) for r in speeds}

    def conclusions(self) -> dict:
        """The verdicts (:meth:`verdicts`, the HB's agreement also per speed: :meth:`agreement_by_speed`); per
        time point its naming (on the wave: 'stable wave' ...; off it: what explains it), the HB's agreement
        there and the sector branch's verdict at its speed; how many points on and off the wave the branch
        calls stable, unstable, not decided or has no stretch at (None)."""
        return {"points": {f"{c.label}, {p.key()}": {"on_wave": p.on, "explanation": p.explanation(),
                                                      "agrees": None if p.on is not True or p.agreement(self.agree)
                                                      is None else p.agreement(self.agree).answer,
                                                      "branch_stable": p.branch_stable}
                           for c, p in self.points()},
                "branch_against_time": {side: {_branch_word(a): sum(str(p.branch_stable) == str(a)
                                                                    for _, p in self.points() if p.on is on)
                                               for a in (True, False, NOT_DECIDED, None)}
                                        for side, on in (("on_wave", True), ("off_wave", False))},
                "hb_agrees_on_wave_by_speed": {k: _json(v) for k, v in self.agreement_by_speed().items()},
                **{name: _json(v) for name, v in self.verdicts().items()}}

    def to_json(self) -> dict:
        return {"conclusions": self.conclusions(),
                "cases": [{"label": c.label, "gap_um": c.gap_um, "preload_N": c.preload_N,
                           "fixed_neighbours": c.fixed.to_json(),
                           "sectors": {str(n): None if b is None else b.to_json() for n, b in c.sectors.items()},
                           "failures": {str(n): why for n, why in c.failures.items()},
                           "sector_costs": {str(n): cost for n, cost in c.costs.items()},
                           "points": [p.to_json(self.agree) for p in c.points]} for c in self.cases]}


def branch_verdicts(branch) -> list[Verdict | None]:
    """Per point of an HB branch the verdict on its largest |multiplier| against 1, its margin the point's own
    error (floquet's floor, the change at half the samples and at 2 H; infinite where no 2 H state is found
    or a touch grazes, which floquet leaves undecided); None where the stability was not evaluated."""
    err = branch.multiplier_error if branch.multiplier_error is not None else [math.inf] * len(branch.rpm)
    out = []
    for mu, e, s in zip(branch.max_multiplier, err, branch.stable):
        if not np.isfinite(mu):
            out.append(None)
            continue
        e = e if e >= 0 else math.inf                                     # an unknown error decides nothing
        margin = math.inf if s is None and abs(mu - 1.0) > e else e      # grazing: floquet's own "undecided"
        out.append(Verdict.of(mu, threshold=1.0, margin=margin, below=True, above=False,
                              reason="largest |multiplier| of the monodromy (the ring's: every nodal diameter) "
                                     "against 1, margin the point's error (floor, n / 2 samples, 2 H)"))
    return out


def branch_answers(branch) -> list:
    """Per point True, False or 'not decided' (:func:`branch_verdicts`); a point whose stability was not
    evaluated takes that of the nearest evaluated points on both sides where they agree (one verdict on both
    sides: ring_hb.located_changes), else None."""
    given = [None if v is None else v.answer for v in branch_verdicts(branch)]
    known = [i for i, a in enumerate(given) if a is not None]
    out = list(given)
    for a, b in zip(known, known[1:]):
        if given[a] == given[b]:
            out[a + 1:b] = [given[a]] * (b - a - 1)
    return out


def branch_at(branch, rpm: float, amplitude: float | None):
    """The branch's answer at ``rpm`` on its stretch crossing it nearest ``amplitude`` (m; None: the
    lowest): that of the stretch's two points where they agree, 'not decided' where the verdict changes
    between them; None where no stretch crosses ``rpm``."""
    ans = branch_answers(branch)
    found = [(abs(a - amplitude) if amplitude is not None else a, ans[i] if ans[i] == ans[i + 1] else NOT_DECIDED)
             for i, a in stretches(branch, rpm)]
    return min(found, key=lambda f: f[0])[1] if found else None


def stretches(branch, rpm: float) -> list[tuple[int, float]]:
    """(i, amplitude m) of every stretch i -> i + 1 of ``branch`` crossing ``rpm``, interpolated."""
    out = []
    for i in range(len(branch.rpm) - 1):
        r0, r1 = branch.rpm[i], branch.rpm[i + 1]
        if r0 != r1 and min(r0, r1) <= rpm <= max(r0, r1):
            t = (rpm - r0) / (r1 - r0)
            out.append((i, float((1 - t) * branch.amplitude_v_L[i] + t * branch.amplitude_v_L[i + 1])))
    return out


def wave_at(p, model: str, rpm: float, H: int) -> float | None:
    """The sector's wave at ``rpm`` from the linear start (m), None where no periodic state is reached."""
    try:
        return sector_at(p, model, rpm, harmonics=H, stability=False)["amplitude_v_L"]
    except RunDiverged:
        return None


def stability(p, model: str, rpm: float, H: int) -> Verdict | None:
    """ring_hb.stability_verdict with its margin at least floquet's floor on a multiplier's error (Hill
    against the monodromy, 0.02: docs/hb-stability.md). The change from H to 2 H alone misses the error of
    the contact states held over each of the monodromy's samples: where the switches stay on the same
    samples it is nil (1 um, 12 blades, 12000 r/min: |mu| 1.0001 at H = 10, 20 and 40 on 516 samples,
    0.994 to 1.005 on 1026 to 8196; docs/ring-tuned.md). None where the wave is not reached at H or 2 H
    from the linear start."""
    try:
        v = stability_verdict(p, model, rpm, H)
    except RunDiverged:
        return None
    return Verdict.of(v.value, threshold=v.threshold, margin=max(v.margin, floquet.MULTIPLIER_FLOOR), below=True,
                      above=False, reason=f"{v.reason}, at least floquet's floor {floquet.MULTIPLIER_FLOOR:g}")


def ring_point(p, model: str, rpm: float, o, branch) -> RingPoint:
    """The ring in time from rest at ``rpm`` (E scattered by symmetry_break) and the sector's waves there."""
    q = p.updated({"speed.rpm": rpm})
    run = transient(q.updated({"ring.mistuning_std": o["symmetry_break"], "ring.seed": 1}), model)
    tip, spp = run.trajectory.tip[:, :, 0], q.time.steps_per_period
    window = signals.STEADY_PERIODS * spp
    now = np.array([signals.amplitude(tip[:, j], spp) for j in range(tip.shape[1])])
    before = np.array([signals.amplitude(tip[:-window, j], spp) for j in range(tip.shape[1])])
    wave = wave_at(q, model, rpm, int(o["harmonics"]))
    H = int(o["stability_harmonics"])
    stable = stability(q, model, rpm, H) if q.ring.blades in o["stability_blades"] and wave is not None else None
    beside = ({r: stability(q.updated({"speed.rpm": r}), model, r, H) if r > 0 else None
               for r in (rpm - THRESHOLD_STEP, rpm + THRESHOLD_STEP)}
              if stable is not None and stable.answer == NOT_DECIDED else {})
    return RingPoint(blades=q.ring.blades, rpm=rpm, amplitudes=[float(a) for a in now],
                     period=signals.detect_period(tip[:, 0], spp), drift=float(np.abs(before / now - 1).max()),
                     wave=wave, coexisting=[] if branch is None else waves_on(branch, rpm), stability=stable,
                     wave_spread=o["wave_spread"], stability_tried=q.ring.blades in o["stability_blades"],
                     branch_stable=None if branch is None else branch_at(branch, rpm, wave), beside=beside)


def waves_on(branch, rpm: float) -> list[float]:
    """Every wave of ``branch`` at ``rpm`` (m, interpolated), whatever its stability."""
    return sorted(a for _, a in stretches(branch, rpm))


def compute(scene) -> RingTunedComparison:
    params, o = scene.params.updated({"ring.mistuning": (), "ring.mistuning_std": 0.0}), scene.options
    model, H = o["model"], int(o["branch_harmonics"])
    cases = []
    contacts = ([(f"gap {g:g} um", g, 0.0, {"contact.gap": g * 1e-6}) for g in o["gaps_um"]]
                + [(f"preload {n:g} N", 0.0, n, {"contact.N0": n}) for n in o["preloads_N"]])
    for label, g, n0, contact in contacts:
        case = params.updated({**contact, "ring.blades": 0})
        fixed = run_hb(case, model, o["rpm_from"], o["rpm_to"], harmonics=H)
        sectors, failures, points = {}, {}, []
        costs = {}
        for n, spread in zip(o["blades"], o["branch_stability_points"]):
            p = case.updated({"ring.blades": int(n)})
            wall, cpu = time.perf_counter(), time.process_time()
            try:
                sectors[n] = run_ring_hb(p, model, o["rpm_from"], o["rpm_to"], H,
                                         stability_points=spread or None,
                                         stability_at=tuple(o["td_rpms"])).branch
                costs[n] = {"cpu_s": time.process_time() - cpu, "wall_s": time.perf_counter() - wall,
                            "points": len(sectors[n].rpm),
                            "evaluated": int(np.isfinite(sectors[n].max_multiplier).sum())}
            except RunDiverged as e:
                sectors[n], failures[n] = None, str(e)
            points += [ring_point(p, model, float(r), o, sectors[n]) for r in o["td_rpms"]]
        cases.append(RingCase(label=label, gap_um=g, preload_N=n0, fixed=fixed, sectors=sectors, failures=failures,
                              points=points, costs=costs))
    return RingTunedComparison(cases=cases, agree=o["agree"])


PANELS_PER_ROW = 4


def panels(n: int, height: float):
    """A figure of ``n`` panels, at most PANELS_PER_ROW a row (the rows' spare panels hidden): (fig, axes)."""
    cols = min(n, PANELS_PER_ROW)
    rows = -(-n // cols)
    fig, axes = figure(rows, cols, width=4.8 * cols, height=height * rows)
    for ax in axes.ravel()[n:]:
        ax.set_visible(False)
    return fig, list(axes.ravel()[:n])


def plot(result: RingTunedComparison, scene, out: Path) -> list[str]:
    """Per case: the branches and the ring's time points (ring_tuned.png); every blade's amplitude at the time
    points (ring_tuned_blades.png); the points as CSV."""
    cases = result.cases
    fig, axes = panels(len(cases), 5.2)
    for ax, c in zip(axes, cases):
        draw_branch(ax, c.fixed, "k", 1.4, "fixed neighbours (HB)")
        for i, (n, br) in enumerate(c.sectors.items()):
            colour = f"C{i}"
            if br is not None:     # widest first: where the shrouds do not touch every ring is the free blade
                draw_branch(ax, br, colour, 1.0 + 0.9 * (len(c.sectors) - 1 - i), f"{n} blades: sector HB",
                            alpha=0.8)
            for p in (q for q in c.points if q.blades == n):
                a = 1e6 * np.asarray(p.amplitudes)
                on = p.on is True
                ax.plot([p.rpm, p.rpm], [a.min(), a.max()], "-", color=colour, lw=2.5, alpha=0.6)
                ax.plot([p.rpm], [a.mean()], "o" if on else "x", color=colour, ms=6, mfc=colour if on else "none")
                if p.wave is not None:
                    s = None if p.stability is None else p.stability.answer
                    ax.plot([p.rpm + 60], [1e6 * p.wave], {True: "^", False: "v"}.get(s, "d"), color=colour, ms=5,
                            mfc="white")
        ax.set_xlabel("speed (r/min)")
        ax.set_xticks(np.linspace(scene.options["rpm_from"], scene.options["rpm_to"], 5))
        ax.set_ylabel("v_L amplitude (um)")
        plain_log(ax, "y")
        for answer, style in LINE_STYLES.items():
            ax.plot([], [], style, color="grey", lw=1.2, label=f"HB branch: {LINE_WORDS[answer]}")
        ax.plot([], [], "ko", ms=5, label="ring in time on a wave (bar: its blades)")
        ax.plot([], [], "kx", ms=5, label="ring in time off the wave")
        ax.plot([], [], "k^", mfc="white", ms=5, label="sector wave there: stable")
        ax.plot([], [], "kv", mfc="white", ms=5, label="unstable")
        ax.plot([], [], "kd", mfc="white", ms=5, label="not decided or not computed")
        ax.set_title(f"Fig. 11 contact, {c.label}", fontsize=9)
        ax.legend(fontsize=6, loc="upper center", bbox_to_anchor=(0.5, -0.16), ncol=2)
    save(fig, out / "ring_tuned.png")

    fig, axes = panels(len(cases), 3.4)
    for ax, c in zip(axes, cases):
        for i, n in enumerate(c.sectors):
            for k, p in enumerate(q for q in c.points if q.blades == n):
                if p.on is True:
                    continue
                a = np.asarray(p.amplitudes)
                ax.plot(np.arange(n) / n, 100 * (a / a.mean() - 1), ["-", "--", ":", "-."][k % 4], color=f"C{i}",
                        marker=".", ms=3, lw=1.0, label=f"{n} blades, {p.rpm:g} r/min (mean {1e6 * a.mean():.1f} um)")
        ax.axhline(0.0, color="k", lw=0.6)
        ax.set_xlabel("blade j / N")
        ax.set_ylabel("blade amplitude / ring mean - 1 (%)")
        ax.set_title(f"{c.label}: where the ring left the wave, blade by blade", fontsize=9)
        if any(p.on is not True for p in c.points):
            ax.legend(fontsize=5.5, loc="best")
        else:
            ax.text(0.5, 0.5, "on the travelling wave at every time point", ha="center", va="center",
                    transform=ax.transAxes, fontsize=8)
    save(fig, out / "ring_tuned_blades.png")

    with open_replacing(out / "ring_tuned_points.csv") as fh:
        w = csv.writer(fh)
        w.writerow(["case", "blades", "rpm", "min_amplitude_m", "max_amplitude_m", "period", "spread", "wave_m",
                    "coexisting_waves", "largest_multiplier", "explanation"])
        for c, p in result.points():
            w.writerow([c.label, p.blades, p.rpm, min(p.amplitudes), max(p.amplitudes), p.period, p.spread,
                        p.wave, len(p.coexisting), None if p.stability is None else p.stability.value,
                        p.explanation()])
    return ["ring_tuned.png", "ring_tuned_blades.png"]


LINE_STYLES = {True: "-", False: "--", NOT_DECIDED: ":"}     # a branch's line per stability verdict
LINE_WORDS = {True: "stable", False: "unstable", NOT_DECIDED: "not decided"}


def draw_branch(ax, branch, colour: str, lw: float, label: str, alpha: float = 1.0) -> None:
    """``branch``'s v_L amplitude (um) over speed, its line per point's verdict (:func:`branch_answers`):
    stable solid, unstable dashed, not decided dotted (so is a stretch whose ends differ)."""
    answers, amp = branch_answers(branch), 1e6 * np.asarray(branch.amplitude_v_L)
    change = np.array([a != b for a, b in zip(answers, answers[1:])] + [False])
    change[1:] |= change[:-1]              # both ends of a stretch whose verdict changes: drawn not decided
    for k, (answer, style) in enumerate(LINE_STYLES.items()):
        y = np.where([a == answer and a is not None for a in answers] | (change & (answer == NOT_DECIDED)), amp,
                     np.nan)
        ax.plot(branch.rpm, y, style, color=colour, lw=lw, alpha=alpha, label=label if k == 0 else None)


# What a verdict's None says where "no such point" would not (nothing to judge)
VACUOUS = {THRESHOLD_VERDICT: "no settled wave's stability is undecided: nothing to bracket"}
OPEN_EXPLANATIONS = ("stability not decided", "stability not reached at 2 H", "stability not computed")


def _json(v: Verdict | None) -> dict | None:
    return None if v is None else v.to_json()


def _stable_word(v: Verdict) -> str:
    """A stability verdict in words with its |multiplier| and margin: 'stable (0.915 +- 0.02)'."""
    return f"{LINE_WORDS[v.answer]} ({v.value:.4g} +- {v.margin:.2g})"


def _branch_word(answer) -> str:
    """The branch's stability verdict at a time point's speed in words (None: the branch has no stretch
    there)."""
    return {True: "stable", False: "unstable", NOT_DECIDED: "not decided", None: "no stretch there"}[answer]


def _um(x: float | None) -> str:
    return "-" if x is None else f"{1e6 * x:.3f}"


def stable_stretches(branch) -> str:
    """The speed ranges (r/min) of the branch's stretches drawn stable, in branch order."""
    answers, out, start = branch_answers(branch), [], None
    for i, a in enumerate([*answers, None]):
        if a is True and start is None:
            start = i
        elif a is not True and start is not None:
            lo, hi = sorted((branch.rpm[start], branch.rpm[i - 1]))
            out.append(f"{lo:.0f}-{hi:.0f}")
            start = None
    return ", ".join(out) or "none"


def branch_row(name: str, branch, cost: dict | None) -> tuple:
    v = [x for x in branch_verdicts(branch) if x is not None]
    counts = [sum(x.answer == a for x in v) for a in (True, False, NOT_DECIDED)]
    return (name, len(branch.rpm), len(v), *counts, stable_stretches(branch),
            "-" if cost is None else f"{cost['cpu_s']:.1f}", "-" if cost is None else f"{cost['wall_s']:.1f}")


def report(result: RingTunedComparison, scene, files: list[str]) -> str:
    o = scene.options
    concl = result.conclusions()
    lines = [f"# {scene.title}\n",
             f"Fig. 11 contact (alpha {scene.params.contact.alpha_deg:g} deg, kt {scene.params.contact.kt:g} N/m, "
             f"mu {scene.params.contact.mu:g}), engine order {scene.params.load.ke}, model {o['model']}, "
             f"H = {o['harmonics']}; the ring in time from rest over {scene.params.time.periods} periods with E "
             f"scattered by {o['symmetry_break']:g} (symmetry broken); stability of the sector's wave against "
             f"every nodal diameter for {', '.join(str(n) for n in o['stability_blades'])} blades "
             f"(H = {2 * o['stability_harmonics']} against {o['stability_harmonics']}).\n"]
    for c in result.cases:
        rows = []
        fixed_at = {p.rpm: crossings(c.fixed, p.rpm, True) for p in c.points}
        for p in c.points:
            v = p.agreement(result.agree)
            rows.append((p.blades, f"{p.rpm:g}", f"{_um(min(p.amplitudes))} .. {_um(max(p.amplitudes))}",
                         "-" if p.period is None else f"P{p.period}", f"{100 * p.spread:.2f}", _um(p.wave),
                         len(p.coexisting), "-" if p.stability is None else
                         f"{p.stability.value:.3f} +- {p.stability.margin:.3f}",
                         _branch_word(p.branch_stable),
                         "-" if v is None else f"{100 * v.value:.2f}", p.explanation(),
                         "-" if p.pattern_nd is None else str(p.pattern_nd),
                         ", ".join(_um(a) for a in fixed_at[p.rpm]) or "-"))
        lines += [f"## {c.label}\n", markdown_table(
            ["N", "r/min", "ring in time (um)", "period", "spread %", "sector wave (um)", "waves on branch",
             "max |mu|", f"branch (H = {o['branch_harmonics']})", "HB diff %", "named", "spread's nd", "fixed neighbours, stable (um)"], rows), ""]
        for n, why in c.failures.items():
            lines.append(f"- {n} blades: no sector branch from {o['rpm_from']:g} r/min ({why}).")
        lines += ["", f"Branches' stability (H = {o['branch_harmonics']}; evaluated: points whose ring monodromy "
                      "was computed, the others between evaluated points of one verdict):\n",
                  markdown_table(["branch", "points", "evaluated", "stable", "unstable", "not decided",
                                  "stable stretches (r/min)", "CPU s", "wall s"],
                                 [branch_row(f"{n} blades" if n else "fixed neighbours", br, c.costs.get(n))
                                  for n, br in [(0, c.fixed), *c.sectors.items()] if br is not None]), ""]
    verdicts = {**result.verdicts(), **{f"hb_agrees_where_on_wave at {k}": v
                                        for k, v in result.agreement_by_speed().items()}}
    lines += ["## Conclusions\n"]
    lines += [f"- `{name}`: {VACUOUS.get(name, 'no such point') if v is None else v.sentence()}"
              for name, v in verdicts.items()]
    lines += ["- The branch's verdict at the time points, where the ring in time settled on the wave: "
              + ", ".join(f"{k} {v}" for k, v in concl["branch_against_time"]["on_wave"].items())
              + "; where it left the wave: "
              + ", ".join(f"{k} {v}" for k, v in concl["branch_against_time"]["off_wave"].items()) + ".", ""]
    lines += [f"![{f}]({f})" for f in files]
    return "\n".join(lines) + "\n"


run = study(compute, plot, report)
