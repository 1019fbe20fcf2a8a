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

``--against REV`` times the same branch by the code of an earlier commit too,
in the same run (each repeat: the time domain, this tree's HB, then REV's in
a child process on REV's own tree), so a change's cost is read against the
same load; ``--set`` (contact.* keys), ``--rpm-to`` and ``--min-points`` pick
another case, e.g. the 1 um gap of Fig. 11 (docs/hb-stability.md):

    python benchmarks/bench_hb.py --models reduced --repeat 5 --against 064d800
    python benchmarks/bench_hb.py --models reduced --repeat 5 --against 064d800 --gap 1e-6 --rpm-to 25000 \
        --min-points 60 --set contact.alpha_deg=30 contact.kt=5e6 contact.mu=0.3
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tarfile
import tempfile
import time
from pathlib import Path

import numpy as np

from reduced_model.system import at_speed, build_system
from shroud.analysis.hb import run_hb
from shroud.analysis.sweep import run_sweep
from shroud.params import Parameters

# run in a child on another commit's tree: one warm-up, then the branch timed (wall, CPU) as JSON
CHILD = """
import json, sys, time
from shroud.params import Parameters
from shroud.analysis.hb import run_hb
a = json.loads(sys.argv[1])
p = Parameters().updated(a["params"])
run_hb(p, a["model"], a["rpm_from"], a["rpm_from"] + 1000.0, harmonics=3, samples=64)
run_hb(p, a["model"], a["rpm_from"], a["rpm_to"], a["harmonics"], a["samples"], a["min_points"])
w0, c0 = time.perf_counter(), time.process_time()
run_hb(p, a["model"], a["rpm_from"], a["rpm_to"], a["harmonics"], a["samples"], a["min_points"])
print(json.dumps([time.perf_counter() - w0, time.process_time() - c0]))
"""


def timed(fn):
    w0, c0 = time.perf_counter(), time.process_time()
    out = fn()
    return out, time.perf_counter() - w0, time.process_time() - c0


def tree_of(rev: str, into: Path) -> Path:
    """The source tree of commit ``rev`` (git archive), unpacked under ``into``."""
    archive = into / "tree.tar"
    subprocess.run(["git", "archive", "-o", str(archive), rev], check=True, cwd=Path(__file__).resolve().parents[1])
    with tarfile.open(archive) as tar:
        tar.extractall(into / "tree", filter="data")
    return into / "tree"


def timed_at(tree: Path, job: dict) -> tuple[float, float]:
    """(wall, CPU) of the branch ``job`` run by the code in ``tree`` (a child process, warmed up first)."""
    env = dict(os.environ, PYTHONPATH=str(tree))
    out = subprocess.run([sys.executable, "-c", CHILD, json.dumps(job)], env=env, check=True,
                         capture_output=True, text=True, cwd=tree)
    return tuple(json.loads(out.stdout.strip().splitlines()[-1]))


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
    ap.add_argument("--rpm-to", type=float, default=20000.0)
    ap.add_argument("--min-points", type=int, default=None)
    ap.add_argument("--set", nargs="*", default=[], metavar="KEY=VALUE", help="contact.* parameters (numbers)")
    ap.add_argument("--against", metavar="REV", help="also time the branch by the code of commit REV")
    args = ap.parse_args()
    if "fe-reduced" in args.models:
        import dolfinx_solver  # noqa: F401  (before any DOLFINx import)
    print(f"load average at start: {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores")
    overrides = {"contact.gap": args.gap, **{k: float(v) for k, v in (kv.split("=", 1) for kv in args.set)}}
    params = Parameters().updated(overrides)
    rpms = np.arange(5000.0, args.rpm_to + 1, 100.0)
    scratch = tempfile.TemporaryDirectory()
    tree = tree_of(args.against, Path(scratch.name)) if args.against else None
    for model in args.models:
        run_hb(params, model, 5000.0, 6000.0, harmonics=3, samples=64)        # compile / load the kernels
        if not args.hb_only:
            run_sweep(params, model, rpms[:2])
        job = {"params": overrides, "model": model, "rpm_from": 5000.0, "rpm_to": args.rpm_to,
               "harmonics": args.harmonics, "samples": args.samples, "min_points": args.min_points}
        hb_runs, td_runs, then_runs = [], [], []
        for _ in range(args.repeat):
            hb_runs.append(timed(lambda: run_hb(params, model, 5000.0, args.rpm_to, harmonics=args.harmonics,
                                                samples=args.samples, min_points=args.min_points)))
            if not args.hb_only:
                td_runs.append(timed(lambda: run_sweep(params, model, rpms)))
            if tree is not None:
                then_runs.append(timed_at(tree, job))
        hb_wall = statistics.median(w for _, w, _ in hb_runs)
        hb_cpu = statistics.median(c for _, _, c in hb_runs)
        branch = hb_runs[-1][0]
        print(f"{model}: {', '.join(f'{k} {v:g}' for k, v in overrides.items())}, 5000-{args.rpm_to:g} r/min")
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
        if then_runs:
            then_wall = statistics.median(w for w, _ in then_runs)
            then_cpu = statistics.median(c for _, c in then_runs)
            print(f"  the same branch by {args.against}: {then_wall:.2f} s wall, {then_cpu:.2f} s CPU; "
                  f"this tree / {args.against}: {hb_cpu / then_cpu:.2f} CPU"
                  + (f"; time domain / {args.against}'s HB: {td_cpu / then_cpu:.1f}x CPU" if td_runs else ""))


if __name__ == "__main__":
    main()
