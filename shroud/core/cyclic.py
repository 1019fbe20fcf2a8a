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

from shroud.core import harmonic_balance as hb
from shroud.core.contact import ContactLaw


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


# --- the tuned ring's travelling wave by one sector (harmonic balance) ------------------------------

def time_shift(H: int, angle: float) -> np.ndarray:
    """(nh, nh): the real coefficients [a_0, a_1, b_1, ...] of x(tau + angle) from those of x(tau).

    Harmonic h turns by h angle: a cos h(tau + angle) + b sin h(tau + angle) has
    a' = a cos(h angle) + b sin(h angle), b' = b cos(h angle) - a sin(h angle),
    i.e. (a' - i b') = (a - i b) exp(i h angle).
    """
    T = np.zeros((2 * H + 1, 2 * H + 1))
    T[0, 0] = 1.0
    for h in range(1, H + 1):
        c, s = math.cos(h * angle), math.sin(h * angle)
        a, b = 2 * h - 1, 2 * h
        T[a, a], T[a, b], T[b, a], T[b, b] = c, s, -s, c
    return T


def sector_projection(S1: np.ndarray, S2: np.ndarray, H: int, phi: float) -> np.ndarray:
    """P (nh c, nh m): the harmonics of interface 0's relative coordinates from those of the sector's
    contact coordinates y (m of them; S1, S2 (c, m) pick its faces' points).

    A travelling wave has q_1(tau) = q_0(tau + phi) (U_1,h = exp(i h phi) U_0,h), so
    y_rel = S2 y_0(tau) - S1 y_0(tau + phi): P = I (x) S2 - T(phi) (x) S1, harmonic-major as the
    harmonic balance stacks its coefficients. Its transpose carries the interfaces' forces back:
    interface 0's on side 2, and on side 1 interface N-1's, which is interface 0's delayed by phi
    (T(phi)^T = T(-phi)).
    """
    nh = 2 * H + 1
    return np.kron(np.eye(nh), S2) - np.kron(time_shift(H, phi), S1)


def ring_shifts(samples: int, N: int, ke: int) -> np.ndarray:
    """Sample offsets of interfaces 0..N-1: interface j at sample i is interface 0 at i + j samples ke / N
    (a whole number of samples: ``samples`` a multiple of N / gcd(N, ke))."""
    step = samples * ke / N
    if step != int(step):
        raise ValueError(f"{samples} samples do not shift by whole samples between {N} blades at engine order {ke}")
    return (np.arange(N) * int(step)) % samples


@dataclass(frozen=True)
class SectorBalance:
    """Residual of the sector's harmonic balance and its pieces."""

    R: np.ndarray                  # (nh nx,) N
    J: np.ndarray | None           # dR/dX
    contact: hb.ContactHarmonics   # the law along interface 0 (its relative coordinates)
    Lam_y: np.ndarray              # (nh, m) forces on the sector's contact coordinates, N


@dataclass(frozen=True)
class Faces:
    """Interface 0 seen from the sector: its relative coordinates S2 y(tau) - S1 y(tau + phi) from the
    sector's contact coordinates y (m of them; S1, S2 (c, m) pick its faces' points), phi = 2 pi ke / N."""

    S1: np.ndarray
    S2: np.ndarray
    phi: float

    def projection(self, H: int, Wx: np.ndarray | None = None) -> np.ndarray:
        """:func:`sector_projection` at H harmonics (nh c, nh m), dense; with ``Wx`` (y = Wx x) the one on x,
        P (I (x) Wx) = I (x) S2 Wx - T (x) S1 Wx (nh c, nh nx)."""
        if Wx is None:
            return sector_projection(self.S1, self.S2, H, self.phi)
        return sector_projection(self.S1 @ Wx, self.S2 @ Wx, H, self.phi)


def sector_balance(X: np.ndarray, lin: hb.LinearHarmonics, law: ContactLaw, basis: hb.Fourier,
                   faces: Faces | None, L: np.ndarray | None = None, Fr: np.ndarray | None = None,
                   jacobian: bool = True) -> SectorBalance:
    """R(X) = L X - F - Pa^T Lam(Pa X), Pa = P (I (x) Wx) (P: :func:`sector_projection`), and its analytic
    Jacobian L - Pa^T dLam/dY Pa.

    ``lin``: the blade's linear part (shroud.core.harmonic_balance), on its
    contact coordinates (condensed) or all DOFs; ``law``: interface 0's
    points on its relative coordinates (shroud.core.ring.interface_elements
    on the identity); ``faces``: how the sector sees them, or None where the
    unknowns are the law's coordinates themselves (a whole ring condensed on
    its interfaces: then this is shroud.core.harmonic_balance.balance).

    Pa is not formed: the AFT of shroud.core.harmonic_balance runs on the
    unknowns and their shifted copy, Z_h = (X_h, (T(phi) X)_h), whose
    relative coordinates are y_rel = Wz z with Wz = (S2 Wx, -S1 Wx) the
    same at every harmonic, so the law's Jacobian comes projected element by
    element on 2 nx coordinates (nx the unknowns a harmonic, the smaller of
    the blade's DOFs and contact coordinates) and is brought back to X by the
    chain rule through T, instead of a dense (nh c)^2 matrix pressed
    through Pa (fe-reduced sector, 99 points a face, H = 10: 1.09 s ->
    0.079 s CPU a residual with its Jacobian, docs/ring.md).
    """
    nh, nx = basis.nh, lin.nx
    L = lin.L if L is None else L
    Fr = lin.Fr if Fr is None else Fr
    if faces is None:
        b = hb.balance(X, lin, law, basis, L, Fr, jacobian)
        return SectorBalance(R=b.R, J=b.J, contact=b.contact, Lam_y=b.contact.Lam)
    T = time_shift(basis.H, faces.phi)
    Xm = X.reshape(nh, nx)
    Wz = np.hstack([faces.S2 @ lin.Wx, -faces.S1 @ lin.Wx])          # (c, 2 nx)
    ch = hb.contact_harmonics(np.hstack([Xm, T @ Xm]), Wz, law, basis, jacobian, condensed=False)
    Lam_y = ch.Lam @ faces.S2 - T.T @ (ch.Lam @ faces.S1)             # P^T Lam: on the sector's y
    R = L @ X - Fr.ravel() - (Lam_y if lin.condensed else Lam_y @ lin.Wx).ravel()
    if not jacobian:
        return SectorBalance(R=R, J=None, contact=ch, Lam_y=Lam_y)
    D = ch.dLam_x.reshape(nh, 2, nx, nh, 2, nx)                       # d(Wz^T Lam)/dZ
    # dX_kilj = sum_ab (T_a^T)_kh D_hai,gbj (T_b)_gl with T_0 = I, T_1 = T: rows, then columns, by matrix
    # products (numpy's einsum of the same sums took 20x longer at nh = 41, nx = 2)
    rows = D[:, 0] + (T.T @ D[:, 1].reshape(nh, -1)).reshape(nh, nx, nh, 2, nx)
    shifted = rows[:, :, :, 1].transpose(0, 1, 3, 2).reshape(-1, nh) @ T
    dX = rows[:, :, :, 0] + shifted.reshape(nh, nx, nx, nh).transpose(0, 1, 3, 2)
    return SectorBalance(R=R, J=L - dX.reshape(nh * nx, nh * nx), contact=ch, Lam_y=Lam_y)
