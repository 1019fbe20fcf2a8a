"""Swept hexahedral solid of the twisted, shrouded blade (``fe.cell = "hex"``).

The blade is a rectangle swept along X while it turns (geometry.md), the
shroud a box on its tip turned by alpha further: both are extrusions of one
quadrilateral mesh of the tip plane X = R_d + L, in the tip-section
coordinates (v along e_v(L), w along e_w(L)):

* the tip rectangle T = [-h/2, h/2] x [-b/2, b/2] is an n_v x n_w grid
  (:func:`grid`); a corner of T outside the shroud footprint S (b_s along
  e_vs, l_s along e_ws, paper Eq. 7) is cut off along S's edge inside its
  corner cell, which becomes 5 quads (the cut triangle: blade only);
* the ring S minus T is triangulated by gmsh with T's outline at half
  resolution and every triangle split into 3 quads, so that it meets T's
  cells node to node (:func:`_structured_plane`);
* the blade is T's quads swept from the root to the tip, each layer turned
  by beta(x) (ruled, linearly twisted prism: nodes exactly on the
  helicoidal faces; layers graded towards root and junction), the shroud
  S's quads extruded by t_s along X; the two share the tip-plane nodes of
  T and S's common part (one conforming body).

With alpha = 15 deg two tip corners stand 0.2 mm past the shroud ends: two
cut corner cells. Where a cut does not fit in a corner cell (alpha = 30 deg:
3 mm past the contact faces) gmsh meshes the whole plane with quads instead
(:func:`_free_plane`: a structured middle block, free end blocks). A
footprint that cuts T within a quarter chord of its centre (where the tip
nodes sit) is refused: sweep a tetrahedral mesh instead.

The airfoil (``blade.section = "naca4"``, tapers included) sweeps the same
way from a gmsh all-quadrilateral mesh of its tip plane (:func:`_profile_plane`:
the tip profile and the footprint, fragmented); each profile node keeps its
chord fraction and share of the half-thickness (:func:`_section_map`), so
that every layer's nodes lie on the tapered profile at x. Its closed
trailing edge is one quadrilateral corner of the wedge's angle (about
20 deg at the spec's tip): sharp, not collapsed.

Cells are Lagrange hexahedra of order ``fe.order`` (order 2: 27 nodes,
tensor-product Q2, the element DOLFINx builds from gmsh's hex27), written
to a .msh with the physical groups of meshes.blade.
"""

from __future__ import annotations

import math

import numpy as np

from reduced_model.airfoil import chord_and_thickness, naca4_coordinates, naca4_place
from meshes.spec import (BLADE, CONTACT_SIDE1, CONTACT_SIDE2, ROOT, SHROUD, MeshSpec, section_frame,
                         tip_points)
from shroud.base.errors import InputError

# Shroud cells (ring around the blade tip, layers through t_s) are this many times
# fe.mesh_size: a compact block, it moves nearly rigidly.
SHROUD_CELL = 1.5
# Span layers are graded towards the clamped root and the blade/shroud junction, where
# the stresses vary fastest: x / L = t - SPAN_BUMP sin(2 pi t) / (2 pi), so end layers
# are (1 - SPAN_BUMP) and mid-span layers (1 + SPAN_BUMP) times the mean.
SPAN_BUMP = 0.5
# gmsh element types: hexahedra and quadrilaterals of order 1 and 2.
HEX = {1: 5, 2: 12}
QUAD = {1: 3, 2: 10}


def span_position(t: float) -> float:
    """x / L of the span coordinate t in [0, 1] (graded layers, SPAN_BUMP)."""
    return t - SPAN_BUMP * math.sin(2.0 * math.pi * t) / (2.0 * math.pi)


def _half_planes(spec: MeshSpec) -> list[tuple[np.ndarray, float, str]]:
    """The shroud footprint S as n . (v, w) <= d, with the name of each side."""
    a = spec.alpha
    e_vs, e_ws = np.array([math.cos(a), math.sin(a)]), np.array([-math.sin(a), math.cos(a)])
    return [(e_vs, 0.5 * spec.shroud_width, "contact face"), (-e_vs, 0.5 * spec.shroud_width, "contact face"),
            (e_ws, 0.5 * spec.shroud_length, "end"), (-e_ws, 0.5 * spec.shroud_length, "end")]


def _tip_corners(spec: MeshSpec) -> np.ndarray:
    h, b = 0.5 * spec.thickness, 0.5 * spec.width
    return np.array([(-h, -b), (h, -b), (h, b), (-h, b)])


