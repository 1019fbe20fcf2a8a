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
from numba import njit

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


# --- the modes over a speed range, for continuation in speed -----------------------------------

PANEL_RPM = 2500.0     # the speed axis is cut into panels this wide (r/min)
PANEL_NODES = 6        # Chebyshev nodes in Omega^2 per panel
PANEL_TOLERANCE = 1e-7  # largest interpolation error a panel may have (checked against exact modes)


class ModesOverSpeed:
    """The nr lowest modes of (K(Omega), M) and the lowest frequencies as polynomials in Omega^2.

    K(Omega) = K_e + Omega^2 (K_c1 + K_s1) is exactly quadratic in Omega, and
    its modes are smooth in Omega^2 away from crossings: on each panel of
    ``PANEL_RPM`` they are interpolated (Lagrange, on ``PANEL_NODES``
    Chebyshev nodes in Omega^2) from exact modes at the nodes, each mode
    matched to the panel's first node by its mass-weighted overlap and
    sign. A panel is built on first use, and certified: at its two ends
    (where the error of a Chebyshev interpolant peaks) the interpolated shapes
    are compared with the exact ones (the part of each outside the exact
    nr-mode subspace, in the mass norm) and the frequencies too; a panel whose modes cross or
    whose error exceeds ``PANEL_TOLERANCE`` uses exact modes at every speed
    instead, as does a panel that reaches a speed where the stiffness is no
    longer positive (each speed then raises its own error when asked).
    ``errors`` holds each panel's measured error (None: exact).

    The basis at every speed is turned within its own subspace to lie
    nearest (in the mass norm) to the first speed's modes: N* Q with Q the
    orthogonal polar factor of N*^T M N*_ref (Procrustes). The reduced model
    depends only on the subspace (its damping is Rayleigh's on the projected
    M and K), but a model with more contact coordinates than modes (the
    extended beam) is balanced on these coordinates, and they must mean the
    same from one panel to the next and through a veering of two kept modes
    (the extended beam's flap2 and torsion1 at 13842 r/min), where the
    eigenvectors themselves turn by 90 degrees within 1 r/min.
    """

    def __init__(self, M: np.ndarray, stiffness, nr: int, frequencies: int = 2):
        self.M, self.stiffness, self.nr, self.count = M, stiffness, nr, max(nr, frequencies)
        self._panels: dict[int, tuple | None] = {}
        self._edges: dict[int, tuple] = {}              # exact modes at the panels' ends, by panel index
        self._reference: np.ndarray | None = None
        self.errors: dict[int, float | None] = {}

    def exact(self, omega: float) -> tuple[np.ndarray, np.ndarray]:
        """(f_hz of the lowest modes, the basis of the nr lowest, turned to the reference) at Omega (rad/s)."""
        modes = undamped_modes(self.M, self.stiffness(omega))
        shapes = modes.truncated(self.nr) if self.nr else modes.shapes[:, :0]
        if not self.nr:                                 # the full model keeps no basis
            return modes.f_hz[:self.count], shapes
        if self._reference is None:
            self._reference = shapes
        U, _, Vt = np.linalg.svd(shapes.T @ self.M @ self._reference)
        return modes.f_hz[:self.count], shapes @ (U @ Vt)

    def at(self, omega: float) -> tuple[np.ndarray, np.ndarray]:
        """(f_hz, shapes) at Omega (rad/s): interpolated on a certified panel, else exact."""
        panel = self.panel(omega)
        if panel is None:
            return self.exact(omega)
        return interpolated(*panel, omega * omega)

    def panel(self, omega: float) -> tuple | None:
        """The certified panel holding Omega (rad/s): (nodes in Omega^2, their barycentric weights, f_hz^2 and
        shapes at the nodes), built on first use; None where the modes are exact at every speed."""
        p = int(abs(omega) * 60.0 / (2.0 * np.pi) // PANEL_RPM)
        if p not in self._panels:
            self._panels[p] = self._panel(p)
        return self._panels[p]

    def _panel(self, p: int):
        lo, hi = (2 * np.pi / 60 * PANEL_RPM * np.array([p, p + 1])) ** 2
        k = np.arange(PANEL_NODES)
        x2 = 0.5 * (lo + hi) + 0.5 * (hi - lo) * np.cos((2 * k + 1) * np.pi / (2 * PANEL_NODES))
        try:
            f, shapes = zip(*(self.exact(np.sqrt(x)) for x in x2))
        except InputError:                              # the panel reaches past the blade's stability:
            self.errors[p] = None                       # each speed says so itself, if asked
            return None
        shapes = np.array(shapes)
        for j in range(1, PANEL_NODES):                 # the same mode, the same sign at every node
            overlap = shapes[0].T @ self.M @ shapes[j]
            if not np.all(np.abs(np.diag(overlap)) > 0.9):
                self.errors[p] = None                   # modes cross inside the panel
                return None
            shapes[j] *= np.sign(np.diag(overlap))
        bary = 1.0 / np.prod(x2[:, None] - x2[None, :] + np.eye(PANEL_NODES), axis=1)
        panel = (x2, bary, np.array(f) ** 2, shapes)
        error = 0.0
        for edge, x in ((p, lo), (p + 1, hi)):          # the panel's ends: where the interpolation errs most
            if edge not in self._edges:                 # (each shared with the neighbouring panel)
                self._edges[edge] = self.exact(np.sqrt(x))
            f_exact, exact = self._edges[edge]
            f_int, interp = interpolated(*panel, x)
            error = max(error, float(np.max(np.abs(f_int / f_exact - 1))))
            if self.nr:                                 # the part of each shape outside the exact subspace
                outside = interp - exact @ (exact.T @ self.M @ interp)
                error = max(error, float(np.max(np.sqrt(np.einsum("ij,ik,kj->j", outside, self.M, outside)
                                                        / np.einsum("ij,ik,kj->j", interp, self.M, interp)))))
        self.errors[p] = error
        return panel if error <= PANEL_TOLERANCE else None


def interpolated(x2: np.ndarray, bary: np.ndarray, f2: np.ndarray, shapes: np.ndarray,
                 x: float) -> tuple[np.ndarray, np.ndarray]:
    """(f_hz, shapes) at Omega^2 = x from a panel (its nodes x2 in Omega^2, their barycentric weights, f_hz^2
    and shapes at the nodes): their Lagrange interpolants (numpy, and compiled as it is by model kernels)."""
    w = lagrange_weights(x2, bary, x)
    basis = np.zeros(shapes.shape[1:])
    for j in range(w.size):
        basis += w[j] * shapes[j]
    # no clamp: a certified panel's f^2 is within PANEL_TOLERANCE of the exact, positive one (over the default
    # blade's panels 0-60000 r/min the smallest interpolated f^2 is 0.77 of the largest nodal one); a negative
    # one would come out nan, never silently 0
    return np.sqrt(w @ f2), basis


@njit(cache=True)
def lagrange_weights(nodes: np.ndarray, bary: np.ndarray, x: float) -> np.ndarray:
    """Weights of the Lagrange interpolant on ``nodes`` at x (barycentric form, ``bary`` the nodes'
    barycentric weights 1 / prod_k (x_j - x_k))."""
    w = np.zeros(nodes.size)
    for j in range(nodes.size):
        if x == nodes[j]:
            w[j] = 1.0
            return w
        w[j] = bary[j] / (x - nodes[j])
    return w / w.sum()
