"""The swept hexahedral solid (fe.cell = "hex"): geometry, tags, one body, refusals, and the
tetrahedral solid of the same blade as a second discretization."""

from __future__ import annotations

import dataclasses
import math
import subprocess
import sys

import numpy as np
import pytest

from meshes.blade import MeshSpec, mesh_file, tip_points
from shroud.base.errors import InputError
from shroud.params import Parameters


def _hex(**changes) -> Parameters:
    return Parameters().updated({"fe.cell": "hex", "fe.mesh_size": 0.0065, **changes})


def test_unknown_cell_kind_is_one_line_exit_2():
    run = subprocess.run([sys.executable, "-m", "workbench.cli", "modal", "--model", "fe",
                          "--set", "fe.cell=prism"], capture_output=True, text=True)
    assert run.returncode == 2
    assert run.stderr.strip().startswith("error: fe.cell:")
    assert len(run.stderr.strip().splitlines()) == 1


def test_a_footprint_cutting_the_tip_middle_is_refused_before_gmsh(tmp_path, monkeypatch):
    """A shroud half the chord long cuts the tip at its quarter-chord points: no sweep; tets suggested."""
    monkeypatch.setenv("SHROUD_CACHE", str(tmp_path))
    spec = MeshSpec.from_params(_hex(**{"shroud.length": 0.02}))
    with pytest.raises(InputError) as err:
        mesh_file(spec)
    assert err.value.key == "fe.cell" and '"tet"' in str(err.value)
    assert not list(tmp_path.rglob("*.msh"))


def test_a_hex_run_of_that_geometry_is_one_line_exit_2():
    run = subprocess.run([sys.executable, "-m", "workbench.cli", "modal", "--model", "fe",
                          "--set", "fe.cell=hex", "--set", "shroud.length=0.02"], capture_output=True, text=True)
    assert run.returncode == 2
    assert run.stderr.strip().startswith("error: fe.cell:") and "tet" in run.stderr
    assert len(run.stderr.strip().splitlines()) == 1


def _components(cells: np.ndarray) -> int:
    """Connected components of cells sharing nodes (union-find)."""
    parent = np.arange(cells.max() + 1)

    def find(i):
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    for row in cells:
        roots = {find(v) for v in row}
        first = roots.pop()
        for r in roots:
            parent[r] = first
    return len({find(v) for v in np.unique(cells)})


@pytest.mark.fe
@pytest.mark.parametrize("alpha", [0.0, 15.0, 30.0])      # tip inside the footprint; corners cut; free mesher
def test_hex_solid_volume_faces_tags_and_one_body(alpha, tmp_path, monkeypatch):
    import dolfinx_solver  # noqa: F401
    import meshio
    import ufl
    from dolfinx import fem
    from meshes.blade import BLADE, CONTACT_SIDE1, CONTACT_SIDE2, ROOT, SHROUD
    from reference_fe.solid import solid_model
    monkeypatch.setenv("SHROUD_CACHE", str(tmp_path))
    params = _hex(**{"contact.alpha_deg": alpha})
    spec = MeshSpec.from_params(params)
    model = solid_model(params)
    dx = ufl.Measure("dx", domain=model.mesh, subdomain_data=model.cell_tags)
    ds = ufl.Measure("ds", domain=model.mesh, subdomain_data=model.facet_tags)

    def integral(measure) -> float:
        return fem.assemble_scalar(fem.form(fem.Constant(model.mesh, 1.0) * measure))

    # A twisted prism keeps its volume L b h; the Q2 cells hold its helicoidal faces to 1e-8.
    assert integral(dx(BLADE)) == pytest.approx(spec.length * spec.width * spec.thickness, rel=1e-8)
    assert integral(dx(SHROUD)) == pytest.approx(
        spec.shroud_length * spec.shroud_width * spec.shroud_thickness, rel=1e-12)
    assert integral(ds(ROOT)) == pytest.approx(spec.width * spec.thickness, rel=1e-12)
    for tag in (CONTACT_SIDE1, CONTACT_SIDE2):
        assert integral(ds(tag)) == pytest.approx(spec.shroud_length * spec.shroud_thickness, rel=1e-12)
    mesh = meshio.read(mesh_file(spec))
    hexes = np.vstack([b.data for b in mesh.cells if b.type == "hexahedron27"])
    assert _components(hexes) == 1                              # blade and shroud conform: one body
    for p in tip_points(spec):                                  # tip nodes are mesh nodes
        assert np.min(np.linalg.norm(mesh.points - p, axis=1)) < 1e-12
    assert np.all(model.tip_dofs >= 0)


@pytest.mark.fe
@pytest.mark.slow
def test_hex_and_tet_solids_agree_mode_by_mode():
    """Two discretizations of one solid (27-node bricks 6.5 mm, P2 tetrahedra 3.5 mm): both lie
    above the converged frequencies, the tets by up to 0.29 % (README), so they agree within 0.3 %."""
    from reference_fe.modal import solve_modes
    hexa = solve_modes(_hex(), 10000.0, 5, coriolis=False)
    tet = solve_modes(Parameters().updated({"fe.cell": "tet", "fe.mesh_size": 0.0035}), 10000.0, 5,
                      coriolis=False)
    assert hexa.labels == tet.labels == ("flap1", "chord1", "flap2", "torsion1", "flap3")
    assert np.allclose(hexa.f_undamped, tet.f_undamped, rtol=3e-3), (hexa.f_undamped, tet.f_undamped)
    assert hexa.dofs < 0.7 * tet.dofs


def test_span_layers_are_graded_and_cover_the_blade():
    from meshes.hexa import span_position
    t = np.linspace(0.0, 1.0, 21)
    x = np.array([span_position(v) for v in t])
    assert x[0] == 0.0 and x[-1] == pytest.approx(1.0, abs=1e-15)
    steps = np.diff(x)
    assert np.all(steps > 0)
    assert steps[0] < steps[10] and steps[-1] < steps[10]       # finer at root and junction
    assert steps[0] == pytest.approx(steps[-1], rel=1e-9)


def test_cut_depth_of_the_default_footprint():
    """geometry.md: with alpha = 15 deg two tip corners stand 0.2 mm past the shroud ends."""
    from meshes.hexa import cut_depth
    spec = MeshSpec.from_params(_hex())
    # the cut meets the long edge where w_s = l_s / 2 on v = -h/2
    a = spec.alpha
    w_cut = (0.5 * spec.shroud_length - 0.5 * spec.thickness * math.sin(a)) / math.cos(a)
    assert cut_depth(spec) == pytest.approx(0.5 * spec.width - w_cut, rel=1e-12)
    assert 0.2e-3 < cut_depth(spec) < 0.3e-3
    assert cut_depth(dataclasses.replace(spec, alpha=0.0)) == 0.0