def cut_depth(spec: MeshSpec) -> float:
    """How far (along the chord, from its ends) the shroud footprint's edges cut the tip rectangle, m.

    0 when the tip rectangle lies inside the footprint. Per side of S, the
    part of T outside it is the convex hull of T's corners outside and of
    the side's crossings with T's edges.
    """
    corners = _tip_corners(spec)
    depth = 0.0
    for n, d, _ in _half_planes(spec):
        g = corners @ n - d
        if not np.any(g > 0):
            continue
        pts = [corners[g > 0]]
        for i in range(4):
            gi, gj = g[i], g[(i + 1) % 4]
            if gi * gj < 0:
                t = gi / (gi - gj)
                pts.append((corners[i] + t * (corners[(i + 1) % 4] - corners[i]))[None, :])
        pts = np.vstack(pts)
        depth = max(depth, 0.5 * spec.width - np.abs(pts[:, 1]).min())
    return depth


def grid(spec: MeshSpec) -> tuple[int, int, int, int, int]:
    """(n_v, n_w, n_end, n_x, n_t): cells through the thickness, along the chord (of which
    n_end at each end hold the footprint's cuts), along the span and through the shroud.

    Cells are at most ``spec.size`` long in the plane (an even number
    through the thickness: the plane mesh is split in two) and
    ``spec.span_ratio * spec.size`` along the span; the chord count is a
    multiple of 4 / order (and even) so that the tip points (centre,
    +/- b/4) are nodes.
    """
    s, k = spec.size, spec.order
    n_v = 2 * max(1, math.ceil(spec.thickness / (2 * s) - 1e-9))     # even: the plane mesh is split in 2
    step = 2 if k == 2 else 4
    n_w = step * max(1, math.ceil(spec.width / s / step - 1e-9))
    cell = spec.width / n_w
    depth = cut_depth(spec) if spec.has_shroud else 0.0
    n_end = math.ceil(depth / cell - 1e-9) if depth > 1e-9 * spec.width else 0
    n_x = max(1, math.ceil(spec.length / (spec.span_ratio * s) - 1e-9))
    n_t = max(1, math.ceil(spec.shroud_thickness / (SHROUD_CELL * s) - 1e-9)) if spec.has_shroud else 0
    return n_v, n_w, n_end, n_x, n_t


# Cells this many times longer than thick, measured here on the blade (5 mm cells): at 100 (blade.thickness
# 0.1 mm) the modes solve as usual; at 10^4 (1 um) MUMPS stops with FACTOR_OUTMEMORY at 0.7 GB (the
# stiffness across a cell exceeds that along it by the aspect squared, and pivoting runs away).
MAX_CELL_ASPECT = 100.0


def cell_aspect(spec: MeshSpec) -> float:
    """The blade's cells' longest side (chord or span) over their thickness."""
    n_v, n_w, _, n_x, _ = grid(spec)
    return max(spec.width / n_w, spec.length / n_x) / (spec.thickness / n_v)


def check_hex_geometry(spec: MeshSpec) -> None:
    """Raise InputError for a solid the swept hexahedral mesh cannot hold (before gmsh runs)."""
    aspect = cell_aspect(spec)
    if aspect > MAX_CELL_ASPECT:
        raise InputError("blade.thickness", f"{spec.thickness:g} m makes the solid's cells {aspect:.3g} times longer "
                         f"than thick at fe.mesh_size {spec.size:g} m, past what a direct factor survives "
                         f"({MAX_CELL_ASPECT:g}); allowed: a thickness >= {spec.thickness * aspect / MAX_CELL_ASPECT:.3g} m, "
                         f"or fe.mesh_size <= {spec.size * MAX_CELL_ASPECT / aspect:.3g} m")
    if not spec.has_shroud or spec.section == "naca4":     # the airfoil's tip points are vertices of any plane mesh
        return
    n_v, n_w, n_end, _, _ = grid(spec)
    if n_end and (n_w - 2 * n_end) * 4 < n_w * 2:      # the cuts reach the tip points at |w| <= b/4
        raise InputError("fe.cell", f'"hex" cannot sweep this shroud: its footprint cuts the blade tip '
                         f"{1e3 * cut_depth(spec):.1f} mm from the chord ends, past the quarter-chord tip "
                         f'points; allowed: a footprint covering the middle half of the tip, or fe.cell = "tet"')


def _plane_mesh(gmsh, spec: MeshSpec):
    """Quadrilaterals of the tip plane: (points (n, 2) in (v, w), quads (m, 4) counter-clockwise,
    in_T (m,), in_S (m,)): the structured tip grid if the footprint allows it, else gmsh's; the airfoil's
    tip profile always gmsh's."""
    if spec.section == "naca4":
        return _profile_plane(gmsh, spec)
    found = _structured_plane(gmsh, spec)
    if found is None:
        gmsh.model.remove()
        gmsh.model.add("tip_plane")
        found = _free_plane(gmsh, spec)
    return found


