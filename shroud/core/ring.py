"""A ring of N blades coupled through their shrouds (docs/geometry.md, "Moving neighbours"; docs/ring.md).

The disk is rigid and carries N blades, blade j at 2 pi j / N, each in its
own sector frame and with its own basis (a mistuned blade has its own
modes). Interface j joins blade j's side 2 (face at v_s = +b_s/2) and blade
j+1's side 1 (indices mod N). The contact law is shroud.core.contact's, the
same Jenkins element as the paper's fixed neighbours, acting on relative
coordinates of the two blades (contact element e of the interface pairs
blade j's e-th side-2 point with blade j+1's e-th side-1 point):

    g_j = v_s,j - v_s,j+1,    r_j = w_s,j - w_s,j+1,

as the law's side 2 (s = +1): N_j = max(0, N0 + kn g_j), one slider per
element, friction F_j = kt (z_j - r_j) in stick. The forces go back through
the transpose of the relative projection: (-N_j, F_j) on blade j and
(+N_j, -F_j) on blade j+1, equal and opposite. With blade j+1 held still
this is the paper's side 2 of blade j; with blade j held still, g = -v_s,j+1
and N = max(0, N0 - kn v_s,j+1): the paper's side 1 of blade j+1 (its
slider mirrored, z -> -z, which the odd law maps onto itself).

Load: blade j carries F0 sin(ke Omega t + j phi) along e_v, phi = 2 pi ke / N
(an engine-order travelling wave, nodal diameter ke mod N), i.e.
f_aero (cos(j phi) sin(ke Omega t) + sin(j phi) cos(ke Omega t)).

Units: SI.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Sequence

import numpy as np
import scipy.linalg

from shroud.core.linear_solvers import dense
from shroud.core.system import ContactElements, StructuralSystem


@dataclass(frozen=True)
class BladeRing:
    """N blades (dense systems of one size nb) and the pairing of their shroud faces.

    ``side1[j]``, ``side2[j]``: (c, nb) rows of blade j's side-1 and side-2
    contact points, [normal (v_s), tangent (w_s)] per point, c = 2 e for e
    points per face; ``weight``: (e,) each point's share of an interface's
    kn, kt and N0.
    """

    blades: tuple[StructuralSystem, ...]
    ke: int                     # engine order of the load
    side1: np.ndarray           # (N, c, nb)
    side2: np.ndarray           # (N, c, nb)
    weight: np.ndarray          # (e,)

    @property
    def count(self) -> int:
        return len(self.blades)

    @property
    def blade_dofs(self) -> int:
        return self.side1.shape[2]

    @property
    def dofs(self) -> int:
        return self.count * self.blade_dofs

    @property
    def rows_per_interface(self) -> int:
        return self.side1.shape[1]

    @property
    def phase(self) -> float:
        """The load's inter-blade phase angle phi = 2 pi ke / N, rad."""
        return 2.0 * math.pi * self.ke / self.count

    @property
    def omega_e(self) -> float:
        return self.blades[0].omega_e

    def projection(self) -> np.ndarray:
        """W (m, n): the relative coordinates [g, r] of every interface's points from the ring's DOFs
        (blade-major: blade j's DOFs are j nb .. (j+1) nb - 1)."""
        N, c, nb = self.count, self.rows_per_interface, self.blade_dofs
        W = np.zeros((N * c, N * nb))
        for j in range(N):
            k = (j + 1) % N
            W[j * c:(j + 1) * c, j * nb:(j + 1) * nb] += self.side2[j]
            W[j * c:(j + 1) * c, k * nb:(k + 1) * nb] -= self.side1[k]
        return W

    def contact(self) -> ContactElements:
        """The interfaces' points as contact elements of the law's side 2 on the relative coordinates."""
        return interface_elements(self.weight, self.projection())

    def loads(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(f_const, f_sin, f_cos), each (N, nb): blade j's load is f_const + f_sin sin(ke Omega t)
        + f_cos cos(ke Omega t), the travelling wave F0 sin(ke Omega t + j phi) along e_v."""
        phi = self.phase
        f_const = np.array([b.f_const for b in self.blades])
        f_sin = np.array([b.f_aero * math.cos(j * phi) for j, b in enumerate(self.blades)])
        f_cos = np.array([b.f_aero * math.sin(j * phi) for j, b in enumerate(self.blades)])
        return f_const, f_sin, f_cos

    def assembled(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """M, C, K of the whole ring without contact (block diagonal, blade-major)."""
        return tuple(scipy.linalg.block_diag(*[dense(getattr(b, name)) for b in self.blades])
                     for name in ("M", "C", "K"))

    def tip(self) -> np.ndarray:
        """(N, 2, nb): v_L, w_L rows of each blade."""
        return np.array([dense(b.tip) for b in self.blades])


def face_selectors(contact: ContactElements) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(S1, S2, weights): 0/1 matrices (c, m) picking each face's [normal, tangent] coordinates from a
    blade's projected coordinates y = W q, paired in order, and each pair's weight (e,).

    The e-th point of side 2 faces the neighbour's e-th point of side 1 (the
    same place along e_ws: the builders list both faces' points in the same
    order).
    """
    m = contact.W.shape[0]
    picks = []
    for s in (1, 2):
        idx = np.flatnonzero(contact.side == s)
        S = np.zeros((2 * idx.size, m))
        S[2 * np.arange(idx.size), contact.normal_row[idx]] = 1.0
        S[2 * np.arange(idx.size) + 1, contact.tangent_row[idx]] = 1.0
        picks.append((idx, S))
    (i1, S1), (i2, S2) = picks
    if i1.size != i2.size or not np.allclose(contact.weight[i1], contact.weight[i2]):
        raise ValueError("a ring pairs each side-2 contact point with one side-1 point of equal weight; "
                         f"this blade has {i1.size} and {i2.size} points")
    return S1, S2, np.asarray(contact.weight[i2], dtype=float)


def paired_by_position(contact: ContactElements, points: np.ndarray, normal: np.ndarray) -> ContactElements:
    """``contact`` with its side-1 points listed in the order of the side-2 points they touch on a ring.

    The neighbour's side-1 face, turned by 2 pi / N into blade j's sector frame, lies against blade j's
    side-2 face: a side-2 point p touches the neighbour's image of the side-1 point q that sits at the
    same place in the face plane, (p - q) along the normal e_vs. ``points`` (k, 3): each element's
    position, m; ``normal``: e_vs. The blade itself is unchanged (its law does not depend on the order);
    :func:`face_selectors` then pairs in order. Faces whose points do not match (a mesh not conforming
    across the interface) are refused: an image between points would need interpolation.
    """
    points, n = np.asarray(points, float), np.asarray(normal, float) / np.linalg.norm(normal)
    if points.shape != (contact.count, 3):
        raise ValueError(f"{points.shape[0]} contact points given for {contact.count} contact elements")
    i1, i2 = np.flatnonzero(contact.side == 1), np.flatnonzero(contact.side == 2)
    plane = points - np.outer(points @ n, n)                   # position in the face plane
    extent = np.ptp(plane[i2], axis=0).max()
    gap = np.linalg.norm(plane[i2][:, None, :] - plane[i1][None, :, :], axis=2)    # (side 2, side 1)
    nearest = gap.argmin(axis=1)
    if i1.size != i2.size or np.unique(nearest).size != i2.size or gap.min(axis=1).max() > 1e-6 * extent:
        raise ValueError("a ring pairs each side-2 contact point with the neighbour's side-1 point at the same "
                         "place of the face; this blade's faces do not match point for point")
    order = np.arange(contact.count)
    order[i1] = i1[nearest]                # the e-th side-1 slot now holds the point facing side 2's e-th
    return ContactElements(W=contact.W, normal_row=contact.normal_row[order],
                           tangent_row=contact.tangent_row[order], side=contact.side[order],
                           weight=contact.weight[order])


def faces(contact: ContactElements) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(side-1 rows, side-2 rows, weights) of one blade's contact points, paired in order: each face's
    rows of W (c, nb), [normal, tangent] per point (:func:`face_selectors`)."""
    S1, S2, weight = face_selectors(contact)
    W = dense(contact.W)
    return S1 @ W, S2 @ W, weight


def interface_elements(weight: np.ndarray, W: np.ndarray) -> ContactElements:
    """Interfaces of e points each (``weight``), on relative coordinates y = W x ([g, r] per point,
    interface after interface), as contact elements of the law's side 2."""
    k = W.shape[0] // 2
    return ContactElements(W=W, normal_row=2 * np.arange(k), tangent_row=2 * np.arange(k) + 1,
                           side=np.full(k, 2), weight=np.tile(weight, k // weight.size))


def with_rayleigh(system: StructuralSystem, rayleigh: tuple[float, float]) -> StructuralSystem:
    """``system`` with its damping alpha M + beta K replaced by the given (alpha, beta) (geometry.md:
    every blade of a mistuned ring takes the tuned blade's coefficients)."""
    if system.rayleigh is None:
        raise ValueError(f"the {system.model} model does not say which Rayleigh coefficients its C holds")
    (a0, b0), (a, b) = system.rayleigh, rayleigh
    C = system.C + (a - a0) * system.M + (b - b0) * system.K
    return dataclasses.replace(system, C=C, rayleigh=(a, b))


def ring_of(blades: Sequence[StructuralSystem], ke: int) -> BladeRing:
    """The ring of ``blades`` (blade j in its own sector frame, dense, equal sizes) under engine order ke."""
    if len(blades) < 2:
        raise ValueError("a ring has at least two blades")
    if any(b.contact is None for b in blades):
        raise ValueError("a ring couples its blades through their shroud contact; a blade has none")
    sizes = {b.dofs for b in blades}
    if len(sizes) != 1:
        raise ValueError(f"the blades of a ring have one size here; got {sorted(sizes)}")
    pairs = [faces(b.contact) for b in blades]
    return BladeRing(blades=tuple(blades), ke=int(ke), side1=np.array([p[0] for p in pairs]),
                     side2=np.array([p[1] for p in pairs]), weight=pairs[0][2])


def ring_harmonics(ring: BladeRing, H: int):
    """The whole ring's linear part per harmonic 0..H (shroud.core.harmonic_balance.LinearHarmonics),
    condensed exactly on every blade's own contact coordinates x_j = W_j q_j (Petrov & Ewins 2003), its
    contact on the interfaces' relative coordinates y = Wr x.

    Blade by blade (the linear ring is block diagonal): with Z_j,h = K_j - (h w)^2 M_j + i h w C_j the
    receptance W_j Z_j,h^-1 W_j^T and the load's W_j Z_j,h^-1 F_j,h, F_j,1 = f_cos,j - i f_sin,j (the
    travelling wave; a_h - i b_h convention). Not on y itself: around a ring of point shrouds the g_j sum
    to zero, so the receptance on y is singular. Wr takes S2_j x_j - S1_j+1 x_j+1 for interface j (the
    faces' selectors of :func:`face_selectors`). The tip rows are every blade's (v_L, w_L): 2 N outputs,
    blade j's in rows 2j, 2j+1, through the forces Wr^T Lam on x.
    """
    import dataclasses
    from shroud.core import harmonic_balance as hb     # the ring's time loop needs none of it
    N, nb, w = ring.count, ring.blade_dofs, ring.omega_e
    own = [dense(b.contact.W) for b in ring.blades]
    mb = own[0].shape[0]
    f_const, f_sin, f_cos = ring.loads()
    tip = ring.tip()
    WS = np.zeros((H + 1, N * mb, N * mb + 1), complex)
    tipS = np.zeros((H + 1, 2 * N, N * mb + 1), complex)
    for j, b in enumerate(ring.blades):
        rows = slice(j * mb, (j + 1) * mb)
        M, C, K = dense(b.M), dense(b.C), dense(b.K)
        for h in range(H + 1):
            F = f_const[j] if h == 0 else f_cos[j] - 1j * f_sin[j] if h == 1 else np.zeros(nb)
            S = np.linalg.solve(K - (h * w) ** 2 * M + 1j * h * w * C, np.column_stack([own[j].T, F]))
            WS[h, rows, rows] = own[j] @ S[:, :mb]
            WS[h, rows, -1] = own[j] @ S[:, mb]
            tipS[h, 2 * j:2 * j + 2, rows] = tip[j] @ S[:, :mb]
            tipS[h, 2 * j:2 * j + 2, -1] = tip[j] @ S[:, mb]
    lin = hb.condensed(w, WS, tipS)
    S1, S2, _ = face_selectors(ring.blades[0].contact)
    c = S1.shape[0]
    Wr = np.zeros((N * c, N * mb))
    for j in range(N):
        k = (j + 1) % N
        Wr[j * c:(j + 1) * c, j * mb:(j + 1) * mb] += S2
        Wr[j * c:(j + 1) * c, k * mb:(k + 1) * mb] -= S1
    return dataclasses.replace(lin, Wx=Wr, tip_lam=lin.tip_lam @ Wr.T.astype(complex),
                               tip_x=np.zeros((H + 1, 2 * N, N * mb), complex), condensed=False)


def assembled_system(ring: BladeRing, model: str) -> StructuralSystem:
    """The ring as one StructuralSystem (block-diagonal M, C, K; the interfaces' contact on W; blade 0's
    tip rows; the load's sine part only: the harmonic balance takes the wave's load from ring_harmonics,
    the stability needs none)."""
    M, C, K = ring.assembled()
    f_const, f_sin, _ = ring.loads()
    tip = np.zeros((2, ring.dofs))
    tip[:, :ring.blade_dofs] = dense(ring.blades[0].tip)
    return StructuralSystem(model=model, M=M, C=C, K=K, f_const=f_const.ravel(), f_aero=f_sin.ravel(),
                            omega_e=ring.omega_e, tip=tip, contact=ring.contact())
