"""The tuned ring's sector branch with its stability against every nodal diameter (ring_hb.run_ring_hb with
``stability_points``, ring_hb.located_changes; comparisons/ring_tuned.py draws it).

Truths: a verdict that changes at a known point (where the located subset must put the change); the branch
with its stability evaluated at every point (which the subset must reproduce point by point); the whole ring
in time from rest with E scattered by 1e-4 (every nodal diameter excited), which stays on the travelling
wave where it is stable and leaves it where it is not.
"""

import numpy as np
import pytest

from comparisons.ring_tuned import branch_answers, branch_at
from shroud.analysis.ring_hb import located_changes, run_ring_hb
from shroud.api import transient
from shroud.core import signals
from shroud.core.floquet import Stability
from shroud.params import Parameters


@pytest.mark.parametrize("n, flips", [(100, [37]), (100, [10, 80]), (100, [5, 20, 60]), (7, [3])])
def test_located_changes_puts_every_change_between_adjacent_evaluated_points(n, flips):
    """A branch whose verdict flips (stable <-> unstable) after each index in ``flips`` (each stretch longer
    than the spread points' spacing, 14 here: a shorter one between two of one verdict is not seen): every
    flip lies between two adjacent evaluated points, every point not evaluated between two evaluated ones of its own
    verdict, at fewer evaluations than the points (bisection: a few per flip)."""
    def mu(i):
        return 1.5 if sum(i > f for f in flips) % 2 else 0.8
    calls = []

    def evaluate(i):
        calls.append(i)
        return Stability(multipliers=np.array([mu(i)]), error=0.02)
    done = located_changes(evaluate, n, 8)
    assert len(calls) == len(set(calls)) == len(done)
    for f in flips:
        assert f in done and f + 1 in done
    known = sorted(done)
    for a, b in zip(known, known[1:]):
        assert all((mu(i) < 1) is done[a].stable for i in range(a, b + 1)) or b == a + 1
    assert len(done) < n or n <= 8


def test_the_branch_stability_is_every_points_and_the_ring_in_time_follows_it():
    """6 blades (the paper's contact), 5000-8000 r/min, H = 10: the branch's stability at 6 spread points and
    where it changes (13 evaluated of 32, measured) reads as the same verdict at every point as the branch
    evaluated everywhere. At 6000 r/min the branch is stable and the ring in time from rest settles on the
    wave (P1, the blades within 0.5 %: 0.14 % measured); at 7200 r/min it is unstable and the ring leaves
    the wave (not P1, 5.7 % spread)."""
    p = Parameters().with_overrides(["ring.blades=6"])
    every = run_ring_hb(p, "reduced", 5000.0, 8000.0, 10).branch
    located = run_ring_hb(p, "reduced", 5000.0, 8000.0, 10, stability_points=6).branch
    evaluated = np.isfinite(located.max_multiplier)
    assert evaluated.sum() < len(located.rpm) and np.allclose(located.rpm, every.rpm)
    assert branch_answers(located) == branch_answers(every)
    for rpm, stable in ((6000.0, True), (7200.0, False)):
        assert branch_at(located, rpm, None) is stable
        q = p.updated({"speed.rpm": rpm, "time.periods": 300, "ring.mistuning_std": 1e-4, "ring.seed": 1})
        tip, spp = transient(q, "reduced").trajectory.tip[:, :, 0], q.time.steps_per_period
        a = np.array([signals.amplitude(tip[:, j], spp) for j in range(tip.shape[1])])
        on_wave = bool(signals.detect_period(tip[:, 0], spp) == 1 and np.ptp(a) / a.mean() < 0.005)
        assert on_wave is stable


def test_located_changes_finds_a_stretch_between_spread_points_from_an_index_it_is_given():
    """A stable stretch (indices 40-49) between two unstable spread points (0, 33, 66, 99) is missed from the
    spread points alone and located, both its ends, once one of its indices is given (``also``: the time
    points' stretches in ring_tuned)."""
    def evaluate(i):
        return Stability(multipliers=np.array([0.8 if 40 <= i <= 49 else 1.5]), error=0.02)
    alone = located_changes(evaluate, 100, 4)
    assert not any(done.stable for done in alone.values())
    given = located_changes(evaluate, 100, 4, [45])
    assert {39, 40, 49, 50} <= given.keys() and given[40].stable and not given[39].stable
