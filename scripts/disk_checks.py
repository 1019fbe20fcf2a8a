"""The numbers docs/disk.md quotes for the 24-blade disk sector: its rigid-disk limit and its mesh convergence.

    python scripts/disk_checks.py rigid          # disk.E_factor 1000 against the clamped blade, k = 0 .. 12
    python scripts/disk_checks.py convergence    # 3.5 / 2.8 / 2.2 mm, k = 0 and 12, Richardson

Both on P2 tetrahedra, without Coriolis, at 0 and 10000 r/min (reference_fe.cyclic.diameter_modes).
"""

from __future__ import annotations

import sys

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
    from scipy.optimize import brentq
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
        (h1, h2, h3), (f1, f2, f3) = sizes, f
        p = brentq(lambda q: (f1 - f2) / (h1**q - h2**q) - (f2 - f3) / (h2**q - h3**q), 0.3, 8.0)
        limit = f3 - (f2 - f3) / (h2**p - h3**p) * h3**p
        print(f"{rpm:g} r/min nd {k:2d} {label:9s} order {p:.2f}  extrapolated {limit:.3f} Hz  "
              f"3.5 mm {100 * (f1 / limit - 1):+.3f} %  2.2 mm {100 * (f3 / limit - 1):+.3f} %")


if __name__ == "__main__":
    {"rigid": rigid, "convergence": convergence}[sys.argv[1]]()
