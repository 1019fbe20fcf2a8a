"""Mesh convergence of the solid FE frequencies for both cell kinds, their cost, and the default mesh.

The prestressed blade (default geometry, no Coriolis) is solved at each
speed of ``rpms`` on a series of tetrahedral (P2) and hexahedral (27-node
Q2, meshes.hexa) meshes, and on a reference series of cubic displacements
(P3, :func:`cubic_modes`) on the P2 tetrahedra of ``p3_sizes``. Per series,
a Richardson extrapolation of the three finest meshes gives a converged
estimate and the observed order; the effective element size is
h = DOF^(-1/3) (refinement is not nested). The converged values are those
of the ``reference`` series (the others' estimates are reported beside
them). For the P3 reference, how well they are known is measured from its
finest step (:func:`reference_uncertainty`): the limit of a sequence
converging at any order from ORDER_FLOOR up lies between its finest value
and that value extrapolated at ORDER_FLOOR.

The default mesh is the cheapest (fewest DOF: the measured solve times are
noisy on a shared machine and the first mesh also pays the forms' JIT
compilation) whose first ``n_modes`` frequencies lie within
``tolerance_pct`` of the converged values at every speed. The FE cost growth is fitted as time ~ DOF^a and
factor memory ~ DOF^b (log-log least squares over each kind's meshes):
time is the modal solve (operators and eigen-solves, mesh cached), memory
the MUMPS Cholesky factor of K + M (entries x 8 bytes), the object that
bounds the transient's step. :func:`conclusions` turns the returned numbers
into what the report concludes.

The study is compute (:func:`compute` -> :class:`ConvergenceResult`) -> plot -> report.
"""

from __future__ import annotations

import csv
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy.optimize import brentq

from comparisons import paper
from comparisons._study import study
from shroud.base.errors import InputError
from shroud.params import FE
from shroud.base.markdown import markdown_table
from shroud.core.plotting import MODEL_COLOURS, figure, save
from shroud.core.verdict import MEMORY_MB, MEMORY_RATIO, Verdict, cost, declared_rounding, timing, with_rounding
from shroud.base.outputs import open_replacing

OPTIONS = {
    "tet_sizes": [0.0035, 0.0028, 0.0022],          # fe.mesh_size of the tetrahedral meshes, m
    "hex_sizes": [0.0065, 0.005, 0.0035, 0.0025],   # ... of the hexahedral meshes, m
    "rpms": [8500.0, 10000.0],
    "n_modes": 5,
    "tolerance_pct": 0.15,
    # fe.mesh_size of the P2 tetrahedra that carry cubic displacements (the reference series, coarse to fine):
    # three or more: Richardson on the three finest; one: its values stand, how well they are known unmeasured
    "p3_sizes": [0.0035, 0.0028, 0.0022],
    "reference": "p3",      # whose estimate is the converged value: "p3", "hex" or "tet"
    "pictures": True,       # mesh and mode-shape PNGs, and the modes as VTK, of the chosen mesh
    # The shell model's own sequence (shell.mesh_size, coarse to fine; [] = none): Richardson on its three
    # finest (h = the size: structured triangles), the cheapest size within shell_tolerance_pct of that
    # with no turning point below it (monotone_to_finest) chosen, and each size's distance from the
    # solid's converged values (docs/shell.md).
    "shell_sizes": [0.008, 0.004, 0.002],
    "shell_tolerance_pct": 0.5,
}
KINDS = ("tet", "hex")          # the project's cells (fe.cell, fe.order 2): the candidates for the default
SERIES = KINDS + ("p3",)        # ... and the cubic reference (fe.order is 1 or 2: a study's own model)
CELL = {"tet": "tet", "hex": "hex", "p3": "tet"}     # each series' fe.cell
# Eigenfrequency errors of a smooth solution fall as h^(2k) for elements of degree k (twice the energy-norm
# order): h^4 for the quadratic cells, h^6 for the cubic ones; an observed order within ASYMPTOTIC (1) of it
# marks a sequence in its asymptotic range.
ELEMENT_ORDER = {"tet": 4.0, "hex": 4.0, "p3": 6.0}
ASYMPTOTIC = 1.0
# The slowest the blade's eigenfrequency errors can fall, h^(2 lambda) (any element degree) with lambda the
# smallest edge-singularity exponent of its corners (Williams): 0.5445 at the blade/shroud junction's
# re-entrant 270 deg edges (traction-free), 0.71 at the clamped root's 90 deg edges (nu = 0.3); 2 lambda =
# 1.09, floored to 1 (vertex singularities of a polyhedron cost less; any edge's lambda >= 1/2, a crack's).
ORDER_FLOOR = 1.0

# The frequencies' round-off, relative: the eigen-solve's last digits (SLEPc Krylov-Schur, shift-invert on
# MUMPS's factor) are set by rounding that the rank count changes (the partition, the factor's ordering
# and pivots): the quick scene's frequencies moved by up to 2.5e-10 of themselves under
# mpirun -n 2 and 3 (docs/reproducibility.md), declared at 5e-10 (the full scene's finer meshes were not
# measured). Numbers drawn from differences of frequencies (the errors in %, Richardson's observed orders)
# carry it amplified, and declare it so.
FREQUENCY_ROUNDING = 5e-10
ROUNDING_REASON = ("the eigen-solve's rounding, which the rank count changes (frequencies moved by up to 2.5e-10 "
                   f"of themselves under mpirun -n 2 and 3; declared at {FREQUENCY_ROUNDING:g}), carried through "
                   "Richardson's extrapolation to the errors and orders drawn from differences of frequencies")

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


