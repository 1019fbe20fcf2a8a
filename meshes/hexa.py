"""Structured hexahedral solid of the twisted, shrouded blade (``fe.cell = "hex"``).

The blade is a rectangle swept along X while it turns (geometry.md), the
shroud a box on its tip turned by alpha further: both are extrusions of one
plane mesh, the tip plane X = R_d + L in the tip-section coordinates
(v along e_v(L), w along e_w(L)):

* the plane holds the tip rectangle T = [-h/2, h/2] x [-b/2, b/2] and the
  shroud footprint S (b_s along e_vs, l_s along e_ws, paper Eq. 7);
  gmsh fragments them, so every edge of either is a mesh line, and meshes
  the plane with quadrilaterals: the middle of T as a structured grid
  (n_v through the thickness, uniform chord cells), the rest all-quad;
* the blade is the quads of T swept from the root to the tip, each layer
  turned by beta(x) (ruled, linearly twisted prism: nodes exactly on the
  helicoidal faces), the shroud the quads of S extruded by t_s along X;
  the two share the nodes of T and S's common part at the tip plane (one
  conforming body).

Where the tip rectangle leaves the shroud footprint (alpha = 15 deg: two
corners 0.2 mm past the shroud ends; 30 deg: 3 mm past its contact faces)
the cut lines sit in the end blocks of T, which are meshed freely and swept
like the rest. A footprint that cuts T within a quarter chord of its centre
(where the tip nodes sit) is refused: sweep a tetrahedral mesh instead.

Cells are Lagrange hexahedra of order ``fe.order`` (order 2: 27 nodes,
tensor-product Q2, the element DOLFINx builds from gmsh's hex27); the
quadrature of the forms is DOLFINx's default for them.
"""

from __future__ import annotations

import math

import numpy as np

from meshes.blade import (BLADE, CONTACT_SIDE1, CONTACT_SIDE2, ROOT, SHROUD, MeshSpec, section_frame,
                          tip_points)
from shroud.base.errors import InputError

# gmsh element types: hexahedra and quadrilaterals of order 1 and 2.
HEX = {1: 5, 2: 12}
QUAD = {1: 3, 2: 10}


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
    n_t = max(1, math.ceil(spec.shroud_thickness / s - 1e-9)) if spec.has_shroud else 0
    return n_v, n_w, n_end, n_x, n_t


def check_hex_geometry(spec: MeshSpec) -> None:
    """Raise InputError for a solid the swept hexahedral mesh cannot hold (before gmsh runs)."""
    if not spec.has_shroud:
        return
    n_v, n_w, n_end, _, _ = grid(spec)
    if n_end and (n_w - 2 * n_end) * 4 < n_w * 2:      # the cuts reach the tip points at |w| <= b/4
        raise InputError("fe.cell", f'"hex" cannot sweep this shroud: its footprint cuts the blade tip '
                         f"{1e3 * cut_depth(spec):.1f} mm from the chord ends, past the quarter-chord tip "
                         f'points; allowed: a footprint covering the middle half of the tip, or fe.cell = "tet"')


