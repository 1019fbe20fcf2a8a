"""Mesh convergence of the solid FE frequencies, and the default mesh size it picks.

The prestressed blade (default geometry, no Coriolis) is solved on a series
of meshes; a Richardson extrapolation of the three finest gives the
converged estimate and the observed order of convergence. The effective
element size of an unstructured mesh is h = DOF^(-1/3) (refinement is not
nested, so the nominal size ratio is only approximate). The default
``fe.mesh_size`` is the coarsest mesh whose first four frequencies lie
within ``tolerance_pct`` of the estimate.
"""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np
from scipy.optimize import brentq

from comparisons import paper
from shroud.core.plotting import MODEL_COLOURS, figure, save

OPTIONS = {
    "sizes": [0.0035, 0.0028, 0.0022],   # element sizes, m, coarse to fine
    "rpm": 8500.0,
    "n_modes": 4,
    "tolerance_pct": 0.5,
    "pictures": True,       # mesh and mode-shape PNGs, and the modes as VTK, of the coarsest mesh
}

# Paper Table 1, FE column (ANSYS Beam188, torsion restrained), 8500 r/min, Hz.
PAPER_FE = paper.TABLE1_FE


def richardson(h: np.ndarray, f: np.ndarray) -> tuple[float, float | None]:
    """Extrapolated value and observed order from three (h, f) pairs, h decreasing.

    Solves (f1 - f2) / (f2 - f3) = (h1^p - h2^p) / (h2^p - h3^p) for p, then
    f_inf = f3 - (f2 - f3) / ((h2 / h3)^p - 1). Non-monotone data has no
    order: the finest value is returned with ``None``.
    """
    h1, h2, h3 = h
    f1, f2, f3 = f
    d12, d23 = f1 - f2, f2 - f3
    if d12 * d23 <= 0 or d23 == 0:
        return float(f3), None
    ratio = d12 / d23

    def gap(p):
        return (h1**p - h2**p) / (h2**p - h3**p) - ratio

    lo, hi = 0.2, 12.0
    if gap(lo) * gap(hi) > 0:
        return float(f3), None
    p = brentq(gap, lo, hi)
    return float(f3 - d23 / ((h2 / h3) ** p - 1.0)), float(p)


def _check_sizes(params, sizes: list[float]) -> None:
    from meshes.blade import MeshSpec, check_geometry
    from shroud.base.errors import InputError
    if len(sizes) < 3 or sorted(sizes, reverse=True) != list(sizes):
        raise InputError("options.sizes", f"{sizes!r}; allowed: at least three sizes, coarse to fine")
    for size in sizes:
        check_geometry(MeshSpec.from_params(params.updated({"fe.mesh_size": size})))


def run(scene, out: Path) -> dict:
    from reference_fe.modal import solve_modes
    opts = scene.options
    sizes = [float(s) for s in opts["sizes"]]
    k = int(opts["n_modes"])
    _check_sizes(scene.params, sizes)
    rows = []
    for i, size in enumerate(sizes):
        # The coarsest mesh also gets the gyroscopic solve: how far Coriolis moves each mode.
        modes = solve_modes(scene.params.updated({"fe.mesh_size": size}), opts["rpm"], k + 2, i == 0)
        if i == 0:
            coarse = modes
            if opts["pictures"]:
                _pictures(modes, out)
        rows.append({"size": size, "dofs": modes.dofs, "solve_s": modes.solve_s,
                     "labels": list(modes.labels[:k]), "f": modes.f_undamped[:k].tolist()})
    f = np.array([r["f"] for r in rows])
    h = np.array([r["dofs"] for r in rows], dtype=float) ** (-1.0 / 3.0)
    estimates, orders = zip(*(richardson(h[-3:], f[-3:, j]) for j in range(k)))
    estimate = np.array(estimates)
    error_pct = 100 * (f / estimate - 1.0)
    within = np.all(np.abs(error_pct) <= opts["tolerance_pct"], axis=1)
    chosen = next((sizes[i] for i in range(len(sizes)) if within[i:].all()), None)

    with open(out / "convergence.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["mesh_size_m", "dofs", "solve_s"] + [f"f{j + 1}_hz" for j in range(k)]
                   + [f"err{j + 1}_pct" for j in range(k)])
        for r, e in zip(rows, error_pct):
            w.writerow([r["size"], r["dofs"], f"{r['solve_s']:.2f}"] + [f"{x:.4f}" for x in r["f"]]
                       + [f"{x:.4f}" for x in e])

    fig, axes = figure(1, 1)
    ax = axes[0, 0]
    dofs = np.array([r["dofs"] for r in rows])
    for j in range(k):
        ax.loglog(dofs, np.maximum(np.abs(error_pct[:, j]), 1e-6), "o-",
                  label=f"{rows[-1]['labels'][j]} ({estimate[j]:.1f} Hz)")
    ax.axhline(opts["tolerance_pct"], color=MODEL_COLOURS["paper"], ls="--", label="tolerance")
    ax.set_xlabel("degrees of freedom")
    ax.set_ylabel("|f - f_Richardson| / f_Richardson (%)")
    ax.set_title(f"Solid FE mesh convergence at {opts['rpm']:g} r/min (P{scene.params.fe.order} tetrahedra)")
    ax.legend()
    save(fig, out / "convergence.png")

    _write_report(out / "report.md", scene, rows, estimate, orders, error_pct, chosen, coarse)
    return {"coarsest_mesh": {"labels": list(coarse.labels), "f_undamped_hz": coarse.f_undamped.tolist(),
                              "f_coriolis_hz": coarse.f_coriolis.tolist(),
                              "coriolis_shift_pct": (100 * coarse.coriolis_shift).tolist(),
                              "participation": list(coarse.participation)},
            "mesh_size_m": sizes, "dofs": dofs.tolist(), "solve_s": [r["solve_s"] for r in rows],
            "labels": rows[-1]["labels"], "frequencies_hz": f.tolist(),
            "richardson_hz": estimate.tolist(), "observed_order": list(orders),
            "error_pct": error_pct.tolist(), "chosen_mesh_size_m": chosen,
            "paper_fe_hz": list(PAPER_FE[:k])}