def richardson_rounding(h: np.ndarray, f: np.ndarray, extrapolate=richardson,
                        eps: float = FREQUENCY_ROUNDING) -> tuple[float, float]:
    """How far ``extrapolate(h, f)``'s value (relative to itself) and observed order (absolute) move when each
    frequency moves by ``eps`` of itself: the sum of the three moves, a first-order bound. Where the
    observed order is low, (h2 / h3)^p - 1 is small and the extrapolation amplifies the frequencies' round-off
    (flap1 at order 0.54: about x40 in the runs measured)."""
    value, order = extrapolate(h, f)
    moved_value = moved_order = 0.0
    for k in range(len(f)):
        g = np.array(f, dtype=float)
        g[k] *= 1.0 + eps
        v, p = extrapolate(h, g)
        moved_value += abs(v - value)
        if p is not None and order is not None:
            moved_order += abs(p - order)
    return moved_value / abs(value), moved_order


def error_rounding(f: np.ndarray, reference: np.ndarray, reference_spread: np.ndarray,
                   eps: float | np.ndarray = FREQUENCY_ROUNDING) -> float:
    """The round-off (in %) of the errors 100 (f / reference - 1), largest entry: ``f`` known to ``eps`` of
    itself and ``reference`` to ``reference_spread`` of itself (relative, per entry)."""
    return float(np.max(100.0 * np.abs(f / reference) * (eps + reference_spread)))


def _extrapolated(h: np.ndarray, f: np.ndarray, extrapolate=richardson) -> tuple[np.ndarray, list, np.ndarray,
                                                                                  np.ndarray]:
    """Per speed and mode of ``f`` (sizes, speeds, modes): the extrapolated values, the observed orders, and
    their round-off (:func:`richardson_rounding`: the values' relative, the orders' absolute)."""
    speeds, modes = range(f.shape[1]), range(f.shape[2])
    est = [[extrapolate(h, f[:, i, j]) for j in modes] for i in speeds]
    spread = np.array([[richardson_rounding(h, f[:, i, j], extrapolate) for j in modes] for i in speeds])
    return (np.array([[e for e, _ in row] for row in est]), [[p for _, p in row] for row in est],
            spread[..., 0], spread[..., 1])


def reference_uncertainty(h: np.ndarray, f: np.ndarray, converged: np.ndarray) -> np.ndarray:
    """How well ``converged`` is known, relative, per entry, from a series' two finest meshes (h (2,)
    decreasing, f (2, ...)): the limit of a sequence converging monotonically as C h^q, at any order q from
    ORDER_FLOOR up, lies between its finest value (q infinite) and that value extrapolated from the finest
    step at q = ORDER_FLOOR, f2 - (f1 - f2) / ((h1 / h2)^ORDER_FLOOR - 1); the farther of the two from
    ``converged``. (At the observed order the Richardson estimate lies between them.)

    >>> float(reference_uncertainty(np.array([2.0, 1.0]), np.array([102.0, 101.0]), np.array(100.5)))
    0.004975124378109453
    """
    finest, step = f[1], f[0] - f[1]
    slowest = finest - step / ((h[0] / h[1]) ** ORDER_FLOOR - 1.0)
    return np.maximum(np.abs(converged - finest), np.abs(converged - slowest)) / np.abs(converged)


def uncertainty_rounding(h: np.ndarray, f: np.ndarray, converged: np.ndarray, converged_spread: np.ndarray,
                         eps: float = FREQUENCY_ROUNDING) -> np.ndarray:
    """The round-off of :func:`reference_uncertainty` per entry (relative, absolute as it is): each of the two
    meshes' frequencies moved by ``eps`` of itself, moves summed, and ``converged`` known to
    ``converged_spread`` of itself (first order)."""
    known = reference_uncertainty(h, f, converged)
    moved = 0.0
    for i in range(2):
        g = np.array(f, dtype=float)
        g[i] *= 1.0 + eps
        moved = moved + np.abs(reference_uncertainty(h, g, converged) - known)
    return moved + converged_spread


def _check(params, opts) -> None:
    from meshes.blade import MeshSpec, check_geometry
    shell = opts["shell_sizes"]
    if shell and (len(shell) < 3 or any(b >= a for a, b in zip(shell, shell[1:]))):
        raise InputError("options.shell_sizes", f"{shell}; allowed: [] or at least 3 sizes, decreasing")
    if opts["reference"] not in SERIES:
        raise InputError("options.reference", f"{opts['reference']!r}; allowed: \"p3\", \"hex\" or \"tet\"")
    for kind in SERIES:
        sizes, least = opts[f"{kind}_sizes"], 1 if kind == "p3" else 3
        if len(sizes) < least and kind == opts["reference"]:
            raise InputError(f"options.{kind}_sizes", f"{sizes}; allowed: the reference series needs at least "
                             + ("one size" if kind == "p3" else "3 sizes (Richardson)"))
        if any(b >= a for a, b in zip(sizes, sizes[1:])):
            raise InputError(f"options.{kind}_sizes", f"{sizes}; allowed: sizes decreasing (coarse to fine)")
        for size in sizes:
            check_geometry(MeshSpec.from_params(params.updated({"fe.cell": CELL[kind], "fe.mesh_size": size})))


def factor_bytes(params) -> float:
    """Memory of the MUMPS Cholesky factor of K + M at the operators' speed, bytes (entries x 8)."""
    from reference_fe.solid import lu_solver, rotating_operators
    ops = rotating_operators(params)
    A = ops.K.copy()
    A.axpy(1.0, ops.M)
    ksp = lu_solver(A, A.getComm(), "shroud_convergence_")
    ksp.setUp()
    entries = ksp.getPC().getFactorMatrix().getMumpsInfog(29)
    ksp.destroy()
    A.destroy()
    return 8.0 * float(entries)


