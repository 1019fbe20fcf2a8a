"""Cyclic symmetry of a tuned ring: one sector per nodal diameter (docs/ring.md).

In a tuned ring (shroud.core.ring) a motion of nodal diameter n has
q_j = Q exp(i j theta), theta = 2 pi n / N, for every blade j. The relative
coordinates of interface j are then

    y_j = side2 q_j - side1 q_j+1 = (side2 - exp(i theta) side1) Q exp(i j theta) = B(theta) Q exp(i j theta),

and the forces lam_j of the interfaces come back on blade j as
side2^T lam_j - side1^T lam_j-1 = B(theta)^H Lam exp(i j theta) (side1,
side2 real). So the sector carries the ring with the Bloch projection
B(theta) in place of the relative projection; for the point shroud
(side1 = side2 = P) B = (1 - exp(i theta)) P, whose modulus
|1 - exp(i theta)| = 2 |sin(theta / 2)| is how much more (near n = N/2) or
less (near n = 0) the interface moves than a blade against a fixed
neighbour (factor 1).

Linear limits: with every contact as linear springs D (kn on normals, kt on
tangents) the sector's stiffness is K + B^H D B, Hermitian; its modes at
each n, with nodal diameters n and N - n sharing frequencies without
Coriolis, are those of the N-blade ring.

Units: SI.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.linalg


def bloch_rows(side1: np.ndarray, side2: np.ndarray, theta: float) -> np.ndarray:
    """B(theta) = side2 - exp(i theta) side1 (c, nb): the interface's relative coordinates per sector amplitude."""
    return side2 - np.exp(1j * theta) * side1


def nodal_diameters(N: int) -> range:
    """0 .. N // 2: the distinct nodal diameters of N blades (n and N - n are mirror images)."""
    return range(N // 2 + 1)


@dataclass(frozen=True)
class Modes:
    """Undamped modes, ascending: frequencies (Hz) and shapes (nb, k), complex in general."""

    f_hz: np.ndarray
    shapes: np.ndarray


def modes(M: np.ndarray, K: np.ndarray, count: int, G: np.ndarray | None = None) -> Modes:
    """The ``count`` lowest modes of M q'' + G q' + K q = 0, K Hermitian positive definite, M real.

    Without G the Hermitian pencil (K, M); with the gyroscopic G (real,
    skew) the state-space problem in flexibility form, mu = 1 / lambda,
    keeping lambda = i omega with omega > 0 (for a Bloch sector, omega < 0
    belongs to the mirror nodal diameter N - n).
    """
    if G is None or not np.any(G):
        w2, shapes = scipy.linalg.eigh(K, M)
        order = np.argsort(w2)[:count]
        return Modes(f_hz=np.sqrt(np.abs(w2[order])) / (2.0 * math.pi), shapes=shapes[:, order])
    nb = M.shape[0]
    A = np.block([[np.zeros((nb, nb)), np.eye(nb)], [-np.linalg.solve(K, M), -np.linalg.solve(K, G)]])
    mu, vec = scipy.linalg.eig(A)
    lam = 1.0 / mu
    keep = np.flatnonzero(lam.imag > 0)
    keep = keep[np.argsort(lam[keep].imag)][:count]
    return Modes(f_hz=lam[keep].imag / (2.0 * math.pi), shapes=vec[:nb, keep])


def sector_stiffness(K: np.ndarray, springs: np.ndarray, side1: np.ndarray, side2: np.ndarray,
                     N: int, nd: int) -> np.ndarray:
    """K + B^H D B of nodal diameter ``nd`` of N blades (Hermitian): ``springs`` (c,) the stiffness
    (N/m) on each relative coordinate of an interface (zeros: free interfaces)."""
    B = bloch_rows(side1, side2, 2.0 * math.pi * nd / N)
    K_n = K + B.conj().T @ (springs[:, None] * B)
    return 0.5 * (K_n + K_n.conj().T)
