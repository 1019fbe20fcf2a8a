"""The 1 um gap case of issue 23: which P1 states of a time-domain sweep the HB branches hold, and at what cost.

Gap 1 um, alpha 30 deg, kt 5e6 N/m, mu 0.3 (the Fig. 11 contact), 5000-25000 r/min. A sweep from rest every
250 r/min (81 speeds); at each P1 point the state it reached is found by Newton from the harmonics of its
contact coordinates over its last period (shroud.analysis.hb.time_domain_state), and looked for on the
branch continued from 5000 r/min alone and on the family seeded from runs at 40 other speeds
(shroud.analysis.hb.run_hb_family): held when a branch's state there is the same (amplitude within 1e-3)
and not shown unstable. Prints the counts and the wall times (docs/hb-stability.md).

    PYTHONPATH=$PWD OMP_NUM_THREADS=1 python benchmarks/bench_hb_family.py
"""

from __future__ import annotations

import time

import numpy as np

from comparisons._hb import starts_at
from shroud.analysis.hb import checkpoint, run_hb, run_hb_family, time_domain_state
from shroud.params import Parameters

PARAMS = Parameters().updated({"contact.alpha_deg": 30.0, "contact.kt": 5e6, "contact.mu": 0.3,
                               "contact.gap": 1e-6})


def held(branches, rpm: float, amplitude: float) -> bool:
    for br in branches:
        for X, _ in starts_at(br, rpm):
            sol = checkpoint(PARAMS, "reduced", rpm, start=X, retry=False)
            if sol.converged and abs(sol.amplitude_v_L / amplitude - 1) <= 1e-3 and sol.stable is not False:
                return True
    return False


def main() -> None:
    t0 = time.perf_counter()
    continued = run_hb(PARAMS, "reduced", 5000.0, 25000.0, min_points=60)
    t1 = time.perf_counter()
    family = run_hb_family(PARAMS, "reduced", 5000.0, 25000.0, np.arange(5125.0, 25000.0, 500.0), min_points=60)
    t2 = time.perf_counter()
    print(f"continued branch: {len(continued.rpm)} points, {t1 - t0:.1f} s; "
          f"{int(continued.uncertain.sum())} undecided, {sum(s is False for s in continued.stable)} unstable")
    print(f"family: {len(family.branches)} branches ({', '.join(str(len(b.rpm)) for b in family.branches)} points), "
          f"{t2 - t1:.1f} s; new branches from seeds at "
          + ", ".join(f"{s.rpm:.0f}" for s in family.seeds if s.outcome == "new branch") + " r/min")
    p1 = alone = together = 0
    for rpm in np.linspace(5000.0, 25000.0, 81):
        Y, period = time_domain_state(PARAMS, "reduced", rpm)
        if period != 1:
            continue
        p1 += 1
        reached = checkpoint(PARAMS, "reduced", rpm, start=Y.ravel(), retry=False)
        a = reached.amplitude_v_L
        alone += held([continued], rpm, a)
        together += held(family.branches, rpm, a)
    print(f"P1 states of the sweep: {p1}; on the continued branch alone: {alone}; on the family: {together}")


if __name__ == "__main__":
    main()