def cubic_modes(params, rpms: list[float], n_modes: int) -> dict:
    """The prestressed solid's ``n_modes`` lowest undamped frequencies (no Coriolis) at each of ``rpms`` with
    cubic displacements (Lagrange P3) on the P2 tetrahedra of ``params``' mesh: the order raised, the mesh and
    its quadratic geometry kept. fe.order is 1 or 2 (shroud.params): the space is built here on the cached
    mesh, with reference_fe.solid's clamp, tip nodes and operators (as solve_modes). Returns a row of
    :func:`compute`'s table: DOF, the modes' labels per speed, frequencies (speeds, modes), the time of
    operators and eigen-solves, and the bytes of the MUMPS factor of K (K + M has its pattern)."""
    import dataclasses
    from reference_fe.solid import ROOT, RotatingOperators, _tip_dofs, _unit_operators, solid_model  # before dolfinx
    from dolfinx import fem
    from petsc4py import PETSc
    from meshes.spec import tip_points
    from reference_fe.modal import _stiffness_factor, _undamped, tip_components
    from shroud.core.modes import label_modes
    t0 = time.perf_counter()
    quadratic = solid_model(params)
    V = fem.functionspace(quadratic.mesh, ("Lagrange", 3, (3,)))
    root = fem.locate_dofs_topological(V, 2, quadratic.facet_tags.find(ROOT))
    cubic = dataclasses.replace(quadratic, V=V, bcs=(fem.dirichletbc(np.zeros(3, dtype=PETSc.ScalarType), root, V),),
                                clamped_dofs=np.sort((3 * root[:, None] + np.arange(3)).ravel()),
                                tip_dofs=_tip_dofs(V, tip_points(quadratic.spec), quadratic.spec.size))
    # uncached (lru_cache's __wrapped__): the finest mesh's cubic operators hold GBs, dropped on return
    unit = _unit_operators.__wrapped__(cubic)
    f, labels = [], []
    for rpm in rpms:
        ops = RotatingOperators.at(cubic, unit, rpm)
        ksp, factor = _stiffness_factor(ops)
        entries = factor.getMumpsInfog(29)
        freqs, shapes = _undamped(ops, n_modes + 2, ksp)
        ksp.destroy()
        factor.destroy()
        labels.append(label_modes(np.array([tip_components(cubic, x) for x in shapes[:n_modes]]).real)[0])
        f.append(freqs[:n_modes])
    return {"dofs": cubic.global_dofs, "labels": labels, "f": np.array(f), "solve_s": time.perf_counter() - t0,
            "factor_bytes": 8.0 * float(entries)}


def slope(dofs, values) -> float:
    """Exponent a of values ~ dofs^a (log-log least squares)."""
    return float(np.polyfit(np.log(dofs), np.log(values), 1)[0])


@dataclass(frozen=True)
class ConvergenceResult:
    """Every mesh's frequencies at every speed, the Richardson estimates, the cost growth, the chosen mesh."""

    rpms: list[float]
    labels: list[str]              # the modes, by tip-kinematics label
    rows: list[dict]               # per mesh: kind (series), size, DOF, labels per speed, solve time, factor
                                   # bytes, f, errors, params
    estimates: dict[str, tuple]    # series -> (Richardson values (speeds, modes), observed orders)
    round_off: dict[str, tuple]    # series -> round-off of those values (relative) and orders (absolute)
    reference: str                 # the series whose estimate (or finest values) are the converged values
    converged: np.ndarray          # the converged values (speeds, modes), Hz
    converged_spread: np.ndarray   # their round-off, relative
    tolerance_pct: float
    known: float | None            # how well the converged values are known, % (None: not measured)
    known_spread: float | None     # its round-off, %
    chosen: dict | None            # the row of the mesh with the fewest DOF within the tolerance
    growth: dict[str, dict]        # series -> time and factor-memory slopes over DOF (costs)
    chosen_modes: object | None    # the chosen mesh's modes at the first speed (option pictures)
    shell: dict | None             # the shell model's own mesh sequence (shell_sequence; None: no shell_sizes)

    def to_json(self) -> dict:
        rows, chosen, estimates = self.rows, self.chosen, self.estimates
        reference, reference_spread = self.converged, self.converged_spread
        results = {"labels": self.labels, "rpms": self.rpms, "tolerance_pct": self.tolerance_pct,
                   "converged_known_to_pct": self.known,
                   "meshes": [_mesh_json(r, error_rounding(r["f"], reference, reference_spread)) for r in rows],
                   "converged_hz": reference.tolist(), "reference": self.reference,
                   "richardson_hz": {kind: e[0].tolist() for kind, e in estimates.items()},
                   "observed_order": {kind: e[1] for kind, e in estimates.items()},
                   # fits of run times and of factor memory: declared so (shroud compare skips them)
                   "cost_growth": {kind: {"time_slope": timing(g["time_slope"]),
                                          "memory_slope": cost(g["memory_slope"], MEMORY_RATIO)}
                                   for kind, g in self.growth.items()},
                   "chosen": None if chosen is None else with_rounding(
                       {"cell": chosen["kind"], "mesh_size_m": chosen["size"], "dofs": chosen["dofs"],
                        "worst_error_pct": chosen["worst_pct"]}, ROUNDING_REASON,
                       worst_error_pct=error_rounding(chosen["f"], reference, reference_spread)),
                   "paper_fe_hz": list(PAPER_FE), "shell": self.shell}
        known = {} if self.known is None else {"converged_known_to_pct": self.known_spread}
        results = with_rounding(results, ROUNDING_REASON, observed_order=max(
            float(np.max(orders)) for _, orders in self.round_off.values()), **known)
        results["conclusions"] = conclusions(results)
        return results


