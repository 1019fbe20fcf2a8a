"""The nodes of the two shroud contact faces, their area weights and projections.

The penalty of each side (paper Eqs. 3-6: totals k_n, k_t and the preload
N_0) is spread over the nodes of its contact face in proportion to the
consistent nodal area ``a_i = int_face phi_i dA``: the nodal forces of a
uniform contact pressure. These are exact for the face area and its first
and second moments with quadratic elements (where the triangle corners
get zero and the edge midpoints a third of each facet's area: the corners
then carry no spring and are dropped; the 9-node quadrilaterals of a
hexahedral mesh give every node a positive share, 1/36, 4/36 and 16/36 of
a rectangle's area at corners, edges and centre). Each kept node becomes one contact
element with its own stick/slip state, acting on its displacement along the
shroud normal e_vs and along the friction direction e_ws (paper Eq. 7).

The tip outputs v_L, w_L are taken at the shroud centre: the mean of the two
faces' area-averaged displacements (the faces lie at v_s = -b_s/2 and
+b_s/2, so their midpoint is the shroud centre).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import dolfinx_solver  # noqa: F401  (must precede dolfinx)
import numpy as np
import scipy.sparse as sp
import ufl
from dolfinx import fem, la
from mpi4py import MPI

from reference_fe.distributed import global_offset
from shroud.base.errors import InputError
from shroud.params import Parameters
from shroud.core.system import ContactElements


@dataclass(frozen=True)
class TipFrame:
    """Unit vectors in (X, Y, Z) of the tip section and the shroud contact frame (geometry.md)."""

    e_v: np.ndarray     # thickness direction at x = L
    e_w: np.ndarray     # chord direction at x = L
    e_vs: np.ndarray    # contact normal, Eq. (7)
    e_ws: np.ndarray    # friction direction, Eq. (7)


def tip_frame(params: Parameters) -> TipFrame:
    beta = params.blade.beta(params.blade.length)
    alpha = math.radians(params.contact.alpha_deg)
    e_v = np.array([0.0, math.cos(beta), math.sin(beta)])
    e_w = np.array([0.0, -math.sin(beta), math.cos(beta)])
    return TipFrame(e_v=e_v, e_w=e_w,
                    e_vs=math.cos(alpha) * e_v + math.sin(alpha) * e_w,
                    e_ws=-math.sin(alpha) * e_v + math.cos(alpha) * e_w)


@dataclass(frozen=True)
class ContactFace:
    """Nodes of one contact face that carry a share of its penalty."""

    side: int              # 1: face at v_s = -b_s/2; 2: face at +b_s/2
    dofs: np.ndarray       # (k, 3) unrolled DOF indices (x, y, z components) in the vector space
    weight: np.ndarray     # (k,) area share, sums to 1
    area: float            # face area, m^2
    coords: np.ndarray     # (k, 3) node positions, m
    # A point of the face that a node carries at an arm a from it (the shell's plate edge: the face
    # centre t_s/2 out along X) moves by u + theta x a: the node's rotation DOFs (k, 3), and a (3,), m.
    rotation_dofs: np.ndarray | None = None
    arm: np.ndarray | None = None

    @property
    def centroid(self) -> np.ndarray:
        return self.weight @ self.coords


def face_nodes(V: fem.FunctionSpace, facet_tags, tag: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Consistent nodal areas of the facets tagged ``tag``: (dofs (k, 3), areas (k,), coords (k, 3)).

    The nodes with a positive area, gathered from every rank and put in
    one order whatever the ranks (by position: x, then y, then z, to the
    nanometre), so that the contact elements, their states and every sum
    over them are the same serially and under mpirun -n 2 or 3; ``dofs`` are
    global unrolled indices (DOLFINx/PETSc numbering; the local ones serially).
    """
    V0, to_parent = V.sub(0).collapse()
    ds = ufl.Measure("ds", domain=V.mesh, subdomain_data=facet_tags)
    nodal = fem.assemble_vector(fem.form(ufl.TestFunction(V0) * ds(tag)))
    nodal.scatter_reverse(la.InsertMode.add)
    owned = V0.dofmap.index_map.size_local
    areas = nodal.array[:owned]
    comm = V.mesh.comm
    largest = comm.allreduce(np.abs(areas).max(initial=0.0), op=MPI.MAX)
    # Corner nodes of quadratic triangles integrate to zero (up to round-off).
    keep = np.flatnonzero(areas > 1e-12 * max(largest, 1e-300))
    first = global_offset(V) + np.asarray(to_parent).ravel()[keep]
    dofs = first[:, None] + np.arange(3)[None, :]
    parts = comm.allgather((dofs, areas[keep], V0.tabulate_dof_coordinates()[keep]))
    dofs, areas, coords = (np.concatenate([p[i] for p in parts]) for i in range(3))
    order = np.lexsort(np.round(coords, 9).T[::-1])        # x first: lexsort's last key is the primary one
    return dofs[order], areas[order], coords[order]


