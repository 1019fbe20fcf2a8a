"""Speed of the harmonic-balance curve against the time-domain sweep of the same range (one run).

Goal: the 0.1 mm gap curve of the reduced beam from 5000 to
20000 r/min, with the stability of every point, at least 10x faster than
the time-domain sweep of that range at 100 r/min resolution (151 speeds,
``time.periods`` each, run from rest on every core). Both are timed here,
side by side, on the same machine and load: wall time (the user's wait)
and CPU time (what the work costs; the sweep's is summed over its worker
processes). Medians of ``--repeat`` runs. For the beams it also states
the error of their speed-range systems (the modes interpolated in Omega^2,
reduced_model.reduction.ModesOverSpeed) against the per-speed builds the
time domain uses: the largest relative difference of the contact
receptance W Z^-1 W^T and the tip response to the load at harmonics 1-3
of the excitation, at 61 speeds over the range.

fe-reduced (goal: a curve under 10 s with its speed-range basis cached;
the basis is built at ``speed.rpm`` = 10000 r/min on first use) is timed
without its time-domain sweep (``--hb-only``):

    python benchmarks/bench_hb.py [--models reduced full] [--repeat 3] [--harmonics 10 --samples 512]
    python benchmarks/bench_hb.py --models fe-reduced --hb-only --harmonics 7 --samples 256
"""

from __future__ import annotations

import argparse
import os
import statistics
import time

import numpy as np

from reduced_model.system import at_speed, build_system
from shroud.analysis.hb import run_hb
from shroud.analysis.sweep import run_sweep
from shroud.params import Parameters


def timed(fn):
    w0, c0 = time.perf_counter(), time.process_time()
    out = fn()
    return out, time.perf_counter() - w0, time.process_time() - c0


def speed_range_error(params: Parameters, reduced: bool, rpms) -> float:
    """Largest relative difference of the beam's speed-range systems from its per-speed builds (contact
    receptance and tip response to the load at harmonics 1-3 of the excitation)."""
    one, worst = at_speed(params, reduced), 0.0
    for rpm in rpms:
        a, b = one(float(rpm)), build_system(params.updated({"speed.rpm": float(rpm)}), reduced)
        for k in (1, 2, 3):
            w = k * b.omega_e
            ra, rb = (np.vstack([s.contact.W, s.tip]) @ np.linalg.solve(
                s.K - w * w * s.M + 1j * w * s.C, np.column_stack([s.contact.W.T, s.f_aero])) for s in (a, b))
            worst = max(worst, float(np.abs(ra - rb).max() / np.abs(rb).max()))
    return worst


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--models", nargs="+", default=["reduced", "full"])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--harmonics", type=int, default=10)
    ap.add_argument("--samples", type=int, default=512)
    ap.add_argument("--gap", type=float, default=1e-4)
    ap.add_argument("--hb-only", action="store_true", help="time the harmonic balance only")
    args = ap.parse_args()
    if "fe-reduced" in args.models:
        import dolfinx_solver  # noqa: F401  (before any DOLFINx import)
    print(f"load average at start: {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores")
    params = Parameters().updated({"contact.gap": args.gap})
    rpms = np.arange(5000.0, 20000.0 + 1, 100.0)
    for model in args.models:
        run_hb(params, model, 5000.0, 6000.0, harmonics=3, samples=64)        # compile / load the kernels
        if not args.hb_only:
            run_sweep(params, model, rpms[:2])
        hb_runs, td_runs = [], []
        for _ in range(args.repeat):
            hb_runs.append(timed(lambda: run_hb(params, model, 5000.0, 20000.0, harmonics=args.harmonics,
                                                samples=args.samples)))
            if not args.hb_only:
                td_runs.append(timed(lambda: run_sweep(params, model, rpms)))
        hb_wall = statistics.median(w for _, w, _ in hb_runs)
        hb_cpu = statistics.median(c for _, _, c in hb_runs)
        branch = hb_runs[-1][0]
        print(f"{model}: gap {args.gap * 1e3:g} mm, 5000-20000 r/min")
        if model in ("reduced", "full"):
            print(f"  speed-range systems against per-speed builds: largest relative difference "
                  f"{speed_range_error(params, model == 'reduced', np.linspace(5000.0, 20000.0, 61)):.1e}")
        if td_runs:
            td_wall = statistics.median(w for _, w, _ in td_runs)
            td_cpu = statistics.median(r.cpu_s for r, _, _ in td_runs)
            sweep = td_runs[-1][0]
            print(f"  time domain: {len(rpms)} speeds x {params.time.periods} periods: {td_wall:.2f} s wall, "
                  f"{td_cpu:.2f} s CPU summed over the runs; resonance {sweep.resonance['rpm']:.0f} r/min, "
                  f"{sweep.resonance['amplitude'] * 1e3:.4f} mm")
        print(f"  harmonic balance H = {branch.harmonics}, {branch.samples} samples: {len(branch.rpm)} points "
              f"with stability, {branch.iterations} Newton iterations: {hb_wall:.2f} s wall, {hb_cpu:.2f} s CPU; "
              f"resonance {branch.resonance['rpm']:.0f} r/min, {branch.resonance['amplitude'] * 1e3:.4f} mm; "
              f"{len(branch.bifurcations)} stability changes")
        if td_runs:
            print(f"  ratio time domain / harmonic balance: {td_wall / hb_wall:.1f}x wall, "
                  f"{td_cpu / hb_cpu:.1f}x CPU (medians of {args.repeat})")


if __name__ == "__main__":
    main()
