"""The tuned ring's HB curve with stability against the single blade's, side by side (issue 32; docs/performance.md).

The case of issue 32: 24 blades, preload 20 N, kn 1e7, kt 5e6, mu 0.3, alpha 30 deg (``--set`` adds or
overrides keys), the reduced beam, H = 10, 8000-14000 r/min. In one run, alternated ``--repeat`` times
after a first round that compiles the kernels and builds the models:

- the single blade between fixed neighbours (shroud.analysis.hb.run_hb), stability at every point;
- the tuned ring's sector (ring_hb.run_ring_hb) with the ring's stability at every point;
- the same with the ring's stability at ``--spread`` points and where the verdict changes
  (ring_hb.located_changes; 0: not run);
- the same without stability.

Prints per curve its points, whether it is complete, CPU and wall medians and the ratio of the CPU
median to the single blade's. ``--anatomy``: where a ring point's stability goes, piece by piece, at
every point of the curve (the pieces of ring_hb.ring_stability timed one by one, CPU s). ``--profile``:
the ring's curve with stability at every point under cProfile (CPU clock), summed by piece (the names of
before and after the ring's halves, so that it runs on either tree).

    OMP_NUM_THREADS=1 python benchmarks/bench_ring_curve.py [--repeat 3] [--spread 12] [--anatomy] [--profile]
"""

from __future__ import annotations

import argparse
import cProfile
import pstats
import statistics
import time

import numpy as np

import reduced_model  # noqa: F401  (registers the beams)
from shroud.analysis import ring_hb
from shroud.analysis.hb import REFINED_ITERATIONS, SpeedModel, run_hb
from shroud.core import harmonic_balance as hb
from shroud.params import Parameters

CASE = ["ring.blades=24", "contact.N0=20", "contact.kn=1e7", "contact.kt=5e6", "contact.mu=0.3",
        "contact.alpha_deg=30"]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--set", nargs="*", default=[], metavar="KEY=VALUE")
    ap.add_argument("--rpm-from", type=float, default=8000.0)
    ap.add_argument("--rpm-to", type=float, default=14000.0)
    ap.add_argument("--harmonics", type=int, default=10)
    ap.add_argument("--spread", type=int, default=12)
    ap.add_argument("--anatomy", action="store_true")
    ap.add_argument("--profile", action="store_true")
    a = ap.parse_args()
    p = Parameters().with_overrides([*CASE, *a.set])
    lo, hi, H = a.rpm_from, a.rpm_to, a.harmonics
    if a.profile:
        profile(p, lo, hi, H)
        return
    curves = {"single blade, stability at every point": lambda: run_hb(p, "reduced", lo, hi, harmonics=H),
              "ring sector, stability at every point": lambda: ring_hb.run_ring_hb(p, "reduced", lo, hi, H).branch,
              f"ring sector, stability at {a.spread} spread points and changes":
                  lambda: ring_hb.run_ring_hb(p, "reduced", lo, hi, H, stability_points=a.spread).branch,
              "ring sector, no stability": lambda: ring_hb.run_ring_hb(p, "reduced", lo, hi, H, stability=False).branch}
    if not a.spread:
        curves = {k: v for k, v in curves.items() if "spread" not in k}
    results = {name: curve() for name, curve in curves.items()}       # compiles, builds the models
    cpu = {name: [] for name in curves}
    wall = {name: [] for name in curves}
    for _ in range(a.repeat):
        for name, curve in curves.items():
            w0, c0 = time.perf_counter(), time.process_time()
            results[name] = curve()
            wall[name].append(time.perf_counter() - w0)
            cpu[name].append(time.process_time() - c0)
    single = statistics.median(next(iter(cpu.values())))
    print(f"{p.ring.blades} blades, {lo:.0f}-{hi:.0f} r/min, H = {H}; CPU and wall medians of {a.repeat}:")
    for name, r in results.items():
        c, w = statistics.median(cpu[name]), statistics.median(wall[name])
        evaluated = int(np.isfinite(np.asarray(r.max_multiplier, float)).sum())
        print(f"  {name}: {len(r.rpm)} points ({evaluated} with multipliers), complete {r.complete}, "
              f"CPU {c:.3f} s ({1e3 * c / len(r.rpm):.2f} ms a point), wall {w:.3f} s; "
              f"{c / single:.1f}x the single blade's CPU", flush=True)
    if a.anatomy:
        anatomy(p, lo, hi, H, results["ring sector, no stability"])


