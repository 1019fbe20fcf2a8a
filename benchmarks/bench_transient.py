"""Speed of the transient kernel and of a sweep (figures go in the README).

Goals: 100 excitation periods (25,600 steps, nr = 6, contact on) in <= 10 ms
after compilation (500x the paper's 5.37 s); the 30-DOF full model in
<= 30 ms; the extended beam (torsion, rigid shroud: 8 contact points), nr = 6,
in <= 15 ms; a 300-speed sweep of 200 periods each in <= 20 s on 2 cores.
The ratio to the plain reference loop is measured in the same run.

    python benchmarks/bench_transient.py [--sweep-speeds 300]
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np

from comparisons.paper import TABLE3_SECONDS
from shroud.analysis.api import build_system
from shroud.analysis.transient import contact_law_for
from shroud.core.newmark import NewmarkScheme, integrate
from shroud.params import Parameters
from shroud.analysis.sweep import run_sweep


def best_of(fn, repeat: int) -> tuple[float, float]:
    """(best wall time, CPU time of that run), s."""
    best = (float("inf"), 0.0)
    for _ in range(repeat):
        w0, c0 = time.perf_counter(), time.process_time()
        fn()
        best = min(best, (time.perf_counter() - w0, time.process_time() - c0))
    return best


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--sweep-speeds", type=int, default=300)
    ap.add_argument("--repeat", type=int, default=7)
    args = ap.parse_args()
    print(f"load average at start: {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores "
          "(other processes share the cores: compare CPU times)")
    params = Parameters()                                   # Fig. 8 case: N0 = 0, 10000 r/min
    for model in ("reduced", "full", "extended"):
        system = build_system(params, model)
        law = contact_law_for(system, params.contact)
        scheme = NewmarkScheme(params.time_step)
        steps = params.time.periods * params.time.steps_per_period
        run = lambda method: integrate(system, law, scheme, steps, method=method, energy_window=2560)  # noqa: E731
        run("kernel")                                       # compile / load the cache
        kw, kc = best_of(lambda: run("kernel"), args.repeat)
        free = contact_law_for(system, params.updated({"contact.enabled": False}).contact)
        fw, fc = best_of(lambda: integrate(system, free, scheme, steps, method="kernel", energy_window=2560),
                         args.repeat)
        rw, rc = best_of(lambda: run("reference"), 1)
        tr = run("kernel")
        print(f"{model:8s} {system.dofs:3d} DOF, {steps} steps, implicit contact "
              f"(max {tr.contact_iterations} active-set iterations): kernel {1e3 * kw:.1f} ms wall "
              f"({1e3 * kc:.1f} ms CPU, {1e9 * kc / steps:.0f} ns/step; contact off {1e3 * fc:.1f} ms CPU), "
              f"reference {rw:.2f} s; ratio {rw / kw:.0f}x; "
              f"paper Table 3: {TABLE3_SECONDS.get(model, '-')} s")
    p = params.updated({"time.periods": 200})
    rpms = np.linspace(4000, 30000, args.sweep_speeds)
    run_sweep(p, "reduced", rpms[:4])
    t0 = time.perf_counter()
    res = run_sweep(p, "reduced", rpms)
    wall = time.perf_counter() - t0
    print(f"sweep: {len(rpms)} speeds x 200 periods (reduced, build + run each): {wall:.1f} s wall, "
          f"{res.cpu_s:.1f} s summed over runs; resonance {res.resonance['rpm']:.0f} r/min")


if __name__ == "__main__":
    main()
