"""Section properties of the blade from the shape of its cross-section, computed numerically.

The beam (reduced_model.beam) needs, per section, in the section frame
(eta_v along e_v, the thickness direction; eta_w along e_w, the chord):

    A                      area, m^2
    (c_v, c_w)             centroid, m
    I_v = int eta_v^2 dA   second moment for bending along e_v (flap), m^4
    I_w = int eta_w^2 dA   second moment for bending along e_w (chord), m^4
    I_vw = int eta_v eta_w dA, and the principal angle
                           theta_p = 1/2 atan2(2 I_vw, I_w - I_v), rad
    I_p = I_v + I_w        polar second moment about the centroid, m^4
    I_rr = int r^4 dA      fourth polar moment, r^2 = eta_v^2 + eta_w^2, m^6
                           (the extension-twist coupling of a pretwisted beam)
    I_rrv, I_rrw = int r^2 eta_v dA, int r^2 eta_w dA, m^5 (the bending-twist
                           coupling of pretwist; zero for a doubly symmetric section)
    J                      St-Venant torsion constant, m^4
    Gamma = int omega^2 dA warping constant, omega the St-Venant warping
                           function about the shear centre, m^6
    (v_s, w_s)             shear centre, m
    kappa_v, kappa_w       shear coefficients along the principal axes nearest
                           e_v and e_w, by Cowper's or the energy definition, -

all about the centroid. They come from one function of the shape,
:func:`section_properties`, which takes any shape given by a predicate
``inside(eta_v, eta_w)`` on its bounding box, so an airfoil section can
replace the rectangle without touching the beam. A shape given by its
outline (a polygon, with holes) is solved instead on P2 triangles by
reduced_model.section_mesh, into the same SectionProperties (docs/sections.md).

* Area and moments: sums over the cells of a grid laid on the bounding box,
  each cell whose centre lies inside counting with its exact cell integrals
  (exact for shapes whose edges follow the grid, such as the rectangle; a
  staircase of the outline otherwise, converging as the cell size).
* Torsion constant: Prandtl's stress function, nabla^2 Phi = -2 in the
  section, Phi = 0 on its outline, J = 2 int Phi dA (Timoshenko & Goodier,
  Theory of Elasticity, Sect. 104), by the five-point finite-difference
  Laplacian on the grid nodes (nodes outside the shape or on its outline hold
  Phi = 0), solved on two grids and Richardson-extrapolated (the scheme is
  second order). The series solutions of the rectangle (Timoshenko &
  Goodier, Sect. 109) are the checks (tests/test_reduced_section.py).
* Warping function and shear centre: omega from the same Phi (its harmonic
  conjugate), the shear centre as the pole that makes it orthogonal to the
  linear functions, Gamma = int omega^2 dA (Vlasov's warping constant, the
  stiffness E Gamma of a section whose warping is held, as at a clamped root).

* Shear coefficients: the Saint-Venant flexure problem of a shear force Q
  along a principal axis e (y = (p - c) . e, z across it, I = int y^2 dA,
  I_o = int z^2 dA), in the shear stresses tau = (Q / I) (grad chi + c d),
  c = -nu / (2 (1 + nu)), d = ((y^2 - z^2) / 2, y z) in (e, e_perp): the
  equilibrium div tau = -Q y / I and traction-free sides tau . n = 0 are the
  weak form  int (grad chi + c d) . grad(delta) dA = int y delta dA  (the side
  condition natural, so no boundary integral: the grid's cells serve any
  shape), and d carries the compatibility of the anticlastic Poisson strains
  (curl tau = -nu Q z / ((1 + nu) I)). chi = chi_1 + c chi_2 is linear in c,
  so the two solves per axis give every nu. Solved by bilinear (Q1) finite
  elements on the cells, twice as the torsion constant and
  Richardson-extrapolated. Two definitions from the one solution
  (tests/test_reduced_section.py holds both to their closed forms):
    - Cowper's (J. Appl. Mech. 33, 1966): the shear force over the
      difference of the mean slope (1/A) int u_y' dA and the mean rotation
      (1/I) int u_x y dA,
          1/kappa = (A / I^2) int chi y dA + (c / 2) (I - I_o) / I;
      10 (1 + nu) / (12 + 11 nu) for every rectangle (the harmonic part of
      its chi, a cosine series across the width, integrates to nothing
      against y), 6 (1 + nu) / (7 + 6 nu) for the circle;
    - the energy one: Q^2 / (kappa G A) = int |tau|^2 / G dA,
          1/kappa = (A / I^2) int |grad chi + c d|^2 dA;
      5/6 for a narrow rectangle, far below it for a wide one (the Poisson
      strains crowd the shear flow towards the edges of the width),
      6 (1 + nu)^2 / (7 + 14 nu + 8 nu^2) for the circle (the energy of
      Timoshenko & Goodier's exact stresses, Sect. 121).
  Both are equal at nu = 0. (A third, Hutchinson's, J. Appl. Mech. 68,
  2001, gives 6 (1 + nu)^2 / (7 + 12 nu + 4 nu^2) for the circle and
  5 (1 + nu) / (6 + 5 nu) for a narrow rectangle; it is not computed here.)
  Along principal axes; the cross coefficient, zero for a section with an
  axis of symmetry, is left out. The beam with the twist field takes
  Cowper's (reduced_model.beam). The grid for a thin direction needs cells
  across it: the shape's v_range gets ``cells_v`` of them.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field
from typing import Callable

import numpy as np
import scipy.sparse
import scipy.sparse.linalg

from shroud.base.errors import InputError
from shroud.base.resources import in_words, physical_memory

GRID_THICKNESS_CELLS = 24     # cells across the thickness on the coarser grid of the J solve
# What section_properties holds per node of its finest torsion grid (2 cells_v x 2 cells_w), measured
# here on the rectangle (peak RSS less the interpreter's): 0.28 GB at chord/thickness 100 (235 000
# nodes), 1.1 GB at 400 (941 000): 1.2 KB a node, growing with the chord's share of the grid.
BYTES_PER_GRID_NODE = 1.2e3
SYMMETRIC_ORDERING = "MMD_AT_PLUS_A"   # SuperLU's fill-reducing ordering for the symmetric grid operators


SHEAR_DEFINITIONS = ("cowper", "energy")


@dataclass(frozen=True)
class Flexure:
    """Dimensionless integrals of the flexure problem for a shear force along one principal axis.

    With c = -nu / (2 (1 + nu)) (module docstring):
    Cowper's 1/kappa = cowper[0] + c cowper[1],
    the energy 1/kappa = energy[0] + 2 c energy[1] + c^2 energy[2].
    """

    cowper: tuple
    energy: tuple

    def kappa(self, nu: float, definition: str = "cowper") -> float:
        """The shear coefficient at Poisson's ratio ``nu`` by ``definition`` ("cowper" or "energy")."""
        c = -nu / (2.0 * (1.0 + nu))
        if definition == "cowper":
            return 1.0 / (self.cowper[0] + c * self.cowper[1])
        if definition == "energy":
            return 1.0 / (self.energy[0] + 2.0 * c * self.energy[1] + c * c * self.energy[2])
        raise ValueError(f"shear coefficient definition {definition!r}: one of {SHEAR_DEFINITIONS}")


