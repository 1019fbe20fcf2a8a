"""Cost and misses of the tuned ring's stability along a sector branch (issue 26; figures in docs/ring-tuned.md).

The branch of scenes/ring_tuned.toml's case (``--gap`` um or ``--preload`` N) for a ring of ``--blades``,
at H = 10 over 6000-14000 r/min, with the ring's stability against every nodal diameter at every point
(``--spread 0``) and at each ``--spread`` count of spread points (then where the verdict changes,
ring_hb.located_changes; ``--at``: the time points' speeds whose stretches are evaluated too). Prints
per run the points evaluated, CPU and wall seconds, and how many points' answers (stable, unstable, not
decided: comparisons.ring_tuned.branch_answers) differ from the first run's, by kind.

    python benchmarks/bench_ring_branch_stability.py --gap 1 --blades 48 --spread 0 40 12 [--at 8000 10000 12000]
"""

from __future__ import annotations

import argparse
import time
from collections import Counter

import numpy as np

from comparisons.ring_tuned import branch_answers
from shroud.analysis.ring_hb import run_ring_hb
from workbench.scene import load_scene


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    case = ap.add_mutually_exclusive_group(required=True)
    case.add_argument("--gap", type=float, help="um")
    case.add_argument("--preload", type=float, help="N0 per interface, N")
    ap.add_argument("--blades", type=int, default=24)
    ap.add_argument("--spread", type=int, nargs="+", default=[0, 40])
    ap.add_argument("--at", type=float, nargs="*", default=[])
    a = ap.parse_args()
    scene = load_scene("scenes/ring_tuned.toml")
    contact = {"contact.gap": a.gap * 1e-6} if a.gap is not None else {"contact.N0": a.preload}
    p = scene.params.updated({"ring.mistuning": (), "ring.mistuning_std": 0.0, **contact, "ring.blades": a.blades})
    first = None
    for spread in a.spread:
        wall, cpu = time.perf_counter(), time.process_time()
        b = run_ring_hb(p, "reduced", 6000.0, 14000.0, 10, stability_points=spread or None,
                        stability_at=tuple(a.at)).branch
        cpu, wall = time.process_time() - cpu, time.perf_counter() - wall
        answers = branch_answers(b)
        first = first or answers
        differ = Counter((str(x), str(y)) for x, y in zip(first, answers) if x != y)
        print(f"{a.blades} blades, spread {spread or 'every point'}: evaluated "
              f"{int(np.isfinite(b.max_multiplier).sum())} of {len(b.rpm)}, {cpu:.1f} s CPU, {wall:.1f} s wall; "
              f"answers differing from the first run's: {sum(differ.values())} {dict(differ)}", flush=True)


if __name__ == "__main__":
    main()
