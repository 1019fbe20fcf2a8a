"""The FE models' static response to a force at the blade tip (``shroud static``).

(K_e + K_sigma + K_spin) u = f at the speed asked: the stiffness about the
centrifugal state, which the response is measured from (as every model's
vibration is). The force is spread, not put on a node (a point force on a
solid or a shell has no finite displacement under it):

* with a shroud, evenly over the shroud (the solid's box volume, the shell's plate);
* without, evenly over the tip section (the solid's tip face X = R_d + L,
  the shell's tip line).

The reported displacement is the tip centre's (the node at (R_d + L, 0, 0)).
"""

from __future__ import annotations

import time

import dolfinx_solver  # noqa: F401  (must precede dolfinx / petsc4py)
import numpy as np
import ufl
from dolfinx import fem

from meshes.spec import SHROUD
from reference_fe.modal import operators_of
from reference_fe.solid import SolidModel, assemble_vector, lu_solver, solid_model
from shroud.core.results import StaticResult, tip_displacement
from shroud.params import Parameters


def solid_tip_load(model: SolidModel, force: np.ndarray):
    """The load vector of ``force`` (N, X, Y, Z) spread evenly over the shroud box, or the tip face."""
    msh, spec = model.mesh, model.spec
    v = ufl.TestFunction(model.V)
    if spec.has_shroud:
        measure = ufl.Measure("dx", domain=msh, subdomain_data=model.cell_tags)(SHROUD)
        indicator = 1.0
    else:       # the exterior facets at the tip plane: 1 there, 0 at every quadrature point elsewhere
        measure = ufl.Measure("ds", domain=msh)
        X = ufl.SpatialCoordinate(msh)
        indicator = ufl.conditional(ufl.gt(X[0], spec.tip_x - 1e-9 * spec.length), 1.0, 0.0)
    size = msh.comm.allreduce(fem.assemble_scalar(fem.form(indicator * measure)))
    F = fem.Constant(msh, np.asarray(force, dtype=float) / size)
    return assemble_vector(indicator * ufl.inner(F, v) * measure, model.bcs)


def static_response(params: Parameters, rpm: float, force, kind: str = "fe") -> StaticResult:
    """Tip-centre displacement under ``force`` (N, global X, Y, Z) at ``rpm``: the solid (``kind="fe"``) or the shell."""
    t0 = time.perf_counter()
    params.blade.check_modelled(profile=True)     # the tip load spreads over the shroud: a STEP file names none
    if kind == "shell":
        from reference_fe.shell import shell_model, tip_load
        model = shell_model(params)
        b = tip_load(model, np.asarray(force, dtype=float))
    else:
        model = solid_model(params)
        b = solid_tip_load(model, np.asarray(force, dtype=float))
    ops = operators_of(kind)(params, rpm)
    x = ops.K.createVecRight()
    ksp = lu_solver(ops.K, model.comm, f"shroud_{kind}_static_")
    ksp.solve(b, x)
    ksp.destroy()
    centre = model.gather_tip(x)[0].real
    return StaticResult(model=kind, rpm=float(rpm), dofs=model.global_dofs, force=tuple(force),
                        tip=tip_displacement(centre, params.blade.beta(params.blade.length)),
                        elapsed_s=time.perf_counter() - t0)
