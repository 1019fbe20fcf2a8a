"""Section properties of any polygon outline (with holes) by quadratic finite elements on triangles.

The grid method of reduced_model.section lays a staircase on the outline;
this one meshes the outline itself, so an airfoil's thin trailing edge, a
thin wall or the slice of a solid is resolved as it is. Same quantities,
same frame (eta_v, eta_w) and same SectionProperties (reduced_model.section):

* Mesh: the outline's edges cut to at most ``size``, a triangular lattice of
  spacing ``size`` inside (points nearer than 0.6 size to the boundary
  dropped), scipy's Delaunay triangulation of both, boundary edges missing
  from it split at their middle until every one is there (a conforming
  Delaunay mesh), triangles whose centroid lies outside removed. Straight-
  sided triangles tile the polygon exactly, so area, centroid and second
  moments (6-point degree-4 rule, exact for them and I_rr) are the
  polygon's to round-off.
* P2 (six-node) triangles for the two torsion problems of Saint-Venant
  (Timoshenko & Goodier, Theory of Elasticity, Sects. 104-105), which bound J
  from both sides:
    - the warping function omega, nabla^2 omega = 0 with
      d omega / dn = eta_w n_v - eta_v n_w on the boundary (a Neumann
      problem: int grad omega . grad delta dA = int (eta_w, -eta_v) . grad delta dA,
      about the centroid), J = I_p - int |grad omega|^2 dA: the minimum of
      int |grad omega - (eta_w, -eta_v)|^2 dA, so the discrete J is an upper
      bound;
    - Prandtl's stress function Phi, nabla^2 Phi = -2, Phi = 0 on the outer
      boundary and a constant Phi_k on each hole's (Bredt's condition, the
      constants unknowns of the same minimum), J = 2 int Phi dA + 2 sum_k Phi_k A_k
      (A_k the hole's area): the maximum of a complementary energy, so the
      discrete J is a lower bound.
  J is the upper one (the warping function also gives the shear centre);
  ``J_bounds`` holds both, and their gap bounds the error of J.
* Shear centre: Trefftz's (the pole about which omega is orthogonal to
  eta_v and eta_w, as the grid method; the thin-walled theory's shear centre
  in the thin limit), Gamma = int omega_S^2 dA about it.
* Shear coefficients: the grid method's flexure problem and its two
  definitions (Cowper's, the energy one; reduced_model.section) on the same
  P2 elements, one mesh, no extrapolation.
Accuracy measured in tests/test_section_mesh.py and docs/sections.md.
"""

from __future__ import annotations

import functools

import numpy as np
import scipy.sparse.linalg
import scipy.spatial

from shroud.base.errors import InputError
from reduced_model.section import SYMMETRIC_ORDERING, Elements, SectionProperties, _flexure

LATTICE_CLEARANCE = 0.6      # lattice points nearer the boundary than this share of ``size`` are dropped
FLAT = 1e-9                  # a triangle of area below this share of size^2 is flat (collinear corners)
MAX_SPLIT_ROUNDS = 30        # rounds of boundary-edge splitting before a mesh is declared impossible

# Dunavant's 6-point rule on the triangle, exact for polynomials of degree 4: barycentric points, weights
_A, _B = 0.445948490915965, 0.091576213509771
_WA, _WB = 0.223381589678011, 0.109951743655322
_BARY = np.array([[_A, _A, 1 - 2 * _A], [_A, 1 - 2 * _A, _A], [1 - 2 * _A, _A, _A],
                  [_B, _B, 1 - 2 * _B], [_B, 1 - 2 * _B, _B], [1 - 2 * _B, _B, _B]])
_RULE_WEIGHTS = np.array([_WA] * 3 + [_WB] * 3)


