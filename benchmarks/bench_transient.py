"""Speed of the transient kernel and of a sweep (figures go in the README).

Goals: 100 excitation periods (25,600 steps, nr = 6, contact on) in <= 10 ms
after compilation (500x the paper's 5.37 s); the 30-DOF full model in
<= 30 ms; the extended beam (torsion, rigid shroud: 4 contact points), nr = 6,
in <= 15 ms; a 300-speed sweep of 200 periods each in <= 20 s on 2 cores.
Times are medians of CPU time over repeated runs (other processes share the
cores; the wall time is printed too). The ratio to the plain reference loop
is measured in the same run.

    python benchmarks/bench_transient.py [--repeat 15] [--sweep-speeds 300] [--against REV]
                                         [--models reduced full extended [fe-reduced]]

``--against REV`` also times the kernel of shroud/core/newmark.py as it was at
git revision REV against the working tree's, interleaved run by run in this
process (the same systems, the same load), and says whether their
trajectories are identical bit for bit.
"""

from __future__ import annotations

import argparse
import importlib.util
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

import shroud.core.newmark as newmark
from comparisons.paper import TABLE3_SECONDS
from shroud.analysis.api import build_system
from shroud.analysis.sweep import run_sweep
from shroud.analysis.transient import contact_law_for
from shroud.params import Parameters

MODELS = ("reduced", "full", "extended")
RECORDS = ("tip", "normal", "friction", "tangential", "state", "element_share", "element_peak_normal")


def timed(fn, repeat: int) -> tuple[float, float]:
    """(median wall time, median CPU time) of ``repeat`` calls, s."""
    wall, cpu = [], []
    for _ in range(repeat):
        w0, c0 = time.perf_counter(), time.process_time()
        fn()
        wall.append(time.perf_counter() - w0)
        cpu.append(time.process_time() - c0)
    return statistics.median(wall), statistics.median(cpu)


def newmark_at(rev: str):
    """shroud/core/newmark.py as it was at git revision ``rev``, loaded as a module of its own."""
    root = Path(__file__).resolve().parents[1]
    source = subprocess.run(["git", "show", f"{rev}:shroud/core/newmark.py"], cwd=root, check=True,
                            capture_output=True, text=True).stdout
    path = Path(tempfile.mkdtemp(prefix="newmark_at_")) / "newmark_at_rev.py"
    path.write_text(source)
    spec = importlib.util.spec_from_file_location("newmark_at_rev", path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module          # dataclasses look their module up
    spec.loader.exec_module(module)
    return module


def identical(a, b) -> bool:
    """Two trajectories equal bit for bit (records and energy balance)."""
    return (all(np.array_equal(getattr(a, f), getattr(b, f)) for f in RECORDS)
            and a.energy.to_json() == b.energy.to_json())


def side_by_side(params: Parameters, rev: str, rounds: int, models) -> None:
    """Median CPU time of the kernel at ``rev`` and now, interleaved; whether the results are identical."""
    versions = {rev: newmark_at(rev), "now": newmark}
    steps = params.time.periods * params.time.steps_per_period
    print(f"kernel at {rev} against the working tree, {rounds} interleaved runs each (median CPU time):")
    for model in models:
        system = build_system(params, model)
        law = contact_law_for(system, params.contact)

        def run(module):
            return module.integrate(system, law, module.NewmarkScheme(params.time_step), steps, method="kernel",
                                    energy_window=2560)
        results = {name: run(module) for name, module in versions.items()}     # compile / load the caches
        cpu = {name: [] for name in versions}
        for _ in range(rounds):
            for name, module in versions.items():
                c0 = time.process_time()
                run(module)
                cpu[name].append(time.process_time() - c0)
        before, now = (statistics.median(cpu[name]) for name in versions)
        print(f"  {model:8s} {system.dofs:3d} DOF: {rev} {1e3 * before:.2f} ms, now {1e3 * now:.2f} ms "
              f"({before / now:.2f}x); identical trajectories: {identical(*results.values())}")


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--sweep-speeds", type=int, default=300, help="0: no sweep")
    ap.add_argument("--repeat", type=int, default=15)
    ap.add_argument("--against", metavar="REV", help="also time newmark.py at this git revision, side by side")
    ap.add_argument("--models", nargs="+", default=list(MODELS), help="registered models with a dense kernel")
    args = ap.parse_args()
    print(f"load average at start: {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores "
          "(other processes share the cores: compare CPU times)")
    params = Parameters()                                   # Fig. 8 case: N0 = 0, 10000 r/min
    steps = params.time.periods * params.time.steps_per_period
    scheme = newmark.NewmarkScheme(params.time_step)
    for model in args.models:
        system = build_system(params, model)
        law = contact_law_for(system, params.contact)
        run = lambda method: newmark.integrate(system, law, scheme, steps, method=method,  # noqa: E731
                                               energy_window=2560)
        run("kernel")                                       # compile / load the cache
        kw, kc = timed(lambda: run("kernel"), args.repeat)
        free = contact_law_for(system, params.updated({"contact.enabled": False}).contact)
        fw, fc = timed(lambda: newmark.integrate(system, free, scheme, steps, method="kernel",
                                                 energy_window=2560), args.repeat)
        rw, rc = timed(lambda: run("reference"), 1)
        tr = run("kernel")
        print(f"{model:8s} {system.dofs:3d} DOF, {steps} steps, implicit contact "
              f"(max {tr.contact_iterations} active-set iterations): kernel {1e3 * kc:.1f} ms CPU "
              f"({1e3 * kw:.1f} ms wall, {1e9 * kc / steps:.0f} ns/step; contact off {1e3 * fc:.1f} ms CPU), "
              f"reference {rw:.2f} s; ratio {rw / kw:.0f}x; "
              f"paper Table 3: {TABLE3_SECONDS.get(model, '-')} s")
    if args.against:
        side_by_side(params, args.against, args.repeat, args.models)
    if args.sweep_speeds > 0:
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
