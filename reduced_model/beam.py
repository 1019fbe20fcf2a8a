"""Galerkin matrices of the rotating, pretwisted Timoshenko blade (paper Eqs. 1, 10).

Kinematics
----------
Rotating disk frame O-XYZ (shared/spec/geometry.md): the disk spins about +Z
at Omega, X runs radially through the root-section centre at X = R_d, the
blade axis is x = X - R_d in [0, L]. The section at x is the rectangle
b (chord, along e_w) x h (thickness, along e_v), turned about X by
beta(x) = beta_1 + beta_t x / L, so e_v = (0, c, s), e_w = (0, -s, c) with
c, s = cos beta, sin beta.

The five fields are written in the (non-twisting) disk frame:

    u(x)        radial (X) displacement of the section centre, m
    v_Y, w_Z    displacement of the section centre along Y and Z, m
    psi_Y,psi_Z tilt of the section normal towards Y and Z, rad
                (a section point at (Y, Z) moves -Y psi_Y - Z psi_Z along X)

Torsion is restrained, as in the paper. Working in the disk frame keeps the
kinematics exact for any twist rate: the pretwist enters only through the
section tensor I(x) = int (Y, Z) (x) (Y, Z) dA turned by beta(x),

    I_YY = I_v c^2 + I_w s^2,  I_ZZ = I_v s^2 + I_w c^2,  I_YZ = (I_v - I_w) c s,

with I_v = b h^3/12 (bending along e_v, flap) and I_w = h b^3/12 (along e_w,
chord); the section-frame components the paper works in are recovered at the
tip, v_L = c_L v_Y(L) + s_L w_Z(L), w_L = -s_L v_Y(L) + c_L w_Z(L).

Energies (rho, E, G = E / (2 (1 + nu)), A = b h)
-------------------------------------------------
* strain:      1/2 int EA u'^2 + E psi'^T I psi' + k G A |(v_Y, w_Z)' - psi|^2 dx,
               k = 10 (1 + nu) / (12 + 11 nu), Cowper's coefficient for a
               rectangle (it follows from the 3D solution, which the FE
               reference is; 5/6 is its nu = 0 value);
* kinetic:     1/2 int rho A |q_dot|^2 + rho psi_dot^T I psi_dot dx
               + 1/2 m_s |q_dot(L)|^2, m_s = rho l_s b_s t_s a point mass at
               x = L on the axis (the paper's lumped shroud);
* centrifugal stiffening (prestress of the axial force, Eq. 10's F_1 per
  unit length, integrated from the tip)
               P(x) = Omega^2 [rho A (R_d (L - x) + (L^2 - x^2)/2) + m_s (R_d + L)],
               1/2 int P (u'^2 + v_Y'^2 + w_Z'^2 + psi'^T I psi' / A) dx,
  the 3D geometric stiffness sigma0 : grad(u)^T grad(u) of a uniaxial
  prestress P / A integrated over the section;
* spin softening: -1/2 rho Omega^2 |X and Y components of the displacement|^2,
  i.e. -1/2 Omega^2 [int rho A (u^2 + v_Y^2) + rho psi^T I psi dx
  + m_s (u_L^2 + v_Y(L)^2)]: minus the mass on u, v_Y and the rotary inertia;
* Coriolis: 2 rho Omega e_Z x u_dot, coupling u and v_Y (the section-offset
  terms integrate to zero about the centroid);
* angular acceleration Omega_dot (Euler force -rho Omega_dot e_Z x r):
  a skew coupling of u and v_Y (K_acc) and the lag loads
  -rho A Omega_dot (R_d + x) on v_Y, -rho Omega_dot (I_YY, I_YZ) on psi
  (Eq. 10, F_2..F_5, written in the disk frame).

With q = [u, v_Y, w_Z, psi_Y, psi_Z] coefficients of the N shape functions
of reduced_model.basis each (5N DOF), the equations are paper Eq. (1):

    M q'' + (G + D) q' + (K_e + K_c + K_s + K_acc) q = F.

Loads (Eq. 10): F_1 = Omega^2 f_c1 (centrifugal, on u); the aerodynamic load
F_e along e_v(x) = (0, cos beta, sin beta) per unit length; the tip forces
F_y, F_z along e_v(L), e_w(L) enter as tip^T (F_y, F_z).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np

from reduced_model.basis import Quadrature, sample
from shroud.params import Blade, Material

FIELDS = ("u", "v_Y", "w_Z", "psi_Y", "psi_Z")


def shear_coefficient(nu: float) -> float:
    """Cowper's shear coefficient of a solid rectangle, 10 (1 + nu) / (12 + 11 nu)."""
    return 10.0 * (1.0 + nu) / (12.0 + 11.0 * nu)


