"""The solid FE models with shroud contact: reduction against the full model and SLEPc.

Coarse linear tetrahedra (about 6000 DOF) keep these within CI time; the
checks are the ones that hold on any mesh: the reduction keeps the solid's
lowest frequencies exactly (an independent SLEPc eigen-solve), and the
reduced transient with per-node impact and friction follows the full one.
"""

import numpy as np
import pytest

pytestmark = pytest.mark.fe

pytest.importorskip("dolfinx_solver")

from comparisons._agreement import agreement  # noqa: E402
from shroud.params import Parameters  # noqa: E402

COARSE = ["fe.mesh_size=0.0035", "fe.order=1"]


@pytest.fixture(scope="module")
def params():
    return Parameters().with_overrides(COARSE + ["time.periods=3"])


def test_reduction_keeps_the_lowest_solid_frequencies(params):
    from reference_fe.modal import modal_analysis
    from reference_fe.system import build_system
    system = build_system(params, reduced=True)
    reduced = np.sqrt(np.diag(system.K)[:4]) / (2 * np.pi)
    slepc = modal_analysis(params, rpm=params.speed.rpm, n_modes=4, coriolis=False).frequencies()
    np.testing.assert_allclose(reduced, np.sort(slepc), rtol=1e-6)


def test_contact_elements_carry_the_side_totals(params):
    from reference_fe.system import build_system
    system = build_system(params, reduced=False)
    c = system.contact
    for side in (1, 2):
        assert c.weight[c.side == side].sum() == pytest.approx(1.0, rel=1e-12)
    assert set(np.unique(c.side)) == {1, 2}


@pytest.mark.slow
def test_reduced_fe_transient_follows_the_full_fe_transient(params):
    """Four models' Fig. 8 case on a coarse mesh: fe-reduced against fe, NRMSE of every signal."""
    from reference_fe.system import build_system
    from shroud.transient import simulate
    runs = {}
    for reduced in (True, False):
        result = simulate(build_system(params, reduced), params)
        tr = result.trajectory
        runs[reduced] = (tr.t, {"v_L": tr.tip[:, 0], "w_L": tr.tip[:, 1], "N1": tr.normal[:, 0],
                                "N2": tr.normal[:, 1], "Ff1": tr.friction[:, 0], "Ff2": tr.friction[:, 1]})
    period = 2 * np.pi / (params.load.ke * params.speed.omega)
    fit = agreement(*runs[True], *runs[False], period=period, periods=2)
    assert max(runs[False][1]["N1"]) > 0 and max(runs[False][1]["N2"]) > 0   # both sides touch
    assert fit.worst_nrmse < 0.02, fit.nrmse
