"""The measurements of docs/ring-tuned.md, "At the threshold": ring_tuned's one wave not decided (1 um gap,
12 blades, 12000 r/min, the scene's Fig. 11 contact) and its largest Floquet multipliers:

    PYTHONPATH=. OMP_NUM_THREADS=1 python scripts/ring_tuned_threshold.py states       # interfaces, neutral count
    PYTHONPATH=. OMP_NUM_THREADS=1 python scripts/ring_tuned_threshold.py resolution   # H and samples
    PYTHONPATH=. OMP_NUM_THREADS=1 python scripts/ring_tuned_threshold.py speeds       # over speed, two samplings
    PYTHONPATH=. OMP_NUM_THREADS=1 python scripts/ring_tuned_threshold.py friction     # mu 0.28, 0.30, 0.32

The wave is solved at H with the default samples (shroud.analysis.ring_hb, as the study does); the ring's
monodromy (every nodal diameter, shroud.core.floquet) samples its contact law at ``x`` times as many instants.
Each line: |mu| @ arg(mu) (rad) of the largest multipliers (one of each complex pair), per block (the ring's
periodic and antiperiodic halves, ring_hb.ring_blocks).
"""

from __future__ import annotations

import sys

import numpy as np

from shroud.analysis import ring_hb
from shroud.core import floquet
from shroud.core import harmonic_balance as hb
from shroud.core.contact import SEPARATE, SLIP, STICK
from workbench.scene import load_scene

GAP, BLADES, RPM, MODEL = 1e-6, 12, 12000.0, "reduced"


def ring(rpm: float, H: int, **more):
    """(speeds, sector, basis, X) of the 1 um 12-blade wave at ``rpm``, H harmonics."""
    p = load_scene("scenes/ring_tuned.toml").params.updated(
        {"ring.mistuning": (), "ring.mistuning_std": 0.0, "contact.gap": GAP, "ring.blades": BLADES,
         "speed.rpm": rpm, **more})
    speeds, sector, basis = ring_hb._ring_system(p, MODEL, rpm, H, hb.default_samples(H), whole=False)
    return speeds, sector, basis, ring_hb._ring_state(p, MODEL, rpm, speeds, sector, basis, None)[0]


def blocks_multipliers(rpm: float, H: int, times: int, **more):
    """(the orbit's states, [multipliers of each block]) with the law sampled at ``times`` the default."""
    speeds, sector, basis, X = ring(rpm, H, **more)
    system, lin, _, _ = speeds.at(rpm)
    blocks, count = ring_hb.ring_blocks(system, sector)
    orbit = ring_hb._ring_orbit(sector, lin, X, basis, ring_hb._ring_samples(sector, basis.samples * times), count)
    return orbit[0], [floquet.block_multipliers([b], *orbit[:2], lin.omega, orbit[2])[0] for b in blocks]


def words(mu: np.ndarray, least: float = 0.85) -> str:
    mu = mu[(np.abs(mu) > least) & (mu.imag >= 0)]
    return " ".join(f"{abs(m):.4f}@{np.angle(m):.2f}" for m in mu)


def states() -> None:
    state, parts = blocks_multipliers(RPM, 20, 1)
    print(f"interface 0: stick {np.mean(state[0] == STICK):.3f}, slip {np.mean(state[0] == SLIP):.3f}, "
          f"separated {np.mean(state[0] == SEPARATE):.3f} of the period; stuck all period: "
          f"{int(np.all(state == STICK, axis=1).sum())} of {state.shape[0]} (a block's)")
    for b, mu in enumerate(parts):
        print(f"block {b}: {mu.size} multipliers, within 0.02 of +1: {int(np.sum(np.abs(mu - 1) < 0.02))}; "
              f"largest {words(mu)}")


def resolution() -> None:
    for H in (10, 20, 40):
        for times in (1, 2, 4, 8, 16):
            state, parts = blocks_multipliers(RPM, H, times)
            print(f"H {H:2d}, {state.shape[1]:5d} samples: {words(parts[0], 0.95)}", flush=True)


def speeds(rpms=(11700, 11800, 11900, 11920, 11940, 11960, 11980, 11990, 12000, 12010, 12020, 12040, 12100,
                 12200, 12300), **more) -> None:
    for times in (1, 16):
        for rpm in rpms:
            state, parts = blocks_multipliers(float(rpm), 20, times, **more)
            print(f"x{times:2d} {rpm:6g} r/min: " + " | ".join(words(mu) for mu in parts), flush=True)


def friction() -> None:
    """The peak over speed of the pair that sits on the unit circle at 12000 r/min (block 0, arg near 2 rad)."""
    for mu in (0.28, 0.30, 0.32):
        peak = []
        for rpm in range(11850, 12126, 25):
            m = blocks_multipliers(float(rpm), 20, 8, **{"contact.mu": mu})[1][0]
            peak.append((float(np.abs(m[np.abs(np.abs(np.angle(m)) - 2.0) < 0.3]).max(initial=0.0)), rpm))
        print(f"mu {mu}: the pair near arg 2 rad peaks at |mu| {max(peak)[0]:.4f} at {max(peak)[1]} r/min "
              "(x8 samples, 11850-12125 r/min)", flush=True)


if __name__ == "__main__":
    {"states": states, "resolution": resolution, "speeds": speeds, "friction": friction}[sys.argv[1]]()