def _free_plane(gmsh, spec: MeshSpec):
    """The tip plane meshed by gmsh: a structured middle block of T, the rest free quadrilaterals."""
    n_v, n_w, n_end, _, _ = grid(spec)
    occ = gmsh.model.occ
    h, b = spec.thickness, spec.width
    w_c = 0.5 * b - n_end * b / n_w
    blocks = [occ.addRectangle(-0.5 * h, -w_c, 0, h, 2 * w_c)]
    if n_end:
        blocks += [occ.addRectangle(-0.5 * h, -0.5 * b, 0, h, 0.5 * b - w_c),
                   occ.addRectangle(-0.5 * h, w_c, 0, h, 0.5 * b - w_c)]
    tools = []
    if spec.has_shroud:
        S = occ.addRectangle(-0.5 * spec.shroud_width, -0.5 * spec.shroud_length, 0,
                             spec.shroud_width, spec.shroud_length)
        occ.rotate([(2, S)], 0, 0, 0, 0, 0, 1, spec.alpha)
        tools = [(2, S)]
    occ.fragment([(2, t) for t in blocks], tools)
    occ.synchronize()
    model = gmsh.model
    tol = 1e-6 * h
    # the middle block, whole: the rectangle of area 2 w_c h centred on the blade axis
    middle = [t for _, t in model.getEntities(2)
              if np.allclose(occ.getCenterOfMass(2, t), 0.0, atol=tol)
              and abs(occ.getMass(2, t) - 2 * w_c * h) < tol * h]
    if len(middle) != 1:
        raise RuntimeError("the middle block of the tip rectangle was cut by the shroud footprint")
    # gmsh meshes at half resolution, then splits every triangle into 3 and every quad
    # into 4 quadrilaterals (all-quad for any footprint); the middle grid stays structured.
    for _, c in model.getBoundary([(2, middle[0])], oriented=False):
        x0, y0, _, x1, y1, _ = model.getBoundingBox(1, c)
        along_chord = abs(y1 - y0) > abs(x1 - x0)
        model.mesh.setTransfiniteCurve(abs(c), (n_w - 2 * n_end if along_chord else n_v) // 2 + 1)
    model.mesh.setTransfiniteSurface(middle[0])
    parts = {t: (abs(c[0]) < 0.5 * h and abs(c[1]) < 0.5 * b,
                 spec.has_shroud and all(c @ n < d for n, d, _ in _half_planes(spec)))
             for _, t in model.getEntities(2) for c in [np.array(occ.getCenterOfMass(2, t))[:2]]}
    return _quad_cover(gmsh, spec, parts)


def _quad_cover(gmsh, spec: MeshSpec, parts: dict[int, tuple[bool, bool]], curvature: int = 0):
    """All-quadrilateral mesh of the plane surfaces of the current gmsh model, each surface ``t`` of the
    blade's section and/or the shroud's footprint as ``parts[t]`` says: (points, quads, in_T, in_S) as
    :func:`_plane_mesh`. gmsh meshes at twice ``spec.size`` and splits every triangle into 3 and every
    quad into 4 quadrilaterals (all-quad for any outline); transfinite parts stay structured.
    ``curvature``: edges per 2 pi of a curved outline's turn (before the split; 0: the size alone)."""
    model, occ = gmsh.model, gmsh.model.occ
    for t in parts:
        model.mesh.setRecombine(2, t)
    gmsh.option.setNumber("Mesh.Algorithm", 8)                # frontal-Delaunay for quads
    gmsh.option.setNumber("Mesh.RecombinationAlgorithm", 1)   # blossom
    gmsh.option.setNumber("Mesh.SubdivisionAlgorithm", 1)     # all quadrilaterals
    gmsh.option.setNumber("Mesh.MeshSizeMax", 2 * spec.size)
    gmsh.option.setNumber("Mesh.MeshSizeMin", 0.0)
    gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", curvature)
    model.mesh.generate(2)
    tags, x, _ = model.mesh.getNodes()
    index = np.full(int(tags.max()) + 1, -1)
    index[tags.astype(int)] = np.arange(tags.size)
    points = x.reshape(-1, 3)[:, :2]
    quads, in_T, in_S = [], [], []
    for t, (blade, shroud) in parts.items():
        types, _, nodes = model.mesh.getElements(2, t)
        if any(ty != QUAD[1] for ty in types):
            raise InputError("fe.cell", '"hex" could not mesh the tip plane with quadrilaterals only; '
                             'allowed: fe.cell = "tet" for this geometry')
        q = index[nodes[0].astype(int)].reshape(-1, 4)
        quads.append(q)
        in_T.append(np.full(len(q), blade))
        in_S.append(np.full(len(q), shroud))
    union = sum(occ.getMass(2, t) for t in parts)
    quads = _valid_cover(points, np.vstack(quads), union)
    if quads is None:
        raise RuntimeError("the quadrilaterals of the tip plane are not a valid cover of it")
    return points, quads, np.concatenate(in_T), np.concatenate(in_S)


# Edges per 2 pi of the profile's turn: its nose (radius 1.1 tau^2 c, 0.6 mm at the spec's tip) gets
# cells that follow it rather than cells of fe.mesh_size across it.
NOSE_EDGES = 12


def _profile_plane(gmsh, spec: MeshSpec):
    """The tip plane of the airfoil blade: the tip profile T (two B-splines through its points, as the
    loft's sections) and the shroud footprint S, fragmented, with the tip points (meshes.spec.tip_points)
    as vertices; all quadrilaterals (:func:`_quad_cover`). Which surface is T's or S's is read from
    the fragment's map, not guessed from centres (S minus T is a ring about T)."""
    occ = gmsh.model.occ
    outline = spec.profile(spec.length, PLANE_SPLINE_POINTS)
    corners = [occ.addPoint(v, w, 0.0) for v, w in outline]
    leading = PLANE_SPLINE_POINTS - 1      # trailing edge -> upper -> leading edge -> lower, as the loft's
    T = occ.addPlaneSurface([occ.addCurveLoop([occ.addSpline(corners[:leading + 1]),
                                               occ.addSpline(corners[leading:] + corners[:1])])])
    shapes = [(2, T)]
    if spec.has_shroud:
        S = occ.addRectangle(-0.5 * spec.shroud_width, -0.5 * spec.shroud_length, 0,
                             spec.shroud_width, spec.shroud_length)
        occ.rotate([(2, S)], 0, 0, 0, 0, 0, 1, spec.alpha)
        shapes.append((2, S))
    quarter = 0.25 * spec.tip_chord                  # the tip points in (v, w): the centroid and w = -/+ c(L)/4
    tips = [(0, occ.addPoint(0.0, w, 0.0)) for w in (0.0, -quarter, quarter)]
    _, children = occ.fragment(shapes, tips)
    occ.synchronize()
    mine = [{t for d, t in c if d == 2} for c in children[:len(shapes)]]
    in_S = mine[1] if spec.has_shroud else set()
    return _quad_cover(gmsh, spec, {t: (t in mine[0], t in in_S) for t in mine[0] | in_S}, NOSE_EDGES)


def _cross(a, b):
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def _valid_cover(points: np.ndarray, quads: np.ndarray, area: float):
    """``quads`` turned counter-clockwise in (v, w) (+X out of the plane), or None unless every
    corner is convex and they cover ``area`` (m^2) exactly once: within half the smallest quad (a gap or
    an overlap of a cell, not the straight edges' sag under a curved outline, 1e-6 of the airfoil's plane)."""
    P = points[quads]
    signed = 0.5 * _cross(P[:, 2] - P[:, 0], P[:, 3] - P[:, 1])
    quads = np.where((signed < 0)[:, None], quads[:, ::-1], quads)
    P = points[quads]
    corner = min(np.min(_cross(P[:, (i + 1) % 4] - P[:, i], P[:, (i + 3) % 4] - P[:, i])) for i in range(4))
    if corner <= 0 or abs(np.abs(signed).sum() - area) > 0.5 * np.abs(signed).min():
        return None
    return quads


def _structured_plane(gmsh, spec: MeshSpec):
    """The tip rectangle T as an n_v x n_w grid, the shroud footprint's rest S \\ T from gmsh.

    A corner of T outside the footprint is cut off by one side of it within
    its corner cell: the cell becomes the cut triangle (3 quads about its
    centroid, blade only) and the pentagon left (2 quads). S \\ T is
    triangulated by gmsh with T's outline at half resolution, and each
    triangle split into 3 quadrilaterals whose points on T's outline are
    T's nodes. None when a cut does not fit in its corner cell (then the
    free mesher serves).
    """
    n_v, n_w, _, _, _ = grid(spec)
    h, b = spec.thickness, spec.width
    tol = 1e-9 * h
    planes = _half_planes(spec) if spec.has_shroud else []
    points = [np.array([v, w]) for v in np.linspace(-0.5 * h, 0.5 * h, n_v + 1)
              for w in np.linspace(-0.5 * b, 0.5 * b, n_w + 1)]

    def nid(i: int, j: int) -> int:
        return i * (n_w + 1) + j

    def add(p) -> int:
        points.append(np.asarray(p, dtype=float))
        return len(points) - 1

    def outside(p) -> list[int]:
        return [k for k, (n, d, _) in enumerate(planes) if p @ n > d + tol]

    corners = [(0, 0), (0, n_w), (n_v, n_w), (n_v, 0)]
    if any(outside(points[nid(i, j)]) for i in range(n_v + 1) for j in range(n_w + 1)
           if (i, j) not in corners):
        return None
    quads, in_S = [], []
    cut = {}                      # corner node -> (point on its w-edge, point on its v-edge)
    for i, j in corners:
        C = nid(i, j)
        A = nid(i, j + (1 if j == 0 else -1))           # along the chord
        D = nid(i + (1 if i == 0 else -1), j)           # through the thickness
        B = nid(i + (1 if i == 0 else -1), j + (1 if j == 0 else -1))
        sides = outside(points[C])
        if not sides:
            continue
        if len(sides) > 1:
            return None
        n, d, _ = planes[sides[0]]
        t_A = (d - points[C] @ n) / ((points[A] - points[C]) @ n)
        t_D = (d - points[C] @ n) / ((points[D] - points[C]) @ n)
        if not (0 < t_A < 0.9 and 0 < t_D < 0.9):
            return None
        P_A = add(points[C] + t_A * (points[A] - points[C]))
        P_D = add(points[C] + t_D * (points[D] - points[C]))
        m = add(0.5 * (points[P_A] + points[P_D]))
        G = add((points[C] + points[P_A] + points[P_D]) / 3.0)
        m_A, m_D = add(0.5 * (points[C] + points[P_A])), add(0.5 * (points[C] + points[P_D]))
        quads += [[C, m_A, G, m_D], [m_A, P_A, m, G], [m_D, G, m, P_D], [P_A, A, B, m], [m, B, D, P_D]]
        in_S += [False, False, False, True, True]
        cut[C] = (P_A, m_A, P_D, m_D)
    cut_cells = {(0 if nid(0, 0) <= C < nid(1, 0) else n_v - 1, 0 if C % (n_w + 1) == 0 else n_w - 1)
                 for C in cut}
    for i in range(n_v):
        for j in range(n_w):
            if (i, j) not in cut_cells:
                quads.append([nid(i, j), nid(i, j + 1), nid(i + 1, j + 1), nid(i + 1, j)])
                in_S.append(bool(planes))
    n_T = len(quads)
    # T's outline, counter-clockwise in (v, w), cut corners replaced by their cut points.
    ring = ([nid(0, j) for j in range(n_w)] + [nid(i, n_w) for i in range(n_v)]
            + [nid(n_v, j) for j in range(n_w, 0, -1)] + [nid(i, 0) for i in range(n_v, 0, -1)])
    outline, anchors = [], set()
    for C in ring:
        if C in cut:
            P_A, m_A, P_D, m_D = cut[C]
            i_prev = ring[ring.index(C) - 1]
            along_chord_first = abs(points[i_prev][0] - points[C][0]) < tol   # arriving along the chord
            seq = [P_A, m_A, C, m_D, P_D] if along_chord_first else [P_D, m_D, C, m_A, P_A]
            outline += seq
            anchors |= {seq[0], C, seq[-1]}
        else:
            outline.append(C)
            if C in {nid(*c) for c in corners}:
                anchors.add(C)
    if not planes:
        quads = _valid_cover(np.array(points), np.array(quads), h * b)
        return (np.array(points), quads, np.ones(n_T, bool), np.zeros(n_T, bool)) if quads is not None else None
    # Half resolution along the outline: every other node from each anchor (chains are even).
    start = next(k for k, p in enumerate(outline) if p in anchors)
    outline = outline[start:] + outline[:start]
    half, between, chain = [], {}, []
    for p in outline + [outline[0]]:
        chain.append(p)
        if p in anchors and len(chain) > 1:
            if (len(chain) - 1) % 2:
                return None
            half += chain[:-1:2]
            for a, mid, c in zip(chain[:-2:2], chain[1::2], chain[2::2]):
                between[frozenset((a, c))] = mid
            chain = [p]
    ring_S = _shroud_ring(gmsh, spec, points, half, between)
    if ring_S is None:
        return None
    points = np.array(points)
    quads = np.vstack([np.array(quads), ring_S[0]])
    quads = _valid_cover(points, quads, h * b + ring_S[1])
    if quads is None:
        return None
    n_S = len(quads) - n_T
    return (points, quads, np.concatenate([np.ones(n_T, bool), np.zeros(n_S, bool)]),
            np.concatenate([np.array(in_S, bool), np.ones(n_S, bool)]))


def _shroud_ring(gmsh, spec: MeshSpec, pts: list, half: list[int], between: dict):
    """Quadrilaterals of S \\ T (the footprint outside the tip rectangle) and its area, or None.

    gmsh triangulates S minus the polygon of T's outline nodes ``half``
    (every other node, each segment one mesh edge) at twice the cell size;
    every triangle is split into 3 quadrilaterals about its centroid, with
    the outline node ``between`` two half-resolution nodes as the point on
    that edge (so the quads meet T's cells node to node). New points are
    appended to ``pts``.
    """
    occ, model = gmsh.model.occ, gmsh.model
    tol = 1e-9 * spec.thickness
    S = occ.addRectangle(-0.5 * spec.shroud_width, -0.5 * spec.shroud_length, 0,
                         spec.shroud_width, spec.shroud_length)
    occ.rotate([(2, S)], 0, 0, 0, 0, 0, 1, spec.alpha)
    tags = [occ.addPoint(*pts[p], 0.0) for p in half]
    lines = [occ.addLine(tags[k], tags[(k + 1) % len(tags)]) for k in range(len(tags))]
    T = occ.addPlaneSurface([occ.addCurveLoop(lines)])
    ring, _ = occ.cut([(2, S)], [(2, T)])
    occ.synchronize()
    if not ring:
        return None
    area = sum(occ.getMass(2, t) for _, t in ring)

    def outline_node(x) -> int | None:
        return next((p for p in half if np.linalg.norm(pts[p] - x[:2]) < tol), None)

    for _, c in model.getEntities(1):
        ends = [outline_node(np.asarray(model.getValue(0, v, []))) for _, v in model.getBoundary([(1, c)])]
        if None not in ends and frozenset(ends) in between:
            model.mesh.setTransfiniteCurve(c, 2)             # one segment: T's outline at half resolution
    gmsh.option.setNumber("Mesh.Algorithm", 6)               # frontal-Delaunay triangles
    gmsh.option.setNumber("Mesh.MeshSizeMax", 2 * SHROUD_CELL * spec.size)
    gmsh.option.setNumber("Mesh.MeshSizeMin", 0.0)
    gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 0)
    model.mesh.generate(2)
    node_tags, x, _ = model.mesh.getNodes()
    mine = {}
    for tag, p in zip(node_tags.astype(int), x.reshape(-1, 3)):
        hit = outline_node(p)
        if hit is None:
            pts.append(p[:2].copy())
            hit = len(pts) - 1
        mine[tag] = hit
    edge_point = dict(between)

    def on_edge(a: int, c: int) -> int:
        key = frozenset((a, c))
        if key not in edge_point:
            pts.append(0.5 * (pts[a] + pts[c]))
            edge_point[key] = len(pts) - 1
        return edge_point[key]

    quads = []
    for _, t in ring:
        types, _, nodes = model.mesh.getElements(2, t)
        if any(ty != 2 for ty in types):
            return None
        for a, c, e in np.array([mine[n] for n in nodes[0].astype(int)]).reshape(-1, 3):
            pts.append((pts[a] + pts[c] + pts[e]) / 3.0)
            g = len(pts) - 1
            ac, ce, ea = on_edge(a, c), on_edge(c, e), on_edge(e, a)
            quads += [[a, ac, g, ea], [c, ce, g, ac], [e, ea, g, ce]]
    return np.array(quads), area