def inside_polygon(points: np.ndarray, loops: list[np.ndarray]) -> np.ndarray:
    """Even-odd rule: which of ``points`` (n, 2) lie inside the region bounded by the closed ``loops``."""
    inside = np.zeros(len(points), dtype=bool)
    for loop in loops:
        a, b = loop, np.roll(loop, -1, axis=0)
        pv, pw = points[:, :1], points[:, 1:]
        crosses = (a[:, 1] > pw) != (b[:, 1] > pw)
        with np.errstate(divide="ignore", invalid="ignore"):
            at = a[:, 0] + (pw - a[:, 1]) * (b[:, 0] - a[:, 0]) / (b[:, 1] - a[:, 1])
        inside ^= (np.sum(crosses & (pv < at), axis=1) % 2).astype(bool)
    return inside


def _signed_area(loop: np.ndarray) -> float:
    a, b = loop, np.roll(loop, -1, axis=0)
    return 0.5 * float(np.sum(a[:, 0] * b[:, 1] - b[:, 0] * a[:, 1]))


def _cut(loop: np.ndarray, size: float) -> np.ndarray:
    """The loop's vertices with every edge longer than ``size`` cut into equal pieces."""
    out = []
    for a, b in zip(loop, np.roll(loop, -1, axis=0)):
        n = max(1, int(np.ceil(np.linalg.norm(b - a) / size)))
        out.append(a + np.outer(np.arange(n) / n, b - a))
    return np.concatenate(out)


def triangulate(outline: np.ndarray, holes: tuple = (), size: float | None = None):
    """Triangles (P1) on the polygon ``outline`` (n, 2) less ``holes``, edges at most ``size`` (m).

    Returns (points (p, 2), triangles (t, 3) counter-clockwise, loops: for the
    outline and each hole the point numbers along it).
    """
    loops_in = [np.asarray(outline, dtype=float)] + [np.asarray(h, dtype=float) for h in holes]
    for k, loop in enumerate(loops_in):
        if loop.ndim != 2 or loop.shape[1] != 2 or len(loop) < 3 or not np.all(np.isfinite(loop)):
            raise InputError("section outline", f"loop {k} is not a polygon of >= 3 finite (eta_v, eta_w) points")
        if _signed_area(loop) == 0.0:
            raise InputError("section outline", f"loop {k} encloses no area")
    if size is None:
        span = np.ptp(loops_in[0], axis=0)
        size = 0.05 * float(span.min())
    if not size > 0:
        raise InputError("section mesh size", f"{size!r}; allowed: a length > 0 m")
    loops = [_cut(loop, size) for loop in loops_in]
    # a triangular lattice inside, clear of the boundary
    lo, hi = loops[0].min(axis=0), loops[0].max(axis=0)
    rows = np.arange(lo[0], hi[0] + size, size * np.sqrt(3) / 2)
    lattice = np.concatenate([np.column_stack([np.full(n.size, r), n]) for i, r in enumerate(rows)
                              for n in [np.arange(lo[1] + (0.5 * size if i % 2 else 0.0), hi[1] + size, size)]])
    lattice = lattice[inside_polygon(lattice, loops_in)]
    boundary = np.concatenate(loops)
    if len(lattice):
        gap, _ = scipy.spatial.cKDTree(boundary).query(lattice)
        lattice = lattice[gap > LATTICE_CLEARANCE * size]
    for _ in range(MAX_SPLIT_ROUNDS):
        points = np.concatenate([np.concatenate(loops), lattice])
        starts = np.cumsum([0] + [len(loop) for loop in loops])
        numbers = [np.arange(s, s + len(loop)) for s, loop in zip(starts, loops)]
        simplices = scipy.spatial.Delaunay(points).simplices
        p = len(points)
        edges = np.sort(np.concatenate([simplices[:, [0, 1]], simplices[:, [1, 2]], simplices[:, [2, 0]]]), axis=1)
        present = set((edges[:, 0] * p + edges[:, 1]).tolist())
        split = False
        for k, (loop, n) in enumerate(zip(loops, numbers)):
            ends = np.sort(np.column_stack([n, np.roll(n, -1)]), axis=1)
            missing = ~np.isin(ends[:, 0] * p + ends[:, 1], list(present))
            if missing.any():
                split = True
                middles = 0.5 * (loop + np.roll(loop, -1, axis=0))
                order = np.argsort(np.concatenate([np.arange(len(loop)), np.flatnonzero(missing) + 0.5]),
                                   kind="stable")
                loops[k] = np.concatenate([loop, middles[missing]])[order]
        if not split:
            break
    else:
        raise InputError("section outline", f"no conforming mesh after {MAX_SPLIT_ROUNDS} rounds of edge "
                                            "splitting; allowed: a simple polygon (no crossing edges)")
    corners = points[simplices]
    d1, d2 = corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]
    twice_area = d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]
    # Qhull's triangulated output holds flat triangles on runs of collinear boundary points; their
    # centroid lies on the boundary, so the inside test cannot place them: they cover nothing, drop them
    keep = inside_polygon(corners.mean(axis=1), loops_in) & (np.abs(twice_area) > FLAT * size**2)
    triangles = simplices[keep]
    flip = twice_area[keep] < 0
    triangles[flip] = triangles[flip][:, [0, 2, 1]]
    # conforming: the edges of one triangle only are exactly the boundary's
    p = len(points)
    edges = np.sort(np.concatenate([triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]]), axis=1)
    code, count = np.unique(edges[:, 0] * p + edges[:, 1], return_counts=True)
    sides = np.concatenate([np.sort(np.column_stack([n, np.roll(n, -1)]), axis=1) for n in numbers])
    if not np.array_equal(np.sort(code[count == 1]), np.sort(sides[:, 0] * p + sides[:, 1])) or count.max() > 2:
        raise InputError("section outline", "its triangles do not conform to it; allowed: a simple polygon "
                                            "(no crossing or touching edges)")
    return points, triangles, numbers