def _mesh_json(row: dict, error_spread: float) -> dict:
    """One mesh's row of results.json, its errors' round-off declared. The factor's memory is a cost the rank
    count sets (a distributed factor has its own fill and buffers: 0.1-2.2 % more or less on 2 and 3 ranks),
    declared so, as its solve time is one the machine sets: shroud compare skips both."""
    return with_rounding({"cell": CELL[row["kind"]], "order": 3 if row["kind"] == "p3" else 2,
                          "mesh_size_m": row["size"], "dofs": row["dofs"],
                          "solve_s": row["solve_s"], "factor_MB": cost(row["factor_bytes"] / 1e6, MEMORY_MB),
                          "frequencies_hz": row["f"].tolist(), "error_pct": row["error_pct"].tolist(),
                          "worst_error_pct": row["worst_pct"]}, ROUNDING_REASON,
                         error_pct=error_spread, worst_error_pct=error_spread)


def compute(scene) -> ConvergenceResult:
    """Every mesh at every speed; the Richardson estimates, each mesh's error, the cost growth, the choice."""
    from reference_fe.modal import solve_modes
    opts = scene.options
    _check(scene.params, opts)
    k, rpms = int(opts["n_modes"]), [float(r) for r in opts["rpms"]]
    # the cubic series first: its finest operators (GBs) are dropped before the quadratic ones fill the caches
    cubic = [{"kind": "p3", "size": float(size),
              **cubic_modes(scene.params.updated({"fe.cell": "tet", "fe.mesh_size": float(size)}), rpms, k)}
             for size in opts["p3_sizes"]]
    rows = []
    for kind in KINDS:
        for size in opts[f"{kind}_sizes"]:
            params = scene.params.updated({"fe.cell": kind, "fe.mesh_size": float(size)})
            f, labels, t0 = [], [], time.perf_counter()
            for rpm in rpms:
                modes = solve_modes(params, rpm, k + 2, coriolis=False)
                labels.append(list(modes.labels[:k]))
                f.append(modes.f_undamped[:k])
            rows.append({"kind": kind, "size": float(size), "dofs": modes.dofs, "labels": labels,
                         "solve_s": time.perf_counter() - t0, "f": np.array(f),
                         "factor_bytes": factor_bytes(params.updated({"speed.rpm": rpms[-1]})),
                         "params": params})
    rows += cubic
    estimates, round_off = {}, {}
    for kind in SERIES:
        mine = [r for r in rows if r["kind"] == kind]
        if len(mine) < 3:
            continue
        values, orders, value_spread, order_spread = _extrapolated(_size(mine[-3:]),
                                                                   np.array([r["f"] for r in mine[-3:]]))
        estimates[kind], round_off[kind] = (values, orders), (value_spread, order_spread)
    reference, reference_spread, known, known_spread = _converged(rows, estimates, round_off, opts["reference"])
    labels = rows[0]["labels"][0]
    for r in rows:
        if any(found != labels for found in r["labels"]):
            raise RuntimeError(f"{r['kind']} {r['size']}: modes {r['labels']} (per speed) differ from {labels}")
        r["error_pct"] = 100 * (r["f"] / reference - 1.0)
        r["worst_pct"] = float(np.max(np.abs(r["error_pct"])))
    fit = [r for r in rows if r["kind"] in KINDS
           and within(r["worst_pct"], opts["tolerance_pct"], known, opts["reference"]).answer is True]
    chosen = min(fit, key=lambda r: r["dofs"]) if fit else None
    growth = {kind: {"time_slope": slope([r["dofs"] for r in rows if r["kind"] == kind],
                                         [r["solve_s"] for r in rows if r["kind"] == kind]),
                     "memory_slope": slope([r["dofs"] for r in rows if r["kind"] == kind],
                                           [r["factor_bytes"] for r in rows if r["kind"] == kind])}
              for kind in SERIES if sum(r["kind"] == kind for r in rows) >= 2}
    shell = (shell_sequence(scene.params, opts, rpms, labels, reference, reference_spread)
             if opts["shell_sizes"] else None)
    chosen_modes = (solve_modes(chosen["params"], rpms[0], k, coriolis=False)
                    if opts["pictures"] and chosen is not None else None)
    return ConvergenceResult(rpms=rpms, labels=labels, rows=rows, estimates=estimates, round_off=round_off,
                             reference=opts["reference"], converged=reference, converged_spread=reference_spread,
                             tolerance_pct=opts["tolerance_pct"], known=known, known_spread=known_spread,
                             chosen=chosen, growth=growth, chosen_modes=chosen_modes, shell=shell)


def _size(rows: list[dict]) -> np.ndarray:
    """The effective element sizes h = DOF^(-1/3) of ``rows`` (refinement is not nested)."""
    return np.array([r["dofs"] for r in rows], dtype=float) ** (-1.0 / 3.0)


def _converged(rows: list[dict], estimates: dict, round_off: dict, reference: str) -> tuple:
    """The converged values (speeds, modes) and their round-off (relative), how well they are known and its
    round-off (%; None: not measured). The ``reference`` series' Richardson estimate, or with fewer than three
    meshes its finest values. The cubic series is known to :func:`reference_uncertainty` of its two finest
    meshes; a quadratic one to the other series' estimates against it (two discretizations of one solid)."""
    mine = [r for r in rows if r["kind"] == reference]
    if reference in estimates:
        values, spread = estimates[reference][0], round_off[reference][0]
    else:
        values, spread = mine[-1]["f"], np.full(mine[-1]["f"].shape, FREQUENCY_ROUNDING)
    if reference == "p3":
        if len(mine) < 2:
            return values, spread, None, None
        h, f = _size(mine[-2:]), np.array([r["f"] for r in mine[-2:]])
        return (values, spread, 100 * float(np.max(reference_uncertainty(h, f, values))),
                100 * float(np.max(uncertainty_rounding(h, f, values, spread))))
    others = [kind for kind in estimates if kind != reference]
    if not others:
        return values, spread, None, None
    return (values, spread, max(100 * float(np.max(np.abs(estimates[kind][0] / values - 1.0))) for kind in others),
            max(error_rounding(estimates[kind][0], values, spread, eps=round_off[kind][0]) for kind in others))


