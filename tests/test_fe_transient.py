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

from shroud.params import Parameters  # noqa: E402

COARSE = ["fe.cell=tet", "fe.mesh_size=0.0035", "fe.order=1"]    # linear tetrahedra: the cheap solid


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


def test_reduced_contact_compliance_equals_the_full_solid(params):
    """Attachment modes of every contact direction make W K^-1 W^T (the faces' flexibility) exact."""
    import scipy.sparse.linalg as spla
    from reference_fe.system import build_system
    every = params.with_overrides(["fe.interface_modes=0"])
    full, red = build_system(every, reduced=False), build_system(every, reduced=True)
    W = full.contact.W
    exact = W @ spla.splu(full.K.tocsc()).solve(W.T.toarray())
    reduced = red.contact.W @ np.linalg.solve(red.K, red.contact.W.T)
    assert np.abs(reduced - exact).max() < 1e-8 * np.abs(exact).max()


def test_contact_elements_carry_the_side_totals(params):
    from reference_fe.system import build_system
    system = build_system(params, reduced=False)
    c = system.contact
    for side in (1, 2):
        assert c.weight[c.side == side].sum() == pytest.approx(1.0, rel=1e-12)
    assert set(np.unique(c.side)) == {1, 2}


@pytest.mark.slow
def test_fig8_study_reduced_fe_follows_the_full_fe(tmp_path):
    """The Fig. 8 study on a coarse mesh: fe-reduced against fe, NRMSE of every signal, and its files."""
    from comparisons import fig8
    from workbench.scene import load_scene
    scene = load_scene("scenes/fig8.toml", COARSE + [
        "time.periods=3", 'options.models=["fe-reduced", "fe"]', "options.window_periods=2",
        "options.plot_periods=1"])
    results = fig8.run(scene, tmp_path)
    pair = results["pairs"]["fe-reduced vs fe"]
    assert pair["worst_nrmse"] < 0.02, pair
    assert results["peak"]["fe"]["N1"] > 0 and results["peak"]["fe"]["N2"] > 0      # both sides touch
    assert [r["model"] for r in results["table3"]] == ["fe-reduced", "fe"]
    for name in ("fig8.png", "table3.csv", "agreement.csv", "report.md"):
        assert (tmp_path / name).stat().st_size > 0
    assert "status: complete" in (tmp_path / "transient_fe.csv").read_text().splitlines()[0]


@pytest.mark.slow
def test_a_diverging_fe_run_is_reported_and_its_csv_kept_marked_incomplete(tmp_path):
    """Explicit contact at kn = 1e9 N/m and 32 steps per period grows without bound (stability scene)."""
    from comparisons import fig8
    from workbench.scene import load_scene
    scene = load_scene("scenes/fig8.toml", COARSE + [
        "time.periods=3", "time.steps_per_period=32", 'time.contact=explicit', "contact.kn=1e9",
        'options.models=["fe-reduced"]', "options.reference=fe-reduced", "options.window_periods=1",
        "options.plot_periods=1"])
    results = fig8.run(scene, tmp_path)
    assert "grows without bound" in results["diverged"]["fe-reduced"]
    assert (tmp_path / "transient_fe-reduced.csv").read_text().startswith("# status: incomplete")
    assert "diverged" in (tmp_path / "report.md").read_text()