def _plane_nodes(points: np.ndarray, quads: np.ndarray, order: int):
    """Order-``order`` nodes of the plane quads: (positions (p, 2), node of (quad, i, j) (m, k+1, k+1)).

    (i, j) count along the quad's local axes xi (corner 0 -> 1) and eta
    (corner 0 -> 3); bilinear placement (the plane's edges are straight).
    Quads share a node when they share the vertex, the edge or the cell it
    belongs to (by index, not by position).
    """
    k = order
    keys, pos = {}, []
    lattice = np.empty((len(quads), k + 1, k + 1), dtype=np.int64)
    corner_of = {(0, 0): 0, (k, 0): 1, (k, k): 2, (0, k): 3}
    for q, corners in enumerate(quads):
        P = points[corners]
        for i in range(k + 1):
            for j in range(k + 1):
                if (i, j) in corner_of:                      # a vertex: shared by its index
                    key = ("v", int(corners[corner_of[(i, j)]]))
                elif 0 < i < k and 0 < j < k:                # inside the quad
                    key = ("c", q, i, j)
                else:                                        # on an edge: shared by its two vertices
                    a, b = ((corners[0], corners[1]) if j == 0 else (corners[3], corners[2]) if j == k
                            else (corners[0], corners[3]) if i == 0 else (corners[1], corners[2]))
                    along = i if j in (0, k) else j
                    key = ("e", int(a), int(b), along) if a < b else ("e", int(b), int(a), k - along)
                if key not in keys:
                    s_, t_ = i / k, j / k
                    keys[key] = len(pos)
                    pos.append((1 - s_) * (1 - t_) * P[0] + s_ * (1 - t_) * P[1] + s_ * t_ * P[2]
                               + (1 - s_) * t_ * P[3])
                lattice[q, i, j] = keys[key]
    return np.array(pos), lattice