def contact_faces(V: fem.FunctionSpace, facet_tags, tags: tuple[int, int],
                  params: Parameters) -> tuple[ContactFace, ContactFace]:
    """The two contact faces, ordered side 1 then side 2 by where they lie along e_vs.

    Raises InputError (key fe.mesh_size) when a face has no node: the mesh is
    too coarse for the shroud.
    """
    frame = tip_frame(params)
    found = []
    for tag in tags:
        dofs, areas, coords = face_nodes(V, facet_tags, tag)
        if areas.size == 0:
            raise InputError("fe.mesh_size", f"contact face (facet tag {tag}) has no nodes; "
                             "allowed: an element size that resolves the shroud faces "
                             f"(at most shroud.thickness = {params.shroud.thickness} m)")
        found.append((dofs, areas, coords))
    # Side 1 faces passive blade 1 at v_s = -b_s/2 (geometry.md): the lower e_vs position.
    order = np.argsort([(a @ c) @ frame.e_vs / a.sum() for _, a, c in found])
    return tuple(ContactFace(side=i + 1, dofs=found[k][0], weight=found[k][1] / found[k][1].sum(),
                             area=float(found[k][1].sum()), coords=found[k][2])
                 for i, k in enumerate(order))


def contact_elements(faces: tuple[ContactFace, ...], frame: TipFrame, free_index: np.ndarray,
                     n: int) -> ContactElements:
    """One contact element per face node: rows 2j (along e_vs) and 2j+1 (along e_ws) of W.

    ``free_index`` maps an unrolled DOF of the space to its column in the
    model's (free-DOF) numbering; the contact faces are never clamped.
    """
    directions = np.vstack([frame.e_vs, frame.e_ws])
    W = sp.vstack([point_rows(f, directions, free_index, n) for f in faces]).tocsr()
    k = W.shape[0] // 2
    return ContactElements(W=W, normal_row=2 * np.arange(k), tangent_row=2 * np.arange(k) + 1,
                           side=np.concatenate([np.full(f.dofs.shape[0], f.side) for f in faces]),
                           weight=np.concatenate([f.weight for f in faces]))


def point_rows(face: ContactFace, directions: np.ndarray, free_index: np.ndarray, n: int) -> sp.csr_matrix:
    """(d k, n): the displacement of each of the face's k points along each of ``directions`` (d, 3),
    point by point (rows j d .. j d + d - 1 for point j): e . u, plus (a x e) . theta with an arm a."""
    d, k = directions.shape[0], face.dofs.shape[0]
    rows = np.repeat(np.arange(d * k), 3)
    cols = np.repeat(free_index[face.dofs], d, axis=0).ravel()
    vals = np.tile(directions, (k, 1)).ravel()
    if face.rotation_dofs is not None:
        rows = np.concatenate([rows, rows])
        cols = np.concatenate([cols, np.repeat(free_index[face.rotation_dofs], d, axis=0).ravel()])
        vals = np.concatenate([vals, np.tile(np.cross(face.arm, directions), (k, 1)).ravel()])
    return sp.csr_matrix((vals, (rows, cols)), shape=(d * k, n))


def tip_rows(faces: tuple[ContactFace, ...], frame: TipFrame, free_index: np.ndarray, n: int):
    """(2, n) rows giving v_L, w_L of the shroud centre: the mean of the faces' area averages."""
    directions = np.vstack([frame.e_v, frame.e_w])
    return sum(sp.csr_matrix(0.5 * np.kron(f.weight, np.eye(2))) @ point_rows(f, directions, free_index, n)
               for f in faces).tocsr()