def plot(result: ConvergenceResult, scene, out: Path) -> list[str]:
    """Error and cost against DOF (convergence.png), the chosen mesh and its modes (option pictures); the CSV."""
    rows, labels, rpms = result.rows, result.labels, result.rpms
    with open_replacing(out / "convergence.csv") as fh:
        w = csv.writer(fh)
        w.writerow(["cell", "mesh_size_m", "dofs", "solve_s", "factor_MB", "rpm"]
                   + [f"{lab}_hz" for lab in labels] + [f"{lab}_err_pct" for lab in labels])
        for r in rows:
            for i, rpm in enumerate(rpms):
                w.writerow([r["kind"], r["size"], r["dofs"], f"{r['solve_s']:.2f}", f"{r['factor_bytes'] / 1e6:.1f}",
                            rpm] + [f"{x:.4f}" for x in r["f"][i]] + [f"{x:.4f}" for x in r["error_pct"][i]])
    files = [_figure(rows, result.growth, scene.options, out / "convergence.png").name]
    if result.chosen_modes is not None:
        files += [p.name for p in _pictures(result.chosen_modes, out)]
    return files


def report(result: ConvergenceResult, scene, files: list[str]) -> str:
    return (_report(scene, result, result.to_json()["conclusions"])
            + ("" if result.shell is None else _shell_report(result.shell, result.labels, result.rpms)))


run = study(compute, plot, report)


def shell_sequence(params, opts, rpms, labels, solid_hz: np.ndarray, solid_spread: np.ndarray) -> dict:
    """The shell model's frequencies over ``options.shell_sizes``, its Richardson values and chosen size.

    Each size's frequencies for the solid's ``labels`` (matched by label) at every speed; the error
    against the shell's own converged values (Richardson on the three finest sizes, h = the size)
    chooses the cheapest size within ``shell_tolerance_pct`` among those from which every frequency
    moves one way down to the finest size (:func:`monotone_to_finest`); the converged shell against the
    converged solid (``solid_hz``, known to ``solid_spread`` of itself) is the model's own difference, which
    no mesh removes. The errors and orders declare their round-off (:data:`ROUNDING_REASON`).
    """
    from reference_fe.modal import solve_modes
    rows = []
    for size in opts["shell_sizes"]:
        p = params.updated({"shell.mesh_size": float(size)})
        f, t0 = [], time.perf_counter()
        for rpm in rpms:
            modes = solve_modes(p, rpm, len(labels) + 2, coriolis=False, kind="shell")
            found = dict(zip(modes.labels, modes.f_undamped))
            missing = [lab for lab in labels if lab not in found]
            if missing:
                raise RuntimeError(f"shell {size}: no mode {missing} among {modes.labels}")
            f.append([found[lab] for lab in labels])
        rows.append({"mesh_size_m": float(size), "dofs": modes.dofs, "solve_s": time.perf_counter() - t0,
                     "frequencies_hz": np.array(f)})
    h = np.array([r["mesh_size_m"] for r in rows[-3:]])
    f = np.array([r["frequencies_hz"] for r in rows[-3:]])
    converged, orders, spread, order_spread = _extrapolated(h, f, _shell_richardson)
    for r, monotone in zip(rows, monotone_to_finest(np.array([r["frequencies_hz"] for r in rows]))):
        r["monotone_to_finest"] = monotone
        r["error_pct"] = 100 * (r["frequencies_hz"] / converged - 1.0)
        r["worst_error_pct"] = float(np.max(np.abs(r["error_pct"])))
        r["versus_solid_pct"] = 100 * (r["frequencies_hz"] / solid_hz - 1.0)
    fit = [r for r in rows if r["worst_error_pct"] <= opts["shell_tolerance_pct"] and r["monotone_to_finest"]]
    chosen = min(fit, key=lambda r: r["dofs"]) if fit else None
    as_json = [with_rounding({k: v.tolist() if isinstance(v, np.ndarray) else v for k, v in r.items()},
                             ROUNDING_REASON,
                             **dict.fromkeys(("error_pct", "worst_error_pct"),
                                             error_rounding(r["frequencies_hz"], converged, spread)),
                             versus_solid_pct=error_rounding(r["frequencies_hz"], solid_hz, solid_spread))
               for r in rows]
    chosen_json = None if chosen is None else with_rounding(
        {"mesh_size_m": chosen["mesh_size_m"], "dofs": chosen["dofs"], "worst_error_pct": chosen["worst_error_pct"]},
        ROUNDING_REASON, worst_error_pct=error_rounding(chosen["frequencies_hz"], converged, spread))
    shell = {"meshes": as_json, "converged_hz": converged.tolist(), "observed_order": orders,
             "converged_versus_solid_pct": (100 * (converged / solid_hz - 1.0)).tolist(),
             "tolerance_pct": opts["shell_tolerance_pct"], "chosen": chosen_json}
    return with_rounding(shell, ROUNDING_REASON, observed_order=float(np.max(order_spread)),
                         converged_versus_solid_pct=error_rounding(converged, solid_hz, solid_spread, eps=spread))


SHELL_ORDERS = (1.0, 4.0)    # plausible observed orders of the shell's frequencies (CR rotations: 2)


