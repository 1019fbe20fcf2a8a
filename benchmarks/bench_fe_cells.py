"""The Fig. 8 response of the solid on both cell kinds, side by side in one process.

The hexahedral default mesh (5 mm; the Fig. 8 scene itself runs on 10 mm)
against the P2 tetrahedra of 3.5 mm (the solid before fe.cell existed), or
against ``--candidates``: each model of ``--models`` runs on every mesh;
reported per run DOF, contact elements, build and per-step times, and the
hexahedral run's agreement with the tetrahedral one (NRMSE and peak error of
the Fig. 8 signals over the last ``--window`` periods, shroud/analysis/agreement.py).

    python benchmarks/bench_fe_cells.py                               # fe-reduced, 100 periods
    python benchmarks/bench_fe_cells.py --models fe --periods 4       # the full solid, per step
    python benchmarks/bench_fe_cells.py --factor                      # factor size, back-substitution

``--candidates``: other meshes (each a comma-separated list of overrides of
the 5 mm hexahedra) against those instead of the tetrahedra, with the
errors of the steady amplitudes too; how the Fig. 8 scene's own mesh (10 mm)
was chosen:

    python benchmarks/bench_fe_cells.py --candidates fe.mesh_size=0.01 fe.hex_span_ratio=2 \
        fe.mesh_size=0.007,fe.hex_span_ratio=1.5

``--factor``: the MUMPS Cholesky factor of K + M at 10000 r/min on each mesh
(entries) and the median time of 20 back-substitutions, the meshes
alternated ``--repeats`` times: the object that bounds the full solid's step.
"""

from __future__ import annotations

import argparse
import json
import math
import time

from shroud.analysis.agreement import agreement, signals_of, window
from shroud.analysis.api import build_system
from shroud.analysis.transient import contact_law_for
from workbench.scene import load_scene
from shroud.core.newmark import NewmarkScheme, integrate

CELLS = {"hex": ["fe.cell=hex", "fe.mesh_size=0.005"], "tet": ["fe.cell=tet", "fe.mesh_size=0.0035"]}


def run(params, model: str):
    t0 = time.perf_counter()
    system = build_system(params, model)
    build_s = time.perf_counter() - t0
    law = contact_law_for(system, params.contact)
    steps = params.time.periods * params.time.steps_per_period
    trajectory = integrate(system, law, NewmarkScheme(dt=params.time_step), steps,
                           implicit=params.time.contact == "implicit", bound=params.blade.length,
                           label=f"{model} {params.fe.cell}")
    return {"dofs": system.dofs, "contact_elements": law.count, "build_s": round(build_s, 2),
            "run_s": round(trajectory.elapsed_s, 2),
            "per_step_ms": round(1e3 * trajectory.elapsed_s / steps, 3)}, trajectory


def factor(repeats: int) -> None:
    import statistics
    from reference_fe.solid import lu_solver, rotating_operators
    times = {cell: [] for cell in CELLS}
    for _ in range(repeats):
        for cell, overrides in CELLS.items():
            ops = rotating_operators(load_scene("scenes/fig8.toml", overrides).params, 10000.0)
            A = ops.K.copy()
            A.axpy(1.0, ops.M)
            ksp = lu_solver(A, A.getComm(), "bench_cells_")
            ksp.setUp()
            entries = ksp.getPC().getFactorMatrix().getMumpsInfog(29)
            b = A.createVecLeft()
            b.set(1.0)
            x = b.duplicate()
            t0 = time.perf_counter()
            for _ in range(20):
                ksp.solve(b, x)
            times[cell].append(1e3 * (time.perf_counter() - t0) / 20)
            ksp.destroy()
            print(json.dumps({"cell": cell, "dofs": A.getSize()[0], "factor_entries": entries,
                              "solve_ms": round(times[cell][-1], 2)}), flush=True)
    a, b = (statistics.median(times[c]) for c in ("hex", "tet"))
    print(json.dumps({"median_solve_ms": {"hex": round(a, 2), "tet": round(b, 2)}, "ratio_tet_hex": round(b / a, 2)}))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--periods", type=int, default=100)
    parser.add_argument("--window", type=int, default=10)
    parser.add_argument("--models", nargs="+", default=["fe-reduced"])
    parser.add_argument("--factor", action="store_true")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--candidates", nargs="+", default=[], metavar="KEY=VALUE,...",
                        help="meshes (comma-separated overrides each) compared with the default hex mesh instead")
    args = parser.parse_args()
    if args.factor:
        factor(args.repeats)
        return
    meshes = ({"hex": CELLS["hex"], **{c: CELLS["hex"] + c.split(",") for c in args.candidates}} if args.candidates
              else CELLS)
    reference = "hex" if args.candidates else "tet"
    for model in args.models:
        runs = {}
        for cell, overrides in meshes.items():
            params = load_scene("scenes/fig8.toml", overrides + [f"time.periods={args.periods}"]).params
            row, runs[cell] = run(params, model)
            print(json.dumps({"model": model, "cell": cell, **row}), flush=True)
        period = 2 * math.pi / (params.load.ke * params.speed.omega)
        ref = runs[reference]
        for cell, got in runs.items():
            if cell == reference:
                continue
            fit = agreement(got.t, signals_of(got), ref.t, signals_of(ref), period, min(args.window, args.periods))
            print(json.dumps({"model": model, f"{cell}_against_{reference}": fit.to_json(),
                              "amplitude_error": amplitude_error(got, ref, period, min(args.window, args.periods))}),
                  flush=True)


def amplitude_error(got, ref, period: float, periods: int) -> dict[str, float]:
    """Relative error of the steady amplitudes (max - min) / 2 of v_L and w_L over the last ``periods``."""
    def amplitude(tr):
        tip = tr.tip[window(tr.t, period, periods)]
        return 0.5 * (tip.max(axis=0) - tip.min(axis=0))
    a, b = amplitude(got), amplitude(ref)
    return {name: round(float(x / y - 1.0), 5) for name, x, y in zip(("v_L", "w_L"), a, b)}


if __name__ == "__main__":
    main()
