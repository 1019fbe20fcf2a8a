"""The contact-state map on the two shroud contact faces of the solid (issue 6).

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
* :func:`draw`: a pyvista off-screen picture, one row per side and one
  column per state, nodes coloured by their share of the window.

Faces are drawn in their own plane: horizontal the friction direction e_ws
(paper Eq. 7), vertical the radial coordinate X, both in mm. Units: SI in
the data, mm in the picture.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import dolfinx_solver  # noqa: F401  (must precede dolfinx)
import numpy as np
from dolfinx import mesh as dmesh

from reference_fe.contact_faces import contact_faces, tip_frame
from reference_fe.solid import solid_model
from shroud.core.contact import STATE_NAMES
from shroud.params import Parameters


@dataclass(frozen=True)
class FaceGeometry:
    """One shroud contact face: its contact elements' nodes and its facets."""

    side: int                  # 1: face at v_s = -b_s/2; 2: at +b_s/2
    nodes: np.ndarray          # (k, 3) positions of the face's contact elements, m
    weight: np.ndarray         # (k,) area share of each node, sums to 1
    facets: np.ndarray         # (t, c, 3) corner positions of the face's facets (c = 3 or 4), m


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
        out.append(FaceGeometry(side=face.side, nodes=face.coords, weight=face.weight, facets=by_tag[tag]))
    return tuple(out)


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


def _in_plane(points: np.ndarray, params: Parameters) -> np.ndarray:
    """(..., 3) positions -> (..., 3) picture coordinates (e_ws, X, 0) in mm."""
    e_ws = tip_frame(params).e_ws
    flat = np.stack([points @ e_ws, points[..., 0], np.zeros(points.shape[:-1])], axis=-1)
    return 1e3 * flat


def draw(path: Path, params: Parameters, faces: tuple[FaceGeometry, ...], share: np.ndarray,
         title: str) -> Path:
    """PNG of both faces, one row per side and one column per state, nodes coloured by share."""
    import pyvista as pv
    pv.OFF_SCREEN = True
    shares = split_by_side(faces, share)
    plotter = pv.Plotter(shape=(len(faces), len(STATE_NAMES)), off_screen=True,
                         window_size=(1500, 330 * len(faces)), border=False)
    for row, (face, s) in enumerate(zip(faces, shares)):
        poly = _in_plane(face.facets, params)
        t, c = poly.shape[:2]
        cells = np.hstack([np.full((t, 1), c), np.arange(c * t).reshape(-1, c)]).ravel()
        surface = pv.PolyData(poly.reshape(-1, 3), faces=cells)
        for col, name in enumerate(STATE_NAMES):
            plotter.subplot(row, col)
            plotter.add_mesh(surface, color="lightgrey", show_edges=True, edge_color="grey", line_width=0.5)
            points = pv.PolyData(_in_plane(face.nodes, params) + [0.0, 0.0, 0.01])
            points[name] = s[:, col]
            plotter.add_mesh(points, scalars=name, cmap="viridis", clim=(0.0, 1.0), point_size=9,
                             render_points_as_spheres=True,
                             scalar_bar_args={"title": f"side {face.side}: share of window {name} (-)",
                                              "n_labels": 6, "fmt": "%.1f", "vertical": False,
                                              "position_x": 0.15, "position_y": 0.04, "width": 0.7,
                                              "height": 0.08, "title_font_size": 14, "label_font_size": 12})
            plotter.add_text(f"side {face.side}: {name}" + (f"   ({title})" if row == col == 0 else ""),
                             font_size=9, position="upper_left")
            plotter.add_text("horizontal: e_ws, vertical: radius X (face plane)", font_size=7,
                             position="upper_right")
            plotter.view_xy()
            plotter.enable_parallel_projection()
            plotter.camera.zoom(1.3)
    plotter.screenshot(str(path))
    plotter.close()
    return path
