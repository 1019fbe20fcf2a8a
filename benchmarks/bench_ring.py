"""Speed of the whole ring in time (issue 26; figures go in docs/ring.md).

Goal: a 24-blade ring of the reduced beam (nr 6), 400 excitation periods
(102,400 steps, every interface's contact solved at once each step), in
under 2 s after compilation. Times are medians of CPU time over repeated
runs (other processes share the cores; the wall time is printed too).

    python benchmarks/bench_ring.py [--repeat 5] [--blades 24] [--periods 400] [--models reduced extended]
"""

from __future__ import annotations

import argparse
import statistics
import time

import reduced_model  # noqa: F401  (registers the beams)
from shroud.analysis.ring import build_ring, run_ring
from shroud.core import signals
from shroud.params import Parameters


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--blades", type=int, default=24)
    ap.add_argument("--periods", type=int, default=400)
    ap.add_argument("--models", nargs="+", default=["reduced", "extended"])
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
    args = ap.parse_args()
    p = Parameters().with_overrides([f"ring.blades={args.blades}", f"time.periods={args.periods}", *args.set])
    for model in args.models:
        ring = build_ring(p, model)
        run_ring(ring, p.updated({"time.periods": 1}))          # compile (or load numba's cache)
        wall, cpu, tr = [], [], None
        for _ in range(args.repeat):
            w0, c0 = time.perf_counter(), time.process_time()
            tr = run_ring(ring, p)
            wall.append(time.perf_counter() - w0)
            cpu.append(time.process_time() - c0)
        spp = p.time.steps_per_period
        amps = [signals.amplitude(tr.tip[:, j, 0], spp) for j in range(ring.count)]
        print(f"{model}: {ring.count} blades x {ring.blade_dofs} DOF, {tr.steps} steps: "
              f"CPU {statistics.median(cpu):.3f} s, wall {statistics.median(wall):.3f} s (median of {args.repeat}); "
              f"v_L amplitude {1e6 * min(amps):.3f} .. {1e6 * max(amps):.3f} um, "
              f"energy balance {tr.energy.relative_error:.2e}, most contact iterations {tr.contact_iterations}")


if __name__ == "__main__":
    main()
