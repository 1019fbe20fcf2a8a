"""Mode shapes of the solid to VTK (ParaView), and as arrays for a picture.

``write_modes_vtk`` writes one .pvd series (one .vtu per mode, "time" = mode
number), quadratic cells kept, in parallel too. ``mode_grid`` hands the
studies the cells and the nodal shapes of a serial run to draw
(comparisons._pictures).
"""

from __future__ import annotations

from dataclasses import dataclass
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


@dataclass(frozen=True)
class ModeGrid:
    """Mode shapes at the nodes of the solid's (quadratic) cells, ready to draw."""

    topology: np.ndarray        # VTK cell connectivity
    cell_types: np.ndarray      # VTK cell types
    points: np.ndarray          # (p, 3) node positions, m
    shapes: np.ndarray          # (k, p, 3) mass-normalized mode shapes at the nodes
    labels: tuple[str, ...]
    f_hz: tuple[float, ...]     # undamped natural frequencies
    length: float               # blade length, m (the warp scale's reference)


def mode_grid(modes: SolidModes, count: int = 4) -> ModeGrid:
    """The first ``count`` mode shapes on the cells' nodes (serial runs)."""
    model = modes.operators.model
    if model.comm.size > 1:
        raise RuntimeError("mode pictures are drawn from a serial run")
    count = min(count, len(modes.vectors))
    topology, cell_types, x = plot.vtk_mesh(model.V)
    shapes = np.stack([_mode_function(modes, i).x.array.reshape(-1, 3) for i in range(count)])
    return ModeGrid(topology=topology, cell_types=cell_types, points=x, shapes=shapes,
                    labels=tuple(modes.labels[:count]), f_hz=tuple(float(f) for f in modes.f_undamped[:count]),
                    length=model.spec.length)
