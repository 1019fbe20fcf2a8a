"""Speed of the whole ring in time (issue 26; figures go in docs/ring.md).

Goals: a 24-blade ring of the reduced beam (nr 6), 400 excitation periods
(102,400 steps, every interface's contact solved at once each step), in
under 2 s after compilation; a tuned sector HB curve at most 2x the single
blade's (``--hb``: the same speed range and H, the sector's with and
without the whole ring's multipliers at each point); a mistuned 24-blade
HB curve under 10 s (``--mistuned``: with the whole ring's linear solves
banded, shroud.core.cyclic_banded, and dense, runs alternated). Times are medians of
CPU time over repeated runs (other processes share the cores; the wall
time is printed too).

The fe-reduced ring (contact solved in the blades' space, docs/ring.md):
``--blades 3 --periods 20 --models fe-reduced``.

    python benchmarks/bench_ring.py [--repeat 5] [--blades 24] [--periods 400] [--models reduced extended]
                                    [--hb --rpm-from 6000 --rpm-to 14000] [--mistuned]
                                    [--monodromy 12 24 48 --harmonics 10 --models]
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

import reduced_model  # noqa: F401  (registers the beams)
from shroud.analysis.hb import SpeedModel, model_at_speed, run_hb
from shroud.analysis.ring import build_ring, run_ring
from shroud.analysis import ring_hb
from shroud.analysis.ring_hb import ring_multipliers, run_ring_hb, sector_of, sector_solve
from shroud.core import harmonic_balance as hb
from shroud.core import signals
from shroud.params import Parameters


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--blades", type=int, default=24)
    ap.add_argument("--periods", type=int, default=400)
    ap.add_argument("--models", nargs="*", default=["reduced", "extended"])
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
    ap.add_argument("--hb", action="store_true", help="time the sector HB curve against the single blade's")
    ap.add_argument("--rpm-from", type=float, default=6000.0)
    ap.add_argument("--rpm-to", type=float, default=14000.0)
    ap.add_argument("--mistuned", action="store_true", help="time the mistuned ring's HB curve (goal 10 s)")
    ap.add_argument("--monodromy", nargs="*", type=int, metavar="N",
                    help="time the ring's monodromy about the wave over the whole period against the wave's "
                         "symmetry (a g / N of it) for these ring sizes (Fig. 11b contact, 1 um, 10000 r/min)")
    ap.add_argument("--harmonics", type=int, default=10)
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
    if args.hb:
        a, b = args.rpm_from, args.rpm_to
        curves = {"single blade": lambda: run_hb(p, "reduced", a, b),
                  "sector, no stability": lambda: run_ring_hb(p, "reduced", a, b, stability=False).branch}
        for name, curve in curves.items():
            r, cpu, wall = timed(curve, args.repeat)
            print(f"HB {name}: {len(r.rpm)} points, complete {r.complete}, CPU {statistics.median(cpu):.3f} s "
                  f"({1e3 * statistics.median(cpu) / len(r.rpm):.2f} ms a point), "
                  f"wall {statistics.median(wall):.3f} s; "
                  f"resonance {r.resonance['rpm']:.0f} r/min {1e6 * r.resonance['amplitude']:.3f} um")
        # the whole ring's multipliers at a few points of the sector's branch (compiled by the first)
        H = r.harmonics
        speeds = SpeedModel(model_at_speed(p, "reduced"), H)
        basis = hb.fourier(H, r.samples)
        picks = np.linspace(0, len(r.rpm) - 1, 6).astype(int)
        cpu = []
        for i in picks:
            system, lin, _, _ = speeds.at(float(r.rpm[i]))
            sector = sector_of(system, p, H)
            c0 = time.process_time()
            mu = np.abs(ring_multipliers(system, sector, lin, r.X[i], basis)).max()
            cpu.append(time.process_time() - c0)
            print(f"  ring monodromy at {r.rpm[i]:.0f} r/min: |mu| {mu:.4f}, CPU {cpu[-1]:.3f} s")
        print(f"HB sector + ring monodromy: {statistics.median(cpu[1:]):.3f} s CPU a point (median after the first)")
    if args.mistuned:
        mistuned_curve(args)
    if args.monodromy:
        monodromies(args)


def timed(curve, repeat: int):
    """``curve()``'s result and its CPU and wall times (s) over ``repeat`` calls after a first one that
    compiles the kernels and builds the blades' models."""
    curve()
    cpu, wall = [], []
    for _ in range(repeat):
        w0, c0 = time.perf_counter(), time.process_time()
        result = curve()
        wall.append(time.perf_counter() - w0)
        cpu.append(time.process_time() - c0)
    return result, cpu, wall


