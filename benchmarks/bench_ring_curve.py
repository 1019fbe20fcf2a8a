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
every point of the curve (the pieces of ring_hb.ring_stability timed one by one, CPU s; the monodromy at
the AFT's samples split into its halves' flows over T / q and their eigenvalues), then the floor: the
ring-size eigenproblem alone and one monodromy alone against the single blade's point and curve.
``--profile``: the ring's curve with stability at every point under cProfile (CPU clock), summed by piece
(the names of before and after the ring's halves, so that it runs on either tree).

    OMP_NUM_THREADS=1 python benchmarks/bench_ring_curve.py [--repeat 3] [--spread 12] [--anatomy] [--profile]

Result (11:51-11:57 UTC 2026-11-29, ``--repeat 3 --anatomy``, load 10-12 on the 2 cores; docs/performance.md):
the goal, the ring's curve with stability at most 2x the single blade's, is not met and no exact method
meets it. The single blade 31 points, 0.067 s CPU (2.15 ms a point); the ring with its stability at every
point 116 points, 11.28 s (97.2 ms a point), 169x; at 12 spread points and the changes 55x; without
stability 0.327 s (2.82 ms a point), 4.9x: the ring's branch alone (116 points through its folds against
31) is past 2x before any stability. The ring-size eigenproblems alone (two halves of 156 states) take
5.9 ms a point, 2.7x the single blade's whole point, 10x its curve over the ring's points; one monodromy's
multipliers (no error estimate) 34 ms a point, 59x. The monodromy is already the one from g / N of the
period by the wave's symmetry (floquet.symmetric_monodromy), on the ring's halves.
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
from shroud.core import floquet
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
        blade = next(iter(results.values()))
        anatomy(p, lo, hi, H, results["ring sector, no stability"], single / len(blade.rpm), len(blade.rpm))


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
            "  sector Newton at 2 H (and the first point's)": cum("sector_newton", where="ring_hb.py")
                                                               + cum("sector_newton", where="starts.py"),
            "    in the monodromies: the run loop (floquet._flow_grazing)": cum("_flow_grazing"),
            "    in the monodromies: eigenvalues (numpy eigvals)": cum("eigvals"),
            "SpeedModel builds (systems, H and 2 H harmonics; in the branch and the stability)":
                cum("system", "_linear_at", where="analysis/hb.py")}
    n = len(r.rpm)
    print(f"cProfile, the ring's curve with stability at every point, {n} points, complete {r.complete}:")
    for name, s in rows.items():
        print(f"  {name}: {s:.3f} s ({1e3 * s / n:.2f} ms a point, {100 * s / total:.0f} %)")


def anatomy(p: Parameters, lo: float, hi: float, H: int, branch, single_point: float, single_points: int) -> None:
    """ring_hb.ring_stability's pieces at every point of ``branch`` (CPU s summed over the points): the
    blade's model and harmonics at the speed (SpeedModel, built afresh here), the ring's subspaces
    (ring_blocks), the monodromy at the AFT's samples (its halves' flows over T / q with their powers, and
    their eigenvalues apart), at half the samples, the 2 H Newton and the 2 H monodromy; then the floor
    against the single blade's curve (``single_point`` its CPU s a point, ``single_points`` its points):
    the ring-size eigenproblem alone, one monodromy alone, over the ring's points."""
    basis = hb.fourier(H, branch.samples)
    at = ring_hb.ring_model_at_speed(p, "reduced")
    pieces = dict.fromkeys(["SpeedModel builds (system, H and 2 H harmonics)", "ring_blocks",
                            "monodromy, the AFT's samples: the halves' flows over T / q (run loop) and powers",
                            "monodromy, the AFT's samples: the halves' eigenvalues (the ring-size eigenproblem)",
                            "monodromy, half the samples", "sector Newton at 2 H", "monodromy at 2 H"], 0.0)
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
        orbit = ring_hb._ring_orbit(sector, lin, X, basis, ring_hb._ring_samples(sector, basis.samples), count)
        monodromies = [floquet.symmetric_monodromy(M, C, K, W, law, *orbit[:2], lin.omega, orbit[2], symmetry)[0]
                       for M, C, K, W, law, symmetry in blocks]
        lap(2)
        for Phi in monodromies:
            floquet.multipliers(Phi)
        lap(3)
        half = ring_hb._ring_samples(sector, max(ring_hb._ring_samples(sector, basis.samples) // 2, 2 * H + 1))
        ring_hb._wave_multipliers(blocks, count, sector, lin, X, hb.fourier(H, half))
        lap(4)
        fine_basis = hb.fourier(2 * H, max(basis.samples, 8 * H + 1))
        X0 = np.zeros((fine_basis.nh, X.size // basis.nh))
        X0[:basis.nh] = X.reshape(basis.nh, -1)
        X2, ok = ring_hb.sector_newton(X0.ravel(), fine_lin, sector, fine_basis, max_iterations=REFINED_ITERATIONS)
        lap(5)
        if ok:
            ring_hb._wave_multipliers(blocks, count, sector, fine_lin, X2, fine_basis)
        lap(6)
    total = sum(pieces.values())
    print(f"ring_stability's pieces over the {len(branch.rpm)} points of the curve without stability "
          f"(CPU, {1e3 * total / len(branch.rpm):.1f} ms a point):")
    for name, s in pieces.items():
        print(f"  {name}: {s:.3f} s ({1e3 * s / len(branch.rpm):.2f} ms a point, {100 * s / total:.0f} %)")
    flows, eigs = (pieces[names[i]] for i in (2, 3))
    curve = single_point * single_points
    print(f"floor against the single blade's curve ({single_points} points, {1e3 * single_point:.2f} ms a point, "
          f"its stability included; the ring's {len(branch.rpm)} points):")
    for name, s in (("the ring-size eigenproblems alone", eigs), ("one monodromy's multipliers alone", flows + eigs)):
        print(f"  {name}: {1e3 * s / len(branch.rpm):.2f} ms a point ({s / len(branch.rpm) / single_point:.1f}x the "
              f"single blade's whole point), over the ring's curve {s / curve:.1f}x the single blade's curve")


if __name__ == "__main__":
    main()
