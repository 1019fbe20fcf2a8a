"""The numbers docs/disk.md quotes for the 24-blade disk sector: its rigid-disk limit and its mesh convergence.

    python scripts/disk_checks.py rigid          # disk.E_factor 1000 against the clamped blade, k = 0 .. 12
    python scripts/disk_checks.py convergence    # 3.5 / 2.8 / 2.2 mm, k = 0 and 12, Richardson
    python scripts/disk_checks.py calculix [out.json]   # against CalculiX's cyclic symmetry, k = 0 .. 12

All on P2 tetrahedra, without Coriolis, at 0 and 10000 r/min (reference_fe.cyclic.diameter_modes).
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np

TETS = {"fe.cell": "tet", "fe.order": 2}
DISK = {"ring.blades": 24, "disk.thickness": 0.04}
SPEEDS = (0.0, 10000.0)


def rigid() -> None:
    """Every nodal diameter with the disk's E x 1000 against the blade clamped at its root (same mesh size)."""
    from reference_fe.cyclic import diameter_modes, sector
    from reference_fe.modal import solve_modes
    from shroud.params import Parameters
    tets = {**TETS, "fe.mesh_size": 0.0035}
    sec = sector(Parameters().updated({**tets, **DISK, "disk.E_factor": 1000.0}))
    for rpm in SPEEDS:
        clamped = solve_modes(Parameters().updated(tets), rpm, 6, coriolis=False)
        print(f"{rpm:g} r/min, clamped: " + " ".join(f"{l}={f:.3f}" for l, f in zip(clamped.labels,
                                                                                 clamped.f_undamped)))
        spread = []
        for k in range(DISK["ring.blades"] // 2 + 1):
            found = diameter_modes(sec, rpm, k, 6, coriolis=False)
            change = 100 * (found.f_hz / clamped.f_undamped - 1)
            spread.append(change)
            print(f"  nd {k:2d} same labels {found.labels == clamped.labels}: "
                  + " ".join(f"{f:.3f} ({c:+.3f} %)" for f, c in zip(found.f_hz, change)))
        print(f"  change over all nd: {np.min(spread):+.3f} .. {np.max(spread):+.3f} %")


def convergence() -> None:
    """k = 0 and N/2 on three meshes; Richardson with the order fitted to the three (non-nested meshes)."""
    from reference_fe.cyclic import diameter_modes, sector
    from shroud.params import Parameters
    sizes = (0.0035, 0.0028, 0.0022)
    values: dict[tuple, list[float]] = {}
    for h in sizes:
        sec = sector(Parameters().updated({**TETS, **DISK, "fe.mesh_size": h}))
        print(f"{h * 1000:g} mm: {sec.M.shape[0]} DOF", flush=True)
        for rpm in SPEEDS:
            for k in (0, DISK["ring.blades"] // 2):
                found = diameter_modes(sec, rpm, k, 6, coriolis=False)
                for label, f in zip(found.labels, found.f_hz):
                    values.setdefault((rpm, k, label), []).append(float(f))
    for (rpm, k, label), f in values.items():
        if len(f) != len(sizes):
            print(f"{rpm:g} r/min nd {k} {label}: not on every mesh (labels changed order)")
            continue
        limit, p = _richardson(sizes, f)
        print(f"{rpm:g} r/min nd {k:2d} {label:9s} order {p:.2f}  extrapolated {limit:.3f} Hz  "
              f"3.5 mm {100 * (f[0] / limit - 1):+.3f} %  2.2 mm {100 * (f[2] / limit - 1):+.3f} %")


def _richardson(sizes, f) -> tuple[float, float]:
    """(limit, order) of three values ``f`` on the meshes of ``sizes``, the order fitted to the three."""
    from scipy.optimize import brentq
    (h1, h2, h3), (f1, f2, f3) = sizes, f
    p = brentq(lambda q: (f1 - f2) / (h1**q - h2**q) - (f2 - f3) / (h2**q - h3**q), 0.3, 8.0)
    return f3 - (f2 - f3) / (h2**p - h3**p) * h3**p, p


def calculix(out: str = "disk_calculix.json") -> None:
    """The 24-blade sector (3.5 mm, the benchmark's) against CalculiX's *CYCLIC SYMMETRY MODEL: k = 0 .. 12 on
    the same mesh (the two codes' difference), and CalculiX's own mesh convergence (3.5 / 2.8 / 2.2 mm,
    Richardson) at k = 0 and 12, the ends of the disk's effect; the issue's 0.5 % read as one verdict per
    mode whose margin is its extrapolation step (finest mesh to the limit). Both codes: linear prestress,
    stress stiffening and spin softening, no Coriolis (reference_fe.calculix). ccx's results are kept in
    ``out`` (JSON) and read back on a second run."""
    from reference_fe.calculix import run_calculix_sector
    from reference_fe.cyclic import diameter_modes, sector
    from shroud.core.verdict import Verdict
    from shroud.params import Parameters
    sizes, top = (0.0035, 0.0028, 0.0022), DISK["ring.blades"] // 2
    runs = [(sizes[0], (0, top))] + [(h, (k, k)) for h in sizes[1:] for k in (0, top)]
    path = Path(out)
    store = json.loads(path.read_text()) if path.exists() else {}
    ccx: dict[tuple, float] = {}           # (h, rpm, k, mode index) -> Hz
    for rpm in SPEEDS[::-1]:
        for h, diameters in runs:
            key = f"{h:g} {rpm:g} {diameters[0]}-{diameters[1]}"
            if key not in store:
                params = Parameters().updated({**TETS, **DISK, "fe.mesh_size": h})
                found, wall = run_calculix_sector(params, rpm, 6, Path(f"ccx_{key.replace(' ', '_')}"), diameters)
                store[key] = {"wall_s": wall, "f_hz": {str(k): f.tolist() for k, f in found.items()}}
                path.write_text(json.dumps(store, indent=1))
            print(f"ccx {h * 1000:g} mm {rpm:g} r/min k {diameters}: {store[key]['wall_s']:.0f} s", flush=True)
            for k, f in store[key]["f_hz"].items():
                ccx.update({(h, rpm, int(k), j): v for j, v in enumerate(f)})
    sec = sector(Parameters().updated({**TETS, **DISK, "fe.mesh_size": sizes[0]}))
    same, checked = 0.0, []         # checked: (ours against ccx's limit, ccx 2.2 mm to its limit), per mode
    for rpm in SPEEDS:
        for k in range(top + 1):
            ours = diameter_modes(sec, rpm, k, 6, coriolis=False).f_hz
            theirs = np.array([ccx[(sizes[0], rpm, k, j)] for j in range(6)])
            same = max(same, np.abs(ours / theirs - 1).max())
            print(f"{rpm:g} r/min nd {k:2d} same mesh: " + " ".join(f"{f:.3f}/{g:.3f}" for f, g in zip(ours, theirs))
                  + f"  largest {np.abs(ours / theirs - 1).max():.1e}", flush=True)
            if k not in (0, top) or any((h, rpm, k, 0) not in ccx for h in sizes):
                continue
            for j, f in enumerate(ours):
                limit, order = _richardson(sizes, [ccx[(h, rpm, k, j)] for h in sizes])
                checked.append((abs(f / limit - 1), abs(ccx[(sizes[-1], rpm, k, j)] / limit - 1)))
                print(f"   mode {j + 1}: ccx " + " / ".join(f"{ccx[(h, rpm, k, j)]:.3f}" for h in sizes)
                      + f" -> {limit:.3f} Hz (order {order:.2f}); ours at 3.5 mm {100 * (f / limit - 1):+.3f} %")
    print(f"largest same-mesh difference {same:.2e}")
    # one verdict per mode (its own extrapolation step as margin); the one nearest 0.5 % printed
    verdicts = [Verdict.of(100 * e, threshold=0.5, margin=100 * m, below="within 0.5 %", above="beyond 0.5 %",
                           unit="%", reason="the 3.5 mm sector against CalculiX extrapolated from 3.5 / 2.8 / "
                           "2.2 mm; margin: that mode's step from ccx's 2.2 mm value to its limit")
                for e, m in checked]
    if verdicts:
        print(f"{len(verdicts)} modes, answers {sorted({v.answer for v in verdicts})}; nearest: "
              + min(verdicts, key=lambda v: v.distance).sentence())

if __name__ == "__main__":
    {"rigid": rigid, "convergence": convergence, "calculix": calculix}[sys.argv[1]](*sys.argv[2:])
