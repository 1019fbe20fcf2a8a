"""The solid against a second FE code: CalculiX (ccx) on the same mesh.

* P2 tetrahedra are CalculiX's C3D10 on the same nodes: at rest the two
  codes give the same frequencies (measured within 9e-6, held to 2e-5), and
  at 10000 r/min too once CalculiX solves the same problem, the documented
  model's linear prestress (reference_fe.calculix, prestress="linear":
  measured within 9e-6, held to 2e-5, the issue's goal being 5e-4);
* CalculiX's usual NLGEOM path adds the initial-displacement matrix to its
  perturbation stiffness, which the documented model leaves out: torsion1
  moves by 1.9e-4 on this short blade (0.06 % on the default one), so the
  test above would fail on it;
* 27-node bricks against C3D20 (serendipity, without the face and centre
  nodes: a smaller space on the same mesh) within 0.2 %.

Skipped (with the reason) where ccx is not installed: bash
scripts/install_calculix.sh installs it where apt-get and root are at hand.
"""

from __future__ import annotations

import numpy as np
import pytest

from shroud.params import Parameters

pytestmark = [pytest.mark.fe, pytest.mark.slow]


SHORT = {"blade.length": 0.06, "blade.twist_deg": 4.0}       # a short blade: a cheap deck


@pytest.mark.parametrize("cell, size, rpm, rtol", [
    ("tet", 0.0035, 0.0, 2e-5),
    ("tet", 0.0035, 10000.0, 2e-5),
    ("hex", 0.0065, 10000.0, 2e-3),
])
def test_same_mesh_in_calculix_gives_the_same_modes(ccx, cell, size, rpm, rtol, tmp_path):
    from reference_fe.calculix import run_calculix
    from reference_fe.modal import solve_modes
    params = Parameters().updated({**SHORT, "fe.cell": cell, "fe.mesh_size": size})
    ours = solve_modes(params, rpm, 5, coriolis=False)
    theirs = run_calculix(params, rpm, 5, tmp_path, coriolis=False)
    assert theirs.labels == ours.labels
    if cell == "tet":
        assert theirs.dofs == ours.dofs               # the same nodes
    assert np.allclose(ours.f_undamped, theirs.f_hz, rtol=rtol), (ours.f_undamped, theirs.f_hz)


def test_coriolis_frequencies_of_both_codes_agree(ccx, tmp_path):
    """CalculiX projects the gyroscopic problem on its *FREQUENCY modes (it misses the axial
    coupling, about 1e-4 here): the two codes agree to 1e-3."""
    from reference_fe.calculix import run_calculix
    from reference_fe.modal import solve_modes
    params = Parameters().updated({**SHORT, "fe.cell": "tet", "fe.mesh_size": 0.0035})
    ours = solve_modes(params, 10000.0, 4, coriolis=True)
    theirs = run_calculix(params, 10000.0, 4, tmp_path, coriolis=True)
    assert np.allclose(np.sort(ours.f_coriolis), theirs.f_coriolis_hz, rtol=1e-3)
    # Coriolis moves the frequencies (and both codes see it)
    assert np.max(np.abs(theirs.f_coriolis_hz / theirs.f_hz - 1)) > 1e-5


def test_calculix_nonlinear_prestress_differs_by_the_initial_displacement_matrix(ccx, tmp_path):
    """NLGEOM: CalculiX's perturbation stiffness about the displaced state softens torsion1 by
    O(strain) ~ 1e-4 at 10000 r/min, the term the linear prestress leaves out; at 5000 r/min by a
    quarter of that (the matrix is linear in the prestatic displacement, u0 ~ Omega^2)."""
    from reference_fe.calculix import run_calculix
    params = Parameters().updated({**SHORT, "fe.cell": "tet", "fe.mesh_size": 0.0035})
    shift = {}
    for rpm in (5000.0, 10000.0):
        lin = run_calculix(params, rpm, 2, tmp_path / f"lin{rpm:g}", coriolis=False, prestress="linear")
        nl = run_calculix(params, rpm, 2, tmp_path / f"nl{rpm:g}", coriolis=False, prestress="nonlinear")
        i = lin.labels.index("torsion1")
        shift[rpm] = nl.f_hz[i] / lin.f_hz[i] - 1
    assert -4e-4 < shift[10000.0] < -1e-4
    assert shift[5000.0] / shift[10000.0] == pytest.approx(0.25, abs=0.05)