@dataclass(frozen=True)
class SectionProperties:
    """Properties of one cross-section about its centroid, section frame (e_v, e_w); SI units."""

    area: float            # A, m^2
    centroid: tuple        # (c_v, c_w), m, in the shape's own coordinates
    I_v: float             # int eta_v^2 dA, m^4 (flap bending)
    I_w: float             # int eta_w^2 dA, m^4 (chord bending)
    I_vw: float            # int eta_v eta_w dA, m^4
    I_rr: float            # int (eta_v^2 + eta_w^2)^2 dA, m^6
    I_rrv: float           # int (eta_v^2 + eta_w^2) eta_v dA, m^5
    I_rrw: float           # int (eta_v^2 + eta_w^2) eta_w dA, m^5
    J: float               # St-Venant torsion constant, m^4
    warping: float         # Gamma = int omega^2 dA, warping constant about the shear centre, m^6
    shear_centre: tuple    # (v_s, w_s), m, in the shape's own coordinates
    flexure_integrals: Callable = field(repr=False, compare=False)   # () -> (2, 5) array, see _flexure
    method: str = "grid"   # how J, Gamma, the shear centre and the flexure were solved
    J_bounds: tuple | None = None   # (lower, upper) bounds of J the solve proves, m^4, where it has them

    @property
    def I_p(self) -> float:
        """Polar second moment I_v + I_w about the centroid, m^4."""
        return self.I_v + self.I_w

    @property
    def principal_angle(self) -> float:
        """Angle (rad) from e_w to the principal axis of the larger second moment."""
        return 0.5 * math.atan2(2.0 * self.I_vw, self.I_w - self.I_v)

    @functools.cached_property
    def flexure(self) -> tuple[Flexure, Flexure]:
        """The flexure integrals for shear along the principal axes nearest e_v and e_w.

        Solved when first asked (the paper's beam, which keeps Cowper's formula, never asks).
        """
        return tuple(Flexure(cowper=tuple(r[:2]), energy=tuple(r[2:])) for r in self.flexure_integrals())

    def shear_coefficients(self, nu: float, definition: str = "cowper") -> tuple[float, float]:
        """(kappa_v, kappa_w): shear coefficients along the principal axes nearest e_v and e_w."""
        return tuple(f.kappa(nu, definition) for f in self.flexure)


