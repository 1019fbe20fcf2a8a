"""Contact-face area weights and projections on a DOLFINx box, against exact integrals."""

import numpy as np
import pytest

pytestmark = pytest.mark.fe

dolfinx_solver = pytest.importorskip("dolfinx_solver")

from mpi4py import MPI  # noqa: E402
from dolfinx import fem, mesh  # noqa: E402

from reference_fe.contact_faces import contact_elements, contact_faces, tip_frame, tip_rows  # noqa: E402
from shroud.base.errors import InputError  # noqa: E402
from shroud.params import Parameters  # noqa: E402

LOW, HIGH = 1, 2   # facet tags of the faces y = 0 and y = 2


def box(order: int):
    """Box [0,1] x [0,2] x [0,3] with its faces y = 0 and y = 2 tagged."""
    m = mesh.create_box(MPI.COMM_WORLD, [[0, 0, 0], [1, 2, 3]], [3, 2, 5], mesh.CellType.tetrahedron)
    low = mesh.locate_entities_boundary(m, 2, lambda x: np.isclose(x[1], 0.0))
    high = mesh.locate_entities_boundary(m, 2, lambda x: np.isclose(x[1], 2.0))
    facets = np.concatenate([low, high])
    values = np.concatenate([np.full(low.size, LOW), np.full(high.size, HIGH)]).astype(np.int32)
    order_ = np.argsort(facets)
    tags = mesh.meshtags(m, 2, facets[order_], values[order_])
    return fem.functionspace(m, ("Lagrange", order, (3,))), tags


@pytest.mark.parametrize("order", [1, 2])
def test_area_weights_integrate_area_and_moments_exactly(order):
    V, tags = box(order)
    faces = contact_faces(V, tags, (HIGH, LOW), Parameters())
    for face in faces:
        x, z = face.coords[:, 0], face.coords[:, 2]
        assert face.area == pytest.approx(3.0, rel=1e-12)             # 1 x 3 m^2
        assert face.weight.sum() == pytest.approx(1.0, rel=1e-12)
        assert face.weight @ x == pytest.approx(0.5, rel=1e-12)       # centroid
        assert face.weight @ z == pytest.approx(1.5, rel=1e-12)
        if order == 2:                                                 # int z^2 dA / A = 3
            assert face.weight @ z**2 == pytest.approx(3.0, rel=1e-12)
        assert np.all(face.weight > 0)


def test_sides_are_ordered_along_the_contact_normal_not_by_tag():
    V, tags = box(2)
    params = Parameters()
    frame = tip_frame(params)
    assert frame.e_vs[1] > 0          # e_vs points to +Y at beta_L + alpha = 55 deg
    for given in [(LOW, HIGH), (HIGH, LOW)]:
        side1, side2 = contact_faces(V, tags, given, params)
        assert np.allclose(side1.coords[:, 1], 0.0) and np.allclose(side2.coords[:, 1], 2.0)


def test_projections_of_a_rigid_translation_and_the_resultant_force():
    V, tags = box(2)
    params = Parameters()
    frame = tip_frame(params)
    faces = contact_faces(V, tags, (LOW, HIGH), params)
    n = V.dofmap.index_map.size_local * 3
    free = np.arange(n)
    elements = contact_elements(faces, frame, free, n)
    d = np.array([0.3, -1.1, 0.7])
    q = np.tile(d, n // 3)
    y = elements.W @ q
    np.testing.assert_allclose(y[elements.normal_row], d @ frame.e_vs, rtol=1e-13)
    np.testing.assert_allclose(y[elements.tangent_row], d @ frame.e_ws, rtol=1e-13)
    np.testing.assert_allclose(tip_rows(faces, frame, free, n) @ q, [d @ frame.e_v, d @ frame.e_w], rtol=1e-13)
    # A unit normal pressure of total 1 N per face: resultant and moment about the origin.
    for side, face in zip((1, 2), faces):
        lam = np.zeros(elements.W.shape[0])
        lam[elements.normal_row[elements.side == side]] = elements.weight[elements.side == side]
        f = (elements.W.T @ lam).reshape(-1, 3)
        np.testing.assert_allclose(f.sum(axis=0), frame.e_vs, atol=1e-13)
        coords = V.tabulate_dof_coordinates()
        np.testing.assert_allclose(np.cross(coords, f).sum(axis=0),
                                   np.cross(face.centroid, frame.e_vs), atol=1e-12)


def test_a_face_without_nodes_names_the_mesh_size():
    V, tags = box(2)
    with pytest.raises(InputError) as err:
        contact_faces(V, tags, (LOW, 99), Parameters())
    assert err.value.key == "fe.mesh_size"
