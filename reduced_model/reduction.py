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

from shroud.base.errors import InputError


@dataclass(frozen=True)
class ModalBasis:
    """Undamped modes of (K, M): frequencies (Hz) ascending, mass-normalized shapes."""

    f_hz: np.ndarray       # (n,)
    shapes: np.ndarray     # (n_dof, n), shapes^T M shapes = I

    def truncated(self, nr: int) -> np.ndarray:
        """N*: the nr lowest modes (nr = 0 keeps all of them, the full model)."""
        total = self.shapes.shape[1]
        if nr > total:
            raise InputError("reduced.nr", f"{nr} is out of range; allowed: 0..{total} (fields x reduced.N)")
        return self.shapes if nr == 0 else self.shapes[:, :nr]


def stiffness_scaling(K: np.ndarray) -> np.ndarray:
    """s = diag(K)^(-1/2), so that s K s has a unit diagonal.

    Raises InputError when K has lost positive stiffness (spin softening
    beyond the elastic and centrifugal stiffness: the blade is unstable).
    """
    d = np.diag(K)
    if np.any(d <= 0):
        raise _unstable()
    return 1.0 / np.sqrt(d)


def _unstable() -> InputError:
    return InputError("speed.rpm", "the stiffness K_e + K_c + K_s is not positive definite at this speed "
                      "(spin softening exceeds the blade's stiffness); allowed: a lower speed")


def undamped_modes(M: np.ndarray, K: np.ndarray) -> ModalBasis:
    """All modes of the symmetric pencil (K, M), both positive definite.

    Solved in flexibility form, M y = mu K y with lambda = 1 / mu, on the
    diagonally scaled s K s: the shear stiffness of a slender Timoshenko beam
    puts lambda_max / lambda_min beyond 1e16 (L/h > 1000), where K x = lambda M x
    loses the low frequencies; their mu are the largest here and keep full
    relative accuracy.
    """
    s = stiffness_scaling(K)
    S = np.outer(s, s)
    try:
        mu, y = scipy.linalg.eigh(M * S, K * S)
    except np.linalg.LinAlgError:
        raise _unstable() from None
    mu, y = mu[::-1], y[:, ::-1]
    shapes = y * s[:, None] / np.sqrt(mu)          # mass-normalized
    return ModalBasis(f_hz=1.0 / np.sqrt(mu) / (2.0 * np.pi), shapes=shapes)


def project(basis: np.ndarray, matrix: np.ndarray) -> np.ndarray:
    """N*^T X N* (Eq. 12)."""
    return basis.T @ matrix @ basis