def p2_elements(points: np.ndarray, triangles: np.ndarray) -> Elements:
    """Six-node triangles on the mesh (nodes 0 .. p-1 the ``points``, then the edges' middles), degree-4 rule."""
    p = len(points)
    pairs = np.concatenate([triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]])
    key = np.sort(pairs, axis=1)
    unique, edge = np.unique(key[:, 0] * p + key[:, 1], return_inverse=True)
    t = len(triangles)
    conn = np.column_stack([triangles, p + edge.reshape(3, t).T])
    l1, l2, l3 = _BARY.T
    N = np.column_stack([l1 * (2 * l1 - 1), l2 * (2 * l2 - 1), l3 * (2 * l3 - 1), 4 * l1 * l2, 4 * l2 * l3,
                         4 * l3 * l1])
    dl = np.array([[-1.0, -1.0], [1.0, 0.0], [0.0, 1.0]])      # d lambda_k / d (xi, eta), xi = l2, eta = l3
    g1, g2, g3 = ((4 * l - 1)[:, None] * dl[k] for k, l in enumerate((l1, l2, l3)))
    dref = np.stack([g1, g2, g3, 4 * (l1[:, None] * dl[1] + l2[:, None] * dl[0]),
                     4 * (l2[:, None] * dl[2] + l3[:, None] * dl[1]),
                     4 * (l3[:, None] * dl[0] + l1[:, None] * dl[2])], axis=1)         # (g, 6, 2)
    corners = points[triangles]
    jac = np.stack([corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]], axis=-1)   # (t, 2, 2)
    det = jac[:, 0, 0] * jac[:, 1, 1] - jac[:, 0, 1] * jac[:, 1, 0]
    dN = np.einsum("gar,crs->cgas", dref, np.linalg.inv(jac))    # inv(jac)[r, s] = d xi_r / d x_s
    X = np.einsum("gk,ckd->cgd", _BARY[:, [0, 1, 2]], corners)
    weight = 0.5 * det[:, None] * _RULE_WEIGHTS[None, :]
    return Elements(conn=conn, X=X, weight=weight, N=N, dN=dN, nodes=p + len(unique))


def _solve_held(K, f: np.ndarray, held: np.ndarray) -> np.ndarray:
    """K u = f with u = 0 on the ``held`` nodes."""
    free = np.setdiff1d(np.arange(K.shape[0]), held)
    u = np.zeros(K.shape[0])
    u[free] = scipy.sparse.linalg.splu(K[free][:, free].tocsc(), permc_spec=SYMMETRIC_ORDERING).solve(f[free])
    return u


