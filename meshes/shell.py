"""The blade's mid-surface for the shell model: the camber surface, and the shroud as a plate on its tip.

The mid-surface is the surface swept by the section's camber line from X =
R_d to X = R_d + L while it turns by beta(x) = beta_1 + beta_t x / L
(docs/geometry.md, "Shell model" and "Airfoil blades"):

    P(x, s) = (R_d + x) e_X + c(x) (y_c(s) - y_C(x)) e_v(x) + c(x) (s - s_C(x)) e_w(x),

0 <= x <= L, s in [0, 1] the chord fraction from the leading edge, c(x)
the (tapered) chord, y_c the camber line (0 for the rectangle; the NACA
four-digit camber of reduced_model.airfoil) and (s_C, y_C) the section's
area centroid in chord units, which is on the X axis: the sections are
stacked on their centroids exactly as the solid's loft stacks them
(meshes.blade, the same polygon of SPLINE_POINTS per surface). For the
untapered rectangle this is the right helicoid P = (R_d + x) e_X + s' e_w(x),
|s'| <= b/2. (A loft of the root and tip lines alone would be the
hyperbolic paraboloid through them, a different surface: its chord lines
do not turn uniformly and are not of length b.) gmsh skins it through
camber lines every <= 2 deg of twist; every mesh node is then put back on
the exact surface along e_v of its own section (:func:`on_mid_surface`), so
the geometry does not depend on the skin.

The shell's thickness at P(x, s) (:meth:`ShellSpec.mid_thickness`): t(x)
on the rectangle, 2 c(x) y_t(s) (the NACA thickness normal to the camber
line, reduced_model.airfoil) on the profile; the shell section's area
int 2 c y_t ds_arc is then the profile's own (c^2 int 2 y_t / cos(theta)
ds).

Cells: three-node (flat) triangles, because the rotation space of the shell
(reference_fe.shell) is Crouzeix-Raviart, defined on simplices only, and a
triangulation joins the blade and the shroud along the tip line without
constraints; the displacement is P2 on these cells (Campello et al. 2003;
J. Bleyer's linear shell tour).

The shroud (shroud.thickness > 0) is a flat plate of thickness t_s in the
tip plane X = R_d + L: the rectangle l_s (along e_ws) x b_s (along e_vs)
of the solid's shroud box, centred on the X axis, with the blade's tip line
embedded in it (a T-joint: a facet there has three cells). What it leaves
out against the solid's box: the box's centre sits t_s/2 further out, and
the box is stiffer in bending than a plate of its thickness; both are
measured in docs/shell.md. Its two edges at v_s = -b_s/2 and +b_s/2 are the
contact faces (side 1, side 2), each cut into ``contact_points`` equal
segments whose midpoints are the contact points (there the P2 displacement
and the Crouzeix-Raviart rotation both have a node).

Physical groups: cells BLADE, SHROUD; facets (lines) ROOT, CONTACT_SIDE1,
CONTACT_SIDE2 and TIP (the blade's tip line). The tip points
(meshes.spec.tip_points) are nodes: on the rectangle's tip line, or
embedded in the plate for the NACA profile (its centroid is off the camber
line; a bare NACA shell is refused). Meshes are cached on disk like the solid's (meshes.blade).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from meshes.blade import SPLINE_POINTS, check_msh_complete
from meshes.spec import BLADE, CONTACT_SIDE1, CONTACT_SIDE2, ROOT, SHROUD, SweptBlade, section_frame, tip_points
from reduced_model.airfoil import chord_and_thickness, naca4_camber, naca4_centroid, naca4_half_thickness
from shroud.base.cache import cached
from shroud.base.errors import InputError
from shroud.base.resources import in_words, physical_memory
from shroud.params import Parameters

TIP = 4                 # facet tag of the blade's tip line
MAX_TWIST_PER_SECTION = math.radians(2.0)
EDGE_TOLERANCE = 1e-6     # chord fraction: far above the skin's error, far below any cell
CAMBER_POINTS = 41        # points of a NACA camber line's spline in the skin (cosine-spaced)
LEADING_EDGE_BUMP = 0.25  # gmsh "Bump": the chord's end cells this share of its middle ones (the NACA y_t ~ sqrt(s))


@dataclass(frozen=True)
class ShellSpec(SweptBlade):
    """Everything that shapes the mid-surface mesh: the blade's geometry (the shroud box's t_s the
    plate's thickness) and the cells, SI units (m, rad)."""

    size: float               # target element size, m
    contact_points: int = 11  # segments (their midpoints the contact points) per contact edge

    @classmethod
    def from_params(cls, params: Parameters) -> "ShellSpec":
        return cls(**SweptBlade.geometry(params, profile=True), size=params.shell.mesh_size,
                   contact_points=params.shell.contact_points)

    @classmethod
    def strip(cls, length: float, width: float, thickness: float, twist: float, size: float,
              stagger: float = 0.0) -> "ShellSpec":
        """A bare twisted strip clamped at X = 0 (benchmarks: MacNeal-Harder's beam, NAFEMS FV16's plate)."""
        return cls(disk_radius=0.0, length=length, width=width, thickness=thickness, stagger=stagger,
                   twist=twist, shroud_length=0.0, shroud_width=0.0, shroud_thickness=0.0, alpha=0.0,
                   size=size)

    @property
    def area(self) -> float:
        """Mid-surface area of blade and shroud plate, m^2 (the helicoid's, to O(twist^2 b^2 / L^2))."""
        return (self.length * 0.5 * (self.width + self.tip_chord)
                + self.has_shroud * self.shroud_length * self.shroud_width)

    def centroid(self, x) -> np.ndarray:
        """(k, 2) area centroid (s_C, y_C) in chord units of the sections at x m from the root (k values):
        the point on the X axis, computed on the solid loft's polygon (meshes.blade.SPLINE_POINTS)."""
        x = np.atleast_1d(np.asarray(x, dtype=float))
        if self.section != "naca4":
            return np.tile([0.5, 0.0], (x.size, 1))
        stations, where = np.unique(np.round(x, 12), return_inverse=True)
        chord, thickness = chord_and_thickness(self, stations)
        return np.array([naca4_centroid(self.naca_m, self.naca_p, tau, SPLINE_POINTS)
                         for tau in thickness / chord])[where.ravel()]

    def camber(self, x, s) -> tuple[np.ndarray, np.ndarray]:
        """(eta_v, eta_w), m, of the mid-surface's points at x m from the root and chord fractions s (arrays
        alike), in the section frame about the centroid."""
        chord, _ = chord_and_thickness(self, np.asarray(x, dtype=float))
        centre = self.centroid(x).reshape(np.shape(s) + (2,))
        y_c = naca4_camber(self.naca_m, self.naca_p, s)[0] if self.section == "naca4" else np.zeros_like(s)
        return chord * (y_c - centre[..., 1]), chord * (s - centre[..., 0])

    def chord_fraction(self, x, eta_w) -> np.ndarray:
        """s of the mid-surface's point at x m from the root whose coordinate along e_w(x) is eta_w (m)."""
        chord, _ = chord_and_thickness(self, np.asarray(x, dtype=float))
        return eta_w / chord + self.centroid(x).reshape(np.shape(eta_w) + (2,))[..., 0]

    def mid_thickness(self, x, s):
        """Shell thickness, m, at x m from the root and chord fraction s (numpy or UFL): t(x) on the
        rectangle, the NACA profile's 2 c(x) y_t(s) (normal to the camber line) on the airfoil."""
        chord, thickness = chord_and_thickness(self, x)
        if self.section == "naca4":
            return 2 * chord * naca4_half_thickness(thickness / chord, s)
        return thickness + 0 * s


