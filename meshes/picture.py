"""Off-screen PNG of a cached blade mesh (pyvista), on request of a scene."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from meshes.blade import MeshSpec, mesh_file


def mesh_picture(spec: MeshSpec, path: Path) -> Path:
    """Surface of the solid mesh (tetrahedra or hexahedra) with its edges, seen from the suction side and above."""
    import meshio
    import pyvista as pv
    pv.OFF_SCREEN = True
    mesh = meshio.read(mesh_file(spec))
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
    plotter.add_text(f"{len(mesh.points)} nodes, size {spec.size * 1e3:g} mm", font_size=10)
    plotter.screenshot(str(path))
    plotter.close()
    return path
