"""The beam's static response to a force at the blade tip (``shroud static``).

The Galerkin beam (5N or 6N DOF, reduced_model.beam) at speed Omega:
(K_e + K_c + K_s) q = B(0)^T F with B(0) = point_rows(0) the tip centre's
displacement (X, Y, Z): the stiffness the model has about its steady
centrifugal state (which the force's response is measured from). The
``reduced`` and ``extended`` models are reductions of this beam to their
modes; a static force is answered by the beam they are reduced from (the
truncation to nr modes is a dynamic reduction, not a second stiffness).
"""

from __future__ import annotations

import time

import numpy as np

from reduced_model.beam import for_parameters
from shroud.core.results import StaticResult, tip_displacement
from shroud.params import Parameters


def static_response(params: Parameters, rpm: float, force, name: str = "reduced") -> StaticResult:
    """Tip-centre displacement under ``force`` (N, global X, Y, Z) at ``rpm``."""
    t0 = time.perf_counter()
    beam = for_parameters(params)
    omega = 2.0 * np.pi * rpm / 60.0
    B = beam.point_rows(np.zeros(3))
    q = np.linalg.solve(beam.stiffness(omega), B.T @ np.asarray(force, dtype=float))
    tip = tip_displacement(B @ q, params.blade.beta(params.blade.length))
    return StaticResult(model=name, rpm=float(rpm), dofs=beam.dofs, force=tuple(force), tip=tip,
                        elapsed_s=time.perf_counter() - t0)