# Measured here: Frontal-Delaunay triangles at size h cover the area with about 2.3 / h^2 cells
# (default blade, h = 2-8 mm); P2 displacements (3 per node, ~2 nodes per cell) and CR rotations
# (3 per edge, ~1.5 edges per cell) make about 10.5 DOF per cell. A 2D direct factor grows about as
# DOF^1.3; 1 GB held 60 000 DOF (the measured bound used to refuse a mesh).
CELLS_PER_SQUARE = 2.3
DOFS_PER_CELL = 10.5
REFERENCE_DOFS, REFERENCE_BYTES = 60_000, 1.0e9


def estimated_dofs(spec: ShellSpec) -> float:
    return DOFS_PER_CELL * CELLS_PER_SQUARE * spec.area / spec.size**2


def check_geometry(spec: ShellSpec, memory: float | None = None) -> None:
    """Raise InputError for a mid-surface the shell model cannot stand for or this machine cannot hold."""
    if spec.thickness >= spec.width or spec.tip_thickness >= spec.tip_chord:
        raise InputError("blade.thickness", f"{spec.thickness!r} (tip {spec.tip_thickness:g}) is not below the "
                         f"chord {spec.width!r} (tip {spec.tip_chord:g}); allowed for the shell model: a thickness "
                         "below the chord (a plate, not a bar)")
    chord = min(spec.width, spec.tip_chord)
    if spec.size > 0.5 * chord:
        raise InputError("shell.mesh_size", f"{spec.size!r} leaves fewer than two cells across the chord "
                         f"{chord!r}; allowed: a size <= {0.5 * chord:g} m")
    if spec.section == "naca4" and not spec.has_shroud:
        raise InputError("shroud.thickness", "0 with blade.section = \"naca4\": the NACA shell reads its tip "
                         "outputs (the tip section's centroid, off the camber line) on the shroud plate; allowed: "
                         "a shroud (shroud.thickness > 0), or the rectangle for a bare shell")
    if spec.has_shroud and spec.size > 0.5 * spec.shroud_width:
        raise InputError("shell.mesh_size", f"{spec.size!r} leaves fewer than two cells across "
                         f"shroud.width {spec.shroud_width!r}; allowed: a size <= {0.5 * spec.shroud_width:g} m")
    memory = physical_memory() if memory is None else memory
    dofs = estimated_dofs(spec)
    need = REFERENCE_BYTES * (dofs / REFERENCE_DOFS) ** 1.3
    if need > memory:
        fits = spec.size * (need / memory) ** (1 / 2.6)
        raise InputError("shell.mesh_size", f"{spec.size!r} m would make about {dofs:.2g} DOF, needing about "
                         f"{in_words(need)} to solve; this machine has {in_words(memory)}; allowed: a size "
                         f">= {fits:.3g} m here")