def _cell_powers(lo: np.ndarray, hi: np.ndarray, k: int) -> np.ndarray:
    """int_lo^hi s^k ds, exact."""
    return (hi ** (k + 1) - lo ** (k + 1)) / (k + 1)


def _moments(inside, v_edges: np.ndarray, w_edges: np.ndarray) -> dict:
    """Exact integrals of v^i w^j (i + j <= 4) over the cells whose centres are inside."""
    vc, wc = 0.5 * (v_edges[1:] + v_edges[:-1]), 0.5 * (w_edges[1:] + w_edges[:-1])
    mask = inside(vc[:, None], wc[None, :]).astype(float)
    pv = {k: _cell_powers(v_edges[:-1], v_edges[1:], k) for k in range(5)}
    pw = {k: _cell_powers(w_edges[:-1], w_edges[1:], k) for k in range(5)}
    return {(i, j): float(pv[i] @ mask @ pw[j]) for i in range(5) for j in range(5) if i + j <= 4}


def _node_grid(v_range: tuple, w_range: tuple, nv: int, nw: int):
    """Nodes of an (nv x nw)-cell grid on the box: coordinates (V, W) and spacings."""
    v = np.linspace(*v_range, nv + 1)
    w = np.linspace(*w_range, nw + 1)
    V, W = np.meshgrid(v, w, indexing="ij")
    return V, W, v[1] - v[0], w[1] - w[0]


def _prandtl(inside, V: np.ndarray, W: np.ndarray, dv: float, dw: float) -> np.ndarray:
    """Phi on the nodes: nabla^2 Phi = -2 at the nodes inside the shape, Phi = 0 elsewhere and on the box."""
    free = inside(V, W)
    free[[0, -1], :] = False
    free[:, [0, -1]] = False
    index = -np.ones(free.shape, dtype=np.int64)
    n = int(free.sum())
    index[free] = np.arange(n)
    rows, cols, vals = [np.arange(n)], [np.arange(n)], [np.full(n, 2.0 / dv**2 + 2.0 / dw**2)]
    for shift, axis, h in ((1, 0, dv), (-1, 0, dv), (1, 1, dw), (-1, 1, dw)):
        neighbour = np.roll(index, -shift, axis=axis)      # the box edge holds Phi = 0: no wrap-around reaches a free node
        ok = free & (neighbour >= 0)
        rows.append(index[ok])
        cols.append(neighbour[ok])
        vals.append(np.full(int(ok.sum()), -1.0 / h**2))
    A = scipy.sparse.csc_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                                shape=(n, n))
    phi = np.zeros(free.shape)
    phi[free] = scipy.sparse.linalg.spsolve(A, np.full(n, 2.0), permc_spec=SYMMETRIC_ORDERING)
    return phi


