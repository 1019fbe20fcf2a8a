"""Cantilever-admissible shape functions and Gauss quadrature on 0 <= x <= L.

Each of the five beam fields is expanded in the same N functions

    phi_j(x) = sqrt(2j - 1) / L * int_0^x P_{j-1}(2 s / L - 1) ds,   j = 1..N,

the integrated Legendre polynomials of hierarchical p-FEM. They vanish at the
clamped root (every field of a clamped Timoshenko beam does), span exactly the
polynomials of degree 1..N with phi(0) = 0, and their derivatives are the
orthogonal Legendre polynomials on [0, L] (int phi_i' phi_j' dx = delta_ij / L;
phi_1 = x / L, the others vanish at the tip): the uniform bending, shear-strain
and axial energies are then identity-like blocks, so the Galerkin matrices stay
well conditioned up to N = 40 where monomials x^j would not. Polynomials are
used rather than clamped-free beam modes because the section rotation should
lie in the same space as the slope of the deflection; a mismatch between the
two spaces stiffens the shear term and slows convergence. The functions are
dimensionless, so generalized coordinates carry the field's unit (m or rad).
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np
from numpy.polynomial import legendre


@dataclass(frozen=True)
class Quadrature:
    """Gauss points x (m), weights (m) and the functions sampled there."""

    x: np.ndarray        # (g,) points in [0, L], m
    weight: np.ndarray   # (g,) weights, sum = L, m
    value: np.ndarray    # (g, N) phi_j(x_g), dimensionless
    slope: np.ndarray    # (g, N) phi_j'(x_g), 1/m
    curvature: np.ndarray  # (g, N) phi_j''(x_g), 1/m^2
    tip: np.ndarray      # (N,) phi_j(L), dimensionless
    root_slope: np.ndarray  # (N,) phi_j'(0), 1/m


def _integrated_legendre(N: int) -> list[np.ndarray]:
    """Legendre-series coefficients of int_{-1}^t P_{j-1}, j = 1..N."""
    out = []
    for j in range(1, N + 1):
        c = np.zeros(j)
        c[-1] = 1.0
        out.append(legendre.legint(c, lbnd=-1.0))
    return out


@functools.lru_cache(maxsize=64)
def sample(N: int, length: float, points: int | None = None) -> Quadrature:
    """Shape functions and slopes at Gauss points on [0, length].

    ``points`` defaults to N + 12, exact for the polynomial mass and stiffness
    integrands times the smooth twist (cos, sin of beta(x)) and hub terms.
    """
    g = points if points is not None else N + 12
    t, w = legendre.leggauss(g)
    x = 0.5 * length * (t + 1.0)
    weight = 0.5 * length * w
    scale = np.sqrt(2.0 * np.arange(1, N + 1) - 1.0)
    coeffs = _integrated_legendre(N)
    # int_0^x ds / L = (1 / 2) int_{-1}^t dt and d/dx = (2 / L) d/dt
    value = np.stack([0.5 * legendre.legval(t, c) for c in coeffs], axis=1) * scale
    slope = np.stack([legendre.legval(t, np.eye(N)[j]) for j in range(N)], axis=1) * scale / length
    curvature = np.stack([legendre.legval(t, legendre.legder(np.eye(N)[j])) for j in range(N)],
                         axis=1) * scale * 2.0 / length**2
    tip = np.eye(N)[0]              # phi_1(L) = 1; int_{-1}^{1} P_(j-1) = 0 for j > 1, exactly
    root_slope = np.array([legendre.legval(-1.0, np.eye(N)[j]) for j in range(N)]) * scale / length
    for a in (x, weight, value, slope, curvature, tip, root_slope):
        a.flags.writeable = False          # shared through the cache
    return Quadrature(x=x, weight=weight, value=value, slope=slope, curvature=curvature, tip=tip,
                      root_slope=root_slope)


def held_root_slope(q: Quadrature) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """N - 1 functions of ``q`` that also have zero slope at the root, phi_(j+1) - (phi_(j+1)'(0) / phi_1'(0)) phi_1.

    For a field whose derivative is held at the clamped root (the twist rate
    of a section whose warping the clamp holds). Returns value, slope,
    curvature at the points and the tip values, as in Quadrature.
    """
    s = q.root_slope
    Z = np.vstack([-s[1:] / s[0], np.eye(s.size - 1)])
    return q.value @ Z, q.slope @ Z, q.curvature @ Z, q.tip @ Z