def on_mid_surface(points: np.ndarray, spec: ShellSpec) -> np.ndarray:
    """``points`` (k, 3) moved onto the mid-surface along e_v of their section plane X = const.

    s is the chord fraction of the point's coordinate along e_w(x) of its own
    section; a point within EDGE_TOLERANCE of a chord edge is put on it (the
    skin's edges stray from the exact ones by ~1e-8 m between its sections).
    A point already on the surface is returned unchanged.
    """
    x = points[:, 0] - spec.disk_radius
    beta = spec.beta(points[:, 0])
    e_v = np.stack([np.zeros_like(beta), np.cos(beta), np.sin(beta)], axis=1)
    e_w = np.stack([np.zeros_like(beta), -np.sin(beta), np.cos(beta)], axis=1)
    s = spec.chord_fraction(x, np.einsum("ij,ij->i", points, e_w))
    s = np.where(s < EDGE_TOLERANCE, 0.0, np.where(s > 1.0 - EDGE_TOLERANCE, 1.0, s))
    eta_v, eta_w = spec.camber(x, s)
    return np.column_stack([points[:, 0], np.zeros_like(x), np.zeros_like(x)]) + eta_v[:, None] * e_v \
        + eta_w[:, None] * e_w


def _chord_wire(occ, spec: ShellSpec, x: float) -> int:
    """The camber line at blade coordinate x: the rectangle's chord as two segments meeting at the axis
    (so the axis is a mesh line), the NACA camber line as one spline through CAMBER_POINTS."""
    e_v, e_w = section_frame(spec.beta(spec.disk_radius + x))
    centre = np.array([spec.disk_radius + x, 0.0, 0.0])
    naca = spec.section == "naca4"
    s = 0.5 * (1.0 - np.cos(np.linspace(0.0, np.pi, CAMBER_POINTS))) if naca else np.array([0.0, 0.5, 1.0])
    eta_v, eta_w = spec.camber(np.full_like(s, x), s)
    points = [occ.addPoint(*(centre + a * e_v + b * e_w)) for a, b in zip(eta_v, eta_w)]
    if naca:
        return occ.addWire([occ.addSpline(points)])
    return occ.addWire([occ.addLine(points[0], points[1]), occ.addLine(points[1], points[2])])