def _reference(gmsh, element_type: int) -> np.ndarray:
    """gmsh's reference coordinates of the nodes of ``element_type``, in {0, .., k} lattice units."""
    _, dim, k, n, coords, _ = gmsh.model.mesh.getElementProperties(element_type)
    ref = np.asarray(coords).reshape(n, dim)
    return np.rint((ref + 1.0) * 0.5 * k).astype(int)        # gmsh hexes/quads live on [-1, 1]^dim


# Points a surface of the B-splines of the airfoil's tip profile in the plane (the loft's have 21, meshes.blade):
# the profile's area within 3e-6 of the exact one's.
PLANE_SPLINE_POINTS = 41


def _section_map(spec: MeshSpec, plane: np.ndarray):
    """``section(p, x)``: (v, w), m, at x m from the root of the node of the tip plane's point ``plane[p]``.

    The rectangle keeps its (v, w). The airfoil's node keeps its chord fraction s and its share r of the
    half-thickness along the camber line's normal (reduced_model.airfoil.naca4_coordinates at the tip),
    so every layer's nodes on the profile lie on the profile at x, whose chord and thickness taper
    apart (a map affine near both edges: the tip's quadrilaterals stay quadrilaterals at every x).
    """
    if spec.section != "naca4":
        return lambda p, x: plane[p]
    shape = (spec.naca_m, spec.naca_p)
    chord, thickness = chord_and_thickness(spec, spec.length)
    s, r = naca4_coordinates(*shape, thickness / chord, chord, PLANE_SPLINE_POINTS, plane)

    def section(p: int, x: float) -> np.ndarray:
        chord, thickness = chord_and_thickness(spec, x)
        return naca4_place(*shape, thickness / chord, chord, PLANE_SPLINE_POINTS, s[p], r[p])
    return section


