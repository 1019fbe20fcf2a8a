"""Off-screen pictures of the solid: its mesh, its mode shapes, its contact-state maps (pyvista).

The model builders hand over arrays (reference_fe.export.ModeGrid,
reference_fe.contact_map.FaceGeometry, the cached mesh file); drawing them
is the studies' business. Faces are drawn in their own plane: horizontal the
friction direction e_ws (paper Eq. 7), vertical the radial coordinate X,
both in mm.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from shroud.base.offscreen import pyvista
from shroud.core.states import STATE_NAMES


def mesh_picture(mesh_path: Path, size_m: float, path: Path) -> Path:
    """Surface of the solid mesh (tetrahedra or hexahedra) with its edges, seen from the suction side and above."""
    import meshio
    pv = pyvista()
    mesh = meshio.read(mesh_path)
    # The volume cells by their corners: the cell edges, not a tessellation of quadratic faces.
    corners = {"tetra": (4, pv.CellType.TETRA), "tetra10": (4, pv.CellType.TETRA),
               "hexahedron": (8, pv.CellType.HEXAHEDRON), "hexahedron27": (8, pv.CellType.HEXAHEDRON)}
    cells = {}
    for block in mesh.cells:
        if block.type in corners:
            n, kind = corners[block.type]
            cells.setdefault(kind, []).append(block.data[:, :n])
    grid = pv.UnstructuredGrid({k: np.vstack(v) for k, v in cells.items()}, mesh.points)
    plotter = pv.Plotter(off_screen=True, window_size=(900, 700))
    plotter.add_mesh(grid, show_edges=True, color="lightsteelblue")
    plotter.view_vector((1.0, -1.0, 0.6), viewup=(1.0, 0.0, 0.0))
    plotter.add_text(f"{len(mesh.points)} nodes, size {size_m * 1e3:g} mm", font_size=10)
    plotter.screenshot(str(path))
    plotter.close()
    return path


def mode_picture(grid, path: Path) -> Path:
    """The modes of a ModeGrid side by side, each warped so its largest displacement is 10 % of L."""
    pv = pyvista()
    count = len(grid.labels)
    plotter = pv.Plotter(shape=(1, count), off_screen=True, window_size=(320 * count, 520))
    for i in range(count):
        mesh = pv.UnstructuredGrid(grid.topology, grid.cell_types, grid.points)
        shape = grid.shapes[i]
        size = np.linalg.norm(shape, axis=1)
        mesh.point_data["|u|"] = size / size.max()
        mesh.point_data["u"] = shape * (0.1 * grid.length / np.abs(shape).max())
        plotter.subplot(0, i)
        plotter.add_mesh(mesh.warp_by_vector("u"), scalars="|u|", cmap="viridis", show_scalar_bar=False)
        plotter.add_text(f"{grid.labels[i]} {grid.f_hz[i]:.1f} Hz", font_size=9)
        plotter.view_vector((1.0, -1.0, 0.6), viewup=(1.0, 0.0, 0.0))
    plotter.screenshot(str(path))
    plotter.close()
    return path


def _in_plane(points: np.ndarray, e_ws: np.ndarray) -> np.ndarray:
    """(..., 3) positions -> (..., 3) picture coordinates (e_ws, X, 0) in mm."""
    return 1e3 * np.stack([points @ e_ws, points[..., 0], np.zeros(points.shape[:-1])], axis=-1)


def contact_map_picture(path: Path, faces, shares: list[np.ndarray], title: str) -> Path:
    """PNG of both faces, one row per side and one column per state, nodes coloured by their share.

    ``faces``: reference_fe.contact_map.FaceGeometry per side; ``shares``: per face, (k, 3) share of
    the window each node spent separate / stick / slip.
    """
    pv = pyvista()
    plotter = pv.Plotter(shape=(len(faces), len(STATE_NAMES)), off_screen=True,
                         window_size=(1500, 330 * len(faces)), border=False)
    for row, (face, s) in enumerate(zip(faces, shares)):
        poly = _in_plane(face.facets, face.e_ws)              # triangles or quadrilaterals
        t, c = poly.shape[:2]
        cells = np.hstack([np.full((t, 1), c), np.arange(c * t).reshape(-1, c)]).ravel()
        surface = pv.PolyData(poly.reshape(-1, 3), faces=cells)
        for col, name in enumerate(STATE_NAMES):
            plotter.subplot(row, col)
            plotter.add_mesh(surface, color="lightgrey", show_edges=True, edge_color="grey", line_width=0.5)
            points = pv.PolyData(_in_plane(face.nodes, face.e_ws) + [0.0, 0.0, 0.01])
            points[name] = s[:, col]
            # The bar carries ticks only: VTK draws a horizontal bar's title over its ticks, so the
            # quantity goes in the panel's heading; each bar needs its own (blank) title to be its own.
            plotter.add_mesh(points, scalars=name, cmap="viridis", clim=(0.0, 1.0), point_size=9,
                             render_points_as_spheres=True,
                             scalar_bar_args={"title": " " * (1 + row * len(STATE_NAMES) + col),
                                              "n_labels": 6, "fmt": "%.1f", "vertical": False,
                                              "position_x": 0.15, "position_y": 0.04, "width": 0.7,
                                              "height": 0.1, "label_font_size": 12})
            plotter.add_text(f"side {face.side}: {name}, colour: share of the window (-)"
                             + (f"\n{title}" if row == col == 0 else ""),
                             font_size=9, position="upper_left")
            plotter.add_text("horizontal: e_ws, vertical: radius X (face plane)", font_size=7,
                             position="upper_right")
            plotter.view_xy()
            plotter.enable_parallel_projection()
            plotter.camera.zoom(1.3)
    plotter.screenshot(str(path))
    plotter.close()
    return path
