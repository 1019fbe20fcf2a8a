"""The cyclic disk sector (reference_fe.cyclic) against CalculiX's *CYCLIC SYMMETRY MODEL on the same mesh.

CalculiX (reference_fe.calculix.write_sector_deck) reads the sector's P2 tetrahedra as C3D10 on the same
nodes, ties the side theta = +pi/N to the side -pi/N by its own cyclic symmetry (its MPCs per nodal
diameter, the sector doubled into cosine and sine parts), clamps the bore and solves each nodal
diameter: a second code for the whole of the cyclic reduction, the assembly and, spinning, the
prestress (linear, as the documented model) with stress stiffening and spin softening. On one mesh
the two codes solve the same discrete problem: they agree to the eigen-solvers' tolerances and the
.dat file's 7 digits (measured within 2e-5 on the 24-blade sector, 3.5 mm, k = 0, 1, 12 at rest;
every k at 0 and 10000 r/min: scripts/disk_checks.py calculix, docs/disk.md), held to 1e-4.
Skipped where ccx is not installed (bash scripts/install_calculix.sh).
"""

from __future__ import annotations

import numpy as np
import pytest

pytestmark = pytest.mark.fe

# a short blade (as tests/test_calculix.py) on the 24-blade disk: a cheap deck; P2, since CalculiX's C3D4
# integrates its mass on one point (not P1's consistent mass: 3.5e-3 apart on this mesh)
COARSE = {"ring.blades": 24, "disk.thickness": 0.04, "fe.cell": "tet", "fe.mesh_size": 0.0035, "fe.order": 2,
          "blade.length": 0.06, "blade.twist_deg": 4.0}


@pytest.mark.parametrize("rpm, runs, n_modes", [
    (0.0, ((0, 1),), 3),                                                   # CI: one ccx run, k = 0 and 1
    pytest.param(10000.0, ((0, 1), (12, 12)), 6, marks=pytest.mark.slow),
])
def test_sector_has_calculix_cyclic_frequencies_on_the_same_mesh(ccx, rpm, runs, n_modes, tmp_path):
    from reference_fe.calculix import run_calculix_sector
    from reference_fe.cyclic import diameter_modes, sector
    from shroud.params import Parameters
    params = Parameters().updated(COARSE)
    sec = sector(params)
    theirs = {}
    for diameters in runs:
        found, _ = run_calculix_sector(params, rpm, n_modes, tmp_path / f"k{diameters[0]}", diameters)
        theirs.update(found)
    assert sorted(theirs) == sorted({k for a, b in runs for k in range(a, b + 1)})
    for k, f in theirs.items():
        ours = diameter_modes(sec, rpm, k, n_modes, coriolis=False).f_hz
        np.testing.assert_allclose(ours, f, rtol=1e-4, err_msg=f"nodal diameter {k}")
    # the disk is in both: the second frequency of nodal diameter 1 differs from that of 0
    assert abs(theirs[1][1] / theirs[0][1] - 1) > 1e-3
