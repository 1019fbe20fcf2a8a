"""Mode shapes of the solid to VTK (ParaView) and to a PNG.

``write_modes_vtk`` writes one .pvd series (one .vtu per mode, "time" = mode
number), quadratic cells kept, in parallel too. The PNGs are off-screen
pyvista renders of a serial run: each mode warped so that its largest
displacement is 10 % of the blade length, coloured by displacement magnitude.
"""

from __future__ import annotations

from pathlib import Path

import dolfinx_solver  # noqa: F401  (must precede dolfinx)
import numpy as np
from dolfinx import fem, plot
from dolfinx.io import VTKFile

from reference_fe.modal import SolidModes


def _mode_function(modes: SolidModes, i: int) -> fem.Function:
    u = fem.Function(modes.operators.model.V, name="mode_shape")
    modes.vectors[i].copy(u.x.petsc_vec)
    u.x.scatter_forward()
    return u


def write_modes_vtk(modes: SolidModes, path: Path) -> Path:
    """Mass-normalized undamped mode shapes as ``path`` (.pvd), mode i at t = i + 1."""
    model = modes.operators.model
    with VTKFile(model.comm, str(path.with_suffix(".pvd")), "w") as vtk:
        for i in range(len(modes.vectors)):
            vtk.write_function(_mode_function(modes, i), t=float(i + 1))
    return path.with_suffix(".pvd")


def mode_picture(modes: SolidModes, path: Path, count: int = 4) -> Path:
    """PNG of the first ``count`` mode shapes (serial runs)."""
    model = modes.operators.model
    if model.comm.size > 1:
        raise RuntimeError("mode pictures are drawn from a serial run")
    from shroud.base.offscreen import pyvista
    pv = pyvista()
    count = min(count, len(modes.vectors))
    topology, cell_types, x = plot.vtk_mesh(model.V)
    plotter = pv.Plotter(shape=(1, count), off_screen=True, window_size=(320 * count, 520))
    for i in range(count):
        grid = pv.UnstructuredGrid(topology, cell_types, x)
        shape = _mode_function(modes, i).x.array.reshape(-1, 3)
        scale = 0.1 * model.spec.length / np.abs(shape).max()
        grid.point_data["|u|"] = np.linalg.norm(shape, axis=1) / np.linalg.norm(shape, axis=1).max()
        grid.point_data["u"] = shape * scale
        plotter.subplot(0, i)
        plotter.add_mesh(grid.warp_by_vector("u"), scalars="|u|", cmap="viridis", show_scalar_bar=False)
        plotter.add_text(f"{modes.labels[i]} {modes.f_undamped[i]:.1f} Hz", font_size=9)
        plotter.view_vector((1.0, -1.0, 0.6), viewup=(1.0, 0.0, 0.0))
    plotter.screenshot(str(path))
    plotter.close()
    return path
