"""Cost of one full-solid harmonic-balance checkpoint, on 1 or 2 MPI ranks.

Goal: under 3 min on 2 cores. A checkpoint (shroud.analysis.hb.checkpoint,
model "fe") is: build the solid at the speed (DOLFINx, Rayleigh from its
two lowest modes), condense it exactly on its contact coordinates per
harmonic (reference_fe.harmonic: MUMPS on the real block form, m + 1
right-hand sides per harmonic), reach the reduced solid's state there (the
start), and the condensed Newton. Each repeat condenses anew (the
in-process store of condensations is emptied). Medians of ``--repeat``
runs, wall time in s, printed by rank 0:

    python benchmarks/bench_hb_solid.py [--rpm 10000] [--harmonics 7] [--samples 256] [--repeat 3] [--set KEY=VALUE ...]
    mpirun -n 2 python benchmarks/bench_hb_solid.py ...
"""

from __future__ import annotations

import argparse
import os
import statistics

from reference_fe import harmonic
from shroud.analysis.hb import checkpoint
from workbench.scene import load_scene
from shroud.base.parallel import mpi_rank, mpi_size


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--rpm", type=float, default=10000.0)
    ap.add_argument("--harmonics", type=int, default=7)
    ap.add_argument("--samples", type=int, default=256)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
    args = ap.parse_args()
    params = load_scene(None, args.set).params
    say = print if mpi_rank() == 0 else (lambda *a, **k: None)
    say(f"load average at start: {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores; {mpi_size()} rank(s)")
    runs = []
    for i in range(args.repeat):
        while harmonic._KEPT:
            harmonic._release(harmonic._KEPT.popitem()[1][0])
        cp = checkpoint(params, "fe", args.rpm, args.harmonics, args.samples)
        runs.append(cp)
        say(f"  run {i + 1}: condensation {cp.linear_s:.1f} s, start {cp.start_s:.1f} s, Newton {cp.newton_s:.1f} s "
            f"({cp.iterations} iterations), stability {cp.stability_s:.1f} s, total {cp.elapsed_s:.1f} s; "
            f"v_L {cp.amplitude_v_L:.6e} m, {'stable' if cp.stable else 'unstable'} {cp.largest_multiplier}")
    med = {k: statistics.median(getattr(r, k) for r in runs)
           for k in ("linear_s", "start_s", "newton_s", "stability_s", "elapsed_s")}
    cp = runs[-1]
    say(f"fe checkpoint at {args.rpm:g} r/min, {cp.dofs} DOF condensed on {cp.condensed_on} contact coordinates, "
        f"H = {args.harmonics}, {args.samples} samples, {mpi_size()} rank(s), medians of {args.repeat}: "
        f"condensation {med['linear_s']:.1f} s, start (fe-reduced) {med['start_s']:.1f} s, "
        f"Newton {med['newton_s']:.1f} s, stability {med['stability_s']:.1f} s, total {med['elapsed_s']:.1f} s")


if __name__ == "__main__":
    main()