@dataclass(frozen=True)
class SectionTensor:
    """I_YY, I_ZZ, I_YZ (m^4) of the turned rectangle at the quadrature points."""

    YY: np.ndarray
    ZZ: np.ndarray
    YZ: np.ndarray

    @classmethod
    def turned(cls, blade: Blade, beta: np.ndarray) -> "SectionTensor":
        c, s = np.cos(beta), np.sin(beta)
        Iv, Iw = blade.I_v, blade.I_w
        return cls(YY=Iv * c**2 + Iw * s**2, ZZ=Iv * s**2 + Iw * c**2, YZ=(Iv - Iw) * c * s)


@dataclass(frozen=True)
class BeamMatrices:
    """Speed-independent pieces of Eq. (1); combine them with ``at_speed``.

    Units: M kg; K_e, Omega^2 K_c1, Omega^2 K_s1 N/m; Omega G1 N s/m;
    Omega_dot K_acc1 N/m; Omega^2 f_c1, F0 f_aero1, Omega_dot f_acc1 N
    (per unit generalized coordinate, which is m or rad).
    """

    N: int
    M: np.ndarray
    K_e: np.ndarray
    K_c1: np.ndarray       # centrifugal stiffening per Omega^2 (rad/s)^2
    K_s1: np.ndarray       # spin softening per Omega^2
    G1: np.ndarray         # Coriolis per Omega, skew-symmetric
    K_acc1: np.ndarray     # angular acceleration per Omega_dot (rad/s^2), skew
    f_c1: np.ndarray       # Eq. 10 F_1 per Omega^2
    f_aero1: np.ndarray    # load of F_e = 1 N/m along e_v(x)
    f_acc1: np.ndarray     # Euler (lag) load per Omega_dot
    tip: np.ndarray        # (2, 5N): v_L, w_L along e_v(L), e_w(L)
    tip_radial: np.ndarray  # (5N,): u_L along X

    @property
    def dofs(self) -> int:
        return 5 * self.N

    def stiffness(self, omega: float) -> np.ndarray:
        """K_e + K_c + K_s at Omega (rad/s): the symmetric stiffness of Eq. (1)."""
        return self.K_e + omega**2 * (self.K_c1 + self.K_s1)

    def gyroscopic(self, omega: float) -> np.ndarray:
        """G at Omega (rad/s)."""
        return omega * self.G1

    def centrifugal_load(self, omega: float) -> np.ndarray:
        """Eq. 10 F_1 at Omega (rad/s), N."""
        return omega**2 * self.f_c1

    def tip_kinematics(self, shapes: np.ndarray) -> np.ndarray:
        """(k, 4) magnitudes [flap v_L, chord w_L, torsion 0, axial u_L] of ``shapes`` (5N, k)."""
        v, w = np.abs(self.tip @ shapes)
        return np.column_stack([v, w, np.zeros_like(v), np.abs(self.tip_radial @ shapes)])


def _gram(a: np.ndarray, coef: np.ndarray, b: np.ndarray, weight: np.ndarray) -> np.ndarray:
    """int a_i(x) coef(x) b_j(x) dx by the quadrature."""
    return (a * (weight * coef)[:, None]).T @ b


def _load(a: np.ndarray, coef: np.ndarray, weight: np.ndarray) -> np.ndarray:
    """int a_i(x) coef(x) dx by the quadrature."""
    return a.T @ (weight * coef)


