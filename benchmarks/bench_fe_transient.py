"""Speed and size of the solid FE transients ("fe" and "fe-reduced") on the Fig. 8 case.

Goals: "fe" 100 excitation periods of the Fig. 8 scene (its own 10 mm
hexahedra, scenes/fig8.toml) in 300 s or less on 2 ranks, 11.5 ms a step
(the paper's ANSYS beam model: 3260 s); "fe-reduced" 5 s or less (paper:
2329 s). Reported per model: DOFs, contact
elements, build time (mesh, operators, reduction basis; cached on disk
after a first run: run twice to see both), set-up of the time loop (the
factorization of the Newmark operator and its condensation on the contact
coordinates: a zero-step integration), time and CPU time per step (with the
load average: the machine is shared), total, peak memory.

    python benchmarks/bench_fe_transient.py                 # 100 periods, both models
    python benchmarks/bench_fe_transient.py --periods 5     # per-step figures, extrapolated
    python benchmarks/bench_fe_transient.py --set fe.order=1
    python benchmarks/bench_fe_transient.py --models fe --superlu  # SuperLU instead of the model's MUMPS LU
    OMP_NUM_THREADS=1 mpirun -n 2 python benchmarks/bench_fe_transient.py --models fe   # over 2 ranks
    python benchmarks/bench_fe_transient.py --models fe --periods 4 --profile 12   # where the step goes
    python benchmarks/bench_fe_transient.py --models fe --set fe.mesh_size=0.005  # the default mesh

Interface reduction of fe-reduced (fe.interface_modes): ``--interface-modes
0 8 16 32`` runs "fe" once and "fe-reduced" with each count of kept
contact-face patterns, and adds each one's agreement with "fe" (NRMSE of the
Fig. 8 signals over the last ``--window`` periods, shroud/analysis/agreement.py).

    python benchmarks/bench_fe_transient.py --periods 12 --interface-modes 0 8 16 32 64
"""

from __future__ import annotations

import argparse
import cProfile
import json
import math
import os
import pstats
import resource
import time

from shroud.analysis.agreement import agreement, signals_of
from shroud.analysis.api import build_system
from shroud.analysis.transient import contact_law_for
from shroud.core.linear_solvers import default_factorization
from shroud.core.newmark import NewmarkScheme, integrate
from shroud.base.parallel import mpi_rank, mpi_size
from workbench.scene import load_scene


def measure(params, model: str, factorize=None, profile: int = 0):
    """The figures of one model's run, and its trajectory.

    ``factorize``: of the step operator (None: the model's own, else shroud.core.newmark's default).
    ``profile``: print this many functions of the timed run by own time (cProfile, rank 0).
    """
    t0, cpu_build = time.perf_counter(), time.process_time()
    system = build_system(params, model)
    build_s, build_cpu_s = time.perf_counter() - t0, time.process_time() - cpu_build
    law = contact_law_for(system, params.contact)
    scheme = NewmarkScheme(dt=params.time_step)
    steps = params.time.periods * params.time.steps_per_period
    implicit = params.time.contact == "implicit"
    # twice: the first zero-step run also compiles the kernels, which the timed run then finds ready
    # (measured once, the set-up exceeded a 1-period run and the time per step came out negative)
    cpu0 = time.process_time()
    setup = [integrate(system, law, scheme, 0, implicit=implicit, factorize=factorize) for _ in range(2)][-1]
    cpu1 = time.process_time()
    profiler = cProfile.Profile() if profile else None
    if profiler:
        profiler.enable()
    run = integrate(system, law, scheme, steps, implicit=implicit, bound=params.blade.length,
                    factorize=factorize, label=f"bench {model}")
    if profiler:
        profiler.disable()
        if mpi_rank() == 0:
            pstats.Stats(profiler).sort_stats("tottime").print_stats(profile)
    per_step = (run.elapsed_s - setup.elapsed_s) / steps
    # CPU of this process (rank 0) per step: on a shared machine the wall time also counts the
    # time the process waited for a core (and, under mpirun, MPI's busy-waiting counts as CPU)
    cpu_per_step = (time.process_time() - cpu1 - 0.5 * (cpu1 - cpu0)) / steps
    return {
        "model": model, "interface_modes": params.fe.interface_modes, "dofs": system.dofs,
        "contact_elements": law.count, "build_s": build_s, "build_cpu_s": build_cpu_s,
        "setup_s": setup.elapsed_s, "steps": steps, "run_s": run.elapsed_s, "per_step_ms": 1e3 * per_step,
        "cpu_per_step_ms": 1e3 * cpu_per_step, "load_1min": os.getloadavg()[0],
        "run_100_periods_s": setup.elapsed_s + per_step * 100 * params.time.steps_per_period,
        "contact_iterations_max": run.contact_iterations,
        "ranks": mpi_size(), "peak_rss_gb": peak_rss_gb(),
    }, run


def peak_rss_gb() -> float:
    """Peak resident memory of this process, summed over the MPI ranks under mpirun, GB."""
    own = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024**2
    if mpi_size() == 1:
        return own
    from mpi4py import MPI
    return MPI.COMM_WORLD.allreduce(own)


def show(row: dict) -> None:
    if mpi_rank() == 0:
        print(json.dumps({k: round(v, 4) if isinstance(v, float) else v for k, v in row.items()}), flush=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--periods", type=int, default=100)
    parser.add_argument("--models", nargs="+", default=["fe-reduced", "fe"])
    parser.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
    parser.add_argument("--interface-modes", nargs="+", type=int, metavar="K",
                        help="compare fe-reduced with these fe.interface_modes against fe")
    parser.add_argument("--window", type=int, default=10, help="periods compared (--interface-modes)")
    parser.add_argument("--superlu", action="store_true",
                        help="factorize the sparse step operator with SuperLU (default: the model's MUMPS LU)")
    parser.add_argument("--profile", type=int, default=0, metavar="N",
                        help="print the N functions of the timed run that take the most own time (cProfile)")
    args = parser.parse_args()
    params = load_scene("scenes/fig8.toml", args.set + [f"time.periods={args.periods}"]).params
    if not args.interface_modes:
        for model in args.models:
            show(measure(params, model, default_factorization if args.superlu else None, args.profile)[0])
        return
    row, fe = measure(params, "fe")
    show(row)
    period = 2 * math.pi / (params.load.ke * params.speed.omega)
    for k in args.interface_modes:
        row, run = measure(params.with_overrides([f"fe.interface_modes={k}"]), "fe-reduced")
        fit = agreement(run.t, signals_of(run), fe.t, signals_of(fe), period, min(args.window, args.periods))
        show(row | {"worst_nrmse": fit.worst_nrmse} | {f"nrmse_{n}": v for n, v in fit.nrmse.items()})

if __name__ == "__main__":
    main()
