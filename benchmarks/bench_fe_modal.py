"""Cost of one prestressed modal solve of the solid blade (goal: <= 30 s, < 4 GB on 2 cores).

Each size runs in a fresh process, so every in-process cache is cold; the
gmsh mesh itself comes from the disk cache (built once beforehand, its time
reported separately). Timed: mesh read and distribution, assembly of M,
K_e, the prestress solve, K_sigma, K_spin and G, then the undamped (EPS)
and the gyroscopic (Rayleigh-Ritz) eigen-solves for 6 modes at 8500 r/min.

    python benchmarks/bench_fe_modal.py                      # default mesh, serial
    mpirun -n 2 python benchmarks/bench_fe_modal.py          # the same on 2 ranks
    python benchmarks/bench_fe_modal.py --sizes 0.0035 0.0028 0.0022
    python benchmarks/bench_fe_modal.py --versus-calculix          # whole processes, side by side

``--versus-calculix``: the whole process ``shroud modal --model fe --modes 8``
on the default mesh against CalculiX (``ccx``, one thread) on the deck of a
mesh of equal accuracy (``--ccx-set``, default P2 tetrahedra of 2.8 mm, the
C3D10 mesh within 0.15 % of the converged solid: scenes/convergence.toml),
alternated ``--repeats`` times; medians and their ratio. Both solve the
prestressed problem at 10000 r/min with and without Coriolis (ccx: NLGEOM
static step, *FREQUENCY, then *COMPLEX FREQUENCY, CORIOLIS for 8 modes, as
``shroud modal`` reports both); the decks are written beforehand and not timed.
"""

from __future__ import annotations

import argparse
import resource
import subprocess
import sys
import time

WORK = """
import resource, sys, time
t0 = time.perf_counter()
from mpi4py import MPI
from reference_fe.modal import solve_modes
from shroud.params import Parameters
p = Parameters().updated({"fe.mesh_size": %r})
t_import = time.perf_counter() - t0
m = solve_modes(p, 8500.0, 6, coriolis=True)
total = time.perf_counter() - t0
rss = MPI.COMM_WORLD.allreduce(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss, op=MPI.SUM)
if MPI.COMM_WORLD.rank == 0:
    print(m.dofs, round(t_import, 2), round(m.solve_s, 2), round(total, 2), round(rss / 1e6, 3),
          " ".join(f"{l}={f:.2f}" for l, f in zip(m.labels, m.f_undamped)))
"""


def versus_calculix(repeats: int, ccx_set: list[str]) -> None:
    """Medians of whole-process wall times: shroud modal (default mesh) and ccx (``ccx_set`` mesh)."""
    import os
    import statistics
    import tempfile
    from pathlib import Path
    from reference_fe.calculix import ccx, write_deck
    from shroud.params import Parameters
    exe = ccx()
    if exe is None:
        raise SystemExit("ccx (CalculiX) is not installed: bash scripts/install_calculix.sh")
    env = dict(os.environ, OMP_NUM_THREADS="1", CCX_NPROC_EQUATION_SOLVER="1")
    ours = [str(Path(sys.executable).parent / "shroud"), "modal", "--model", "fe", "--modes", "8",
            "--rpm", "10000", "--json"]
    subprocess.run(ours, capture_output=True, check=True, env=env)        # mesh and JIT caches warm
    work = Path(tempfile.mkdtemp(prefix="bench_ccx_"))
    params = Parameters().with_overrides(ccx_set)
    facts = write_deck(params, 10000.0, 8, work / "blade.inp", coriolis=True, prestress="nonlinear")  # one run
    times = {"shroud": [], "ccx": []}
    for _ in range(repeats):
        for name, cmd, cwd in (("shroud", ours, None), ("ccx", [exe, "-i", "blade"], work)):
            t0 = time.perf_counter()
            subprocess.run(cmd, capture_output=True, check=True, env=env, cwd=cwd)
            times[name].append(time.perf_counter() - t0)
    a, b = statistics.median(times["shroud"]), statistics.median(times["ccx"])
    print(f"shroud modal --model fe --modes 8 (default mesh): median {a:.2f} s of {times['shroud']}")
    print(f"ccx {facts['element']} {3 * facts['nodes']} DOF ({' '.join(ccx_set)}): median {b:.2f} s "
          f"of {times['ccx']}")
    print(f"ratio ccx / shroud: {b / a:.2f}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=float, nargs="+", default=[None])
    parser.add_argument("--versus-calculix", action="store_true")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--ccx-set", nargs="+", default=["fe.cell=tet", "fe.mesh_size=0.0028"])
    args = parser.parse_args()
    if args.versus_calculix:
        versus_calculix(args.repeats, args.ccx_set)
        return
    from shroud.params import Parameters
    from meshes.blade import MeshSpec, mesh_file
    from mpi4py import MPI
    ranks = MPI.COMM_WORLD.size
    if MPI.COMM_WORLD.rank == 0:
            print(f"{'size m':>8} {'DOF':>8} {'mesh s':>7} {'import s':>8} {'solve s':>8} {'total s':>8} "
              f"{'peak GB':>8} ranks  frequencies (Hz)")
    for size in args.sizes:
        params = Parameters() if size is None else Parameters().updated({"fe.mesh_size": size})
        t0 = time.perf_counter()
        if MPI.COMM_WORLD.rank == 0:
            mesh_file(MeshSpec.from_params(params))
        mesh_s = time.perf_counter() - t0
        code = WORK % params.fe.mesh_size
        if ranks > 1:
            # Under mpirun this script itself is rank-parallel: run the work in-process.
            exec(compile(code, "bench", "exec"), {})
            continue
        line = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
        dofs, t_imp, solve, total, rss, freqs = line.stdout.split(maxsplit=5)
        print(f"{params.fe.mesh_size:8.4f} {dofs:>8} {mesh_s:7.1f} {t_imp:>8} {solve:>8} {total:>8} "
              f"{rss:>8} {ranks:5d}  {freqs.strip()}")


if __name__ == "__main__":
    resource.setrlimit(resource.RLIMIT_CORE, (0, 0))
    main()