def profile(p: Parameters, lo: float, hi: float, H: int) -> None:
    """cProfile's cumulative CPU times of the ring's curve with stability at every point, by piece."""
    ring_hb.run_ring_hb(p, "reduced", lo, lo + 50.0, H)                # compiles, builds the models
    pr = cProfile.Profile(timer=time.process_time)
    pr.enable()
    r = ring_hb.run_ring_hb(p, "reduced", lo, hi, H).branch
    pr.disable()
    stats = pstats.Stats(pr).stats

    def cum(*names, where=""):
        return sum(v[3] for k, v in stats.items() if k[2] in names and k[0].endswith(where))
    total, stability = cum("run_ring_hb"), cum("ring_stability")
    rows = {"the whole curve": total,
            "the branch (continuation, sector Newton, the models at its speeds)": total - stability,
            "ring_stability": stability,
            "  monodromies at the AFT's samples and at half of them": cum("orbit_stability", "blocks_stability",
                                                                          where="floquet.py"),
            "  monodromy at 2 H": cum("ring_multipliers", "_wave_multipliers", where="ring_hb.py"),
            "  the ring's matrices (_ring_flow before, ring_blocks after)": cum("_ring_flow", "ring_blocks"),
            "  sector Newton at 2 H (and the first point's)": cum("sector_newton", where="ring_hb.py"),
            "    in the monodromies: the run loop (floquet._flow_grazing)": cum("_flow_grazing"),
            "    in the monodromies: eigenvalues (numpy eigvals)": cum("eigvals"),
            "SpeedModel builds (systems, H and 2 H harmonics; in the branch and the stability)":
                cum("system", "_linear_at", where="analysis/hb.py")}
    n = len(r.rpm)
    print(f"cProfile, the ring's curve with stability at every point, {n} points, complete {r.complete}:")
    for name, s in rows.items():
        print(f"  {name}: {s:.3f} s ({1e3 * s / n:.2f} ms a point, {100 * s / total:.0f} %)")


def anatomy(p: Parameters, lo: float, hi: float, H: int, branch) -> None:
    """ring_hb.ring_stability's pieces at every point of ``branch`` (CPU s summed over the points): the
    blade's model and harmonics at the speed (SpeedModel, built afresh here), the ring's subspaces
    (ring_blocks), the monodromies at the AFT's samples and at half of them, the 2 H Newton and the 2 H
    monodromy."""
    basis = hb.fourier(H, branch.samples)
    at = ring_hb.ring_model_at_speed(p, "reduced")
    pieces = dict.fromkeys(["SpeedModel builds (system, H and 2 H harmonics)", "ring_blocks",
                            "monodromy, the AFT's samples", "monodromy, half the samples",
                            "sector Newton at 2 H", "monodromy at 2 H"], 0.0)
    names = list(pieces)
    for rpm, X in zip(branch.rpm, branch.X):
        clock = [time.process_time()]

        def lap(i):
            clock.append(time.process_time())
            pieces[names[i]] += clock[-1] - clock[-2]
        speeds = SpeedModel(at, H)
        system, lin, _, _ = speeds.at(rpm)
        fine = speeds.refined()
        fine_lin = fine.linear(rpm)[0]
        lap(0)
        sector = ring_hb.sector_of(system, p, H)
        blocks, count = ring_hb.ring_blocks(system, sector)
        lap(1)
        ring_hb._wave_multipliers(blocks, count, sector, lin, X, basis)
        lap(2)
        half = ring_hb._ring_samples(sector, max(ring_hb._ring_samples(sector, basis.samples) // 2, 2 * H + 1))
        ring_hb._wave_multipliers(blocks, count, sector, lin, X, hb.fourier(H, half))
        lap(3)
        fine_basis = hb.fourier(2 * H, max(basis.samples, 8 * H + 1))
        X0 = np.zeros((fine_basis.nh, X.size // basis.nh))
        X0[:basis.nh] = X.reshape(basis.nh, -1)
        X2, ok = ring_hb.sector_newton(X0.ravel(), fine_lin, sector, fine_basis, max_iterations=REFINED_ITERATIONS)
        lap(4)
        if ok:
            ring_hb._wave_multipliers(blocks, count, sector, fine_lin, X2, fine_basis)
        lap(5)
    total = sum(pieces.values())
    print(f"ring_stability's pieces over the {len(branch.rpm)} points of the curve without stability "
          f"(CPU, {1e3 * total / len(branch.rpm):.1f} ms a point):")
    for name, s in pieces.items():
        print(f"  {name}: {s:.3f} s ({1e3 * s / len(branch.rpm):.2f} ms a point, {100 * s / total:.0f} %)")


if __name__ == "__main__":
    main()