def mistuned_curve(args) -> None:
    """The mistuned ring's HB curve (the whole ring condensed on its blades' contact coordinates, no
    stability): 24 blades, E scattered by 1.3 % (seed 1), a preload of 20 N at every interface (without
    it the ring settles nowhere near 9000 r/min, docs/ring.md), 8000-10000 r/min, H = 10, 256 samples.
    Goal: under 10 s. Its linear solves banded (ring_hb.STRUCTURED) and dense, one run of each in turn."""
    p = Parameters().with_overrides([f"ring.blades={args.blades}", "ring.mistuning_std=0.013", "ring.seed=1",
                                     "contact.N0=20", *args.set])
    times = {True: ([], []), False: ([], [])}

    def curve(structured):
        ring_hb.STRUCTURED = structured
        w0, c0 = time.perf_counter(), time.process_time()
        r = run_ring_hb(p, "reduced", 8000.0, 10000.0, harmonics=10, samples=256, stability=False)
        times[structured][0].append(time.process_time() - c0)
        times[structured][1].append(time.perf_counter() - w0)
        return r
    results = {s: curve(s) for s in (True, False)}     # compiles the kernels, builds the blades' models
    times = {True: ([], []), False: ([], [])}
    for _ in range(args.repeat):
        results = {s: curve(s) for s in (True, False)}
    ring_hb.STRUCTURED = True
    for structured, r in results.items():
        cpu, wall = times[structured]
        last = r.amplitudes[-1]
        print(f"HB mistuned ring of {args.blades}, {'banded' if structured else 'dense'} solves: "
              f"{len(r.branch.rpm)} points 8000-10000 r/min, complete {r.complete}, CPU {statistics.median(cpu):.3f} s, "
              f"wall {statistics.median(wall):.3f} s (median of {args.repeat}); blades at {r.branch.rpm[-1]:.0f} r/min "
              f"{1e6 * min(last):.4f} .. {1e6 * max(last):.4f} um")


def monodromies(args) -> None:
    """The whole ring's multipliers about the travelling wave (ring_hb.ring_multipliers) integrated over the
    period and by the wave's symmetry (floquet.symmetric_monodromy), CPU medians of ``--repeat`` after a
    first call that compiles, and the largest difference of the multipliers' moduli. The Fig. 11b contact
    (alpha 30 deg, kt 5e6 N/m, mu 0.3, 1 um gap) at 10000 r/min, the ring_tuned study's."""
    H = args.harmonics
    for N in args.monodromy:
        p = Parameters().with_overrides([f"ring.blades={N}", "contact.alpha_deg=30", "contact.kt=5e6",
                                         "contact.mu=0.3", "contact.gap=1e-6", *args.set])
        rpm = 10000.0
        basis = hb.fourier(H, hb.default_samples(H))
        speeds = SpeedModel(model_at_speed(p, "reduced"), H)
        system, lin, _, _ = speeds.at(rpm)
        sector = sector_of(system, p, H)
        X = sector_solve(lin, sector, basis)
        times, mus = {}, {}
        for symmetric in (True, False):
            mus[symmetric], cpu, _ = timed(lambda: ring_multipliers(system, sector, lin, X, basis, symmetric),
                                           args.repeat)
            times[symmetric] = statistics.median(cpu)
        a, b = np.sort(np.abs(mus[True]))[::-1], np.sort(np.abs(mus[False]))[::-1]
        print(f"ring monodromy, {N} blades, H = {H}, {basis.samples} samples: whole period CPU "
              f"{times[False]:.3f} s, by the symmetry {times[True]:.3f} s (median of {args.repeat}): "
              f"{times[False] / times[True]:.1f}x; largest |mu| {a[0]:.6f} / {b[0]:.6f}, "
              f"largest difference of the sorted |mu| {np.abs(a - b).max():.2e}")


if __name__ == "__main__":
    main()
