"""Starts for Newton on a harmonic balance at one speed where the contact-free linear solution fails
(docs/ring.md, "Start"): the linear system with contact springs, then a continuation in the contact's
stiffness. One piece for every system: a ring's sector (the travelling wave, shroud.core.cyclic), a whole
ring on all its interfaces, and the single blade between fixed neighbours (:func:`fixed_neighbours`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from shroud.base.errors import RunDiverged
from shroud.core import harmonic_balance as hb
from shroud.core.contact import KN, KT, N0, ContactLaw
from shroud.core.continuation import continue_branch
from shroud.core.cyclic import Faces, sector_balance
from shroud.core.cyclic_banded import CyclicBanded


@dataclass(frozen=True)
class Sector:
    """What the sector's balance needs besides the blade's linear part."""

    N: int
    ke: int
    faces: Faces | None        # interface 0 seen from the sector; None: the unknowns are the law's coordinates
    law: ContactLaw            # interface 0's points on its relative coordinates (or every interface's)
    banded: CyclicBanded | None = None   # the structure of a whole ring's Jacobian (None: dense solves)

    def solve(self, A: np.ndarray, b: np.ndarray) -> np.ndarray:
        """x with A x = b for a Newton step or a start: banded where the structure is declared."""
        return np.linalg.solve(A, b) if self.banded is None else self.banded(A, b)

    @property
    def phi(self) -> float:
        return 2.0 * math.pi * self.ke / self.N


def fixed_neighbours(law: ContactLaw) -> Sector:
    """The single blade between fixed neighbours as the "sector" of :func:`sector_solve` (no projection: its
    contact law on its own contact coordinates), so the ring's starts serve the blade's checkpoint
    (shroud.analysis.hb.checkpoint)."""
    return Sector(N=1, ke=0, faces=None, law=law)


def projected(sector: Sector, lin: hb.LinearHarmonics, H: int) -> np.ndarray:
    """Pa (nh c, nh nx), dense: the relative coordinates' harmonics from the unknowns' (the whole ring's:
    I (x) Wx), for the one-off uses (Newton's linear starts, the orbit for the stability)."""
    if sector.faces is None:
        return np.kron(np.eye(2 * H + 1), lin.Wx)
    return sector.faces.projection(H, lin.Wx)


def with_springs(lin: hb.LinearHarmonics, sector: Sector, basis: hb.Fourier, share: float) -> np.ndarray:
    """A start for Newton: the linear sector with every interface as springs of ``share`` times the law's kn
    and kt (0: contact-free; 1: stuck; 0.5: the mean of open and closed)."""
    nh = basis.nh
    D = np.zeros(sector.law.m)
    D[sector.law.rows[:, 0]] += share * sector.law.props[:, 1]
    D[sector.law.rows[:, 1]] += share * sector.law.props[:, 2]
    Pa = projected(sector, lin, basis.H)
    return sector.solve(lin.L + Pa.T @ (np.tile(D, nh)[:, None] * Pa), lin.Fr.ravel())


STARTS = (0.5, 1.0, 0.1, 0.0)   # shares of the springs of the linear starts tried, in order
MOST_POINTS = 300               # of the continuation in the contact's stiffness (96 reach 24 tuned blades)


SECTOR_TOLERANCE = 1e-10      # the |R| / |F| :func:`sector_newton` asks for (it accepts at hb.ACCEPT)


def sector_newton(X: np.ndarray, lin: hb.LinearHarmonics, sector: Sector, basis: hb.Fourier,
                  tol: float = SECTOR_TOLERANCE,
                  max_iterations: int = 60) -> tuple[np.ndarray, bool]:
    """Newton on the sector's balance at one speed (the core's damped Newton, with the sector's structured
    solve), accepted at |R| <= 1e-6 |F|."""
    X, _, _, residual, _ = hb.damped_newton(
        lambda X, jacobian: sector_balance(X, lin, sector.law, basis, sector.faces, jacobian=jacobian),
        X, np.linalg.norm(lin.Fr) + 1e-300, tol, max_iterations, solve=sector.solve, shortest_step=1e-4)
    return X, residual <= hb.ACCEPT


def stiffened(law: ContactLaw, share: float) -> ContactLaw:
    """``law`` with kn, kt and N0 times ``share`` (the same gap or interference N0 / kn, softer springs)."""
    props = law.props.copy()
    props[:, [KN, KT, N0]] *= share
    return replace(law, props=props)


def sector_solve(lin: hb.LinearHarmonics, sector: Sector, basis: hb.Fourier, soft: float = 1e-3) -> np.ndarray:
    """The travelling wave at one speed by Newton from linear sectors with springs (:func:`with_springs`,
    STARTS in order), else by continuation in the contact's stiffness from ``soft`` times it (where the
    contact-free solution is Newton's start) up to all of it.

    The contact-free blade alone is a poor start: near its resonance it moves by tens of um where the
    ring's interfaces hold it to a few (6 blades at 10000 r/min: Newton stalls at |R| = |F| / 3 from it and
    converges in 10 steps from half springs). A continuation in the load cannot help where N0 = 0: the
    problem is then homogeneous in the load. 24 blades at 6000 r/min stall at |R| = |F| / 2 from every
    linear start, and the stiffness continuation reaches the wave in 96 points (0.24 s).
    """
    for share in STARTS:
        X, ok = sector_newton(with_springs(lin, sector, basis, share), lin, sector, basis)
        if ok:
            return X

    def residual(X, share):
        b = sector_balance(X, lin, stiffened(sector.law, share), basis, sector.faces)

        def d_share():
            h = 1e-6 * share
            return (sector_balance(X, lin, stiffened(sector.law, share + h), basis, sector.faces,
                                   jacobian=False).R - b.R) / h
        return b.R, b.J, d_share
    X0 = hb.linear_solution(lin)
    path = continue_branch(residual, X0, soft, 1.0, float(np.abs(X0).max()) + 1e-300, ds=0.05, ds_max=0.5,
                           p_scale=1.0, max_points=MOST_POINTS)
    if not (path.complete and path.p and path.p[-1] == 1.0):
        raise RunDiverged(f"no periodic state reached, neither by Newton from linear sectors with springs "
                          f"nor by continuation in the contact's stiffness: {path.stopped}")
    return path.x[-1]
