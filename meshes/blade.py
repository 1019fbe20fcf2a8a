"""Parametric gmsh solid of the linearly twisted, shrouded blade.

The blade is the rectangle b (chord, along e_w) x h (thickness, along e_v)
swept from X = R_d to X = R_d + L while turning about +X by
beta(x) = beta_1 + beta_t x / L (shared/spec/geometry.md; paper Fig. 5 and
Eq. 13 for the section corners). The shroud is a box l_s (along e_ws) x b_s
(along e_vs) x t_s (along X) on the tip, turned by beta_L + alpha about X
(paper Eq. 7 frame). Blade and shroud are two volumes sharing their
interface (conforming mesh, one connected body).

Physical groups (tags below): the clamped root face X = R_d, the two shroud
contact faces (side 1 at v_s = -b_s/2, side 2 at v_s = +b_s/2), the blade
and the shroud volumes. Meshes are tetrahedra of gmsh order ``fe.order``
(``fe.cell = "tet"``, built here) or swept hexahedra (``"hex"``,
meshes.hexa) with the same tags, and are cached on disk by a hash of exactly the inputs that
shape them (:func:`mesh_file`).

Example
-------
>>> from shroud.params import Parameters
>>> spec = MeshSpec.from_params(Parameters())
>>> round(spec.elements_through_thickness, 2)
1.17
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from shroud.base.cache import cached
from shroud.base.errors import InputError
from shroud.params import Parameters

# Physical group tags (facets dim 2, cells dim 3).
ROOT = 1
CONTACT_SIDE1 = 2      # shroud face at v_s = -b_s/2 (outward normal -e_vs)
CONTACT_SIDE2 = 3      # shroud face at v_s = +b_s/2 (outward normal +e_vs)
BLADE = 1
SHROUD = 2

# Edge fibres of a twisted blade run along a helix of angle atan(b/2 * beta_t / L).
# Beyond this the sections overlap each other along X within one chord: the
# "blade" has folded into a screw, which neither model describes.
MAX_HELIX_DEG = 45.0
MIN_ELEMENTS_THROUGH_THICKNESS = 2.0
# Bump when the construction below changes what a given MeshSpec produces.
BUILDER_VERSION = 1


@dataclass(frozen=True)
class MeshSpec:
    """Everything that shapes the mesh, SI units (m, rad)."""

    disk_radius: float
    length: float
    width: float
    thickness: float
    stagger: float            # beta_1, rad
    twist: float              # beta_t, rad
    shroud_length: float      # l_s (along e_ws)
    shroud_width: float       # b_s (along e_vs)
    shroud_thickness: float   # t_s (along X); 0 = no shroud
    alpha: float              # shroud inclination, rad
    size: float               # target element size, m
    order: int                # gmsh element order (geometry), 1 or 2
    cell: str = "tet"         # "tet" (free tetrahedra) or "hex" (swept hexahedra, meshes.hexa)
    span_ratio: float = 1.0   # hex: cell length along the span / size

    @classmethod
    def from_params(cls, params: Parameters) -> "MeshSpec":
        b, s, fe = params.blade, params.shroud, params.fe
        return cls(disk_radius=b.disk_radius, length=b.length, width=b.width,
                   thickness=b.thickness, stagger=math.radians(b.stagger_deg),
                   twist=math.radians(b.twist_deg), shroud_length=s.length,
                   shroud_width=s.width, shroud_thickness=s.thickness,
                   alpha=math.radians(params.contact.alpha_deg), size=fe.mesh_size,
                   order=fe.order, cell=fe.cell,
                   span_ratio=fe.hex_span_ratio if fe.cell == "hex" else 1.0)

    @property
    def has_shroud(self) -> bool:
        return self.shroud_thickness > 0

    @property
    def beta_tip(self) -> float:
        return self.stagger + self.twist

    @property
    def tip_x(self) -> float:
        """X of the blade tip section (blade/shroud interface), m."""
        return self.disk_radius + self.length

    @property
    def elements_through_thickness(self) -> float:
        return self.thickness / self.size

    @property
    def helix_deg(self) -> float:
        """Helix angle of the chord-edge fibres, deg."""
        return math.degrees(math.atan(0.5 * self.width * abs(self.twist) / self.length))


def section_frame(beta: float) -> tuple[np.ndarray, np.ndarray]:
    """e_v, e_w of a section turned by ``beta`` about +X (geometry.md)."""
    c, s = math.cos(beta), math.sin(beta)
    return np.array([0.0, c, s]), np.array([0.0, -s, c])


def shroud_frame(spec: MeshSpec) -> tuple[np.ndarray, np.ndarray]:
    """e_vs (contact normal), e_ws (friction direction): the tip frame turned by alpha (Eq. 7)."""
    return section_frame(spec.beta_tip + spec.alpha)


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
        from meshes.hexa import check_hex_geometry
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


def tip_points(spec: MeshSpec) -> np.ndarray:
    """(3, 3) points of the tip section x = L: its centre, then centre -/+ (b/4) e_w(L).

    They are mesh nodes (embedded in the tip face), so the tip kinematics
    v_L, w_L (centre) and the twist (from the two chord points) are nodal
    values: exact, and the same on any number of MPI ranks.
    """
    _, e_w = section_frame(spec.beta_tip)
    centre = np.array([spec.tip_x, 0.0, 0.0])
    return np.array([centre, centre - 0.25 * spec.width * e_w, centre + 0.25 * spec.width * e_w])


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
        from meshes.hexa import BUILDER_VERSION as HEX_BUILDER, write_hex_mesh as write
        inputs["builder"] = f"hex{HEX_BUILDER}"
    else:
        write = write_mesh
    return cached("mesh", inputs, ".msh", lambda tmp: write(spec, tmp), what="blade mesh")
