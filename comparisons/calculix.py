"""The solid against a second FE code: DOLFINx and CalculiX on the same mesh.

For each mesh of the scene (a cell kind and its element size) the cached
.msh is written as a CalculiX deck (reference_fe.calculix: C3D10 for the
quadratic tetrahedra, the same element as DOLFINx's P2; C3D20 for the
27-node hexahedra, CalculiX having no 27-node brick), with the same root
clamp and material. CalculiX runs the centrifugal prestress (by default
the linear one of the documented model, as DOLFINx; ``prestress =
"nonlinear"``: its NLGEOM static step, whose perturbation stiffness adds
the initial-displacement matrix), a perturbation frequency step about it
and a Coriolis complex-frequency step; DOLFINx (reference_fe.modal) the
linear prestress, the undamped and the gyroscopic eigenproblems. Modes are
paired by their tip-kinematics label.

Times: DOLFINx's is its in-process modal solve (operators and eigen-solves,
mesh cached), CalculiX's the wall time of its ccx runs (one thread; two on the
linear-prestress path); the whole-process comparison is
benchmarks/bench_fe_modal.py.

The study is compute (:func:`compute` -> :class:`CalculixComparison`) -> plot -> report.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from comparisons import convergence
from comparisons._study import study
from shroud.base.errors import InputError
from shroud.base.markdown import markdown_table
from shroud.base.tables import write_records
from shroud.core.verdict import Verdict

OPTIONS = {
    "rpm": 10000.0,
    "n_modes": 5,
    "cells": ["tet", "hex"],          # one mesh per entry ...
    "mesh_sizes": [0.0035, 0.007],    # ... with this fe.mesh_size, m
    "coriolis": True,
    "prestress": "linear",  # CalculiX's prestressed state: "linear" (as DOLFINx's) or "nonlinear" (NLGEOM)
}


# Thresholds of "the codes agree" (per cent of the frequency), by what the two codes solve on one mesh:
SAME_ELEMENT_PCT = 0.01       # C3D10 is P2 on the same nodes: one discrete problem; only the eigen-solvers'
                              # tolerances part them (measured 9e-6 relative at rest, 6.5e-7 at 10000 r/min),
                              # and 0.01 % is a fifteenth of the mesh's own tolerance below
PRINTED_PCT = 5e-5            # ccx prints 7 significant digits: half a unit of the last, in per cent


def agreement(cell: str, worst_diff_pct: float) -> Verdict:
    """Whether DOLFINx and CalculiX agree on one mesh: its worst |difference| (%) against the threshold of
    what the two solve there (the same element for tetrahedra; for bricks two element spaces, held to the
    solid mesh's own discretization tolerance, comparisons.convergence's ``tolerance_pct``)."""
    if cell == "tet":
        threshold, why = SAME_ELEMENT_PCT, ("C3D10 and P2 on the same nodes are one discrete problem: a "
                                            "difference above the eigen-solvers' tolerances is a defect")
    else:
        threshold, why = convergence.OPTIONS["tolerance_pct"], (
            "C3D20 (serendipity) and Q2 (27 nodes) are two element spaces on one mesh: held to the solid mesh's "
            "own tolerance (scenes/convergence.toml)")
    return Verdict.of(worst_diff_pct, threshold=threshold, margin=PRINTED_PCT, below="agree", above="differ",
                      reason=f"{why}; margin: ccx's 7 printed digits", unit="%")


def check(scene) -> None:
    from reference_fe.calculix import PRESTRESS
    opts = scene.options
    if opts["prestress"] not in PRESTRESS:
        raise InputError("options.prestress", f"{opts['prestress']!r}; allowed: "
                         + ", ".join(f'"{v}"' for v in PRESTRESS))
    if len(opts["cells"]) != len(opts["mesh_sizes"]) or not opts["cells"]:
        raise InputError("options.mesh_sizes", "one size per entry of options.cells; allowed: lists of "
                         "equal, non-zero length")


@dataclass(frozen=True)
class CalculixComparison:
    """Per mesh and mode both codes' frequencies (undamped, with Coriolis); per mesh the sizes and costs."""

    modes: list[dict]              # one per mesh and mode
    meshes: list[dict]             # one per mesh: elements, DOF, times, worst difference

    @property
    def verdicts(self) -> dict[str, Verdict]:
        """Per mesh ("hex 5 mm"): whether the two codes agree on its worst undamped frequency."""
        return {_mesh_name(m): agreement(m["cell"], m["worst_diff_pct"]) for m in self.meshes}

    @property
    def conclusions(self) -> dict:
        return {name: v.to_json() for name, v in self.verdicts.items()}

    def to_json(self) -> dict:
        return {"modes": self.modes, "meshes": self.meshes, "conclusions": self.conclusions}


def _mesh_name(mesh: dict) -> str:
    return f"{mesh['cell']} {1e3 * mesh['mesh_size_m']:g} mm"