def _shroud_plate(occ, spec: ShellSpec) -> int:
    e_vs, e_ws = section_frame(spec.beta_tip + spec.alpha)
    centre = np.array([spec.tip_x, 0.0, 0.0])
    corners = [centre + a * 0.5 * spec.shroud_width * e_vs + c * 0.5 * spec.shroud_length * e_ws
               for a, c in ((-1, -1), (-1, 1), (1, 1), (1, -1))]
    points = [occ.addPoint(*p) for p in corners]
    lines = [occ.addLine(points[i], points[(i + 1) % 4]) for i in range(4)]
    return occ.addPlaneSurface([occ.addCurveLoop(lines)])


def _build_model(gmsh, spec: ShellSpec) -> None:
    occ = gmsh.model.occ
    n_sections = 2 + int(math.ceil(abs(spec.twist) / MAX_TWIST_PER_SECTION))
    wires = [_chord_wire(occ, spec, spec.length * i / (n_sections - 1)) for i in range(n_sections)]
    surfaces = occ.addThruSections(wires, makeSolid=False, makeRuled=spec.twist == 0.0)
    # The two halves of the skin come with their own copies of the axis line: fragmenting sews them
    # (and the shroud plate to the tip line) into one conforming surface.
    tools = [(2, _shroud_plate(occ, spec))] if spec.has_shroud else []
    if spec.section == "naca4":     # the tip points, off the camber line, are nodes of the plate
        tools += [(0, occ.addPoint(*p)) for p in tip_points(spec)]
    surfaces, _ = occ.fragment(surfaces, tools)
    occ.synchronize()
    model = gmsh.model
    tol = 1e-6 * spec.length
    blade, shroud = [], []
    for _, tag in model.getEntities(2):
        lo = model.getBoundingBox(2, tag)
        (shroud if lo[0] > spec.tip_x - tol else blade).append(tag)
    e_vs, _ = section_frame(spec.beta_tip + spec.alpha)
    groups = {ROOT: [], TIP: [], CONTACT_SIDE1: [], CONTACT_SIDE2: []}
    blade_edges = {abs(t) for _, t in model.getBoundary([(2, t) for t in blade], combined=False, oriented=False)}
    edges = blade_edges | {abs(t) for _, t in model.getBoundary([(2, t) for t in shroud], combined=False,
                                                                 oriented=False)}
    for _, tag in model.getEntities(1):
        lo = model.getBoundingBox(1, tag)
        if tag not in edges:     # a chord line of the skin's sections, not an edge of the surface
            continue
        if lo[3] < spec.disk_radius + tol:
            groups[ROOT].append(tag)
            continue
        if lo[0] < spec.tip_x - tol:
            continue
        if tag in blade_edges:
            groups[TIP].append(tag)       # (a half of) the blade's tip camber line
            continue
        ends = np.array([model.getValue(0, p, []) for _, p in model.getBoundary([(1, tag)])])
        v_s = ends @ e_vs
        if spec.has_shroud and np.allclose(v_s, -0.5 * spec.shroud_width, atol=tol):
            groups[CONTACT_SIDE1].append(tag)
        elif spec.has_shroud and np.allclose(v_s, 0.5 * spec.shroud_width, atol=tol):
            groups[CONTACT_SIDE2].append(tag)
    missing = [t for t, tags in groups.items() if not tags and (t in (ROOT, TIP) or spec.has_shroud)]
    if missing:
        raise RuntimeError(f"gmsh mid-surface lacks facet groups {missing}: {groups}")
    for tag in groups[CONTACT_SIDE1] + groups[CONTACT_SIDE2]:
        model.mesh.setTransfiniteCurve(tag, spec.contact_points + 1)
    _structured(model, spec, blade, tol)
    for tag, name in ((ROOT, "root"), (TIP, "tip"), (CONTACT_SIDE1, "contact_side1"),
                      (CONTACT_SIDE2, "contact_side2")):
        if groups[tag]:
            model.addPhysicalGroup(1, groups[tag], tag, name=name)
    model.addPhysicalGroup(2, blade, BLADE, name="blade")
    if shroud:
        model.addPhysicalGroup(2, shroud, SHROUD, name="shroud")
    return blade