def monotone_to_finest(f: np.ndarray) -> list[bool]:
    """Per size of ``f`` (sizes coarse to fine, then any axes: speeds, modes), whether every frequency moves
    one way from that size down to the finest, without a turning point between.

    A size before a turning point agrees with the finer ones by crossing them, not by converging: the
    blade's torsion1 falls from 8 to 4 mm while the cells cannot resolve the free chord edges' shear
    boundary layer (width t / sqrt(10) = 2.2 mm), then rises as the nonconforming rotations converge from
    below (bare, 0 r/min: 1810.6 / 1806.1 / 1804.1 / 1806.2 / 1808.8 Hz at 8 / 6 / 4 / 3 / 2 mm; shrouded,
    10000 r/min: 1569.3 / 1563.8 / 1567.9 at 8 / 4 / 2 mm: 8 mm lies within 0.1 % of 2 mm by crossing).

    >>> monotone_to_finest(np.array([[3.0, 1.0], [2.0, 1.1], [2.5, 1.2]]))
    [False, True, True]
    """
    step = np.sign(np.diff(f, axis=0))
    return [bool(np.all(np.all(step[i:] >= 0, axis=0) | np.all(step[i:] <= 0, axis=0))) for i in range(len(f))]


def _shell_richardson(h: np.ndarray, f: np.ndarray) -> tuple[float, float | None]:
    """Richardson on the shell's three finest sizes, trusted only at an order within SHELL_ORDERS.

    Outside it (a turning point among them, :func:`monotone_to_finest`, or a sequence not yet
    asymptotic), the finest value stands, without an order: the errors against it are then lower bounds.
    """
    value, order = richardson(h, f)
    if order is None or not SHELL_ORDERS[0] <= order <= SHELL_ORDERS[1]:
        return float(f[-1]), None
    return value, order


def _shell_report(shell: dict, labels, rpms) -> str:
    table = []
    for r in shell["meshes"]:
        for i, rpm in enumerate(rpms):
            table.append([f"{1e3 * r['mesh_size_m']:g}" + ("" if r["monotone_to_finest"] else " (turning point below)"),
                          r["dofs"], f"{r['solve_s']:.1f}", f"{rpm:g}"]
                         + [f"{x:.2f}" for x in r["frequencies_hz"][i]] + [f"{x:+.3f}" for x in r["error_pct"][i]]
                         + [f"{x:+.2f}" for x in r["versus_solid_pct"][i]])
    for i, rpm in enumerate(rpms):
        table.append(["Richardson", "", "", f"{rpm:g}"] + [f"{x:.2f}" for x in shell["converged_hz"][i]]
                     + ["" if p is None else f"p = {p:.1f}" for p in shell["observed_order"][i]]
                     + [f"{x:+.2f}" for x in shell["converged_versus_solid_pct"][i]])
    chosen = shell["chosen"]
    lines = ["", "## The shell model's own sequence", "",
             "Structured P2/CR triangles of the blade, free ones on the shroud plate (docs/shell.md); error "
             "against the shell's own Richardson values (three finest sizes, h = the size; the finest value "
             "where the observed order is outside 1-4, so that the errors are lower bounds), and against the "
             "solid's converged values. A size is a candidate only if every frequency moves one way from it down "
             "to the finest size: before a turning point a size agrees with the finer ones by crossing them, "
             "not by converging (torsion1 falls while the cells cannot resolve the free chord edges' shear "
             "boundary layer, then rises as the nonconforming rotations converge from below; the shroud plate's "
             "triangles are not the cause: a twice finer or a Delaunay plate moved torsion1 by < 0.01 %).",
             "", markdown_table(["size (mm)", "DOF", "solve (s)", "r/min"] + [f"{lab} (Hz)" for lab in labels]
                                + [f"{lab} err (%)" for lab in labels] + [f"{lab} vs solid (%)" for lab in labels],
                                table), "",
             (f"Chosen shell size: shell.mesh_size = {chosen['mesh_size_m']:g} m ({chosen['dofs']} DOF): the "
              f"cheapest within {shell['tolerance_pct']:g} % of the shell's converged values (worst "
              f"{chosen['worst_error_pct']:.3f} %)." if chosen else
              f"No shell size is within {shell['tolerance_pct']:g} % of its converged values: refine further."),
             "The converged shell's distance from the converged solid is the models' own difference "
             "(shell theory, the shroud as an offset plate), which no mesh removes.", ""]
    return "\n".join(lines)


def mesh_name(cell: str, size_m: float) -> str:
    return f"{cell} {1e3 * size_m:g} mm"


# How each reference's converged values are known (:func:`_converged`), the reason of :func:`within`'s margin.
KNOWN_BY = {"p3": "the converged values (the cubic tetrahedra's Richardson estimate) known to the interval their "
                  "finest step allows: from the finest P3 value to its extrapolation at order "
                  f"{ORDER_FLOOR:g}, the slowest the blade's re-entrant edges allow",
            "hex": "the converged values known to the other series' Richardson estimates",
            "tet": "the converged values known to the other series' Richardson estimates"}


def within(worst_pct: float, tolerance_pct: float, known_pct: float | None, reference: str) -> Verdict:
    """Whether a mesh's worst frequency error lies within the tolerance; the margin is how well the
    converged values of the ``reference`` series are known (:data:`KNOWN_BY`; None when this run does not
    measure it, and then the margin is 0 and the reason says it is unmeasured)."""
    if known_pct is None:
        return Verdict.of(worst_pct, tolerance_pct, 0.0, below=True, above=False, unit="%",
                          reason="how well the converged values are known is not measured in this run (one "
                                 "mesh of the cubic series, or no second estimate): margin 0")
    return Verdict.of(worst_pct, tolerance_pct, known_pct, below=True, above=False, unit="%",
                      reason=KNOWN_BY[reference])


