"""Verification gates of the extended beam (reduced.torsion = true, reduced.shroud = "rigid",
the "extended" model) against the solid on the default mesh (hexahedral Q2, 5 mm, 28 929 DOF;
the figures below were measured on the earlier default, P2 tetrahedra of 3.5 mm, 37 419 DOF).

Measured at 8500 r/min without Coriolis, N = 6, modes paired by label (README,
"Extended beam"): flap1 -0.82 %, chord1 -0.52 %, flap2 -0.98 %, torsion1 -0.12 %,
flap3 -0.74 % (against the convergence scene's Richardson values, N = 10:
-0.78, -0.48, -0.92, +0.05, -1.27 %). The paper's model is 2.7 % off on flap2,
5.2 % on flap3 and has no torsion1. The beam's bending stays 0.5-1 % soft: with
nu = 0 in both models the differences fall below 0.02 % (bending) and 0.2 %
(torsion1), so what is left is the Poisson restraint of the solid's clamped,
wide root, which a beam's section kinematics do not have.
"""

import pytest

from shroud.analysis.api import modal
from shroud.params import Parameters

# |f_beam / f_solid - 1| in %, measured value plus margin for round-off and solver tolerance
GATES = {"flap1": 1.0, "chord1": 1.0, "flap2": 1.2, "torsion1": 0.5, "flap3": 1.2}


@pytest.fixture(scope="module")
def frequencies():
    params = Parameters.from_mapping({"speed": {"rpm": 8500.0}})
    beam = modal(params, "extended", rpm=8500.0, n_modes=6, coriolis=False).by_label()
    solid = modal(params, "fe", rpm=8500.0, n_modes=6, coriolis=False).by_label()
    return beam, solid


@pytest.mark.fe
@pytest.mark.slow
@pytest.mark.parametrize("label", sorted(GATES))
def test_extended_beam_frequency_gate(frequencies, label):
    beam, solid = frequencies
    error = abs(beam[label] / solid[label] - 1) * 100
    assert error <= GATES[label], f"{label}: beam {beam[label]:.1f} Hz, solid {solid[label]:.1f} Hz"