def _structured(model, spec: ShellSpec, blade: list[int], tol: float) -> None:
    """Each half of the helicoid as a structured grid of triangles (alternating diagonals).

    Cells of one shape over the span and the chord: the torsion mode's
    boundary layer along the free chord edges (width h / sqrt(10)) is then
    resolved alike at every station, and its frequency converges smoothly
    with the size (with free triangles it wandered by +/- 0.5 % between
    sizes of 2 and 4 mm).
    """
    along_span = 1 + max(2, math.ceil(spec.length / spec.size))
    naca = spec.section == "naca4"      # one surface over the whole chord, not two halves
    along_chord = 1 + max(1, math.ceil((1.0 if naca else 0.5) * spec.width / spec.size))
    for surface in blade:
        for _, curve in model.getBoundary([(2, surface)], oriented=False):
            lo = model.getBoundingBox(1, abs(curve))
            if lo[3] - lo[0] > 0.01 * spec.length:      # along the span (OCC pads boxes by 1e-7 m)
                model.mesh.setTransfiniteCurve(abs(curve), along_span)
            elif naca:       # finer at both edges, where the thickness falls to 0
                model.mesh.setTransfiniteCurve(abs(curve), along_chord, "Bump", LEADING_EDGE_BUMP)
            else:
                model.mesh.setTransfiniteCurve(abs(curve), along_chord)
        model.mesh.setTransfiniteSurface(surface, "Alternate")


def write_mesh(spec: ShellSpec, path: Path) -> None:
    """Mesh the mid-surface with flat triangles, put the blade's nodes on the exact surface, write ``path``."""
    import gmsh
    gmsh.initialize(interruptible=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add("blade_mid_surface")
        blade = _build_model(gmsh, spec)
        gmsh.option.setNumber("Mesh.MeshSizeMax", spec.size)
        gmsh.option.setNumber("Mesh.MeshSizeMin", 0.0)
        gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 0)
        gmsh.option.setNumber("Mesh.Algorithm", 6)        # Frontal-Delaunay
        gmsh.model.mesh.generate(2)
        for tag in blade:
            nodes, coords, _ = gmsh.model.mesh.getNodes(2, tag, includeBoundary=True)
            moved = on_mid_surface(coords.reshape(-1, 3), spec)
            for node, xyz in zip(nodes, moved):
                gmsh.model.mesh.setNode(int(node), list(xyz), [])
        gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
        gmsh.write(str(path))
    finally:
        gmsh.finalize()


def mesh_file(spec: ShellSpec) -> Path:
    """Path of the cached .msh of ``spec`` (built on this process if missing; call on one rank)."""
    check_geometry(spec)
    inputs = {k: round(v, 12) if isinstance(v, float) else v for k, v in dataclasses.asdict(spec).items()}
    return cached("shell_mesh", inputs, ".msh", lambda tmp: write_mesh(spec, tmp), what="shell mesh",
                  sources=(__name__, "meshes.spec", "reduced_model.airfoil"), check=check_msh_complete)