def _on_the_profile(spec: MeshSpec, plane: np.ndarray, lattice: np.ndarray) -> np.ndarray:
    """``plane`` with the edge nodes of the tip profile's outline moved onto the profile: the nodes
    between two vertices of an outline edge of the blade's quads (``lattice`` (m, k+1, k+1), as
    :func:`_plane_nodes`) sit on its straight chord; each goes along the camber line's normal to the
    profile's surface on the side of the edge's vertices (r = +/-1), so that order-2 cells follow the
    curved profile instead of its polygon."""
    k = lattice.shape[1] - 1
    edges = {}
    for cell in lattice:
        for side in (cell[:, 0], cell[:, k], cell[0, :], cell[k, :]):
            edges.setdefault(frozenset((int(side[0]), int(side[k]))), []).append(side)
    outline = [sides[0] for sides in edges.values() if len(sides) == 1]
    if k == 1 or not outline:
        return plane
    inner = np.array([side[1:k] for side in outline], dtype=np.int64).ravel()
    ends = np.array([side[[0, k]] for side in outline], dtype=np.int64)
    shape = (spec.naca_m, spec.naca_p)
    chord, thickness = chord_and_thickness(spec, spec.length)
    tau = thickness / chord
    s, _ = naca4_coordinates(*shape, tau, chord, PLANE_SPLINE_POINTS, plane[inner])
    _, r_ends = naca4_coordinates(*shape, tau, chord, PLANE_SPLINE_POINTS, plane[ends.ravel()])
    side = np.sign(r_ends.reshape(-1, 2).sum(axis=1))          # an edge's vertices on one surface (r = 0 at the edges)
    moved = plane.copy()
    moved[inner] = naca4_place(*shape, tau, chord, PLANE_SPLINE_POINTS, s, np.repeat(side, k - 1))
    return moved


