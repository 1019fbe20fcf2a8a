"""Cost of the 24-blade sector of blade and flexible disk: 6 modes of every nodal diameter (docs/disk.md).

One whole process (``shroud modal --model fe --interface free`` as a user
runs it): mesh from the disk cache (built beforehand, untimed), assembly,
the k = 0 prestress, then nodal diameters 0 .. 12 at ``--rpm`` (default
10000 r/min, with Coriolis), each with its MUMPS factor of the real form of
K_k (refactored numerically in place from k to k, reference_fe.cyclic).
Prints, over ``--repeat`` processes, the median whole-process wall time and
CPU time (user + system: what the machine's load does not inflate), the
largest peak memory, and the time of each nodal diameter (from the progress
lines of the last run), so whether the cost over k is flat shows.

    python benchmarks/bench_disk_sector.py [--repeat 3]
    python benchmarks/bench_disk_sector.py --set fe.mesh_size=0.0035 --set disk.E_factor=1000 --no-coriolis
"""

from __future__ import annotations

import argparse
import json
import re
import statistics
import subprocess
import sys
import time
from pathlib import Path

BASE = ["ring.blades=24", "disk.thickness=0.04", "fe.cell=tet", "fe.mesh_size=0.0035", "fe.order=2"]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rpm", type=float, default=10000.0)
    parser.add_argument("--set", action="append", default=[], help="extra key=value")
    parser.add_argument("--coriolis", action=argparse.BooleanOptionalAction, default=True)
    parser.add_argument("--repeat", type=int, default=1, help="processes timed (medians reported)")
    args = parser.parse_args()
    sets = [a for s in BASE + args.set for a in ("--set", s)]
    warm = [sys.executable, "-c", "from shroud.params import Parameters; from meshes.disk import DiskSpec, "
            f"sector_mesh_file; print(sector_mesh_file(DiskSpec.from_params(Parameters().with_overrides({BASE + args.set!r}))))"]
    subprocess.run(warm, check=True, capture_output=True)
    command = ["/usr/bin/time", "-f", "peak_rss_kB %M cpu_s %U %S", str(Path(sys.executable).with_name("shroud")),
               "modal", "--model", "fe", "--interface", "free", "--rpm", str(args.rpm), "--modes", "6", "--json",
               "--coriolis" if args.coriolis else "--no-coriolis", *sets]
    walls, cpus, peaks = [], [], []
    for _ in range(args.repeat):
        t0 = time.perf_counter()
        done = subprocess.run(command, check=True, capture_output=True, text=True)
        walls.append(time.perf_counter() - t0)
        peak, user, system = re.search(r"peak_rss_kB (\d+) cpu_s ([0-9.]+) ([0-9.]+)", done.stderr).groups()
        peaks.append(int(peak))
        cpus.append(float(user) + float(system))
    result = json.loads(done.stdout.strip().splitlines()[-1])
    stamps = [float(t) for t in re.findall(r"nd \d+ done at ([0-9.]+) s", done.stderr)]
    print(f"{result['dofs']} DOF, {args.rpm:g} r/min, Coriolis {'on' if args.coriolis else 'off'}, {args.repeat} runs: "
          f"whole process median {statistics.median(walls):.1f} s wall ({', '.join(f'{w:.1f}' for w in walls)}), "
          f"{statistics.median(cpus):.1f} s CPU ({', '.join(f'{c:.1f}' for c in cpus)}), peak {max(peaks) / 1e6:.2f} GB")
    steps = [b - a for a, b in zip([0.0] + stamps[:-1], stamps)]
    for d, step in zip(result["nodal_diameters"], steps):
        print(f"  nd {d['nd']:2d} {step:6.1f} s  " + " ".join(f"{m['label']}={m['f_hz']:.2f}" for m in d["modes"]))


if __name__ == "__main__":
    main()