def _warping(inside, V, W, dv, dw, phi) -> np.ndarray:
    """St-Venant warping function omega (pole at the centroid of the grid) on the nodes inside.

    omega is the harmonic conjugate of Phi + r^2 / 2 (Cauchy-Riemann, from
    tau_xv = G theta' (omega_v - w) = G theta' Phi_w, tau_xw = G theta' (omega_w + v) = -G theta' Phi_v):
    omega_v = w + Phi_w, omega_w = -v - Phi_v, integrated along the grid edges
    by least squares (exact for a gradient field).
    """
    dphi_v, dphi_w = np.gradient(phi, dv, dw, edge_order=2)
    gv, gw = W + dphi_w, -V - dphi_v
    mask = inside(V, W)
    index = -np.ones(mask.shape, dtype=np.int64)
    n = int(mask.sum())
    index[mask] = np.arange(n)
    rows, cols, vals, rhs = [], [], [], []
    k = 0
    for axis, g, h in ((0, gv, dv), (1, gw, dw)):
        a = index.take(range(index.shape[axis] - 1), axis=axis)
        b = index.take(range(1, index.shape[axis]), axis=axis)
        ga = g.take(range(g.shape[axis] - 1), axis=axis)
        gb = g.take(range(1, g.shape[axis]), axis=axis)
        ok = (a >= 0) & (b >= 0)
        m = int(ok.sum())
        e = np.arange(k, k + m)
        rows += [e, e]
        cols += [b[ok], a[ok]]
        vals += [np.ones(m), -np.ones(m)]
        rhs.append(0.5 * (ga[ok] + gb[ok]) * h)
        k += m
    D = scipy.sparse.csc_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(k, n))
    # omega is fixed up to a constant: hold it at node 0 and solve the normal equations for the rest
    D1 = D[:, 1:]
    omega = np.zeros(mask.shape)
    values = np.zeros(n)
    values[1:] = scipy.sparse.linalg.spsolve((D1.T @ D1).tocsc(), D1.T @ np.concatenate(rhs),
                                             permc_spec=SYMMETRIC_ORDERING)
    omega[mask] = values
    return omega


def _torsion_warping(inside, v_range, w_range, nv, nw, centroid) -> tuple[float, float, tuple]:
    """(J, Gamma, shear centre) on one grid: J = 2 int Phi dA; omega about the shear centre.

    The shear centre (v_s, w_s) is the pole that makes omega orthogonal to
    1, v and w (Trefftz's definition; Vlasov's sectorial coordinate): moving
    the pole from the origin to (v_s, w_s) adds -w_s v + v_s w to omega, so
    the weighted least-squares fit omega_O = c0 + w_s (v - c_v) - v_s (w - c_w)
    + omega_S gives it; Gamma = int omega_S^2 dA, m^6.
    """
    V, W, dv, dw = _node_grid(v_range, w_range, nv, nw)
    phi = _prandtl(inside, V, W, dv, dw)
    # trapezoid weights of the box grid, on the nodes inside
    tv, tw = np.full(nv + 1, dv), np.full(nw + 1, dw)
    tv[[0, -1]] *= 0.5
    tw[[0, -1]] *= 0.5
    weight = np.outer(tv, tw) * inside(V, W)
    J = 2.0 * float(np.sum(phi * weight))
    omega = _warping(inside, V, W, dv, dw, phi)
    cv, cw = centroid
    basis = np.stack([np.ones_like(V), V - cv, W - cw], axis=-1)[weight > 0]
    wt = weight[weight > 0]
    coef, *_ = np.linalg.lstsq(basis * np.sqrt(wt)[:, None], omega[weight > 0] * np.sqrt(wt), rcond=None)
    residual = omega[weight > 0] - basis @ coef
    gamma = float(np.sum(wt * residual**2))
    # omega_P = omega_O - w_P v + v_P w (+ const), omega_O about the origin: the fitted linear part is (w_P, -v_P)
    shear_centre = (-coef[2], coef[1])
    return J, gamma, shear_centre