def _solid(spec: MeshSpec, points, quads, in_T, in_S, gmsh):
    """Node positions and hexahedra (gmsh order) of the blade and the shroud, and the tagged facets."""
    k = spec.order
    _, _, _, n_x, n_t = grid(spec)
    pos2, lattice = _plane_nodes(points, quads, k)
    if spec.section == "naca4":
        pos2 = _on_the_profile(spec, pos2, lattice[in_T])
    levels_blade, levels_shroud = k * n_x, k * n_t
    n_levels = levels_blade + levels_shroud + 1
    node_id = np.full((n_levels, len(pos2)), -1, dtype=np.int64)
    coords = []

    section = _section_map(spec, pos2)

    def node(level: int, p: int) -> int:
        if node_id[level, p] < 0:
            v, w = pos2[p]
            if level <= levels_blade:                  # blade section at x, turned by beta(x)
                x = spec.length * span_position(level / levels_blade)
                X0 = spec.disk_radius + x
                e_v, e_w = section_frame(spec.stagger + spec.twist * x / spec.length)
                if level < levels_blade:
                    v, w = section(p, x)
            else:                                      # shroud, in the tip frame
                X0 = spec.tip_x + spec.shroud_thickness * (level - levels_blade) / levels_shroud
                e_v, e_w = section_frame(spec.beta_tip)
            node_id[level, p] = len(coords)
            coords.append(np.array([X0, 0.0, 0.0]) + v * e_v + w * e_w)
        return int(node_id[level, p])

    ref = _reference(gmsh, HEX[k])              # (n_nodes, 3) lattice (i, j, l) of each gmsh hex node
    cells = {BLADE: [], SHROUD: []}
    for tag, chosen, first, layers in ((BLADE, in_T, 0, n_x), (SHROUD, in_S, levels_blade, n_t)):
        for q in np.flatnonzero(chosen):
            for layer in range(layers):
                base = first + k * layer
                cells[tag].append([node(base + l, lattice[q, i, j]) for i, j, l in ref])
    cells = {t: np.array(c, dtype=np.int64).reshape(-1, len(ref)) for t, c in cells.items()}
    return np.array(coords), cells, ref


