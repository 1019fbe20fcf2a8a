"""Speed of a Monte Carlo over mistuning, by harmonic balance or in time, over MPI ranks (issue 26).

Goal: 200 samples (24 blades, E scattered by 1.3 %, each its own seed) over a
speed range in under 10 min on 2 ranks, with the scaling from 1 to 2 ranks
measured and memory flat in the number of samples. Each sample is the whole
mistuned ring by HB (shroud.analysis.ring_hb.whole_ring_at, H = 10, 256
samples, no stability) at each speed; its worst blade per speed is appended
as one JSON line to its rank's file as soon as it ends (flushed and fsync'd:
nothing is gathered in memory), with the rank's peak resident memory then.
The interfaces carry a preload of 20 N: without one the ring settles on no
periodic state near these speeds (docs/ring.md).

``--method time``: each sample as the study ring_mistuning computes it
(comparisons.ring_mistuning.blade_amplitudes: the whole ring in time from
rest, no preload, its full scene's speeds 9500, 10000, 10500 r/min unless
--rpm says otherwise), 200 periods (the scene runs 300 since issue 33; the
timings of docs/ring.md were measured at 200).

    mpirun -n 2 python benchmarks/bench_mistuning.py --samples 200 --out /tmp/mc
    mpirun -n 1 python benchmarks/bench_mistuning.py --samples 20 --out /tmp/mc1
    mpirun -n 2 python benchmarks/bench_mistuning.py --method time --samples 200 --out /tmp/mct

``--compare-solves K``: one HB sample (seed 0), K times with the whole
ring's linear solves banded (shroud.core.cyclic_banded) and K times dense,
alternated, CPU and wall medians of each (one process; no files written).
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import statistics
import time
from pathlib import Path

import reduced_model  # noqa: F401  (registers the beams)
from comparisons.ring_mistuning import blade_amplitudes
from shroud.analysis import ring_hb
from shroud.analysis.ring_hb import whole_ring_at
from shroud.base.parallel import mpi_rank, mpi_size
from shroud.params import Parameters


def sample(seed: int, speeds: list[float], blades: int) -> dict:
    """Sample ``seed``: every blade's v_L amplitude's worst over the blades at each speed (m)."""
    p = Parameters().with_overrides([f"ring.blades={blades}", "ring.mistuning_std=0.013", f"ring.seed={seed}",
                                     "contact.N0=20"])
    worst = [max(whole_ring_at(p, "reduced", rpm, harmonics=10, samples=256, stability=False)
                 ["blades_amplitude_v_L"]) for rpm in speeds]
    return {"seed": seed, "rpm": speeds, "worst_v_L": worst}


def sample_in_time(seed: int, speeds: list[float], blades: int) -> dict:
    """Sample ``seed`` as the study ring_mistuning runs it: the ring in time, 200 periods (the scene: 300)."""
    p = Parameters().with_overrides([f"ring.blades={blades}", "time.periods=200", "ring.mistuning_std=0.013",
                                     f"ring.seed={seed}"])
    return {"seed": seed, "rpm": speeds, "worst_v_L": [max(a) for a in blade_amplitudes(p, "reduced", speeds)]}


def compare_solves(repeat: int, speeds: list[float], blades: int) -> None:
    """One HB sample's CPU and wall medians with the whole ring's linear solves banded and dense."""
    times = {True: ([], []), False: ([], [])}
    worst = {}
    for k in range(repeat + 1):                          # the first round compiles the kernels
        for structured in (True, False):
            ring_hb.STRUCTURED = structured
            w0, c0 = time.perf_counter(), time.process_time()
            worst[structured] = sample(0, speeds, blades)["worst_v_L"]
            if k:
                times[structured][0].append(time.process_time() - c0)
                times[structured][1].append(time.perf_counter() - w0)
    ring_hb.STRUCTURED = True
    for structured, (cpu, wall) in times.items():
        print(f"one HB sample ({blades} blades, {len(speeds)} speeds), {'banded' if structured else 'dense'} solves: "
              f"CPU {statistics.median(cpu):.3f} s, wall {statistics.median(wall):.3f} s (median of {repeat}); "
              f"worst blade {', '.join(f'{1e6 * w:.5f}' for w in worst[structured])} um")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--samples", type=int, default=200)
    ap.add_argument("--blades", type=int, default=24)
    ap.add_argument("--rpm", type=float, nargs="+", default=None,
                    help="speeds (default 8500 9000 9500 by HB, 9500 10000 10500 in time)")
    ap.add_argument("--method", choices=("hb", "time"), default="hb")
    ap.add_argument("--out", type=Path)
    ap.add_argument("--compare-solves", type=int, default=0, metavar="K",
                    help="time one HB sample K times with banded and K times with dense linear solves, and stop")
    args = ap.parse_args()
    if args.compare_solves:
        compare_solves(args.compare_solves, args.rpm or [8500.0, 9000.0, 9500.0], args.blades)
        return
    if args.out is None:
        ap.error("--out is required")
    run = sample if args.method == "hb" else sample_in_time
    speeds = args.rpm or ([8500.0, 9000.0, 9500.0] if args.method == "hb" else [9500.0, 10000.0, 10500.0])
    rank, size = mpi_rank(), mpi_size()
    args.out.mkdir(parents=True, exist_ok=True)
    path = args.out / f"samples.rank{rank}.jsonl"
    run(10**6, speeds[:1], args.blades)                 # compile (numba) before the clock
    t0, c0 = time.perf_counter(), time.process_time()
    with open(path, "w") as fh:
        for seed in range(rank, args.samples, size):
            row = run(seed, speeds, args.blades)
            row["peak_rss_mb"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
            fh.write(json.dumps(row) + "\n")
            fh.flush()
            os.fsync(fh.fileno())
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    rows = [json.loads(line) for line in path.read_text().splitlines()]
    rss = [r["peak_rss_mb"] for r in rows]
    print(f"rank {rank}/{size}: {len(rows)} samples x {len(speeds)} speeds in {wall:.1f} s wall, {cpu:.1f} s CPU "
          f"({wall / max(len(rows), 1):.2f} s a sample); peak RSS {rss[0]:.0f} MB after the first, "
          f"{rss[len(rss) // 2]:.0f} MB at the middle, {rss[-1]:.0f} MB after the last; "
          f"load average {os.getloadavg()[0]:.1f}", flush=True)


if __name__ == "__main__":
    main()