_GAUSS_POINTS, _GAUSS_WEIGHTS = np.polynomial.legendre.leggauss(3)
_GAUSS_T, _GAUSS_W = 0.5 * (_GAUSS_POINTS + 1.0), 0.5 * _GAUSS_WEIGHTS     # the 3-point rule on [0, 1]


@dataclass(frozen=True)
class Elements:
    """Finite elements of a section with their quadrature, for the flexure and torsion solves.

    conn (c, a) node numbers of each element's a shape functions; X (c, g, 2)
    the (eta_v, eta_w) of the g quadrature points, m; weight (c, g) their
    weights, m^2; N (g, a) the shape functions' values there; dN (c, g, a, 2)
    their gradients, 1/m; nodes the number of nodes. Arrays may be broadcast
    views (the grid's cells share N, dN and the weights).
    """

    conn: np.ndarray
    X: np.ndarray
    weight: np.ndarray
    N: np.ndarray
    dN: np.ndarray
    nodes: int

    def stiffness(self) -> scipy.sparse.csc_matrix:
        """K_ij = int grad N_i . grad N_j dA, the Laplacian's stiffness (nodes x nodes), -."""
        Ke = np.einsum("cgai,cgbi,cg->cab", self.dN, self.dN, self.weight)
        a = self.conn.shape[1]
        rows, cols = np.repeat(self.conn, a, axis=1).ravel(), np.tile(self.conn, (1, a)).ravel()
        return scipy.sparse.csc_matrix((Ke.ravel(), (rows, cols)), shape=(self.nodes, self.nodes))

    def load(self, values: np.ndarray) -> np.ndarray:
        """int f N_i dA for f given at the quadrature points (c, g): the nodal load vector."""
        return np.bincount(self.conn.ravel(), np.einsum("cg,cg,ga->ca", values, self.weight, self.N).ravel(),
                           minlength=self.nodes)

    def gradient_load(self, vector: np.ndarray) -> np.ndarray:
        """int q . grad N_i dA for q given at the quadrature points (c, g, 2): the nodal load vector."""
        return np.bincount(self.conn.ravel(), np.einsum("cgi,cgai,cg->ca", vector, self.dN, self.weight).ravel(),
                           minlength=self.nodes)

    def at_points(self, nodal: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """A nodal field's values (c, g) and gradients (c, g, 2) at the quadrature points."""
        local = nodal[self.conn]
        return local @ self.N.T, np.einsum("ca,cgai->cgi", local, self.dN)


def _q1_cells(inside, v_range, w_range, nv, nw) -> Elements:
    """Bilinear elements on the grid cells whose centres are inside, 3 x 3 Gauss points each."""
    v = np.linspace(*v_range, nv + 1)
    w = np.linspace(*w_range, nw + 1)
    dv, dw = v[1] - v[0], w[1] - w[0]
    i, j = np.nonzero(inside(0.5 * (v[1:] + v[:-1])[:, None], 0.5 * (w[1:] + w[:-1])[None, :]))
    node = lambda a, b: a * (nw + 1) + b          # noqa: E731
    conn = np.column_stack([node(i, j), node(i + 1, j), node(i + 1, j + 1), node(i, j + 1)])
    xi, eta = (g.ravel() for g in np.meshgrid(_GAUSS_T, _GAUSS_T, indexing="ij"))
    weight = np.outer(_GAUSS_W, _GAUSS_W).ravel() * dv * dw
    N = np.column_stack([(1 - xi) * (1 - eta), xi * (1 - eta), xi * eta, (1 - xi) * eta])
    dN = np.stack([np.column_stack([-(1 - eta), 1 - eta, eta, -eta]) / dv,
                   np.column_stack([-(1 - xi), -xi, xi, 1 - xi]) / dw], axis=-1)
    X = np.stack([v[i][:, None] + xi[None, :] * dv, w[j][:, None] + eta[None, :] * dw], axis=-1)
    c = conn.shape[0]
    return Elements(conn=conn, X=X, weight=np.broadcast_to(weight, (c, weight.size)), N=N,
                    dN=np.broadcast_to(dN, (c,) + dN.shape), nodes=(nv + 1) * (nw + 1))


def _flexure(elements: Elements) -> np.ndarray:
    """Flexure integrals (2, 5) on one discretisation: per principal axis (nearest e_v, e_w)
    [cowper0, cowper1, energy0, energy1, energy2] (module docstring, class Flexure).

    The area, centroid and second moments are those of the same elements, so
    the load y integrates to zero on the domain that is solved (the Neumann
    problem's condition); chi is held at one node (it is fixed up to a constant).
    """
    weight = elements.weight
    A = float(weight.sum())
    P = elements.X - np.einsum("cgi,cg->i", elements.X, weight) / A      # (c, g, 2) from the centroid
    M2 = np.einsum("cgi,cgj,cg->ij", P, P, weight)                 # [[I_v, I_vw], [I_vw, I_w]]
    theta = 0.5 * math.atan2(2.0 * M2[0, 1], M2[1, 1] - M2[0, 0])
    axes = np.array([[math.sin(theta), math.cos(theta)], [math.cos(theta), -math.sin(theta)]])   # (v, w) comps
    near_w, near_v = axes if abs(axes[0, 1]) >= abs(axes[1, 1]) else axes[::-1]
    K = elements.stiffness()
    used = np.unique(elements.conn)
    keep = used[1:]                                               # chi = 0 at the first node used
    solve = scipy.sparse.linalg.splu(K[keep][:, keep].tocsc(), permc_spec=SYMMETRIC_ORDERING).solve
    out = np.zeros((2, 5))
    for k, (e, e_perp) in enumerate(((near_v, near_w), (near_w, near_v))):
        y, z = P @ e, P @ e_perp                                  # (c, g)
        I, I_o = float(np.sum(y * y * weight)), float(np.sum(z * z * weight))
        d = 0.5 * (y * y - z * z)[..., None] * e + (y * z)[..., None] * e_perp     # (c, g, 2)
        int_chi_y, tau = [], []
        for f, part in ((elements.load(y), 0.0), (-elements.gradient_load(d), d)):
            chi = np.zeros(elements.nodes)
            chi[keep] = solve(f[keep])
            values, grads = elements.at_points(chi)
            int_chi_y.append(float(np.sum(values * y * weight)))
            tau.append(grads + part)
        gram = [[float(np.sum(np.sum(a * b, axis=-1) * weight)) for b in tau] for a in tau]
        scale = A / I**2
        out[k] = (scale * int_chi_y[0], scale * int_chi_y[1] + 0.5 * (I - I_o) / I,
                  scale * gram[0][0], scale * gram[0][1], scale * gram[1][1])
    return out


def _grid_flexure(inside, v_range, w_range, cells_v, cells_w) -> np.ndarray:
    """The flexure integrals on the grids of the torsion constant, Richardson-extrapolated."""
    coarse = _flexure(_q1_cells(inside, v_range, w_range, cells_v, cells_w))
    fine = _flexure(_q1_cells(inside, v_range, w_range, 2 * cells_v, 2 * cells_w))
    return fine + (fine - coarse) / 3.0


def section_properties(inside: Callable, v_range: tuple, w_range: tuple,
                       cells_v: int = GRID_THICKNESS_CELLS) -> SectionProperties:
    """Properties of the shape ``inside(eta_v, eta_w) -> bool`` within the box v_range x w_range (m).

    ``cells_v`` cells across v_range; cells along w_range keep the aspect
    close to one. The torsion constant is the Richardson extrapolation of
    the grids with cells_v and 2 cells_v cells (error O(h^4) for a smooth
    stress function).
    """
    span_v, span_w = v_range[1] - v_range[0], w_range[1] - w_range[0]
    cells_w = max(1, round(cells_v * span_w / span_v))
    fine_v, fine_w = 4 * cells_v, 4 * cells_w
    m = _moments(inside, np.linspace(*v_range, fine_v + 1), np.linspace(*w_range, fine_w + 1))
    A = m[0, 0]
    cv, cw = m[1, 0] / A, m[0, 1] / A
    # central moments from the raw ones (parallel-axis shifts)
    Ivv = m[2, 0] - A * cv**2
    Iww = m[0, 2] - A * cw**2
    Ivw = m[1, 1] - A * cv * cw

    def shifted(i, j):
        """int (v - cv)^i (w - cw)^j dA from the raw moments (binomial expansion)."""
        total = 0.0
        for a in range(i + 1):
            for b in range(j + 1):
                total += (math.comb(i, a) * math.comb(j, b) * (-cv) ** (i - a) * (-cw) ** (j - b) * m[a, b])
        return total

    I_rr = shifted(4, 0) + 2.0 * shifted(2, 2) + shifted(0, 4)
    I_rrv, I_rrw = shifted(3, 0) + shifted(1, 2), shifted(2, 1) + shifted(0, 3)
    coarse = _torsion_warping(inside, v_range, w_range, cells_v, cells_w, (cv, cw))
    fine = _torsion_warping(inside, v_range, w_range, 2 * cells_v, 2 * cells_w, (cv, cw))
    J, gamma = (f + (f - c) / 3.0 for c, f in zip(coarse[:2], fine[:2]))     # Richardson, second order
    return SectionProperties(area=A, centroid=(cv, cw), I_v=Ivv, I_w=Iww, I_vw=Ivw, I_rr=I_rr, J=J,
                             I_rrv=I_rrv, I_rrw=I_rrw,
                             warping=gamma, shear_centre=fine[2],
                             flexure_integrals=functools.partial(_grid_flexure, inside, v_range, w_range,
                                                                 cells_v, cells_w))


def grid_bytes(span_v: float, span_w: float, cells_v: int = GRID_THICKNESS_CELLS) -> float:
    """Memory section_properties needs for a box span_v x span_w (m), estimated before any grid is made."""
    cells_w = max(1, round(cells_v * span_w / span_v))
    return BYTES_PER_GRID_NODE * (2 * cells_v + 1) * (2 * cells_w + 1)


def check_section_grid(chord: float, thickness: float, memory: float | None = None) -> None:
    """Refuse (InputError on blade.thickness) a section whose grids this machine cannot hold.

    The grids keep their cells square, so their size grows with chord / thickness:
    a 1 um blade of 40 mm chord would need about 110 GB.
    """
    memory = physical_memory() if memory is None else memory
    need = grid_bytes(thickness, chord)
    if need > memory:
        thinnest = thickness * need / memory            # the node count grows as chord / thickness
        raise InputError("blade.thickness", f"{thickness:g} m against blade.width {chord:g} m makes the section's "
                         f"torsion grid {chord / thickness:.3g} times longer than thick, about {in_words(need)} to "
                         f"solve; this machine has {in_words(memory)}; allowed: a thickness >= {thinnest:.3g} m "
                         "for this chord")


@functools.lru_cache(maxsize=32)
def rectangle(chord: float, thickness: float) -> SectionProperties:
    """The blade's section: chord b along e_w, thickness h along e_v, centred (m)."""
    check_section_grid(chord, thickness)
    hv, hw = 0.5 * thickness, 0.5 * chord

    def inside(v, w):
        return (np.abs(v) <= hv) & (np.abs(w) <= hw)

    return section_properties(inside, (-hv, hv), (-hw, hw))