def _prandtl_J(elements: Elements, K, loops: list[np.ndarray], hole_areas: list[float]) -> float:
    """Lower bound of J: Prandtl's Phi = 0 on the outline, one unknown constant on each hole's boundary.

    The nodes of each boundary loop (its vertices and the middles of its
    edges: edges of one triangle only) are tied to one value; the outline's
    is held at 0, hole k's is an unknown Phi_k loaded with 2 A_k (Bredt's
    condition, from the complementary energy).
    """
    conn = elements.conn
    ends = conn[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2)             # each edge's ends, in the order of conn[:, 3:]
    middles = conn[:, 3:].ravel()
    once = np.bincount(middles, minlength=elements.nodes)[middles] == 1     # of one triangle: on the boundary
    onto = np.arange(elements.nodes)
    for loop in loops:
        on_loop = once & np.isin(ends, loop).all(axis=1)
        onto[np.concatenate([loop, middles[on_loop]])] = loop[0]
    T = scipy.sparse.csc_matrix((np.ones(elements.nodes), (np.arange(elements.nodes), onto)),
                                shape=(elements.nodes, elements.nodes))
    f = T.T @ (2.0 * elements.load(np.ones_like(elements.weight)))
    for loop, area in zip(loops[1:], hole_areas):
        f[loop[0]] += 2.0 * area
    used = np.unique(onto)
    Kt = (T.T @ K @ T).tocsc()[used][:, used]
    phi = _solve_held(Kt, f[used], held=np.flatnonzero(used == loops[0][0]))
    return float(f[used] @ phi)


def section_on_mesh(outline: np.ndarray, holes: tuple = (), size: float | None = None) -> SectionProperties:
    """Properties of the polygon ``outline`` (n, 2) in (eta_v, eta_w), m, less ``holes``, on P2 triangles.

    ``size`` (m) bounds the triangles' edges (default a twentieth of the outline's smaller extent).
    """
    points, triangles, loops = triangulate(outline, holes, size)
    elements = p2_elements(points, triangles)
    X, weight = elements.X, elements.weight
    A = float(weight.sum())
    cv, cw = np.einsum("cgi,cg->i", X, weight) / A
    v, w = X[..., 0] - cv, X[..., 1] - cw
    I_v, I_w, I_vw = (float(np.sum(q * weight)) for q in (v * v, w * w, v * w))
    I_rr = float(np.sum((v * v + w * w) ** 2 * weight))
    I_rrv, I_rrw = (float(np.sum((v * v + w * w) * q * weight)) for q in (v, w))
    K = elements.stiffness()
    omega = _solve_held(K, elements.gradient_load(np.stack([w, -v], axis=-1)), held=np.array([0]))
    J = I_v + I_w - float(omega @ K @ omega)
    # Trefftz's shear centre: omega_S = omega - c0 - w_s v + v_s w orthogonal to 1, v and w (v, w from the centroid)
    values, _ = elements.at_points(omega)
    mean = float(np.sum(values * weight)) / A
    rhs = np.array([np.sum(values * v * weight), np.sum(values * w * weight)])
    w_s, minus_v_s = np.linalg.solve([[I_v, I_vw], [I_vw, I_w]], rhs)
    omega_s = values - mean - w_s * v - minus_v_s * w
    gamma = float(np.sum(omega_s**2 * weight))
    hole_areas = [abs(_signed_area(np.asarray(h, dtype=float))) for h in holes]
    J_lower = _prandtl_J(elements, K, loops, hole_areas)
    return SectionProperties(area=A, centroid=(float(cv), float(cw)), I_v=I_v, I_w=I_w, I_vw=I_vw, I_rr=I_rr,
                             I_rrv=I_rrv, I_rrw=I_rrw,
                             J=J, warping=gamma, shear_centre=(float(cv - minus_v_s), float(cw + w_s)),
                             flexure_integrals=functools.partial(_flexure, elements),
                             method=f"P2 triangles ({len(triangles)} elements, {elements.nodes} nodes)",
                             J_bounds=(J_lower, J))