def compute(scene, out: Path) -> CalculixComparison:
    """Both codes on every mesh of the scene (CalculiX's decks, logs and .dat into ``out``/ccx_<cell>)."""
    from reference_fe.calculix import ccx, run_calculix
    from reference_fe.modal import solve_modes
    opts = scene.options
    check(scene)
    if ccx() is None:
        raise InputError("calculix", "ccx is not installed; allowed: install CalculiX "
                         "(bash scripts/install_calculix.sh, or see the README)")
    k, rpm = int(opts["n_modes"]), float(opts["rpm"])
    rows, summary = [], []
    for cell, size in zip(opts["cells"], opts["mesh_sizes"]):
        params = scene.params.updated({"fe.cell": cell, "fe.mesh_size": float(size)})
        ours = solve_modes(params, rpm, k + 2, bool(opts["coriolis"]))
        theirs = run_calculix(params, rpm, k + 2, out / f"ccx_{cell}", bool(opts["coriolis"]),
                              opts["prestress"])
        worst = 0.0
        for i, label in enumerate(ours.labels[:k]):
            j = theirs.labels.index(label) if label in theirs.labels else None
            f_ccx = theirs.f_hz[j] if j is not None else float("nan")
            fc_ccx = (theirs.f_coriolis_hz[j] if j is not None and theirs.f_coriolis_hz is not None
                      else float("nan"))
            fc_ours = ours.f_coriolis[i] if ours.f_coriolis is not None else float("nan")
            diff = 100 * (ours.f_undamped[i] / f_ccx - 1.0)
            worst = max(worst, abs(diff)) if np.isfinite(diff) else float("inf")
            rows.append({"cell": cell, "mesh_size_m": size, "label": label,
                         "f_dolfinx_hz": float(ours.f_undamped[i]), "f_calculix_hz": float(f_ccx),
                         "diff_pct": float(diff), "f_coriolis_dolfinx_hz": float(fc_ours),
                         "f_coriolis_calculix_hz": float(fc_ccx),
                         "coriolis_diff_pct": float(100 * (fc_ours / fc_ccx - 1.0))})
        summary.append({"cell": cell, "mesh_size_m": size, "element_calculix": theirs.element,
                        "dofs_dolfinx": ours.dofs, "dofs_calculix": theirs.dofs,
                        "time_dolfinx_s": ours.solve_s, "time_calculix_s": theirs.wall_s,
                        "worst_diff_pct": worst})
    return CalculixComparison(modes=rows, meshes=summary)


def plot(result: CalculixComparison, scene, out: Path) -> list[str]:
    """No figure: the frequencies as CSV (calculix.csv)."""
    write_records(out / "calculix.csv", result.modes)
    return []


PRESTRESS_TEXT = {
    "linear": "the linear centrifugal static step's stresses as initial stresses on the undeformed "
              "mesh (the documented model's prestress, as DOLFINx's: no initial-displacement matrix)",
    "nonlinear": "NLGEOM centrifugal static step (its perturbation stiffness holds the initial-displacement "
                 "matrix, which DOLFINx's linear prestress leaves out)",
}


def report(result: CalculixComparison, scene, files: list[str]) -> str:
    opts, rows, summary = scene.options, result.modes, result.meshes
    lines = [f"# {scene.title}", "",
             f"{opts['rpm']:g} r/min; the same mesh in both codes; modes paired by tip-kinematics label. "
             "DOLFINx: linear prestress (K_e u0 = f_c), Lagrange elements (P2 tetrahedra, Q2 27-node "
             "hexahedra). CalculiX: " + PRESTRESS_TEXT[opts["prestress"]] + ", perturbation *FREQUENCY, "
             "*COMPLEX FREQUENCY, CORIOLIS; C3D10 (the same element as P2) or C3D20 (serendipity: the "
             "27-node brick without its face and centre nodes, a smaller space on the same mesh).", ""]
    lines.append(markdown_table(
        ["mesh", "CalculiX element", "DOF DOLFINx", "DOF CalculiX", "DOLFINx solve (s)", "ccx runs (s)",
         "worst |diff| (%)"],
        [[f"{s['cell']} {1e3 * s['mesh_size_m']:g} mm", s["element_calculix"], s["dofs_dolfinx"],
          s["dofs_calculix"], f"{s['time_dolfinx_s']:.1f}", f"{s['time_calculix_s']:.1f}",
          f"{s['worst_diff_pct']:.3f}"] for s in summary]))
    lines += ["", *[f"- {name}: {v.sentence()}" for name, v in result.verdicts.items()]]
    lines += ["", "Frequencies, Hz (diff = DOLFINx / CalculiX - 1):", ""]
    lines.append(markdown_table(
        ["mesh", "mode", "DOLFINx", "CalculiX", "diff (%)", "Coriolis DOLFINx", "Coriolis CalculiX",
         "diff (%)"],
        [[f"{r['cell']} {1e3 * r['mesh_size_m']:g} mm", r["label"], f"{r['f_dolfinx_hz']:.3f}",
          f"{r['f_calculix_hz']:.3f}", f"{r['diff_pct']:+.3f}", f"{r['f_coriolis_dolfinx_hz']:.3f}",
          f"{r['f_coriolis_calculix_hz']:.3f}", f"{r['coriolis_diff_pct']:+.3f}"] for r in rows]))
    lines += ["", "CalculiX's complex frequencies are a projection onto the modes of its *FREQUENCY step "
              f"({int(opts['n_modes']) + 2} here): it holds the Coriolis coupling among those modes "
              "(chord1 and flap2 move) but not through the axial modes, which are not among them and "
              "through which Coriolis softens flap1 (DOLFINx: about -0.07 %; CalculiX: none): compare "
              "the Coriolis columns with that in mind.", "",
              "Decks, logs and CalculiX's .dat: ccx_<cell>/ beside this report."]
    return "\n".join(lines) + "\n"


run = study(compute, plot, report, writes=True)
