"""The contact-state map on the two shroud contact faces of the solid.

In the solid FE models ("fe", "fe-reduced") every contact-face node with a
share of the face's penalty is one contact element with its own separate /
stick / slip state (reference_fe.contact_faces; paper Eqs. 3-7 per node).
shroud.core.newmark counts, per element, the steps of the final window spent in
each state and the element's peak normal force; this module places those
numbers on the faces:

* :func:`face_geometry`: the node positions of the elements, in the order
  of the models' contact elements (side 1 nodes, then side 2), and the
  facets of each face to draw them on;
* :func:`summarize`: per side, the area-weighted share of each state (the
  share of the face's penalty in that state on average) and its spread over
  the nodes;
The picture of the map is drawn by the studies (comparisons._pictures).
Units: SI.
"""

from __future__ import annotations

from dataclasses import dataclass

import dolfinx_solver  # noqa: F401  (must precede dolfinx)
import numpy as np
from dolfinx import mesh as dmesh

from reference_fe.contact_faces import contact_faces, tip_frame
from reference_fe.solid import solid_model
from shroud.core.states import STATE_NAMES
from shroud.params import Parameters


@dataclass(frozen=True)
class FaceGeometry:
    """One shroud contact face: its contact elements' nodes and its facets."""

    side: int                  # 1: face at v_s = -b_s/2; 2: at +b_s/2
    nodes: np.ndarray          # (k, 3) positions of the face's contact elements, m
    weight: np.ndarray         # (k,) area share of each node, sums to 1
    facets: np.ndarray         # (t, c, 3) corner positions of the face's facets (c = 3 or 4), m
    e_ws: np.ndarray           # (3,) the friction direction (paper Eq. 7) in the face plane


def face_geometry(params: Parameters) -> tuple[FaceGeometry, FaceGeometry]:
    """Side 1 and side 2 faces of the solid for ``params`` (mesh from the mesh cache)."""
    model = solid_model(params)
    faces = contact_faces(model.V, model.facet_tags, model.contact_tags, params)
    msh = model.mesh
    fdim = msh.topology.dim - 1
    msh.topology.create_connectivity(fdim, msh.topology.dim)
    owned = msh.topology.index_map(fdim).size_local
    by_tag = {}
    for tag in model.contact_tags:
        facets = model.facet_tags.find(tag)
        facets = facets[facets < owned]                                  # each facet from one rank
        c = 3 if msh.topology.cell_name() == "tetrahedron" else 4       # triangle or quadrilateral facets
        corners = dmesh.entities_to_geometry(msh, fdim, facets)[:, :c]   # vertices lead the facet's nodes
        if c == 4:
            corners = corners[:, [0, 1, 3, 2]]        # DOLFINx quadrilaterals are tensor-ordered
        # Under mpirun every rank draws (rank 0 into the output): all of the face's facets.
        by_tag[tag] = np.concatenate(msh.comm.allgather(msh.geometry.x[corners].reshape(-1, c, 3)))
    out = []
    for face in faces:
        # the tag whose facets hold this face's nodes: nearest facet-centroid cloud
        tag = min(by_tag, key=lambda t: np.linalg.norm(by_tag[t].mean(axis=(0, 1)) - face.centroid))
        out.append(FaceGeometry(side=face.side, nodes=face.coords, weight=face.weight, facets=by_tag[tag],
                                e_ws=tip_frame(params).e_ws))
    return tuple(out)


def contact_points(params: Parameters) -> tuple[np.ndarray, np.ndarray]:
    """(positions (k, 3) m, the faces' normal e_vs (3,)) of the solid's contact elements, in their order
    (side 1's nodes, then side 2's: reference_fe.system lists them so), for a ring's pairing."""
    faces = face_geometry(params)
    return np.concatenate([f.nodes for f in faces]), tip_frame(params).e_vs


def split_by_side(faces: tuple[FaceGeometry, ...], per_element: np.ndarray) -> list[np.ndarray]:
    """Rows of ``per_element`` (one per contact element, side 1 first) for each face."""
    counts = [f.nodes.shape[0] for f in faces]
    if per_element.shape[0] != sum(counts):
        raise ValueError(f"{per_element.shape[0]} contact elements recorded, the faces have {sum(counts)} nodes")
    return np.split(per_element, np.cumsum(counts)[:-1])


def summarize(faces: tuple[FaceGeometry, ...], share: np.ndarray, peak_normal: np.ndarray) -> dict:
    """Per side: nodes, area-weighted share of each state, its node range, the largest nodal |N|."""
    out = {}
    for face, s, n in zip(faces, split_by_side(faces, share), split_by_side(faces, peak_normal)):
        out[f"side{face.side}"] = {
            "nodes": int(s.shape[0]),
            "area_weighted_share": {name: float(face.weight @ s[:, c]) for c, name in enumerate(STATE_NAMES)},
            "node_share_min": {name: float(s[:, c].min()) for c, name in enumerate(STATE_NAMES)},
            "node_share_max": {name: float(s[:, c].max()) for c, name in enumerate(STATE_NAMES)},
            "peak_normal_max_N": float(n.max()),
        }
    return out