def conclusions(results: dict) -> dict:
    """What the report concludes, as data, from the numbers ``run`` returns (a results.json gives them):

    * meets_tolerance: per mesh of the project's cells (order 2; the cubic series is the reference, not a
      candidate: fe.order is 1 or 2), its first n_modes frequencies within tolerance_pct of the converged
      values at every speed (a verdict, :func:`within`: not decided within how well the converged values
      are known); chosen: the mesh with the fewest DOF that does (None if none);
      default_mesh_meets_tolerance: whether the project's default (shroud.params.FE) does (None when
      it is not among the meshes);
    * observed_order: per series, the Richardson order of each mode at each speed, and asymptotic:
      whether every one lies within ASYMPTOTIC of the element's order ELEMENT_ORDER (its smooth rate);
    * cheaper_at_equal_error: the cell kind that meets the tolerance with fewer DOF ("hex", "tet"),
      or None when the meshes run cannot tell (the other kind's meshes all fail below that DOF).
    """
    tol, known = results["tolerance_pct"], results.get("converged_known_to_pct")
    meshes = [m for m in results["meshes"] if m.get("order", 2) == 2]
    meets = {mesh_name(m["cell"], m["mesh_size_m"]): within(m["worst_error_pct"], tol, known, results["reference"])
             for m in meshes}
    default = mesh_name(FE().cell, FE().mesh_size)
    orders = {kind: {f"{lab} at {rpm:g} r/min": p for rpm, row in zip(results["rpms"], per_speed)
                     for lab, p in zip(results["labels"], row)}
              for kind, per_speed in results["observed_order"].items()}
    found = {"meets_tolerance": meets,
             "chosen": None if results["chosen"] is None else
             mesh_name(results["chosen"]["cell"], results["chosen"]["mesh_size_m"]),
             "default_mesh_meets_tolerance": meets.get(default),
             "observed_order": orders,
             "asymptotic": {kind: all(p is not None and abs(p - ELEMENT_ORDER[kind]) <= ASYMPTOTIC
                                      for p in o.values()) for kind, o in orders.items()},
             "cheaper_at_equal_error": _cheaper(meshes, {n for n, v in meets.items() if v.answer is True})}
    spread = declared_rounding(results).get("observed_order")     # the orders' round-off, as results declare it
    return found if spread is None else with_rounding(found, ROUNDING_REASON, observed_order=spread)


def _cheaper(meshes: list[dict], within_tolerance: set[str]) -> str | None:
    """The kind whose cheapest mesh within the tolerance (named in ``within_tolerance``) has fewer DOF than
    any mesh of the other kind that is within it, the other kind having a mesh at least as large outside
    it or a larger one inside."""
    passing = {k: min((m["dofs"] for m in meshes if m["cell"] == k
                       and mesh_name(m["cell"], m["mesh_size_m"]) in within_tolerance), default=None)
               for k in KINDS}
    for kind, other in (KINDS, KINDS[::-1]):
        n = passing[kind]
        if n is None or not any(m["cell"] == other for m in meshes):
            continue
        if passing[other] is not None and passing[other] <= n:
            continue
        if passing[other] is not None or any(m["cell"] == other and m["dofs"] >= n for m in meshes):
            return kind
    return None


SERIES_NAMES = {"tet": "P2 tetrahedra", "hex": "27-node hexahedra", "p3": "P3 tetrahedra"}
TABLE_NAMES = {"tet": "tet", "hex": "hex", "p3": "tet P3"}


def _figure(rows, growth, opts, path: Path) -> Path:
    fig, axes = figure(1, 3, width=13.0, height=4.0)
    marks = {"tet": "o", "hex": "s", "p3": "^"}
    colours = {"tet": MODEL_COLOURS["full"], "hex": MODEL_COLOURS["fe"], "p3": MODEL_COLOURS["extended"]}
    for kind in SERIES:
        mine = [r for r in rows if r["kind"] == kind]
        if not mine:
            continue
        dofs = np.array([r["dofs"] for r in mine])
        worst = np.maximum([r["worst_pct"] for r in mine], 1e-4)
        secs = np.array([r["solve_s"] for r in mine])
        colour, name = colours[kind], SERIES_NAMES[kind]
        axes[0, 0].loglog(dofs, worst, marks[kind] + "-", color=colour, label=name)
        axes[0, 1].loglog(secs, worst, marks[kind] + "-", color=colour, label=name)
        if kind in growth:
            g = growth[kind]
            axes[0, 2].loglog(dofs, secs, marks[kind] + "-", color=colour,
                              label=f"{name}: time ~ DOF^{g['time_slope']:.2f}")
            axes[0, 2].loglog(dofs, [r["factor_bytes"] / 1e9 for r in mine], marks[kind] + "--", color=colour,
                              mfc="none", label=f"{name}: factor memory ~ DOF^{g['memory_slope']:.2f}")
    for ax in axes[0, :2]:
        ax.axhline(opts["tolerance_pct"], color=MODEL_COLOURS["paper"], ls="--", label="tolerance")
        ax.set_ylabel("worst |f - f_converged| / f_converged (%)")
        ax.legend()
    axes[0, 0].set_xlabel("degrees of freedom")
    axes[0, 1].set_xlabel("modal solve time (s), mesh cached")
    axes[0, 0].set_title(f"error against DOF (first {opts['n_modes']} modes, "
                         + ", ".join(f"{r:g}" for r in opts["rpms"]) + " r/min)")
    axes[0, 1].set_title("error against time")
    axes[0, 2].set_xlabel("degrees of freedom")
    axes[0, 2].set_ylabel("solve time (s, solid) / factor memory (GB, dashed)")
    axes[0, 2].set_title("FE cost growth")
    axes[0, 2].legend(fontsize=7)
    return save(fig, path)


def _pictures(modes, out: Path) -> list[Path]:
    from comparisons._pictures import mesh_picture, mode_picture
    from meshes.blade import mesh_file
    from reference_fe.export import mode_grid, write_modes_vtk
    spec = modes.operators.model.spec
    pictures = [mesh_picture(mesh_file(spec), spec.size, out / "mesh.png"),
                mode_picture(mode_grid(modes), out / "modes.png")]
    write_modes_vtk(modes, out / "modes" / "modes.pvd")
    return pictures


