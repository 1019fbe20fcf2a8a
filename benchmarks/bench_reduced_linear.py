"""Speed of the linear beam model: assembly, one system, one modal solve, a Campbell.

Goals: assembling the N = 6 matrices < 50 ms; a 200-speed Campbell
< 2 s; the extended beam's N = 6 matrices (torsion, rigid shroud,
36 DOF) < 5 ms, its section properties computed once per section. Run: ``python benchmarks/bench_reduced_linear.py``; prints the
median of several repeats (wall time on this machine).
"""

from __future__ import annotations

import statistics
import time

import numpy as np

from reduced_model.models import EXTENDED
from reduced_model.beam import beam_matrices, tip_body
from reduced_model.campbell import campbell
from reduced_model.modal import modal_analysis
from reduced_model.system import build_system
from shroud.params import Parameters


def median_time(fn, repeats: int) -> float:
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def main() -> None:
    p = Parameters.from_mapping({"speed": {"rpm": 8500.0}})
    assemble = lambda q, N: beam_matrices.__wrapped__(q.blade, q.material, tip_body(q), N,  # noqa: E731
                                                       q.reduced.torsion)                     # no cache
    rows = [(f"assemble matrices, N = {N} ({5 * N} DOF)", median_time(lambda: assemble(p, N), 20), 0.050 if N == 6 else None)
            for N in (6, 12, 20)]
    ext = p.updated(EXTENDED)
    rows.append(("assemble extended matrices, N = 6 (36 DOF)", median_time(lambda: assemble(ext, 6), 20), 0.005))
    rows.append(("modal extended, N = 6, no Coriolis", median_time(lambda: modal_analysis(ext, 8500, 6, False), 20),
                 None))
    rows.append(("build_system reduced (nr = 6), cached matrices", median_time(lambda: build_system(p, True), 20), None))
    rows.append(("modal, N = 6, no Coriolis", median_time(lambda: modal_analysis(p, 8500, 6, False), 20), None))
    rows.append(("modal, N = 6, with Coriolis", median_time(lambda: modal_analysis(p, 8500, 6, True), 20), None))
    rpms = np.linspace(0, 15000, 200)
    rows.append(("Campbell 200 speeds, no Coriolis", median_time(lambda: campbell(p, rpms, 4, False), 3), 2.0))
    rows.append(("Campbell 200 speeds, with Coriolis", median_time(lambda: campbell(p, rpms, 4, True), 3), 2.0))
    width = max(len(r[0]) for r in rows)
    for name, t, goal in rows:
        verdict = "" if goal is None else f"   goal < {goal * 1e3:g} ms: {'met' if t < goal else 'MISSED'}"
        print(f"{name:<{width}}  {t * 1e3:9.2f} ms{verdict}")


if __name__ == "__main__":
    main()
