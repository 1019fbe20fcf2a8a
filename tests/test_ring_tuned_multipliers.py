"""The ring's multipliers on ring_tuned's waves against the count of neutral ones the physics predicts.

A Jenkins slider stuck all period may sit at any offset: every offset is another periodic orbit, so the
monodromy would carry one multiplier exactly 1 per such slider (docs/hb-stability.md); shroud.core.floquet
leaves them out, keeping the sliders that both stick and are released (their state is set again at the
release, no neutral direction). So the ring's multipliers number 2 N n (the blades' DOFs and velocities) plus
one per slider with a history, and none lies at +1. ring_tuned's one wave not decided (1 um gap, 12 blades,
12000 r/min, docs/ring-tuned.md "At the threshold") is not such a neutral direction: none of its sliders is
stuck all period and its largest multiplier is a complex pair on the unit circle.
"""

from __future__ import annotations

import numpy as np
import pytest

from comparisons.ring_tuned import OPTIONS
from shroud.analysis.ring_hb import _ring_orbit, _ring_samples, _ring_system, sector_at
from shroud.core.contact import STICK
from shroud.core.floquet import MULTIPLIER_FLOOR, history
from workbench.scene import load_scene

RPM, H, N = 12000.0, 20, 12


@pytest.mark.parametrize("contact, stuck_all_period", [({"contact.N0": 100.0}, True), ({"contact.gap": 1e-6}, False)])
def test_ring_multipliers_leave_out_exactly_the_sliders_stuck_all_period(contact, stuck_all_period):
    """The 100 N preload sticks every interface all period (12 neutral sliders left out: 2 N n multipliers,
    none at +1); the 1 um gap sticks, slips and separates (every slider with a history: 2 N n + 12, none at
    +1, the largest a complex pair within floquet's floor of the unit circle)."""
    scene = load_scene("scenes/ring_tuned.toml")
    p = scene.params.updated({"ring.mistuning": (), "ring.mistuning_std": 0.0, "ring.blades": N,
                              "speed.rpm": RPM, **contact})
    wave = sector_at(p, OPTIONS["model"], RPM, harmonics=H)
    speeds, sector, basis = _ring_system(p, OPTIONS["model"], RPM, H, None, whole=False)
    system, lin, _, _ = speeds.at(RPM)
    state = _ring_orbit(sector, lin, wave["X"], basis, _ring_samples(sector, basis.samples))[0]  # N interfaces
    stuck = int(np.all(state == STICK, axis=1).sum())
    with_history = history(np.ascontiguousarray(state)).size
    assert stuck == (N if stuck_all_period else 0)
    assert stuck + with_history == N                               # every interface touches at some time
    mu = wave["multipliers"]
    assert mu.size == 2 * N * system.M.shape[0] + with_history     # the stuck sliders' neutral 1 left out
    assert not np.any(np.abs(mu - 1.0) < MULTIPLIER_FLOOR)
    if not stuck_all_period:
        assert abs(abs(mu[0]) - 1.0) < MULTIPLIER_FLOOR and abs(mu[0].imag) > 0.5