def _pictures(modes, out: Path) -> None:
    from comparisons._pictures import mesh_picture, mode_picture
    from meshes.blade import mesh_file
    from reference_fe.export import mode_grid, write_modes_vtk
    spec = modes.operators.model.spec
    mesh_picture(mesh_file(spec), spec.size, out / "mesh.png")
    mode_picture(mode_grid(modes), out / "modes.png")
    write_modes_vtk(modes, out / "modes" / "modes.pvd")


def _write_report(path: Path, scene, rows, estimate, orders, error_pct, chosen, coarse) -> None:
    opts = scene.options
    k = len(estimate)
    lines = [f"# {scene.title}", "",
             f"Prestressed solid blade at {opts['rpm']:g} r/min, no Coriolis, quadratic tetrahedra. "
             "Effective size h = DOF^(-1/3); Richardson on the three finest meshes.", "",
             "| size (m) | DOF | solve (s) | " + " | ".join(f"f{j + 1} (Hz)" for j in range(k))
             + " | " + " | ".join(f"err{j + 1} (%)" for j in range(k)) + " |",
             "|" + " --- |" * (3 + 2 * k)]
    for r, e in zip(rows, error_pct):
        lines.append(f"| {r['size']:g} | {r['dofs']} | {r['solve_s']:.1f} | "
                     + " | ".join(f"{x:.2f}" for x in r["f"]) + " | "
                     + " | ".join(f"{x:+.3f}" for x in e) + " |")
    lines.append("| Richardson | | | " + " | ".join(f"{x:.2f}" for x in estimate) + " |" + " |" * k)
    lines.append("| paper FE (beam, torsion restrained) | | | "
                 + " | ".join(f"{x:.1f}" for x in PAPER_FE[:k]) + " |" + " |" * k)
    lines += ["", "Modes (finest mesh): " + ", ".join(rows[-1]["labels"]) + ".",
              "Observed orders: " + ", ".join("n/a" if p is None else f"{p:.2f}" for p in orders) + ".",
              "",
              (f"Chosen default fe.mesh_size = {chosen:g} m: the coarsest mesh whose first {k} "
               f"frequencies are within {opts['tolerance_pct']:g} % of the estimate."
               if chosen is not None else
               f"No mesh is within {opts['tolerance_pct']:g} % on all {k} modes: refine further."),
              "", f"## Coriolis and tip participation (coarsest mesh, {coarse.dofs} DOF)", "",
              "Participation: shares of the squared tip motion (flap along e_v(L), chord along e_w(L), "
              "torsion = twist x b/2, axial along X). The paper's beam restrains torsion, so its "
              "four modes are flap1, chord1, flap2, flap3; the solid's torsion1 has no counterpart there.", "",
              "| mode | f, no Coriolis (Hz) | f, Coriolis (Hz) | shift (%) | MAC | flap | chord | torsion | axial |",
              "|" + " --- |" * 9]
    for lab, f0, fc, sh, mac, part in zip(coarse.labels, coarse.f_undamped, coarse.f_coriolis,
                                          coarse.coriolis_shift, coarse.mac_coriolis, coarse.participation):
        lines.append(f"| {lab} | {f0:.2f} | {fc:.2f} | {100 * sh:+.3f} | {mac:.4f} | "
                     + " | ".join(f"{part[kind]:.3f}" for kind in ("flap", "chord", "torsion", "axial")) + " |")
    lines += ["", "Mesh (coarsest): mesh.png; its mode shapes: modes.png and modes/modes.pvd (ParaView).",
              "", f"Total solve time {sum(r['solve_s'] for r in rows):.1f} s on this machine."]
    path.write_text("\n".join(lines) + "\n")
