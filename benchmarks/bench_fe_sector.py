"""Cost and convergence in H of the fe-reduced ring's sector HB (issue 26; figures in docs/ring.md).

One point of the travelling wave (`ring_hb.sector_solve` from the linear starts) of 3 fe-reduced blades,
unloaded by default, on the speed-range basis the harmonic balance uses; CPU and wall medians over
``--repeat`` runs (other processes share the cores). ``--ring``: the whole ring in time from rest on
the same basis (80 periods), every blade's amplitude against the wave's.

    python benchmarks/bench_fe_sector.py [--harmonics 10 20 30] [--rpm 6000 8000 10000] [--repeat 3]
                                         [--set contact.N0=5] [--ring]
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

from shroud.analysis.hb import SpeedModel
from shroud.analysis.ring import run_ring
from shroud.analysis.ring_hb import _details, ring_model_at_speed, sector_of, sector_solve
from shroud.core import harmonic_balance as hb
from shroud.core import signals
from shroud.core.ring import ring_of
from shroud.params import Parameters


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--harmonics", nargs="*", type=int, default=[10, 20, 30])
    ap.add_argument("--rpm", nargs="*", type=float, default=[6000.0])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--set", action="append", default=["contact.N0=0"], metavar="KEY=VALUE")
    ap.add_argument("--ring", action="store_true", help="the whole ring in time from rest on the same basis")
    args = ap.parse_args()
    for rpm in args.rpm:
        p = Parameters().with_overrides(["ring.blades=3", f"speed.rpm={rpm}", "time.periods=80", *args.set])
        blade = ring_model_at_speed(p, "fe-reduced")
        for H in args.harmonics:
            basis = hb.fourier(H, hb.default_samples(H))
            speeds = SpeedModel(blade, H)
            system, lin, _, _ = speeds.at(rpm)
            sector = sector_of(system, p, H)
            wall, cpu, X = [], [], None
            for _ in range(args.repeat):
                w0, c0 = time.perf_counter(), time.process_time()
                X = sector_solve(lin, sector, basis)
                wall.append(time.perf_counter() - w0)
                cpu.append(time.process_time() - c0)
            amp = _details(speeds, sector, basis, X, rpm, False)["amplitude_v_L"]
            print(f"{rpm:.0f} r/min, H = {H} ({basis.samples} samples, {X.size} unknowns): {amp * 1e6:.5f} um, "
                  f"CPU median {statistics.median(cpu):.2f} s, wall {statistics.median(wall):.2f} s "
                  f"(of {args.repeat})", flush=True)
        if args.ring:
            tr = run_ring(ring_of([blade(rpm)] * 3, p.load.ke), p)
            spp = p.time.steps_per_period
            amps = np.array([signals.amplitude(tr.tip[:, j, 0], spp) for j in range(3)])
            print(f"{rpm:.0f} r/min, ring in time ({p.time.periods} periods, period "
                  f"{signals.detect_period(tr.tip[:, 0, 0], spp)}): blades {np.round(amps * 1e6, 5)} um, "
                  f"against H = {H}'s wave: {np.round((amps / amp - 1) * 100, 2)} %", flush=True)


if __name__ == "__main__":
    main()