@functools.lru_cache(maxsize=64)
def beam_matrices(blade: Blade, material: Material, tip_mass: float, N: int) -> BeamMatrices:
    """Assemble every speed-independent matrix once per (blade, material, m_s, N)."""
    q: Quadrature = sample(N, blade.length)
    x, wq, phi, dphi, t = q.x, q.weight, q.value, q.slope, q.tip
    L, Rd, A = blade.length, blade.disk_radius, blade.area
    rho, E = material.rho, material.E
    kGA = shear_coefficient(material.nu) * material.G * A
    beta = np.radians(blade.stagger_deg) + np.radians(blade.twist_deg) * x / L
    I = SectionTensor.turned(blade, beta)
    one = np.ones_like(x)

    n = 5 * N
    U, V, W, PY, PZ = (slice(k * N, (k + 1) * N) for k in range(5))
    tip_outer = np.outer(t, t)

    # mass of a translating section plus the point mass of the shroud
    m_line = _gram(phi, rho * A * one, phi, wq) + tip_mass * tip_outer
    m_line = 0.5 * (m_line + m_line.T)             # exact symmetry keeps G exactly skew
    rotary = {(PY, PY): _gram(phi, rho * I.YY, phi, wq), (PZ, PZ): _gram(phi, rho * I.ZZ, phi, wq),
              (PY, PZ): _gram(phi, rho * I.YZ, phi, wq)}
    M = np.zeros((n, n))
    for f in (U, V, W):
        M[f, f] = m_line
    _put_symmetric(M, rotary)

    K_e = np.zeros((n, n))
    K_e[U, U] = _gram(dphi, E * A * one, dphi, wq)
    for disp, tilt in ((V, PY), (W, PZ)):          # k G A (d' - psi)^2
        K_e[disp, disp] = _gram(dphi, kGA * one, dphi, wq)
        K_e[disp, tilt] = -_gram(dphi, kGA * one, phi, wq)
        K_e[tilt, disp] = K_e[disp, tilt].T
        K_e[tilt, tilt] = _gram(phi, kGA * one, phi, wq)
    _add_symmetric(K_e, {(PY, PY): _gram(dphi, E * I.YY, dphi, wq), (PZ, PZ): _gram(dphi, E * I.ZZ, dphi, wq),
                         (PY, PZ): _gram(dphi, E * I.YZ, dphi, wq)})

    # axial force per Omega^2: blade outboard of x plus the shroud at the tip
    P1 = rho * A * (Rd * (L - x) + 0.5 * (L**2 - x**2)) + tip_mass * (Rd + L)
    K_c1 = np.zeros((n, n))
    for f in (U, V, W):
        K_c1[f, f] = _gram(dphi, P1, dphi, wq)
    _put_symmetric(K_c1, {(PY, PY): _gram(dphi, P1 * I.YY / A, dphi, wq),
                          (PZ, PZ): _gram(dphi, P1 * I.ZZ / A, dphi, wq),
                          (PY, PZ): _gram(dphi, P1 * I.YZ / A, dphi, wq)})

    # spin softening: minus the inertia of the X and Y displacement components
    K_s1 = np.zeros((n, n))
    K_s1[U, U] = K_s1[V, V] = -m_line
    _put_symmetric(K_s1, {key: -block for key, block in rotary.items()})

    # Coriolis 2 Omega e_Z x u_dot and Euler Omega_dot e_Z x u: both couple u and v_Y
    G1 = np.zeros((n, n))
    G1[U, V] = -2.0 * m_line
    G1[V, U] = -G1[U, V].T
    K_acc1 = 0.5 * G1

    radius_load = _load(phi, rho * A * (Rd + x), wq) + tip_mass * (Rd + L) * t
    f_c1 = np.zeros(n)
    f_c1[U] = radius_load
    f_aero1 = np.zeros(n)
    f_aero1[V], f_aero1[W] = _load(phi, np.cos(beta), wq), _load(phi, np.sin(beta), wq)
    f_acc1 = np.zeros(n)
    f_acc1[V] = -radius_load
    f_acc1[PY], f_acc1[PZ] = -_load(phi, rho * I.YY, wq), -_load(phi, rho * I.YZ, wq)

    bL = blade.beta(L)
    tip = np.zeros((2, n))
    tip[0, V], tip[0, W] = math.cos(bL) * t, math.sin(bL) * t
    tip[1, V], tip[1, W] = -math.sin(bL) * t, math.cos(bL) * t
    tip_radial = np.zeros(n)
    tip_radial[U] = t

    # quadrature sums are symmetric only to round-off; make them exactly so
    M, K_e, K_c1, K_s1 = (0.5 * (X + X.T) for X in (M, K_e, K_c1, K_s1))
    arrays = dict(M=M, K_e=K_e, K_c1=K_c1, K_s1=K_s1, G1=G1, K_acc1=K_acc1, f_c1=f_c1,
                  f_aero1=f_aero1, f_acc1=f_acc1, tip=tip, tip_radial=tip_radial)
    for a in arrays.values():
        a.flags.writeable = False      # shared through the cache: never modified
    return BeamMatrices(N=N, **arrays)


def _put_symmetric(target: np.ndarray, blocks: dict) -> None:
    """Write blocks (i, j) and their transposes (j, i)."""
    for (i, j), block in blocks.items():
        target[i, j] = block
        target[j, i] = block.T


def _add_symmetric(target: np.ndarray, blocks: dict) -> None:
    """Add blocks (i, j) and, off the diagonal, their transposes (j, i)."""
    for (i, j), block in blocks.items():
        target[i, j] += block
        if i != j:
            target[j, i] += block.T


def for_parameters(params) -> BeamMatrices:
    """The cached matrices of ``params`` (blade, material, shroud mass, N)."""
    return beam_matrices(params.blade, params.material, params.shroud_mass, params.reduced.N)
