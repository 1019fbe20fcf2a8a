"""Parametric gmsh solid of the linearly twisted, shrouded blade.

The blade is the rectangle b (chord, along e_w) x h (thickness, along e_v)
swept from X = R_d to X = R_d + L while turning about +X by
beta(x) = beta_1 + beta_t x / L (shared/spec/geometry.md; paper Fig. 5 and
Eq. 13 for the section corners). The shroud is a box l_s (along e_ws) x b_s
(along e_vs) x t_s (along X) on the tip, turned by beta_L + alpha about X
(paper Eq. 7 frame). Blade and shroud are two volumes sharing their
interface (conforming mesh, one connected body).

Physical groups (tags in meshes.spec): the clamped root face X = R_d, the two shroud
contact faces (side 1 at v_s = -b_s/2, side 2 at v_s = +b_s/2), the blade
and the shroud volumes. Meshes are tetrahedra of gmsh order ``fe.order``
(``fe.cell = "tet"``, built here) or swept hexahedra (``"hex"``,
meshes.hexa) with the same tags, and are cached on disk by a hash of
exactly the inputs that shape them (:func:`mesh_file`).
"""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np

from meshes.hexa import BUILDER_VERSION as HEX_BUILDER, check_hex_geometry, write_hex_mesh
from meshes.spec import (BLADE, CONTACT_SIDE1, CONTACT_SIDE2, ROOT, SHROUD, MeshSpec,  # noqa: F401
                         section_frame, shroud_frame, tip_points)
from shroud.base.cache import cached
from shroud.base.errors import InputError

# Edge fibres of a twisted blade run along a helix of angle atan(b/2 * beta_t / L).
# Beyond this the sections overlap each other along X within one chord: the
# "blade" has folded into a screw, which neither model describes.
MAX_HELIX_DEG = 45.0
MIN_ELEMENTS_THROUGH_THICKNESS = 2.0
# Bump when the construction below changes what a given MeshSpec produces.
BUILDER_VERSION = 1


def check_geometry(spec: MeshSpec) -> None:
    """Raise InputError for a solid that cannot be meshed as intended (before gmsh runs)."""
    if spec.has_shroud and spec.shroud_width < spec.thickness:
        raise InputError("shroud.width", f"{spec.shroud_width!r} is narrower than blade.thickness "
                         f"{spec.thickness!r}; allowed: a shroud at least as wide as the blade is thick")
    if spec.helix_deg > MAX_HELIX_DEG:
        raise InputError("blade.twist_deg", f"{math.degrees(spec.twist):g} folds the blade: its chord edges "
                         f"wind at {spec.helix_deg:.0f} deg; allowed: atan(b/2 * twist / L) <= "
                         f"{MAX_HELIX_DEG:g} deg")
    if spec.cell == "hex":
        check_hex_geometry(spec)
        return
    if spec.elements_through_thickness < MIN_ELEMENTS_THROUGH_THICKNESS:
        raise InputError("fe.mesh_size", f"{spec.size!r} leaves {spec.elements_through_thickness:.2f} "
                         f"elements through blade.thickness {spec.thickness!r}; allowed: a size <= "
                         f"{spec.thickness / MIN_ELEMENTS_THROUGH_THICKNESS:g} m")
    if spec.has_shroud and spec.shroud_thickness / spec.size < MIN_ELEMENTS_THROUGH_THICKNESS:
        raise InputError("fe.mesh_size", f"{spec.size!r} leaves fewer than two elements through "
                         f"shroud.thickness {spec.shroud_thickness!r}; allowed: a size <= "
                         f"{spec.shroud_thickness / MIN_ELEMENTS_THROUGH_THICKNESS:g} m")


def _section_wire(occ, spec: MeshSpec, x: float) -> int:
    """Closed wire of the blade section at blade coordinate x (corners A, B, C, D of Eq. 13)."""
    e_v, e_w = section_frame(spec.stagger + spec.twist * x / spec.length)
    centre = np.array([spec.disk_radius + x, 0.0, 0.0])
    corners = [centre + sv * 0.5 * spec.thickness * e_v + sw * 0.5 * spec.width * e_w
               for sv, sw in ((1, 1), (-1, 1), (-1, -1), (1, -1))]
    points = [occ.addPoint(*p) for p in corners]
    lines = [occ.addLine(points[i], points[(i + 1) % 4]) for i in range(4)]
    return occ.addWire(lines)


