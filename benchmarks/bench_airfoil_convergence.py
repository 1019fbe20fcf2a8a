"""Accuracy and cost of the airfoil solid's modes: a mesh sequence, its Richardson limit, CalculiX.

The NACA blade of shared/spec/geometry.md ("Airfoil blades"): m 0.04, p 0.4,
chord 40 -> 30 mm, thickness 7 -> 4.2 mm, the paper's stagger, twist and
shroud, alpha 15 deg; P2 tetrahedra on the loft (meshes.blade) or, with
``--cell hex``, swept Q2 hexahedra (meshes.hexa). Each mesh size
runs in a fresh process: the first ``--modes`` undamped frequencies of the
prestressed solid at 0 and 10000 r/min, DOF, and the wall time of mesh plus
solve. The limit per mode is Richardson's extrapolation f = f_inf + C h^q on
the three finest sizes (q fitted per mode; with fewer sizes the P3 values
stand for it); ``--p3 SIZE`` adds cubic
displacements (P3 on the P2 geometry of the mesh of that size: the order
raised instead of the size lowered, no element size in common with the
sequence's error; comparisons.convergence.cubic_modes, the convergence
scene's reference); ``--ccx SIZE`` CalculiX's C3D10 frequencies on the mesh of
that size (a second code on the same cells).

    python benchmarks/bench_airfoil_convergence.py --sizes 0.002 0.0016 0.0013 0.0011 --p3 0.002 --ccx 0.0013
"""

from __future__ import annotations

import argparse
import json
import math
import subprocess
import sys

import numpy as np

NACA = ["blade.section=naca4", "blade.chord_taper=0.75", "blade.thickness_taper=0.6", "contact.alpha_deg=15",
        "fe.cell=tet"]
SPEEDS = (0.0, 10000.0)

WORK = """
import json, sys, time
t0 = time.perf_counter()
from reference_fe.modal import solve_modes
from shroud.params import Parameters
p = Parameters().with_overrides(%r + ["fe.mesh_size=%r"])
out = {"size": %r}
for rpm in %r:
    m = solve_modes(p, rpm, %d, coriolis=False)
    out[str(rpm)] = m.f_undamped.tolist()
    out["dofs"] = m.dofs
out["wall_s"] = time.perf_counter() - t0
print(json.dumps(out))
"""

P3 = """
import json, time
t0 = time.perf_counter()
from comparisons.convergence import cubic_modes
from shroud.params import Parameters
p = Parameters().with_overrides(%r + ["fe.mesh_size=%r"])
speeds = %r
row = cubic_modes(p, speeds, %d)
out = {"size": p.fe.mesh_size, "dofs": row["dofs"], **{str(rpm): f.tolist() for rpm, f in zip(speeds, row["f"])}}
out["wall_s"] = time.perf_counter() - t0
print(json.dumps(out))
"""

CCX = """
import json, tempfile
from pathlib import Path
from reference_fe.calculix import run_calculix
from shroud.params import Parameters
p = Parameters().with_overrides(%r + ["fe.mesh_size=%r"])
out = {"size": %r}
with tempfile.TemporaryDirectory() as tmp:
    for rpm in %r:
        m = run_calculix(p, rpm, %d, Path(tmp) / str(rpm), coriolis=False)
        out[str(rpm)] = list(m.f_hz)
print(json.dumps(out))
"""


def _run(code: str) -> dict:
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    return json.loads(done.stdout.strip().splitlines()[-1])


def richardson(sizes: np.ndarray, f: np.ndarray) -> tuple[float, float]:
    """(f_inf, q) of f = f_inf + C h^q through three (size, f) pairs (sizes decreasing)."""
    r1, r2 = sizes[0] / sizes[1], sizes[1] / sizes[2]
    d1, d2 = f[0] - f[1], f[1] - f[2]
    q = np.log(abs(d1 / d2)) / np.log(r1) if r1 == r2 else _q_by_bisection(r1, r2, d1 / d2)
    return f[2] - d2 / (r2**q - 1.0), q


def _q_by_bisection(r1: float, r2: float, ratio: float) -> float:
    """q with (r1^q - 1) r2^q / (r2^q - 1) = ratio (unequal refinement ratios)."""
    lo, hi = 0.5, 12.0
    g = (lambda q: (r1**q - 1.0) * r2**q / (r2**q - 1.0) - abs(ratio))
    for _ in range(80):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if g(mid) < 0 else (lo, mid)
    return 0.5 * (lo + hi)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=float, nargs="+", default=[0.002, 0.0016, 0.0013])
    parser.add_argument("--modes", type=int, default=5)
    parser.add_argument("--ccx", type=float, default=None, metavar="SIZE")
    parser.add_argument("--p3", type=float, default=None, metavar="SIZE")
    parser.add_argument("--cell", choices=("tet", "hex"), default="tet",
                        help="P2 tetrahedra on the loft or swept Q2 hexahedra (docs/fe-solid.md)")
    args = parser.parse_args()
    sets = [s for s in NACA if not s.startswith("fe.cell=")] + [f"fe.cell={args.cell}"]
    rows = []
    for size in sorted(args.sizes, reverse=True):
        rows.append(_run(WORK % (sets, size, size, SPEEDS, args.modes)))
        print(json.dumps(rows[-1]), flush=True)
    cubic = _run(P3 % (sets, args.p3, SPEEDS, args.modes)) if args.p3 else None
    if cubic:
        print(json.dumps({"p3": cubic}), flush=True)
    ccx = _run(CCX % (sets, args.ccx, args.ccx, SPEEDS, args.modes)) if args.ccx else None
    if ccx:
        print(json.dumps({"calculix": ccx}), flush=True)
    sizes = np.array([r["size"] for r in rows])
    for rpm in SPEEDS if len(rows) >= 3 or cubic else ():      # a limit needs three sizes or P3
        f = np.array([r[str(rpm)] for r in rows])
        reference = "Richardson limit, order q" if len(rows) >= 3 else "P3"
        print(f"\n{rpm:g} r/min: mode, f per size (Hz), {reference}, error of each size (%)")
        for k in range(f.shape[1]):
            limit, q = richardson(sizes[-3:], f[-3:, k]) if len(rows) >= 3 else (cubic[str(rpm)][k], math.nan)
            errors = " ".join(f"{100 * (x / limit - 1):+.3f}" for x in f[:, k])
            extra = "".join(f", {name} {other[str(rpm)][k]:.2f} ({100 * (other[str(rpm)][k] / limit - 1):+.3f} %)"
                            for name, other in (("P3", cubic), ("CalculiX", ccx)) if other)
            print(f"  {k + 1}: {' '.join(f'{x:.2f}' for x in f[:, k])}  -> {limit:.2f} (q {q:.2f}); {errors}{extra}")
    print("\n" + " ".join(f"{r['size'] * 1e3:g} mm: {r['dofs']} DOF, {r['wall_s']:.0f} s" for r in rows))


if __name__ == "__main__":
    main()
