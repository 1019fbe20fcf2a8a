"""A STEP file to the solid's modes (goal: < 30 s on this machine) and to the beam's (< 10 s), whole process.

The NACA blade of shared/spec/geometry.md ("Airfoil blades": m 0.04, p 0.4,
chord 40 -> 30 mm, thickness 7 -> 4.2 mm, the paper's stagger, twist and
shroud, alpha 15 deg) is written to a STEP file (meshes.blade.write_step, not
timed); then ``shroud modal --model fe --modes 5 --set blade.step=FILE``
runs ``--repeats`` times in fresh processes, each with an empty cache
(reading the file, finding its faces, meshing it with P2 tetrahedra of
``--size``, the prestressed solve at 10000 r/min with Coriolis); then the
same with ``--model extended`` (cutting the file into slices with gmsh, the
slices' sections by P2 triangles, the beam's prestressed modes): the wall
times, CPU times (user + system of the process) and their medians.

    python benchmarks/bench_step.py                      # 2.1 mm: two cells through the 4.2 mm tip
    python benchmarks/bench_step.py --size 0.0016 --repeats 1
    python benchmarks/bench_step.py --models extended    # the beam alone
"""

from __future__ import annotations

import argparse
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from meshes.spec import MeshSpec
from meshes.blade import write_step
from shroud.params import Parameters

NACA = ["blade.section=naca4", "blade.chord_taper=0.75", "blade.thickness_taper=0.6", "contact.alpha_deg=15",
        "fe.cell=tet"]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=float, default=0.0021, help="fe.mesh_size, m (default 0.0021)")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--models", default="fe,extended", help="comma-separated (default fe,extended)")
    args = parser.parse_args()
    sets = NACA + [f"fe.mesh_size={args.size}"]
    with tempfile.TemporaryDirectory() as tmp:
        step = Path(tmp) / "naca.step"
        write_step(MeshSpec.from_params(Parameters().with_overrides(sets)), step)
        for model in args.models.split(","):
            _measure(model, sets + [f"blade.step={step}"], Path(tmp), args)


def _measure(model: str, sets: list[str], tmp: Path, args) -> None:
    """``shroud modal --model MODEL`` on the file, ``--repeats`` times, each in a fresh process and cache."""
    argv = [sys.executable, "-m", "workbench.cli", "modal", "--model", model, "--modes", "5", "--rpm", "10000"]
    argv += [a for s in sets for a in ("--set", s)]
    walls, cpus = [], []
    for i in range(args.repeats):
        env = dict(os.environ, SHROUD_CACHE=str(tmp / f"cache_{model}_{i}"))
        cpu0 = resource.getrusage(resource.RUSAGE_CHILDREN)
        t0 = time.perf_counter()
        done = subprocess.run(argv, capture_output=True, text=True, env=env, check=True)
        walls.append(time.perf_counter() - t0)
        cpu1 = resource.getrusage(resource.RUSAGE_CHILDREN)
        cpus.append(cpu1.ru_utime + cpu1.ru_stime - cpu0.ru_utime - cpu0.ru_stime)
        print(f"{model} run {i + 1}: {walls[-1]:.1f} s wall, {cpus[-1]:.1f} s CPU, load {os.getloadavg()[0]:.1f}",
              flush=True)
    print(done.stdout.strip())
    what = f"fe.mesh_size {args.size:g} m" if model == "fe" else "the beam from the file's slices"
    print(f"STEP -> {model} modes, whole process, {what}: median {statistics.median(walls):.1f} s "
          f"over {len(walls)} runs ({', '.join(f'{w:.1f}' for w in walls)}), "
          f"CPU median {statistics.median(cpus):.1f} s")

if __name__ == "__main__":
    main()
