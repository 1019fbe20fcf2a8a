"""Parametric gmsh solid of the linearly twisted, shrouded blade.

The blade is the rectangle b (chord, along e_w) x h (thickness, along e_v)
swept from X = R_d to X = R_d + L while turning about +X by
beta(x) = beta_1 + beta_t x / L (docs/geometry.md; paper Fig. 5 and
Eq. 13 for the section corners). The shroud is a box l_s (along e_ws) x b_s
(along e_vs) x t_s (along X) on the tip, turned by beta_L + alpha about X
(paper Eq. 7 frame). Blade and shroud are two volumes sharing their
interface (conforming mesh, one connected body).

Physical groups (tags in meshes.spec): the clamped root face X = R_d, the two shroud
contact faces (side 1 at v_s = -b_s/2, side 2 at v_s = +b_s/2), the blade
and the shroud volumes. Meshes are tetrahedra of gmsh order ``fe.order``
(``fe.cell = "tet"``, built here) or swept hexahedra (``"hex"``,
meshes.hexa) with the same tags, and are cached on disk by a hash of
exactly the inputs that shape them and of the code that builds them
(:func:`mesh_file`).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from meshes.hexa import check_hex_geometry, write_hex_mesh
from meshes.spec import (BLADE, CONTACT_SIDE1, CONTACT_SIDE2, ROOT, SHROUD, MeshSpec,  # noqa: F401
                         embed_tip_points, section_frame, shroud_frame, tip_points)
from meshes.step import build_from_step
from shroud.base.cache import cached
from shroud.base.errors import InputError
from shroud.base.resources import in_words, physical_memory

# Edge fibres of a twisted blade run along a helix of angle atan(b/2 * beta_t / L).
# Beyond this the sections overlap each other along X within one chord: the
# "blade" has folded into a screw, which neither model describes.
MAX_HELIX_DEG = 45.0
MIN_ELEMENTS_THROUGH_THICKNESS = 2.0


def check_geometry(spec: MeshSpec) -> None:
    """Raise InputError for a solid that cannot be meshed as intended, or held (before gmsh runs).

    A STEP file's solid is checked when it is read (meshes.step).
    """
    if spec.cell == "hex" and not (spec.is_rectangle or spec.section == "naca4" and not spec.step):
        key = "blade.step" if spec.step else "blade.chord_taper"
        raise InputError("fe.cell", f'"hex" sweeps the untapered rectangle and the airfoil only, not this blade '
                         f'({key}); allowed: "tet" (P2 tetrahedra on the tapered rectangle or the STEP solid)')
    if spec.step:
        return
    if spec.has_shroud and spec.shroud_width < spec.thickness:
        raise InputError("shroud.width", f"{spec.shroud_width!r} is narrower than blade.thickness "
                         f"{spec.thickness!r}; allowed: a shroud at least as wide as the blade is thick")
    if spec.helix_deg > MAX_HELIX_DEG:
        raise InputError("blade.twist_deg", f"{math.degrees(spec.twist):g} folds the blade: its chord edges "
                         f"wind at {spec.helix_deg:.0f} deg; allowed: atan(b/2 * twist / L) <= "
                         f"{MAX_HELIX_DEG:g} deg")
    check_mesh_size(spec)
    if spec.cell == "hex":
        check_hex_geometry(spec)
        return
    if spec.elements_through_thickness < MIN_ELEMENTS_THROUGH_THICKNESS:
        thinnest = min(spec.thickness, spec.tip_thickness)
        raise InputError("fe.mesh_size", f"{spec.size!r} leaves {spec.elements_through_thickness:.2f} "
                         f"elements through the blade's thickness {thinnest!r}; allowed: a size <= "
                         f"{thinnest / MIN_ELEMENTS_THROUGH_THICKNESS:g} m")
    if spec.has_shroud and spec.shroud_thickness / spec.size < MIN_ELEMENTS_THROUGH_THICKNESS:
        raise InputError("fe.mesh_size", f"{spec.size!r} leaves fewer than two elements through "
                         f"shroud.thickness {spec.shroud_thickness!r}; allowed: a size <= "
                         f"{spec.shroud_thickness / MIN_ELEMENTS_THROUGH_THICKNESS:g} m")


# What a mesh of size h costs, measured here on this blade. Tetrahedra (gmsh Frontal-Delaunay/
# Delaunay as in write_mesh): 6807 / 25 518 / 71 413 at h = 3.5 / 2.2 / 1.5 mm, i.e. 6.1 / 5.7 / 5.1
# per h^3 of volume; 1.83 / 1.67 / 1.57 nodes per tetrahedron at order 2, 0.30 / 0.25 at order 1.
# Swept hexahedra (meshes.hexa): 882 / 4872 at h = 5 / 2.5 mm, 2.3 / 1.6 per h^3 (the layers
# through the thickness do not grow as h^-1); 10.9 / 9.5 nodes per 27-node hexahedron, of which about
# an eighth are vertices (the nodes of a linear hexahedral mesh).
# The estimate takes the fine-mesh values, where refusing matters (it undercounts coarse meshes).
CELLS_PER_CUBE = {"tet": 5.1, "hex": 1.6}
NODES_PER_CELL = {("tet", 1): 0.25, ("tet", 2): 1.57, ("hex", 1): 1.2, ("hex", 2): 9.5}
# The full solid's transient on one process (operators, MUMPS factor of the step operator, contact
# columns) held 1.44 GB at 37 419 DOF; a 3D direct factor fills as DOF^(4/3).
REFERENCE_DOFS, REFERENCE_BYTES = 37_419, 1.44e9


@dataclass(frozen=True)
class MeshEstimate:
    """What meshing and solving a solid of ``volume`` (m^3) at element size ``size`` (m) needs."""

    volume: float
    size: float
    cells: float
    dofs: float        # 3 displacement components per node
    bytes: float       # memory of the solid's transient run on one process

    def size_for(self, memory: float) -> float:
        """The smallest element size (m) whose estimate fits in ``memory`` bytes (bytes ~ size^-4)."""
        return self.size * (self.bytes / memory) ** 0.25


def estimate_mesh(volume: float, size: float, order: int, cell: str = "tet") -> MeshEstimate:
    """Cells, DOF and memory of a mesh of ``cell`` kind before it is made.

    >>> e = estimate_mesh(4.76e-5, 0.0035, 2)        # the P2-tet 3.5 mm blade (measured: 6807 cells, 37 419 DOF)
    >>> round(e.cells), round(e.dofs), round(e.bytes / 1e9, 2)
    (5662, 26668, 0.92)
    """
    cells = CELLS_PER_CUBE[cell] * volume / size**3
    dofs = 3.0 * NODES_PER_CELL[(cell, order)] * cells
    return MeshEstimate(volume=volume, size=size, cells=cells, dofs=dofs,
                        bytes=REFERENCE_BYTES * (dofs / REFERENCE_DOFS) ** (4.0 / 3.0))


def solid_volume(spec: MeshSpec) -> float:
    """Volume of blade and shroud, m^3 (A(x) is quadratic in x: Simpson's rule is exact)."""
    blade = spec.length * (spec.section_area(0.0) + 4.0 * spec.section_area(0.5 * spec.length)
                           + spec.section_area(spec.length)) / 6.0
    return blade + spec.shroud_length * spec.shroud_width * spec.shroud_thickness * spec.has_shroud


def check_mesh_size(spec: MeshSpec, memory: float | None = None, volume: float | None = None) -> MeshEstimate:
    """Refuse (InputError on fe.mesh_size) a mesh whose solve this machine cannot hold; else its estimate.

    ``volume``: the solid's, m^3, where not the blade.* keys' (a STEP file's).
    """
    memory = physical_memory() if memory is None else memory
    volume = solid_volume(spec) if volume is None else volume
    estimate = estimate_mesh(volume, spec.size, spec.order, spec.cell)
    if estimate.bytes > memory:
        raise InputError("fe.mesh_size", f"{spec.size!r} m would make about {estimate.cells:.2g} cells and "
                         f"{estimate.dofs:.2g} DOF, needing about {in_words(estimate.bytes)} to solve; this "
                         f"machine has {in_words(memory)}; allowed: a size >= {estimate.size_for(memory):.3g} m here")
    return estimate


# Points per surface of the NACA profile through which the B-spline section runs (cosine-spaced):
# the section's area within 5e-5 of the profile's (41 points: 3e-6, for twice gmsh's time to mesh it).
SPLINE_POINTS = 21


def _section_wire(occ, spec: MeshSpec, x: float) -> tuple[int, list[int]]:
    """Closed wire of the blade section at blade coordinate x: the rectangle's corners A, B, C, D of
    Eq. 13 joined by lines, or the NACA profile's suction and pressure sides as two B-splines through
    its points (trailing edge to leading edge and back), centroid on the X axis. The wire's tag and
    its curves' tags."""
    e_v, e_w = section_frame(spec.stagger + spec.twist * x / spec.length)
    centre = np.array([spec.disk_radius + x, 0.0, 0.0])
    outline = spec.profile(x, SPLINE_POINTS)
    points = [occ.addPoint(*(centre + eta_v * e_v + eta_w * e_w)) for eta_v, eta_w in outline]
    if spec.section != "naca4":
        curves = [occ.addLine(points[i], points[(i + 1) % 4]) for i in range(4)]
    else:
        leading = SPLINE_POINTS - 1        # the outline runs trailing edge -> upper -> leading edge -> lower
        curves = [occ.addSpline(points[:leading + 1]), occ.addSpline(points[leading:] + points[:1])]
    return occ.addWire(curves), curves


def build_solid(occ, spec: MeshSpec) -> list[tuple[int, int]]:
    """The blade's loft and the shroud box on its tip in gmsh's OCC kernel ``occ``: their (3, tag)
    volumes, sharing their interface (not yet synchronized)."""
    # A twisted face is a helicoid; sections every <= 2 deg make the B-spline
    # skin match it to well below the mesh size. The profile's coordinates are linear in c(x) and
    # t(x), so a taper alone is ruled.
    n_sections = 2 + int(math.ceil(abs(math.degrees(spec.twist)) / 2.0))
    sections = [_section_wire(occ, spec, spec.length * i / (n_sections - 1)) for i in range(n_sections)]
    blade = occ.addThruSections([wire for wire, _ in sections], makeSolid=True, makeRuled=abs(spec.twist) == 0.0)
    # The sections' curves stay behind as free entities: remove them, so that neither the mesh nor a
    # STEP file of the solid holds them.
    occ.remove([(1, curve) for _, curves in sections for curve in curves], recursive=True)
    volumes = blade
    if spec.has_shroud:
        box = occ.addBox(spec.tip_x, -0.5 * spec.shroud_width, -0.5 * spec.shroud_length,
                         spec.shroud_thickness, spec.shroud_width, spec.shroud_length)
        occ.rotate([(3, box)], 0, 0, 0, 1, 0, 0, spec.beta_tip + spec.alpha)
        volumes, _ = occ.fragment(blade, [(3, box)])
    return volumes


def contact_faces(model, spec: MeshSpec, faces) -> tuple[list[int], list[int]]:
    """The shroud's contact faces among ``faces`` (surface tags): side 1 (v_s = -b_s/2), side 2 (+b_s/2)."""
    tol = 1e-3 * spec.thickness     # far above OCC bounding-box padding, far below any feature
    side1, side2 = [], []
    e_vs, _ = shroud_frame(spec)
    for tag in faces:
        lo = model.getBoundingBox(2, tag)
        if not spec.has_shroud or lo[0] < spec.tip_x - tol:
            continue
        centre = np.array(model.occ.getCenterOfMass(2, tag))
        lo_uv, hi_uv = model.getParametrizationBounds(2, tag)
        normal = np.array(model.getNormal(tag, 0.5 * (np.asarray(lo_uv) + np.asarray(hi_uv))))
        if abs(abs(normal @ e_vs) - 1.0) > 1e-6:
            continue
        v_s = centre @ e_vs
        if abs(v_s + 0.5 * spec.shroud_width) < tol:
            side1.append(tag)
        elif abs(v_s - 0.5 * spec.shroud_width) < tol:
            side2.append(tag)
    return side1, side2


def _build_model(gmsh, spec: MeshSpec) -> None:
    """The OCC solid and its physical groups in the current gmsh model."""
    volumes = build_solid(gmsh.model.occ, spec)
    gmsh.model.occ.synchronize()
    model = gmsh.model
    tol = 1e-3 * spec.thickness     # far above OCC bounding-box padding, far below any feature
    blade_vols, shroud_vols = [], []
    for dim, tag in volumes:
        x = model.occ.getCenterOfMass(dim, tag)[0]
        (shroud_vols if x > spec.tip_x else blade_vols).append(tag)
    faces = [tag for _, tag in model.getEntities(2)]
    root = [tag for tag in faces if model.getBoundingBox(2, tag)[3] < spec.disk_radius + tol]
    side1, side2 = contact_faces(model, spec, faces)
    if not root or (spec.has_shroud and not (side1 and side2)):
        raise RuntimeError(f"gmsh model lacks a root or contact face (root {root}, sides {side1}, {side2})")
    model.addPhysicalGroup(2, root, ROOT, name="root")
    if spec.has_shroud:
        model.addPhysicalGroup(2, side1, CONTACT_SIDE1, name="contact_side1")
        model.addPhysicalGroup(2, side2, CONTACT_SIDE2, name="contact_side2")
        model.addPhysicalGroup(3, shroud_vols, SHROUD, name="shroud")
    model.addPhysicalGroup(3, blade_vols, BLADE, name="blade")
    embed_tip_points(model, spec)


def write_mesh(spec: MeshSpec, path: Path) -> None:
    """Build the solid, mesh it with tetrahedra of order ``spec.order`` and write ``path`` (.msh)."""
    import gmsh
    check_geometry(spec)
    gmsh.initialize(interruptible=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add("shrouded_blade")
        if spec.step:
            check_mesh_size(spec, volume=build_from_step(gmsh, spec))
        else:
            _build_model(gmsh, spec)
        write_tetrahedra(gmsh, spec.size, spec.order, path)
    finally:
        gmsh.finalize()


def write_tetrahedra(gmsh, size: float, order: int, path: Path, untangle: bool = False) -> None:
    """Mesh the current gmsh model with tetrahedra of at most ``size`` (m), of polynomial order ``order``,
    and write ``path`` (.msh 4.1): the blade's and the disk sector's meshes alike. ``untangle``: gmsh's
    high-order optimizer moves the edge nodes of curved cells whose Jacobian changes sign (the disk
    sector's slivers between the plane root and the curved rim)."""
    gmsh.option.setNumber("Mesh.MeshSizeMax", size)
    gmsh.option.setNumber("Mesh.MeshSizeMin", 0.0)
    gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 0)
    gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", 1)
    gmsh.option.setNumber("Mesh.Algorithm", 6)        # Frontal-Delaunay surfaces
    gmsh.option.setNumber("Mesh.Algorithm3D", 1)      # Delaunay volumes
    gmsh.option.setNumber("Mesh.Optimize", 1)
    gmsh.model.mesh.generate(3)
    gmsh.model.mesh.setOrder(order)
    if untangle and order > 1:
        gmsh.model.mesh.optimize("HighOrder")
    gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
    gmsh.write(str(path))


def write_step(spec: MeshSpec, path) -> None:
    """Write the blade.* keys' blade and shroud (:func:`build_solid`) to the STEP file ``path``, lengths
    in millimetres as the file declares them (what a CAD system writes; meshes.step reads it back)."""
    import gmsh
    gmsh.initialize(interruptible=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.option.setString("Geometry.OCCTargetUnit", "M")    # the model's metres, written as millimetres
        gmsh.model.add("blade_to_step")
        build_solid(gmsh.model.occ, spec)
        gmsh.model.occ.synchronize()
        gmsh.write(str(path))
    finally:
        gmsh.finalize()


def mesh_file(spec: MeshSpec) -> Path:
    """Path of the cached .msh for ``spec``; built (on this process) if missing.

    Call it on one MPI rank only; the others need no file (dolfinx reads on one rank).
    """
    check_geometry(spec)
    inputs = {k: round(v, 12) if isinstance(v, float) else v for k, v in dataclasses.asdict(spec).items()}
    write, sources = (write_hex_mesh, (__name__, "meshes.hexa", "meshes.spec", "reduced_model.airfoil")) \
        if spec.cell == "hex" else \
        (write_mesh, (__name__, "meshes.spec", "meshes.step", "reduced_model.airfoil", "reduced_model.step_slices"))
    return cached("mesh", inputs, ".msh", lambda tmp: write(spec, tmp), what="blade mesh",
                  sources=sources, check=check_msh_complete)


def check_msh_complete(path: Path) -> None:
    """Raise ValueError unless ``path`` ends as a finished gmsh file ends: its $Elements section closed, or
    its $Periodic section, which gmsh writes last where side faces are meshed alike (the disk sector)."""
    with open(path, "rb") as fh:
        fh.seek(max(0, path.stat().st_size - 64))
        tail = fh.read().rstrip()
    if not (tail.endswith(b"$EndElements") or tail.endswith(b"$EndPeriodic")):
        raise ValueError("the file stops before $EndElements or $EndPeriodic: cut short")