def _report(scene, result: ConvergenceResult, found: dict) -> str:
    opts = scene.options
    rows, labels, rpms, estimates, growth, chosen = (result.rows, result.labels, result.rpms, result.estimates,
                                                    result.growth, result.chosen)
    ref, reference = result.converged, opts["reference"]
    lines = [f"# {scene.title}", "",
             "Prestressed solid blade, no Coriolis, at " + ", ".join(f"{r:g}" for r in rpms) + " r/min; "
             "effective size h = DOF^(-1/3); Richardson on the three finest meshes of each series (P2 "
             "tetrahedra, 27-node hexahedra, and cubic displacements on the P2 tetrahedra: tet P3). Converged "
             "values: the " + ("Richardson estimate" if reference in estimates else "finest values")
             + f" of the {SERIES_NAMES[reference]}. Time: the modal solve of every "
             "speed (operators and eigen-solves, mesh cached) on this machine; memory: the MUMPS Cholesky factor "
             "of K + M (of K for P3: the same pattern).", ""]
    table = []
    for r in rows:
        for i, rpm in enumerate(rpms):
            table.append([TABLE_NAMES[r["kind"]], f"{1e3 * r['size']:g}", r["dofs"], f"{r['solve_s']:.1f}",
                          f"{r['factor_bytes'] / 1e6:.0f}", f"{rpm:g}"] + [f"{x:.2f}" for x in r["f"][i]]
                         + [f"{x:+.3f}" for x in r["error_pct"][i]])
    for kind, (est, orders) in estimates.items():
        for i, rpm in enumerate(rpms):
            table.append([f"Richardson {TABLE_NAMES[kind]}", "", "", "", "", f"{rpm:g}"] + [f"{x:.2f}" for x in est[i]]
                         + ["" if p is None else f"p = {p:.1f}" for p in orders[i]])
    lines.append(markdown_table(["cell", "size (mm)", "DOF", "solve (s)", "factor (MB)", "r/min"]
                                + [f"{lab} (Hz)" for lab in labels] + [f"{lab} err (%)" for lab in labels], table))
    for kind in (k for k in estimates if k != reference):
        diff = 100 * np.max(np.abs(estimates[kind][0] / ref - 1.0))
        lines.append(f"The {TABLE_NAMES[kind]} estimate differs from the converged values by at most {diff:.3f} %"
                     + (": how well the converged values are known." if reference != "p3" else "."))
    if reference == "p3":
        lines.append("How well the converged values are known: " + (
            f"{result.known:.4f} %: converging at any order from {ORDER_FLOOR:g} up (2 lambda = 1.09 at the blade/"
            "shroud junction's 270 deg edges), the P3 series' limit lies between its finest values and their "
            f"extrapolation from the finest step at order {ORDER_FLOOR:g}; the farther of the two from the estimate."
            if result.known is not None else "not measured (one mesh of the cubic series)."))
    lines += ["", "FE cost growth (log-log fit over each kind's meshes): "
              + "; ".join(f"{kind}: time ~ DOF^{g['time_slope']:.2f}, factor memory ~ DOF^{g['memory_slope']:.2f}"
                          for kind, g in growth.items()) + ".", ""]
    for kind, orders in found["observed_order"].items():
        known = [p for p in orders.values() if p is not None]
        lines.append(f"Observed order, {kind}: " + (f"{min(known):.1f} to {max(known):.1f}" if known else "none")
                     + (f" ({len(orders) - len(known)} of {len(orders)} non-monotone)" if len(known) < len(orders)
                        else "") + ": " + ("in the asymptotic range" if found["asymptotic"][kind] else
                                           f"not in the asymptotic range ({ELEMENT_ORDER[kind]:g} +- "
                                           f"{ASYMPTOTIC:g}, the element's smooth rate): its estimate carries "
                                           "more than the extrapolation error") + ".")
    cheaper = found["cheaper_at_equal_error"]
    lines += ["", f"At equal error (within {opts['tolerance_pct']:g} %) the "
              + (f"{cheaper} cells need fewer DOF." if cheaper else "meshes run cannot tell which cell kind "
                 "needs fewer DOF.")
              + " Within the tolerance (each verdict with its number, threshold and margin):", "",
              *[f"- {k}: {v.sentence()}" for k, v in found["meets_tolerance"].items()], ""]
    if len(rpms) < len(OPTIONS["rpms"]):
        lines += [f"Checked at {', '.join(f'{r:g}' for r in rpms)} r/min only: the tolerance is not held at the "
                  f"study's other default speeds ({', '.join(f'{r:g}' for r in OPTIONS['rpms'] if r not in rpms)} "
                  "r/min), where the prestress moves every frequency.", ""]
    if chosen is not None:
        lines.append(f"Chosen default: fe.cell = \"{chosen['kind']}\", fe.mesh_size = {chosen['size']:g} m "
                     f"({chosen['dofs']} DOF, {chosen['solve_s']:.1f} s): the mesh with the fewest DOF whose first "
                     f"{len(labels)} frequencies are within {opts['tolerance_pct']:g} % of the converged values "
                     f"at every speed (worst {chosen['worst_pct']:.3f} %).")
    else:
        lines.append(f"No mesh is within {opts['tolerance_pct']:g} % on all modes at every speed: refine further.")
    lines += ["", "Figure convergence.png: error against DOF, against time, and the cost growth."
              + (" Chosen mesh: mesh.png; its mode shapes: modes.png and modes/modes.pvd (ParaView)."
                 if opts["pictures"] and chosen is not None else "")]
    return "\n".join(lines) + "\n"