def _build_model(gmsh, spec: MeshSpec) -> None:
    """The OCC solid and its physical groups in the current gmsh model."""
    occ = gmsh.model.occ
    # A twisted face is a helicoid; sections every <= 2 deg make the B-spline
    # skin match it to well below the mesh size.
    n_sections = 2 + int(math.ceil(abs(math.degrees(spec.twist)) / 2.0))
    wires = [_section_wire(occ, spec, spec.length * i / (n_sections - 1)) for i in range(n_sections)]
    blade = occ.addThruSections(wires, makeSolid=True, makeRuled=abs(spec.twist) == 0.0)
    volumes = blade
    if spec.has_shroud:
        box = occ.addBox(spec.tip_x, -0.5 * spec.shroud_width, -0.5 * spec.shroud_length,
                         spec.shroud_thickness, spec.shroud_width, spec.shroud_length)
        occ.rotate([(3, box)], 0, 0, 0, 1, 0, 0, spec.beta_tip + spec.alpha)
        volumes, _ = occ.fragment(blade, [(3, box)])
    occ.synchronize()

    model = gmsh.model
    tol = 1e-3 * spec.thickness     # far above OCC bounding-box padding, far below any feature
    blade_vols, shroud_vols = [], []
    for dim, tag in volumes:
        x = model.occ.getCenterOfMass(dim, tag)[0]
        (shroud_vols if x > spec.tip_x else blade_vols).append(tag)
    root, side1, side2 = [], [], []
    e_vs, _ = shroud_frame(spec)
    for _, tag in model.getEntities(2):
        lo = model.getBoundingBox(2, tag)
        if lo[3] < spec.disk_radius + tol:
            root.append(tag)
            continue
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
    if not root or (spec.has_shroud and not (side1 and side2)):
        raise RuntimeError(f"gmsh model lacks a root or contact face (root {root}, sides {side1}, {side2})")
    model.addPhysicalGroup(2, root, ROOT, name="root")
    if spec.has_shroud:
        model.addPhysicalGroup(2, side1, CONTACT_SIDE1, name="contact_side1")
        model.addPhysicalGroup(2, side2, CONTACT_SIDE2, name="contact_side2")
        model.addPhysicalGroup(3, shroud_vols, SHROUD, name="shroud")
    model.addPhysicalGroup(3, blade_vols, BLADE, name="blade")
    _embed_tip_points(model, spec)


def _embed_tip_points(model, spec: MeshSpec) -> None:
    tol = 1e-3 * spec.thickness     # far above OCC bounding-box padding, far below any feature
    faces = [tag for _, tag in model.getEntities(2)
             if abs(model.getBoundingBox(2, tag)[0] - spec.tip_x) < tol
             and abs(model.getBoundingBox(2, tag)[3] - spec.tip_x) < tol]
    for point in tip_points(spec):
        host = [tag for tag in faces if model.isInside(2, tag, list(point))]
        if not host:
            raise RuntimeError(f"no tip face holds the tip point {point}")
        tag = model.occ.addPoint(*point)
        model.occ.synchronize()
        model.mesh.embed(0, [tag], 2, host[0])


def write_mesh(spec: MeshSpec, path: Path) -> None:
    """Build the solid, mesh it with tetrahedra of order ``spec.order`` and write ``path`` (.msh)."""
    import gmsh
    check_geometry(spec)
    gmsh.initialize(interruptible=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add("shrouded_blade")
        _build_model(gmsh, spec)
        gmsh.option.setNumber("Mesh.MeshSizeMax", spec.size)
        gmsh.option.setNumber("Mesh.MeshSizeMin", 0.0)
        gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 0)
        gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", 1)
        gmsh.option.setNumber("Mesh.Algorithm", 6)        # Frontal-Delaunay surfaces
        gmsh.option.setNumber("Mesh.Algorithm3D", 1)      # Delaunay volumes
        gmsh.option.setNumber("Mesh.Optimize", 1)
        gmsh.model.mesh.generate(3)
        gmsh.model.mesh.setOrder(spec.order)
        gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
        gmsh.write(str(path))
    finally:
        gmsh.finalize()


def mesh_file(spec: MeshSpec) -> Path:
    """Path of the cached .msh for ``spec``; built (on this process) if missing.

    Call it on one MPI rank only; the others need no file (dolfinx reads on one rank).
    """
    check_geometry(spec)
    inputs = {k: round(v, 12) if isinstance(v, float) else v for k, v in dataclasses.asdict(spec).items()}
    inputs["builder"] = BUILDER_VERSION
    if spec.cell == "hex":
        write = write_hex_mesh
        inputs["builder"] = f"hex{HEX_BUILDER}"
    else:
        write = write_mesh
    return cached("mesh", inputs, ".msh", lambda tmp: write(spec, tmp), what="blade mesh")
