"""What shapes the solid mesh (MeshSpec), its physical tags and the frames and tip points on it.

Shared by both mesh builders (meshes.blade: tetrahedra; meshes.hexa:
swept hexahedra) and by the solid (reference_fe). The swept blade's
geometry (SweptBlade) is the solid's and the shell's (meshes.shell.ShellSpec)
alike. SI units (m, rad); frames as in docs/geometry.md.

Example
-------
>>> from shroud.params import Parameters
>>> spec = MeshSpec.from_params(Parameters().updated({"fe.cell": "tet", "fe.mesh_size": 0.0035}))
>>> round(spec.elements_through_thickness, 2)
2.0
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from reduced_model.airfoil import chord_and_thickness, naca4_outline
from reduced_model.step_slices import step_digest
from shroud.base.errors import InputError
from shroud.params import Parameters

# Physical group tags (facets dim 2, cells dim 3).
ROOT = 1
CONTACT_SIDE1 = 2      # shroud face at v_s = -b_s/2 (outward normal -e_vs)
CONTACT_SIDE2 = 3      # shroud face at v_s = +b_s/2 (outward normal +e_vs)
BLADE = 1
SHROUD = 2


@dataclass(frozen=True)
class SweptBlade:
    """The blade swept by its section from the disk (X = R_d) to the tip while it turns by
    beta(x) = beta_1 + beta_t x / L, and the shroud box on its tip (docs/geometry.md), SI units (m, rad).

    The section is the rectangle b x h or the NACA four-digit profile of chord c(x) and thickness
    t(x), linear from (b, h) at the root to (b chord_taper, h thickness_taper) at the tip
    (geometry.md, "Airfoil blades"); or the blade and shroud are the solid of the STEP file ``step``
    (its bytes' digest ``step_digest`` keys the meshes made from it).
    """

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
    section: str = field(default="rectangle", kw_only=True)    # "rectangle" or "naca4"
    naca_m: float = field(default=0.04, kw_only=True)          # camber, share of the chord
    naca_p: float = field(default=0.4, kw_only=True)           # position of the maximum camber, share of the chord
    chord_taper: float = field(default=1.0, kw_only=True)      # c(L) / b
    thickness_taper: float = field(default=1.0, kw_only=True)  # t(L) / h
    step: str = field(default="", kw_only=True)                # STEP file of blade and shroud ("" = none)
    step_digest: str = field(default="", kw_only=True)         # sha256 of its bytes

    @staticmethod
    def geometry(params: Parameters, profile: bool = False, step: bool = False, disk: bool = False) -> dict:
        """The fields of this class from ``params`` (blade, shroud, contact.alpha_deg).

        ``profile``: the caller builds the NACA section and the tapers; ``step``: it reads a STEP
        file (shroud.params.Blade.check_modelled refuses what it does not); ``disk``: for the disk
        sector (meshes.disk), else the blade alone on its rigid disk (a flexible one is refused).
        """
        b, s = params.blade, params.shroud
        b.check_modelled(profile, step)
        if not disk:
            params.disk.check_rigid()
        return dict(disk_radius=b.disk_radius, length=b.length, width=b.width, thickness=b.thickness,
                    stagger=math.radians(b.stagger_deg), twist=math.radians(b.twist_deg),
                    shroud_length=s.length, shroud_width=s.width, shroud_thickness=s.thickness,
                    alpha=math.radians(params.contact.alpha_deg), section=b.section, naca_m=b.naca_m,
                    naca_p=b.naca_p, chord_taper=b.chord_taper, thickness_taper=b.thickness_taper,
                    step=b.step, step_digest=step_digest(b.step) if b.step else "")

    @property
    def is_rectangle(self) -> bool:
        """The paper's untapered rectangle, read from no file (what the swept hexahedra build)."""
        return self.section == "rectangle" and self.chord_taper == self.thickness_taper == 1.0 and not self.step

    @property
    def tip_chord(self) -> float:
        """c(L), m."""
        return self.width * self.chord_taper

    @property
    def tip_thickness(self) -> float:
        """t(L), m."""
        return self.thickness * self.thickness_taper

    def profile(self, x: float, points: int) -> np.ndarray:
        """Outline (n, 2) of the section at x m from the root, (eta_v, eta_w) m about its centroid:
        the rectangle's corners or the NACA profile with ``points`` per surface."""
        chord, thickness = chord_and_thickness(self, x)
        if self.section == "naca4":
            return naca4_outline(self.naca_m, self.naca_p, thickness / chord, chord, points)
        return 0.5 * np.array([(thickness, chord), (-thickness, chord), (-thickness, -chord), (thickness, -chord)])

    def area_coefficients(self) -> tuple[float, float]:
        """(k_1, k_2) of the section area A = k_1 c t + k_2 t^2, exact for the profile's polygon.

        The NACA outline's coordinates are c (functions of s) + t (functions of s), linear in c and
        t, so its area is a quadratic form in them, with no c^2 term (a zero thickness has no area).
        """
        if self.section != "naca4":
            return 1.0, 0.0
        area = [polygon_area(naca4_outline(self.naca_m, self.naca_p, tau, 1.0)) for tau in (0.1, 0.2)]
        k_2 = (area[1] - 2.0 * area[0]) / 0.02
        return (area[0] - 0.01 * k_2) / 0.1, k_2

    def section_area(self, x):
        """A(x), m^2, at x m from the root (numpy or UFL arguments)."""
        k_1, k_2 = self.area_coefficients()
        chord, thickness = chord_and_thickness(self, x)
        return k_1 * chord * thickness + k_2 * thickness**2

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

    def beta(self, X):
        """Section angle at global X (rad); numpy or UFL arguments."""
        return self.stagger + self.twist * (X - self.disk_radius) / self.length


@dataclass(frozen=True)
class MeshSpec(SweptBlade):
    """Everything that shapes the solid mesh: the blade's geometry and the cells, SI units (m, rad)."""

    size: float               # target element size, m
    order: int                # gmsh element order (geometry), 1 or 2
    cell: str = "tet"         # "tet" (free tetrahedra) or "hex" (swept hexahedra, meshes.hexa)
    span_ratio: float = 1.0   # hex: cell length along the span / size

    @classmethod
    def from_params(cls, params: Parameters) -> "MeshSpec":
        fe = params.fe
        return cls(**SweptBlade.geometry(params, profile=True, step=True), size=fe.mesh_size, order=fe.order,
                   cell=fe.cell, span_ratio=fe.hex_span_ratio if fe.cell == "hex" else 1.0)

    @property
    def elements_through_thickness(self) -> float:
        """Cells through the thinnest section's thickness."""
        return min(self.thickness, self.tip_thickness) / self.size

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


def polygon_area(loop: np.ndarray) -> float:
    """Area of a counter-clockwise or clockwise simple polygon (n, 2), m^2 (shoelace)."""
    a, b = loop, np.roll(loop, -1, axis=0)
    return 0.5 * abs(float(np.sum(a[:, 0] * b[:, 1] - b[:, 0] * a[:, 1])))


def tip_points(spec: SweptBlade) -> np.ndarray:
    """(3, 3) points of the tip section x = L: its centroid, then centroid -/+ (c(L)/4) e_w(L).

    They are mesh nodes (embedded in the tip face), so the tip kinematics
    v_L, w_L (centre) and the twist (from the two chord points) are nodal
    values: exact, and the same on any number of MPI ranks.
    """
    _, e_w = section_frame(spec.beta_tip)
    centre = np.array([spec.tip_x, 0.0, 0.0])
    d = 0.25 * spec.tip_chord
    return np.array([centre, centre - d * e_w, centre + d * e_w])


def embed_tip_points(model, spec: SweptBlade) -> None:
    """Make the tip points (meshes.spec.tip_points) mesh nodes: in the tip face that holds each (the
    blade/shroud interface) or, in a solid read whole from a STEP file, in its volume."""
    tol = 1e-3 * spec.thickness     # far above OCC bounding-box padding, far below any feature
    faces = [(2, tag) for _, tag in model.getEntities(2)
             if abs(model.getBoundingBox(2, tag)[0] - spec.tip_x) < tol
             and abs(model.getBoundingBox(2, tag)[3] - spec.tip_x) < tol]
    for point in tip_points(spec):
        host = [(dim, tag) for dim, tag in faces + model.getEntities(3) if model.isInside(dim, tag, list(point))]
        if not host:
            raise InputError("blade.length", f"the tip point {point.round(6).tolist()} m (the centroid of the tip "
                             "section and a quarter chord either side) lies outside the solid; allowed: "
                             "blade.length, blade.width, blade.chord_taper and the angles that place it inside")
        tag = model.occ.addPoint(*point)
        model.occ.synchronize()
        model.mesh.embed(0, [tag], *host[0])