def _faces(spec: MeshSpec, coords, cells, ref, gmsh) -> dict[int, np.ndarray]:
    """Quadrilateral facets (gmsh order) of the root and of the two contact faces."""
    k = spec.order
    fref = _reference(gmsh, QUAD[k])             # (n, 2) lattice of each gmsh quad node
    lookup = {tuple(r): n for n, r in enumerate(ref)}
    faces = []                                  # the 6 faces of a hex as local node lists (quad order)
    for axis in range(3):
        for side in (0, k):
            a, b = [ax for ax in range(3) if ax != axis]
            order = []
            for s, t in fref:
                r = [0, 0, 0]
                r[axis], r[a], r[b] = side, s, t
                order.append(lookup[tuple(r)])
            faces.append(np.array(order))
    e_vs = section_frame(spec.beta_tip + spec.alpha)[0]
    tol = 1e-9 * spec.length
    found = {ROOT: [], CONTACT_SIDE1: [], CONTACT_SIDE2: []}
    for tag, hexes in cells.items():
        for f in faces:
            nodes = hexes[:, f]
            X = coords[nodes]
            if tag == BLADE:
                on = np.all(np.abs(X[..., 0] - spec.disk_radius) < tol, axis=1)
                found[ROOT].append(nodes[on])
            else:
                v_s = X @ e_vs
                for face_tag, sign in ((CONTACT_SIDE1, -1), (CONTACT_SIDE2, 1)):
                    on = np.all(np.abs(v_s - sign * 0.5 * spec.shroud_width) < tol, axis=1)
                    found[face_tag].append(nodes[on])
    return {t: np.vstack(v) if v else np.empty((0, len(fref)), dtype=np.int64) for t, v in found.items()}


def write_hex_mesh(spec: MeshSpec, path) -> None:
    """Build the swept hexahedral solid and write it as ``path`` (.msh 4.1, physical groups as the tets')."""
    import gmsh
    check_hex_geometry(spec)
    gmsh.initialize(interruptible=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add("tip_plane")
        points, quads, in_T, in_S = _plane_mesh(gmsh, spec)
        coords, cells, ref = _solid(spec, points, quads, in_T, in_S, gmsh)
        facets = _faces(spec, coords, cells, ref, gmsh)
        gmsh.model.remove()
        gmsh.model.add("shrouded_blade")
        model = gmsh.model
        volumes = {t: model.addDiscreteEntity(3) for t, c in cells.items() if len(c)}
        node_tags = np.arange(1, len(coords) + 1)
        model.mesh.addNodes(3, volumes[BLADE], node_tags, coords.ravel())
        first = 1
        for t, vol in volumes.items():
            model.mesh.addElementsByType(vol, HEX[spec.order], np.arange(first, first + len(cells[t])),
                                         (cells[t] + 1).ravel())
            first += len(cells[t])
            model.addPhysicalGroup(3, [vol], t, name="blade" if t == BLADE else "shroud")
        names = {ROOT: "root", CONTACT_SIDE1: "contact_side1", CONTACT_SIDE2: "contact_side2"}
        for t, f in facets.items():
            if not len(f):
                continue
            surface = model.addDiscreteEntity(2)
            model.mesh.addElementsByType(surface, QUAD[spec.order], np.arange(first, first + len(f)),
                                         (f + 1).ravel())
            first += len(f)
            model.addPhysicalGroup(2, [surface], t, name=names[t])
        missing = [p for p in tip_points(spec) if np.min(np.linalg.norm(coords - p, axis=1)) > 1e-9 * spec.size]
        if missing:
            raise RuntimeError(f"tip points {missing} are not nodes of the hexahedral mesh")
        gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
        gmsh.write(str(path))
    finally:
        gmsh.finalize()
