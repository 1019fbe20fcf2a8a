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
from dataclasses import dataclass

import numpy as np

from shroud.params import Parameters

# Physical group tags (facets dim 2, cells dim 3).
ROOT = 1
CONTACT_SIDE1 = 2      # shroud face at v_s = -b_s/2 (outward normal -e_vs)
CONTACT_SIDE2 = 3      # shroud face at v_s = +b_s/2 (outward normal +e_vs)
BLADE = 1
SHROUD = 2


@dataclass(frozen=True)
class SweptBlade:
    """The blade swept by its chord section from the disk (X = R_d) to the tip while it turns by
    beta(x) = beta_1 + beta_t x / L, and the shroud box on its tip (docs/geometry.md), SI units (m, rad)."""

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

    @staticmethod
    def geometry(params: Parameters, disk: bool = False) -> dict:
        """The fields of this class from ``params`` (blade, shroud, contact.alpha_deg); ``disk``: for the
        disk sector (meshes.disk), else the blade alone on its rigid disk (a flexible one is refused)."""
        b, s = params.blade, params.shroud
        b.check_modelled()               # the meshes sweep the rectangle, untapered
        if not disk:
            params.disk.check_rigid()
        return dict(disk_radius=b.disk_radius, length=b.length, width=b.width, thickness=b.thickness,
                    stagger=math.radians(b.stagger_deg), twist=math.radians(b.twist_deg),
                    shroud_length=s.length, shroud_width=s.width, shroud_thickness=s.thickness,
                    alpha=math.radians(params.contact.alpha_deg))

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
        return cls(**SweptBlade.geometry(params), size=fe.mesh_size, order=fe.order, cell=fe.cell,
                   span_ratio=fe.hex_span_ratio if fe.cell == "hex" else 1.0)

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


def tip_points(spec: SweptBlade) -> np.ndarray:
    """(3, 3) points of the tip section x = L: its centre, then centre -/+ (b/4) e_w(L).

    They are mesh nodes (embedded in the tip face), so the tip kinematics
    v_L, w_L (centre) and the twist (from the two chord points) are nodal
    values: exact, and the same on any number of MPI ranks.
    """
    _, e_w = section_frame(spec.beta_tip)
    centre = np.array([spec.tip_x, 0.0, 0.0])
    return np.array([centre, centre - 0.25 * spec.width * e_w, centre + 0.25 * spec.width * e_w])
