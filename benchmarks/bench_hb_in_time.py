"""The 1 um gap case of issue 32: the HB branch's verdicts against the project's own integrator.

Gap 1 um, alpha 30 deg, kt 5e6 N/m, kn 1e7 N/m, mu 0.3. What `shroud sweep --rpm-from 5000 --rpm-to 25000
--rpm-count 81 --set ...` (time domain, from rest, until settled) and `shroud sweep --method hb --rpm-from
5000 --rpm-to 30000 --rpm-count 201 --set ...` compute, and then:

- every P1 state of the time sweep: is it within 3 % in amplitude and 0.5 % in speed of a stable or
  undecided stretch (two neighbouring points neither shown unstable) of the continued branch, and of the
  family seeded from runs at 40 speeds (shroud.analysis.hb.run_hb_family)?
- every point called unstable: did the integrator started on it (shroud.core.period_map.check_in_time,
  100 periods) stay? (None must: a point where it stays is undecided.)
- the two ways: where both the monodromy along the orbit and the integrator's period map decide, do they
  agree, and by how much do their largest |multipliers| differ?
- cost: the branch with the integrator's checks against without them (CPU s).

    PYTHONPATH=$PWD OMP_NUM_THREADS=1 python benchmarks/bench_hb_in_time.py
"""

from __future__ import annotations

import time

import numpy as np

from shroud.analysis import hb
from shroud.analysis.sweep import run_sweep
from shroud.params import Parameters

PARAMS = Parameters().updated({"contact.gap": 1e-6, "contact.alpha_deg": 30.0, "contact.kt": 5e6,
                               "contact.kn": 1e7, "contact.mu": 0.3})
AMPLITUDE, SPEED = 0.03, 0.005


def on_stretch(branches, rpm: float, amplitude: float) -> bool:
    """Whether (rpm, amplitude) lies within AMPLITUDE and SPEED of a segment between two neighbouring points
    of a branch, neither shown unstable."""
    for br in branches:
        for i in range(len(br.rpm) - 1):
            if br.stable[i] is False or br.stable[i + 1] is False:
                continue
            t = np.linspace(0.0, 1.0, 41)
            r = (1 - t) * br.rpm[i] + t * br.rpm[i + 1]
            a = (1 - t) * br.amplitude_v_L[i] + t * br.amplitude_v_L[i + 1]
            if np.any((np.abs(r / rpm - 1) <= SPEED) & (np.abs(a / amplitude - 1) <= AMPLITUDE)):
                return True
    return False


def verdict_counts(br) -> str:
    return (f"{sum(s is True for s in br.stable)} stable, {sum(s is False for s in br.stable)} unstable, "
            f"{sum(s is None for s in br.stable)} undecided")


def main() -> None:
    w0 = time.perf_counter()
    sweep = run_sweep(PARAMS, "reduced", np.linspace(5000.0, 25000.0, 81))
    w1 = time.perf_counter()
    hb.run_hb(PARAMS, "reduced", 10600.0, 11600.0, min_points=12)      # compiles and warms both paths
    band = hb.PERIOD_MAP_BAND
    c0 = time.process_time()
    hb.PERIOD_MAP_BAND = -np.inf                 # the monodromy alone, for the cost
    plain = hb.run_hb(PARAMS, "reduced", 5000.0, 30000.0, min_points=201)
    hb.PERIOD_MAP_BAND = band
    c1 = time.process_time()
    continued = hb.run_hb(PARAMS, "reduced", 5000.0, 30000.0, min_points=201)
    c2 = time.process_time()
    family = hb.run_hb_family(PARAMS, "reduced", 5000.0, 30000.0, np.arange(5125.0, 25000.0, 500.0),
                              min_points=201, continued=continued)
    c3 = time.process_time()
    checked = sum(np.isfinite(continued.period_map_multiplier))
    print(f"time sweep: 81 speeds, wall {w1 - w0:.1f} s; branch: {len(continued.rpm)} points, CPU {c2 - c1:.1f} s "
          f"with the integrator's checks (period map at {checked} points), {c1 - c0:.1f} s without "
          f"({len(plain.rpm)} points); family: {len(family.branches)} branches, CPU {c3 - c2:.1f} s")
    print(f"continued branch: {verdict_counts(continued)}; the monodromy alone: {verdict_counts(plain)}")
    p1 = [(r, a) for r, a, p in zip(sweep.rpm, sweep.amplitude_v_L, sweep.period) if p == 1]
    alone = [r for r, a in p1 if not on_stretch([continued], r, a)]
    together = [r for r, a in p1 if not on_stretch(family.branches, r, a)]
    print(f"P1 states of the time sweep: {len(p1)}; off every stable or undecided stretch of the continued "
          f"branch: {len(alone)} ({', '.join(f'{r:.0f}' for r in alone)}); of the family: {len(together)} "
          f"({', '.join(f'{r:.0f}' for r in together)})")
    for name, branches in (("continued", [continued]), ("family", family.branches)):
        unstable = stays = undecided_by_time = disagree = 0
        gaps = []
        for br in branches:
            for i, s in enumerate(br.stable):
                check = br.in_time[i] if br.in_time else None
                reason = br.stability_reason[i] if br.stability_reason else ""
                unstable += s is False
                stays += s is False and check is not None and check["answer"] == "stays"
                undecided_by_time += "stays" in reason
                disagree += "disagree" in reason
                pm, err = br.period_map_multiplier[i], br.period_map_error[i]
                if np.isfinite(pm) and np.isfinite(err) and br.multiplier_error[i] < np.inf:
                    a, b = br.max_multiplier[i], pm
                    ea = br.multiplier_error[i]
                    if abs(a - 1) > ea and abs(b - 1) > err:
                        gaps.append(abs(a - b))
        unchecked = sum(1 for br in branches for i, s in enumerate(br.stable) if s is False and not br.in_time[i])
        print(f"{name}: {unstable} points called unstable, of which the integrator started on them stays at "
              f"{stays} (not checked: {unchecked}); {undecided_by_time} made undecided because it stays; "
              f"{disagree} where the two ways disagree; where both decide ({len(gaps)} points) their largest "
              f"|multiplier| differ by at most {max(gaps, default=float('nan')):.3f} (median "
              f"{float(np.median(gaps)) if gaps else float('nan'):.3f})")


if __name__ == "__main__":
    main()
