"""Free-interface modal reduction of the beam model (paper Sect. 2.1, steps 1-3).

1. Solve the undamped eigenproblem K xi = lambda M xi at the run's speed with
   K = K_e + K_c + K_s (the paper's "MK"): the prestressed, spin-softened
   stiffness the blade actually has at that speed. The Coriolis and
   angular-acceleration couplings are left out of the basis: they are
   skew, small, and kept exactly in the projected equations.
2. Keep the nr modes of lowest lambda, mass-normalized: N* = [xi_1 .. xi_nr].
3. q = N* q*; every matrix X becomes N*^T X N*, every load N*^T f (Eq. 12).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg

from shroud.errors import InputError


@dataclass(frozen=True)
class ModalBasis:
    """Undamped modes of (K, M): frequencies (Hz) ascending, mass-normalized shapes."""

    f_hz: np.ndarray       # (n,)
    shapes: np.ndarray     # (n_dof, n), shapes^T M shapes = I

    def truncated(self, nr: int) -> np.ndarray:
        """N*: the nr lowest modes (nr = 0 keeps all of them, the full model)."""
        total = self.shapes.shape[1]
        if nr > total:
            raise InputError("reduced.nr", f"{nr} is out of range; allowed: 0..{total} (5 x reduced.N)")
        return self.shapes if nr == 0 else self.shapes[:, :nr]


def undamped_modes(M: np.ndarray, K: np.ndarray) -> ModalBasis:
    """All modes of the symmetric pencil (K, M), M positive definite."""
    lam, shapes = scipy.linalg.eigh(K, M)
    if lam[0] <= 0:
        raise InputError("speed.rpm", "the blade has lost its bending stiffness at this speed "
                         f"(lowest eigenvalue {lam[0]:.3g} <= 0: spin softening exceeds the stiffness); "
                         "allowed: a lower speed")
    return ModalBasis(f_hz=np.sqrt(lam) / (2.0 * np.pi), shapes=shapes)


def project(basis: np.ndarray, matrix: np.ndarray) -> np.ndarray:
    """N*^T X N* (Eq. 12)."""
    return basis.T @ matrix @ basis
