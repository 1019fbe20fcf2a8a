"""The one shape every model takes: a linear structure plus contact elements.

    M q'' + C q' + K q = f_const + f_aero sin(omega_e t) + W^T lambda(W q)

``M, C, K`` are a 6x6 dense matrix (reduced beam) or a 100k-DOF sparse one
(solid FE); the contact acts only on a few projected coordinates ``y = W q``
(paper Eqs. 3-8). One integrator (shroud.core.newmark) serves all four models.

Conventions (docs/geometry.md)
-------------------------------------
* ``y[normal_row[j]]`` is v_s of contact element j (along e_vs, the shroud
  normal) and ``y[tangent_row[j]]`` its w_s (along e_ws, friction direction).
* Element j belongs to side 1 (face at v_s = -b_s/2, neighbour pushes +e_vs)
  or side 2 (face at +b_s/2, neighbour pushes -e_vs); ``weight[j]`` is its
  share of the side's kn, kt and N0 (area weights; they sum to 1 per side).
* ``tip`` maps q to (v_L, w_L), the displacement along e_v(L), e_w(L) of
  the point the model reports: the tip centre (the paper's beam, where the
  point-mass shroud sits), or the shroud centre between its two faces (the
  solid and the beam with a rigid shroud).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable

import numpy as np

from shroud.core.linear_solvers import Factorization, RowShare


@dataclass(frozen=True)
class ContactElements:
    """Penalty contact points acting on projected coordinates ``y = W q``."""

    W: Any                    # (m, n) ndarray or scipy.sparse: projected coordinates
    normal_row: np.ndarray    # (k,) int: row of y that is v_s for element j
    tangent_row: np.ndarray   # (k,) int: row of y that is w_s for element j
    side: np.ndarray          # (k,) int: 1 or 2
    weight: np.ndarray        # (k,) float: share of the side's kn, kt, N0

    @property
    def count(self) -> int:
        return int(self.side.size)


@dataclass(frozen=True)
class StructuralSystem:
    """Linear part of one model at one constant speed, plus its contact points."""

    model: str                # "reduced" | "full" | "fe" | "fe-reduced"
    M: Any
    C: Any                    # damping + gyroscopic (Rayleigh D + Coriolis G)
    K: Any                    # K_e + K_c + K_s (+ K_acc when the speed changes)
    f_const: np.ndarray       # constant generalized load (centrifugal, Eq. 10 F_1)
    f_aero: np.ndarray        # generalized load of F_e = F0 along e_v; times sin(omega_e t)
    omega_e: float            # excitation frequency ke * Omega, rad/s
    tip: Any                  # (2, n): rows giving v_L, w_L
    contact: ContactElements | None
    build_s: float = 0.0      # wall time spent building it, s
    # The model's own direct solver for the Newmark step operator,
    # ``factorize(A) -> Factorization`` (shroud.core.linear_solvers); None:
    # the core's default (dense inverse / SuperLU).
    factorize: Callable[[Any], Factorization] | None = None
    # How the rows of the model's vectors are spread over MPI ranks when M, C,
    # K are row-distributed (a RowShare; the matrices' ``row_block`` holds
    # this rank's rows); None: one process holds every row.
    layout: RowShare | None = None
    # Rayleigh's (alpha 1/s, beta s) in C = alpha M + beta K (+ G), where the model builds its damping so;
    # a ring gives every blade the tuned blade's (shroud.core.ring). None: not known.
    rayleigh: tuple[float, float] | None = None

    @property
    def dofs(self) -> int:
        return int(self.M.shape[0])
