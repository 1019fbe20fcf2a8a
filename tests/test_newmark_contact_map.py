"""The contact-state map of the solid's shroud faces in the Fig. 8 study.

Per-node state shares are counted apart from the per-side state record; the
two must bound each other: a side is separate only when every node is, and
slips whenever any node slips.
"""

import csv

import numpy as np
import pytest

pytestmark = [pytest.mark.fe, pytest.mark.slow]

pytest.importorskip("dolfinx_solver")


@pytest.mark.parametrize("mesh", [["fe.cell=tet", "fe.mesh_size=0.0035", "fe.order=1"],   # triangular facets
                                  ["fe.cell=hex"]],                                      # quadrilateral facets
                         ids=["tet", "hex"])
def test_fig8_contact_map_of_the_reduced_solid(tmp_path, mesh):
    from comparisons import fig8
    from workbench.scene import load_scene
    scene = load_scene("scenes/fig8.toml", [
        *mesh, "time.periods=3", 'options.models=["fe-reduced"]',
        "options.reference=fe-reduced", "options.window_periods=2", "options.plot_periods=1"])
    results = fig8.run(scene, tmp_path)
    cmap = results["contact_map"]["fe-reduced"]
    assert (tmp_path / cmap["png"]).stat().st_size > 10_000
    assert cmap["png"] in (tmp_path / "report.md").read_text()
    rows = list(csv.DictReader(open(tmp_path / cmap["csv"])))
    sides = results["state_fraction"]["fe-reduced"]
    for side in (1, 2):
        nodes = [r for r in rows if int(r["side"]) == side]
        share = np.array([[float(r[k]) for k in ("separate", "stick", "slip")] for r in nodes])
        area = np.array([float(r["area_share"]) for r in nodes])
        summary = cmap[f"side{side}"]
        assert summary["nodes"] == len(nodes) > 10
        np.testing.assert_allclose(share.sum(axis=1), 1.0, atol=1e-12)
        assert area.sum() == pytest.approx(1.0, rel=1e-12)
        assert sum(summary["area_weighted_share"].values()) == pytest.approx(1.0, rel=1e-12)
        record = sides[f"side{side}"]
        assert record["separate"] <= share[:, 0].min() + 1e-12       # separate: every node is
        assert record["slip"] >= share[:, 2].max() - 1e-12           # slip: some node slips
        assert record["separate"] < 1.0 and summary["peak_normal_max_N"] > 0   # the faces touch