def _plane_mesh(gmsh, spec: MeshSpec):
    """Quadrilaterals of the tip plane: (points (n, 2) in (v, w), quads (m, 4), in_T (m,), in_S (m,))."""
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
    for _, t in model.getEntities(2):
        model.mesh.setRecombine(2, t)
    gmsh.option.setNumber("Mesh.Algorithm", 8)                # frontal-Delaunay for quads
    gmsh.option.setNumber("Mesh.RecombinationAlgorithm", 1)   # blossom
    gmsh.option.setNumber("Mesh.SubdivisionAlgorithm", 1)     # all quadrilaterals
    gmsh.option.setNumber("Mesh.MeshSizeMax", 2 * spec.size)
    gmsh.option.setNumber("Mesh.MeshSizeMin", 0.0)
    gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 0)
    model.mesh.generate(2)
    tags, x, _ = model.mesh.getNodes()
    index = np.full(int(tags.max()) + 1, -1)
    index[tags.astype(int)] = np.arange(tags.size)
    points = x.reshape(-1, 3)[:, :2]
    quads, in_T, in_S = [], [], []
    for _, t in model.getEntities(2):
        types, _, nodes = model.mesh.getElements(2, t)
        if any(ty != QUAD[1] for ty in types):
            raise InputError("fe.cell", '"hex" could not mesh the tip plane with quadrilaterals only; '
                             'allowed: fe.cell = "tet" for this geometry')
        q = index[nodes[0].astype(int)].reshape(-1, 4)
        centre = np.array(model.occ.getCenterOfMass(2, t))[:2]
        quads.append(q)
        in_T.append(np.full(len(q), abs(centre[0]) < 0.5 * h and abs(centre[1]) < 0.5 * b))
        in_S.append(np.full(len(q), spec.has_shroud and all(centre @ n < d for n, d, _ in _half_planes(spec))))
    quads = np.vstack(quads)

    def cross(a, b):
        return a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]

    P = points[quads]
    area = 0.5 * cross(P[:, 2] - P[:, 0], P[:, 3] - P[:, 1])
    quads[area < 0] = quads[area < 0][:, ::-1]        # counter-clockwise in (v, w): +X out of the plane
    P = points[quads]
    corner = [cross(P[:, (i + 1) % 4] - P[:, i], P[:, (i + 3) % 4] - P[:, i]) for i in range(4)]
    union = sum(occ.getMass(2, t) for _, t in model.getEntities(2))
    if min(np.min(c) for c in corner) <= 0 or abs(np.abs(area).sum() - union) > 1e-9 * union:
        raise RuntimeError("the quadrilaterals of the tip plane are not a valid cover of it")
    return points, quads, np.concatenate(in_T), np.concatenate(in_S)


def _plane_nodes(points: np.ndarray, quads: np.ndarray, order: int):
    """Order-``order`` nodes of the plane quads: (positions (p, 2), node of (quad, i, j) (m, k+1, k+1)).

    (i, j) count along the quad's local axes xi (corner 0 -> 1) and eta
    (corner 0 -> 3); bilinear placement (the plane's edges are straight).
    """
    k = order
    keys, pos = {}, []
    lattice = np.empty((len(quads), k + 1, k + 1), dtype=np.int64)
    for q, corners in enumerate(quads):
        P = points[corners]
        for i in range(k + 1):
            for j in range(k + 1):
                s, t = i / k, j / k
                p = (1 - s) * (1 - t) * P[0] + s * (1 - t) * P[1] + s * t * P[2] + (1 - s) * t * P[3]
                key = tuple(np.round(p / 1e-9).astype(np.int64))     # 1 nm: shared edges meet exactly
                if key not in keys:
                    keys[key] = len(pos)
                    pos.append(p)
                lattice[q, i, j] = keys[key]
    return np.array(pos), lattice


def _reference(gmsh, element_type: int) -> np.ndarray:
    """gmsh's reference coordinates of the nodes of ``element_type``, in {0, .., k} lattice units."""
    _, dim, k, n, coords, _ = gmsh.model.mesh.getElementProperties(element_type)
    ref = np.asarray(coords).reshape(n, dim)
    return np.rint((ref + 1.0) * 0.5 * k).astype(int)        # gmsh hexes/quads live on [-1, 1]^dim


def _solid(spec: MeshSpec, points, quads, in_T, in_S, gmsh):
    """Node positions and hexahedra (gmsh order) of the blade and the shroud, and the tagged facets."""
    k = spec.order
    _, _, _, n_x, n_t = grid(spec)
    pos2, lattice = _plane_nodes(points, quads, k)
    levels_blade, levels_shroud = k * n_x, k * n_t
    n_levels = levels_blade + levels_shroud + 1
    node_id = np.full((n_levels, len(pos2)), -1, dtype=np.int64)
    coords = []

    def node(level: int, p: int) -> int:
        if node_id[level, p] < 0:
            v, w = pos2[p]
            if level <= levels_blade:                  # blade section at x, turned by beta(x)
                x = spec.length * level / levels_blade
                X0 = spec.disk_radius + x
                e_v, e_w = section_frame(spec.stagger + spec.twist * x / spec.length)
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
