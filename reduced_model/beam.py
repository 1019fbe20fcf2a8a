"""Galerkin matrices of the rotating, pretwisted Timoshenko blade (paper Eqs. 1, 10).

Kinematics
----------
Rotating disk frame O-XYZ (docs/geometry.md): the disk spins about +Z
at Omega, X runs radially through the root-section centre at X = R_d, the
blade axis is x = X - R_d in [0, L]. The section at x (the rectangle b
(chord, along e_w) x h (thickness, along e_v) or the NACA profile, tapered:
reduced_model.airfoil) has its centroid on the axis and is turned about X by
beta(x) = beta_1 + beta_t x / L, so e_v = (0, c, s), e_w = (0, -s, c) with
c, s = cos beta, sin beta.

The fields are written in the (non-twisting) disk frame:

    u(x)        radial (X) displacement of the section centroid, m
    v_Y, w_Z    displacement of the section centroid along Y and Z, m
    psi_Y,psi_Z tilt of the section normal towards Y and Z, rad
                (a section point at (Y, Z) moves -Y psi_Y - Z psi_Z along X)
    theta       twist of the section about X, rad (``reduced.torsion = true``
                only; the paper restrains it)

so the section turns by the small rotation vector r = (theta, -psi_Z, psi_Y)
and a point p = (0, Y, Z) of it moves by U + r x p, U = (u, v_Y, w_Z).
Working in the disk frame keeps the kinematics exact for any twist rate: the
pretwist enters only through the section tensor
Q(x) = rho int p (x) p dA turned by beta(x),

    I_YY = I_v c^2 + I_w s^2 - 2 I_vw c s,  I_ZZ = I_v s^2 + I_w c^2 + 2 I_vw c s,
    I_YZ = (I_v - I_w) c s + I_vw (c^2 - s^2),

with I_v = int eta_v^2 dA (bending along e_v, flap), I_w (along e_w,
chord) and I_vw (zero for the rectangle, not for a cambered profile: its
principal axes are turned from e_v, e_w), J, Gamma, I_rr, the shear centre
from reduced_model.airfoil.span_sections at each Gauss point (docs/extended-beam.md,
"Any blade"); the section-frame components the paper
works in are recovered at the tip, v_L = c_L v_Y(L) + s_L w_Z(L),
w_L = -s_L v_Y(L) + c_L w_Z(L).

Inertia, rotation and loads: one body formula
----------------------------------------------
Each section (per unit length) and the shroud are bodies that move rigidly
with U + r x p; all their inertial terms follow from their mass m, first
moment S = int rho p and second moment Q = int rho p (x) p about the point
they hang on (the section's centroid), with B(p) = [I, -[p x]] (3 x 6) mapping
s = (U, r) to the displacement of p (:func:`body_terms`):

* kinetic energy 1/2 int rho |B s_dot|^2: M = int rho B^T B;
* Coriolis 2 rho Omega e_Z x u_dot (geometry.md): G = int rho B^T 2[e_Z x] B,
  skew; the Euler force of an angular acceleration, -rho Omega_dot e_Z x r,
  gives K_acc = G / 2 (per Omega_dot) and the lag load
  f_acc = -int rho B^T (e_Z x P0) (per Omega_dot), P0 = (R, 0, 0) + p the
  point's position, R = R_d + x;
* centrifugal potential V = -1/2 Omega^2 int rho |Pi P|^2, Pi = diag(1, 1, 0)
  (distance from the spin axis), P = P0 + B s + 1/2 r x (r x p) to second
  order in the rotation (the exact rotation, not its linear part):
    - linear part: the load f_c = Omega^2 int rho B^T Pi P0 (Eq. 10's F_1 on u,
      and on theta the propeller moment -Omega^2 rho I_YZ that turns the
      section towards the plane of rotation);
    - quadratic part: K_s = -Omega^2 int rho B^T Pi B (spin softening of the
      X and Y displacement components) plus, on r,
      K_r = -Omega^2 int rho [sym(Pi P0 p^T) - (Pi P0 . p) I]
          = -Omega^2 [sym(R e_X S^T + Pi Q) - (R S_X + tr(Pi Q)) I],
      the work of the zero-order centrifugal field on the second-order
      displacement of a turning body. For the section it completes the
      propeller moment: the twist stiffness becomes
      Omega^2 rho (I_YY - I_ZZ) = -Omega^2 rho (I_w - I_v) cos 2 beta
      (Bielawa, Rotary Wing Structural Dynamics and Aeroelasticity, 2006,
      Sect. 6.6: the "propeller moment"; Houbolt & Brooks, NACA Rep. 1346,
      1958), and it cancels the rotary spin softening of the in-plane tilt
      (a turn about an axis parallel to the spin axis leaves the distance to
      it unchanged). For the shroud it holds the pendulum stiffening of its
      offset centroid, Omega^2 m_s (R + d) d on both tilts.
  The paper's model keeps only the first quadratic part on the sections
  (its Eq. 1); ``reduced.torsion = true`` uses both. The shroud body always
  uses both (for the point mass, S = Q = 0, both forms agree).

Shroud (``reduced.shroud``): "point" is the paper's mass m_s = rho l_s b_s
t_s at the tip centre (S = Q = 0); "rigid" is the box l_s (along e_ws) x b_s
(along e_vs) x t_s (along X) of geometry.md fused to the tip section, its
centroid d = t_s / 2 above the tip: S = m_s d e_X,
Q = R_s diag(t_s^2, b_s^2, l_s^2) m_s / 12 R_s^T + m_s d^2 e_X e_X^T with R_s
the columns (e_X, e_vs, e_ws). Its terms enter through the tip values
s(L) = T q. Without the torsion field its turn about X is held (theta = 0).

Stiffness (rho, E, G = E / (2 (1 + nu)), section A, I, J, I_rr)
---------------------------------------------------------------
* strain:      1/2 int EA u'^2 + E psi'^T I psi' + k G A |(v_Y, w_Z)' - psi|^2 dx,
               k = 10 (1 + nu) / (12 + 11 nu), Cowper's coefficient for a
               rectangle (it follows from the 3D solution, which the FE
               reference is; 5/6 is its nu = 0 value); with the twist field
               the section's own coefficients kappa_v, kappa_w by Cowper's
               definition (reduced_model.section: the flexure problem solved
               on the section's shape; for a rectangle they are the formula's,
               whatever its aspect ratio; also the paper's beam on any other
               section), along the section's principal axes and turned with it:
               k G A |.|^2 -> gamma^T G A R diag(kappa_v, kappa_w) R^T gamma;
  with torsion and the shear centre p_S off the centroid (a cambered profile:
  Trefftz's shear centre, reduced_model.section_mesh): the shear strain is
  taken where the shear force acts, at the shear centre, whose twist rate
  theta' adds theta' e_X x p_S, so gamma -> gamma + theta' (-Z_s, Y_s)
  (a rigid turn, theta' = 0, strains nothing); with the warping function
  about the shear centre (orthogonal to 1, eta_v, eta_w) bending and
  warping stay uncoupled, and in the Euler-Bernoulli limit the line of shear
  centres bends, E I v_S'', while the centroid, where the mass is, moves
  by v_S - theta e_X x p_S: the shear-centre-referenced model (Banerjee, Int.
  J. Numer. Meth. Eng. 28, 1989), whose kinetic energy carries the offset
  m x_alpha, by a change of variables; here the kinetic energy is the
  centroid's (S = 0 about it) and the offset sits in the strain;
  with torsion: + 1/2 int G J theta'^2 (St-Venant) + 1/2 int E Gamma theta''^2
  (Vlasov: the clamped root holds the section's warping, so theta'(0) = 0;
  the twist functions are those of reduced_model.basis.held_root_slope; the
  tip warps freely, bimoment zero; Timoshenko & Gere, Theory of Elastic
  Stability, Sect. 5.2; for the blade's 40 x 7 mm section the decay length
  sqrt(E Gamma / G J) is 10 mm, and holding the root warping raises torsion1
  at 8500 r/min by 5.7 %, to within 0.05 % of the solid), and the
  extension-twist coupling of the pretwisted section: a fibre at distance r
  from the axis runs on a helix of pitch angle r kappa, kappa = beta_t / L,
  and its strain gains kappa r^2 theta', so
               + int E kappa I_p u' theta' + 1/2 int E kappa^2 I_rr theta'^2
  (Rosen, J. Am. Helicopter Soc. 25(3), 1980; Hodges, J. Appl. Mech. 47,
  1980: a pretwisted strip under tension untwists); against the bending
  strain -Y psi_Y' - Z psi_Z' the same helix term gives
               - int E kappa (T_Y psi_Y' + T_Z psi_Z') theta',
  T = int r^2 (Y, Z) dA turned with the section (zero for a doubly
  symmetric section; the product of the helix term with the warping,
  int omega r^2 dA theta' theta'', is left out);
* centrifugal stiffening (prestress of the axial force, Eq. 10's F_1 per
  unit length, integrated from the tip)
               P(x) = Omega^2 [rho int_x^L A(s) (R_d + s) ds + m_s (R_d + L) + S_X],
               1/2 int P (u'^2 + v_Y'^2 + w_Z'^2 + psi'^T I psi' / A) dx,
  the 3D geometric stiffness sigma0 : grad(u)^T grad(u) of a uniaxial
  prestress P / A integrated over the section; a twist moves the section
  points by theta' (-Z, Y) per unit length, so torsion adds
               1/2 int P (I_p / A) theta'^2 dx
  (the tension of the twisted fibres, Houbolt & Brooks' T k_A^2 term);

With q = [u, v_Y, w_Z, psi_Y, psi_Z (, theta)] coefficients of the N shape
functions of reduced_model.basis each (5N or 6N DOF), the equations are paper
Eq. (1):

    M q'' + (G + D) q' + (K_e + K_c + K_s + K_acc) q = F.

Loads (Eq. 10): F_1 = Omega^2 f_c1 (centrifugal); the aerodynamic load F_e
along e_v(x) = (0, cos beta, sin beta) per unit length at the section
centre; the tip forces F_y, F_z along e_v(L), e_w(L) enter as
tip^T (F_y, F_z); a force at a point p of the shroud as point_rows(p)^T F.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from typing import Callable

import numpy as np

from reduced_model.airfoil import SpanSections, chord_and_thickness, span_sections
from reduced_model.basis import Quadrature, held_root_slope, sample
from shroud.params import Blade, Material, Shroud

FIELDS = ("u", "v_Y", "w_Z", "psi_Y", "psi_Z", "theta")
# s = (U_X, U_Y, U_Z, r_X, r_Y, r_Z) from the fields: (field index, sign); r = (theta, -psi_Z, psi_Y)
_BODY_FROM_FIELD = ((0, 1.0), (1, 1.0), (2, 1.0), (5, 1.0), (4, -1.0), (3, 1.0))
_PI = np.diag([1.0, 1.0, 0.0])
E_X, E_Y, E_Z = np.eye(3)
AXIAL_POINTS = 8       # Gauss points of the axial force's integral outboard of x: exact for A(x) (R_d + x) to degree 15


def shear_coefficient(nu: float) -> float:
    """Cowper's shear coefficient of a solid rectangle, 10 (1 + nu) / (12 + 11 nu)."""
    return 10.0 * (1.0 + nu) / (12.0 + 11.0 * nu)


def cross_matrix(a: np.ndarray) -> np.ndarray:
    """[a x]: the matrix with [a x] b = a x b; a (..., 3) gives (..., 3, 3)."""
    a = np.asarray(a, dtype=float)
    out = np.zeros(a.shape + (3,))
    out[..., 0, 1], out[..., 0, 2] = -a[..., 2], a[..., 1]
    out[..., 1, 0], out[..., 1, 2] = a[..., 2], -a[..., 0]
    out[..., 2, 0], out[..., 2, 1] = -a[..., 1], a[..., 0]
    return out


_EK = cross_matrix(np.eye(3))          # [e_k x], k = 0, 1, 2


@dataclass(frozen=True)
class TipBody:
    """The shroud as a rigid body on the tip centre: mass (kg), first moment S (kg m),
    second moment Q = int rho p (x) p (kg m^2, row-major 9-tuple), p from the tip centre."""

    mass: float
    first: tuple = (0.0, 0.0, 0.0)
    second: tuple = (0.0,) * 9

    @property
    def S(self) -> np.ndarray:
        return np.array(self.first)

    @property
    def Q(self) -> np.ndarray:
        return np.array(self.second).reshape(3, 3)

    @classmethod
    def box(cls, mass: float, length: float, width: float, thickness: float, angle: float) -> "TipBody":
        """Box l_s (along e_ws) x b_s (along e_vs) x t_s (along X) on the tip, centroid t_s/2 up.

        ``angle`` = beta_L + alpha (rad): e_vs = (0, cos, sin), e_ws = (0, -sin, cos).
        """
        c, s = math.cos(angle), math.sin(angle)
        frame = np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])     # columns e_X, e_vs, e_ws
        d = 0.5 * thickness
        Q = frame @ np.diag([thickness**2, width**2, length**2]) @ frame.T * mass / 12.0
        Q[0, 0] += mass * d**2
        return cls(mass=mass, first=(mass * d, 0.0, 0.0), second=tuple(Q.ravel()))


@dataclass(frozen=True)
class BodyTerms:
    """Inertial and rotational terms of bodies in s = (U, r), stacked over a leading axis.

    M kg (kg m, kg m^2); K_s1 per Omega^2; G1 per Omega; f_c1 per Omega^2;
    f_acc1 per Omega_dot (all SI per unit of s).
    """

    M: np.ndarray
    K_s1: np.ndarray
    G1: np.ndarray
    f_c1: np.ndarray
    f_acc1: np.ndarray


def _sandwich(A: np.ndarray, m: np.ndarray, S: np.ndarray, Q: np.ndarray) -> np.ndarray:
    """int rho B^T A B for bodies (m (g,), S (g, 3), Q (g, 3, 3)), B = [I, -[p x]]: (g, 6, 6)."""
    Sx = cross_matrix(S)
    out = np.empty((m.size, 6, 6))
    out[:, :3, :3] = m[:, None, None] * A
    out[:, :3, 3:] = -A @ Sx
    out[:, 3:, :3] = Sx @ A
    # -int [p x] A [p x] = -sum_kl Q_kl [e_k x] A [e_l x]
    out[:, 3:, 3:] = -np.tensordot(Q, np.einsum("kab,bc,lcd->klad", _EK, A, _EK), axes=([1, 2], [0, 1]))
    return out


def _field_load(a0: np.ndarray, Lmat: np.ndarray, m, S, Q) -> np.ndarray:
    """int rho B^T (a0 + Lmat p) for bodies; a0 (g, 3): (g, 6)."""
    out = np.empty((m.size, 6))
    out[:, :3] = m[:, None] * a0 + S @ Lmat.T
    out[:, 3:] = np.cross(S, a0) + np.einsum("gkl,kab,bl->ga", Q, _EK, Lmat)
    return out


def body_terms(m, S, Q, R, second_order: bool = True) -> BodyTerms:
    """Terms of bodies with mass m (g,), moments S (g, 3), Q (g, 3, 3) hung at radius R (g,).

    ``second_order`` adds K_r, the centrifugal potential of the second-order
    displacement 1/2 r x (r x p) (module docstring).
    """
    m, R = np.atleast_1d(np.asarray(m, float)), np.atleast_1d(np.asarray(R, float))
    S, Q = np.asarray(S, float).reshape(-1, 3), np.asarray(Q, float).reshape(-1, 3, 3)
    Ez = cross_matrix(E_Z)
    M = _sandwich(np.eye(3), m, S, Q)
    K_s1 = -_sandwich(_PI, m, S, Q)
    if second_order:
        PQ = _PI @ Q
        outer = R[:, None, None] * np.einsum("a,gb->gab", E_X, S) + PQ
        sym = 0.5 * (outer + outer.transpose(0, 2, 1))
        trace = R * S[:, 0] + np.trace(PQ, axis1=1, axis2=2)
        K_s1[:, 3:, 3:] -= sym - trace[:, None, None] * np.eye(3)
    G1 = _sandwich(2.0 * Ez, m, S, Q)
    f_c1 = _field_load(R[:, None] * E_X, _PI, m, S, Q)
    f_acc1 = -_field_load(R[:, None] * E_Y, Ez, m, S, Q)
    return BodyTerms(M=M, K_s1=K_s1, G1=G1, f_c1=f_c1, f_acc1=f_acc1)


@dataclass(frozen=True)
class BeamMatrices:
    """Speed-independent pieces of Eq. (1); combine them with ``at_speed``.

    Units: M kg; K_e, Omega^2 K_c1, Omega^2 K_s1 N/m; Omega G1 N s/m;
    Omega_dot K_acc1 N/m; Omega^2 f_c1, F0 f_aero1, Omega_dot f_acc1 N
    (per unit generalized coordinate, which is m or rad).
    """

    N: int
    fields: int            # 5 (the paper's model) or 6 (with torsion)
    M: np.ndarray
    K_e: np.ndarray
    K_c1: np.ndarray       # centrifugal stiffening per Omega^2 (rad/s)^2
    K_s1: np.ndarray       # spin softening per Omega^2
    G1: np.ndarray         # Coriolis per Omega, skew-symmetric
    K_acc1: np.ndarray     # angular acceleration per Omega_dot (rad/s^2), skew
    f_c1: np.ndarray       # Eq. 10 F_1 per Omega^2
    f_aero1: np.ndarray    # load of F_e = 1 N/m along e_v(x)
    f_acc1: np.ndarray     # Euler (lag) load per Omega_dot
    tip: np.ndarray        # (2, n): v_L, w_L along e_v(L), e_w(L)
    tip_radial: np.ndarray  # (n,): u_L along X
    tip_body: np.ndarray   # (6, n): s(L) = (U, r) of the tip section
    torsion_arm: float     # b / 2, m: the length that makes the tip twist a displacement for labels

    @property
    def dofs(self) -> int:
        return self.fields * self.N

    def stiffness(self, omega: float) -> np.ndarray:
        """K_e + K_c + K_s at Omega (rad/s): the symmetric stiffness of Eq. (1)."""
        return self.K_e + omega**2 * (self.K_c1 + self.K_s1)

    def gyroscopic(self, omega: float) -> np.ndarray:
        """G at Omega (rad/s)."""
        return omega * self.G1

    @functools.cached_property
    def speed_terms(self) -> np.ndarray:
        """(4, n, n): M, K_e, K_c1 + K_s1, G1, the terms the system at any speed combines (Eq. 1)."""
        return np.ascontiguousarray(np.stack([self.M, self.K_e, self.K_c1 + self.K_s1, self.G1]))

    def centrifugal_load(self, omega: float) -> np.ndarray:
        """Eq. 10 F_1 at Omega (rad/s), N."""
        return omega**2 * self.f_c1

    def point_rows(self, p: np.ndarray) -> np.ndarray:
        """(3, n): displacement (X, Y, Z) of a point p (m, from the tip centre) moving with the tip section."""
        return np.hstack([np.eye(3), -cross_matrix(p)]) @ self.tip_body

    def tip_kinematics(self, shapes: np.ndarray) -> np.ndarray:
        """(k, 4) magnitudes [flap v_L, chord w_L, torsion theta_L b/2, axial u_L] of ``shapes`` (n, k)."""
        v, w = np.abs(self.tip @ shapes)
        twist = np.abs(self.tip_body[3] @ shapes) * self.torsion_arm
        return np.column_stack([v, w, twist, np.abs(self.tip_radial @ shapes)])


def _gram(a: np.ndarray, coef: np.ndarray, b: np.ndarray, weight: np.ndarray) -> np.ndarray:
    """int a_i(x) coef(x) b_j(x) dx by the quadrature."""
    return (a * (weight * coef)[:, None]).T @ b


def _load(a: np.ndarray, coef: np.ndarray, weight: np.ndarray) -> np.ndarray:
    """int a_i(x) coef(x) dx by the quadrature."""
    return a.T @ (weight * coef)


def _body_map(N: int, values: list) -> np.ndarray:
    """(6, fields N): s = (U, r) from q where field f is values[f] . (its N coefficients)."""
    T = np.zeros((6, len(values) * N))
    for a, (f, sign) in enumerate(_BODY_FROM_FIELD):
        if f < len(values):
            T[a, f * N:(f + 1) * N] = sign * values[f]
    return T


def _line_integral(terms: np.ndarray, phis: list, weight: np.ndarray, N: int) -> np.ndarray:
    """int Phi(x)^T terms(x) Phi(x) dx for body terms (g, 6, 6) spread along the line; phis[f] (g, N)."""
    n = len(phis) * N
    out = np.zeros((n, n))
    for a, (fa, sa) in enumerate(_BODY_FROM_FIELD):
        for b, (fb, sb) in enumerate(_BODY_FROM_FIELD):
            coef = terms[:, a, b]
            if fa < len(phis) and fb < len(phis) and np.any(coef):
                out[fa * N:(fa + 1) * N, fb * N:(fb + 1) * N] += sa * sb * _gram(phis[fa], coef, phis[fb], weight)
    return out


def _line_load(terms: np.ndarray, phis: list, weight: np.ndarray, N: int) -> np.ndarray:
    """int Phi(x)^T terms(x) dx for body loads (g, 6)."""
    out = np.zeros(len(phis) * N)
    for a, (f, sign) in enumerate(_BODY_FROM_FIELD):
        if f < len(phis):
            out[f * N:(f + 1) * N] += sign * _load(phis[f], terms[:, a], weight)
    return out


@functools.lru_cache(maxsize=64)
def beam_matrices(blade: Blade, material: Material, tip_body: TipBody, N: int,
                  torsion: bool = False, shroud: Shroud | None = None) -> BeamMatrices:
    """Assemble every speed-independent matrix once per (blade, material, shroud body, N, torsion).

    The sections are the blade's (reduced_model.airfoil.span_sections: the
    rectangle or the NACA profile, tapered, or the slices of the STEP file
    blade.step, which ``shroud``, the shroud keys, must describe); the
    paper's model keeps Cowper's rectangle formula for the rectangle, every
    other beam the section's own shear coefficients.
    """
    blade.check_modelled(profile=True, step=True)   # any section and taper of the blade keys, or a STEP file
    own_kappa = torsion or blade.section != "rectangle" or bool(blade.step)
    return assemble(blade, material, tip_body, N, torsion,
                    functools.partial(span_sections, blade, nu=material.nu if own_kappa else None, shroud=shroud))


def assemble(blade: Blade, material: Material, tip_body: TipBody, N: int, torsion: bool,
             sections: Callable[[np.ndarray], SpanSections]) -> BeamMatrices:
    """The matrices of the beam whose section properties at x (m) are ``sections(x)``.

    Geometry (length, disk radius, stagger, twist, tip chord for the labels)
    from ``blade``. Shear coefficients from the sections where they carry them
    (kappa_v not None), otherwise Cowper's rectangle formula on both axes.
    """
    q: Quadrature = sample(N, blade.length)
    x, wq, phi, dphi, t = q.x, q.weight, q.value, q.slope, q.tip
    L, Rd = blade.length, blade.disk_radius
    sec = sections(x)
    A = sec.area
    rho, E = material.rho, material.E
    beta = np.radians(blade.stagger_deg) + np.radians(blade.twist_deg) * x / L
    c, s = np.cos(beta), np.sin(beta)
    I_YY, I_ZZ, I_YZ = _turned(sec.I_v, sec.I_w, sec.I_vw, c, s)
    # shear stiffness tensor G A kappa: the coefficients along the section's principal axes, turned with it
    near_v, near_w = _principal_axes(sec.I_v, sec.I_w, sec.I_vw)
    kappa = (sec.kappa_v, sec.kappa_w) if sec.kappa_v is not None else (shear_coefficient(material.nu),) * 2
    in_section = [kappa[0] * near_v[i] * near_v[j] + kappa[1] * near_w[i] * near_w[j]
                  for i, j in ((0, 0), (1, 1), (0, 1))]
    kGA = {key: material.G * A * value for key, value in zip(("YY", "ZZ", "YZ"), _turned(*in_section, c, s))}
    fields = 6 if torsion else 5
    n = fields * N
    U, V, W, PY, PZ, TH = (slice(k * N, (k + 1) * N) for k in range(6))

    # inertia, rotation and loads of the sections (per unit length, about their centroids) and of the shroud
    Qsec = np.zeros((x.size, 3, 3))
    Qsec[:, 1, 1], Qsec[:, 2, 2], Qsec[:, 1, 2], Qsec[:, 2, 1] = I_YY, I_ZZ, I_YZ, I_YZ
    line = body_terms(rho * A, np.zeros((x.size, 3)), rho * Qsec, Rd + x, second_order=torsion)
    body = body_terms(tip_body.mass, tip_body.S, tip_body.Q, Rd + L)
    # the twist: N functions whose slope vanishes at the root, where the clamp holds the warping,
    # when the basis resolves that boundary layer; otherwise (slender bars) the free-warping functions
    if warping_held(sec.warping[0], sec.J[0], material, L, N):
        phi_t, dphi_t, ddphi_t, t_t = held_root_slope(sample(N + 1, L, points=x.size))
    else:
        phi_t, dphi_t, ddphi_t, t_t = phi, dphi, q.curvature, t
    phis, tips = [phi] * 5 + [phi_t] * torsion, [t] * 5 + [t_t] * torsion
    T = _body_map(N, tips)

    def assembled(name: str) -> np.ndarray:
        tip_part = getattr(body, name)[0]
        if tip_part.ndim == 1:
            return _line_load(getattr(line, name), phis, wq, N) + T.T @ tip_part
        return _line_integral(getattr(line, name), phis, wq, N) + T.T @ tip_part @ T

    M, K_s1, G1, f_c1, f_acc1 = (assembled(k) for k in ("M", "K_s1", "G1", "f_c1", "f_acc1"))
    G1 = 0.5 * (G1 - G1.T)                         # exactly skew
    K_acc1 = 0.5 * G1

    K_e = np.zeros((n, n))
    K_e[U, U] = _gram(dphi, E * A, dphi, wq)
    strain = {"Y": (V, PY), "Z": (W, PZ)}           # gamma = d' - psi; 1/2 gamma^T kGA gamma
    for a, (disp_a, tilt_a) in strain.items():
        for b, (disp_b, tilt_b) in strain.items():
            k = kGA["YY" if a == b == "Y" else "ZZ" if a == b == "Z" else "YZ"]
            K_e[disp_a, disp_b] += _gram(dphi, k, dphi, wq)
            K_e[disp_a, tilt_b] -= _gram(dphi, k, phi, wq)
            K_e[tilt_a, disp_b] -= _gram(phi, k, dphi, wq)
            K_e[tilt_a, tilt_b] += _gram(phi, k, phi, wq)
    _add_symmetric(K_e, {(PY, PY): _gram(dphi, E * I_YY, dphi, wq), (PZ, PZ): _gram(dphi, E * I_ZZ, dphi, wq),
                         (PY, PZ): _gram(dphi, E * I_YZ, dphi, wq)})

    # axial force per Omega^2: blade outboard of x plus the shroud at the tip
    P1 = rho * _outboard(sections, x, L, Rd) + tip_body.mass * (Rd + L) + tip_body.first[0]
    K_c1 = np.zeros((n, n))
    for f in (U, V, W):
        K_c1[f, f] = _gram(dphi, P1, dphi, wq)
    _add_symmetric(K_c1, {(PY, PY): _gram(dphi, P1 * I_YY / A, dphi, wq),
                          (PZ, PZ): _gram(dphi, P1 * I_ZZ / A, dphi, wq),
                          (PY, PZ): _gram(dphi, P1 * I_YZ / A, dphi, wq)})
    if torsion:
        kappa = math.radians(blade.twist_deg) / L              # pretwist rate, rad/m
        I_p = sec.I_v + sec.I_w
        # the shear centre's arm: a twist rate theta' shears the section at the shear centre by
        # theta' e_X x p_S (p_S its offset from the centroid, turned with the section), so the shear
        # strain there is gamma + theta' a, a = e_X x p_S = (-Z_s, Y_s)
        Y_s, Z_s = sec.shear_v * c - sec.shear_w * s, sec.shear_v * s + sec.shear_w * c
        ka_Y, ka_Z = -kGA["YY"] * Z_s + kGA["YZ"] * Y_s, -kGA["YZ"] * Z_s + kGA["ZZ"] * Y_s
        # the helix strain kappa r^2 theta' against the bending strain -Y psi_Y' - Z psi_Z' (Rosen):
        # int r^2 (Y, Z) dA, turned with the section, nonzero for a section without two symmetry axes
        T_Y, T_Z = sec.I_rrv * c - sec.I_rrw * s, sec.I_rrv * s + sec.I_rrw * c
        _add_symmetric(K_e, {(TH, TH): _gram(dphi_t, material.G * sec.J + E * kappa**2 * sec.I_rr
                                             - Z_s * ka_Y + Y_s * ka_Z, dphi_t, wq)
                             + _gram(ddphi_t, E * sec.warping, ddphi_t, wq),
                             (U, TH): _gram(dphi, E * kappa * I_p, dphi_t, wq),
                             (PY, TH): -_gram(dphi, E * kappa * T_Y, dphi_t, wq) - _gram(phi, ka_Y, dphi_t, wq),
                             (PZ, TH): -_gram(dphi, E * kappa * T_Z, dphi_t, wq) - _gram(phi, ka_Z, dphi_t, wq),
                             (V, TH): _gram(dphi, ka_Y, dphi_t, wq), (W, TH): _gram(dphi, ka_Z, dphi_t, wq)})
        K_c1[TH, TH] = _gram(dphi_t, P1 * I_p / A, dphi_t, wq)

    f_aero1 = np.zeros(n)
    f_aero1[V], f_aero1[W] = _load(phi, c, wq), _load(phi, s, wq)

    bL = blade.beta(L)
    tip = np.zeros((2, n))
    tip[0, V], tip[0, W] = math.cos(bL) * t, math.sin(bL) * t
    tip[1, V], tip[1, W] = -math.sin(bL) * t, math.cos(bL) * t
    tip_radial = np.zeros(n)
    tip_radial[U] = t

    # quadrature sums are symmetric only to round-off; make them exactly so
    M, K_e, K_c1, K_s1 = (0.5 * (X + X.T) for X in (M, K_e, K_c1, K_s1))
    arrays = dict(M=M, K_e=K_e, K_c1=K_c1, K_s1=K_s1, G1=G1, K_acc1=K_acc1, f_c1=f_c1,
                  f_aero1=f_aero1, f_acc1=f_acc1, tip=tip, tip_radial=tip_radial, tip_body=T)
    for a in arrays.values():
        a.flags.writeable = False      # shared through the cache: never modified
    return BeamMatrices(N=N, fields=fields, torsion_arm=0.5 * chord_and_thickness(blade, L)[0], **arrays)


def _outboard(sections: Callable, x: np.ndarray, L: float, Rd: float) -> np.ndarray:
    """int_x^L A(s) (R_d + s) ds, m^3, at each x: the blade's share of the axial force per rho Omega^2 (Eq. 10)."""
    t, w = np.polynomial.legendre.leggauss(AXIAL_POINTS)
    half = 0.5 * (L - x)[:, None]
    s = x[:, None] + half * (t + 1.0)
    return np.sum(half * w * sections(s).area * (Rd + s), axis=1)


def _turned(along_v, along_w, across, c, s) -> tuple:
    """(YY, ZZ, YZ) disk-frame components of the section-frame tensor [[along_v, across], [across, along_w]]
    turned by beta (c, s = cos beta, sin beta): e_v = (0, c, s), e_w = (0, -s, c)."""
    return (along_v * c**2 + along_w * s**2 - 2.0 * across * c * s,
            along_v * s**2 + along_w * c**2 + 2.0 * across * c * s,
            (along_v - along_w) * c * s + across * (c**2 - s**2))


def _principal_axes(I_v, I_w, I_vw) -> tuple:
    """The principal axes nearest e_v and e_w, (v, w) components (2, ...) each (as reduced_model.section._flexure)."""
    theta = 0.5 * np.arctan2(2.0 * I_vw, I_w - I_v)
    first, second = np.array([np.sin(theta), np.cos(theta)]), np.array([np.cos(theta), -np.sin(theta)])
    first_near_w = np.abs(np.cos(theta)) >= np.abs(np.sin(theta))
    return np.where(first_near_w, second, first), np.where(first_near_w, first, second)


def warping_held(warping: float, J: float, material: Material, length: float, N: int) -> bool:
    """Whether the twist functions hold the root's warping (theta'(0) = 0).

    Holding it adds a boundary layer of length lambda = sqrt(E Gamma / G J)
    at the root (Gamma, J the root section's, m^6, m^4; 10 mm for the blade's
    40 x 7 mm section); it changes the torsional stiffness by about lambda / L.
    Polynomials of degree N resolve features down to about L / N^2: a thinner
    layer cannot be carried (the held slope would stiffen a whole L / N^2
    stretch, an error larger than the effect), so then the root warps freely
    (St-Venant) and the error left is below lambda / L < 1 / N^2.
    """
    decay = math.sqrt(material.E * warping / (material.G * J))
    return decay >= length / N**2


def _add_symmetric(target: np.ndarray, blocks: dict) -> None:
    """Add blocks (i, j) and, off the diagonal, their transposes (j, i)."""
    for (i, j), block in blocks.items():
        target[i, j] += block
        if i != j:
            target[j, i] += block.T


def tip_body(params) -> TipBody:
    """The shroud of ``params`` as the beam sees it (``reduced.shroud``: "point" or "rigid")."""
    sh = params.shroud
    if params.reduced.shroud == "rigid":
        angle = params.blade.beta(params.blade.length) + math.radians(params.contact.alpha_deg)
        return TipBody.box(params.shroud_mass, sh.length, sh.width, sh.thickness, angle)
    return TipBody(mass=params.shroud_mass)


def for_parameters(params) -> BeamMatrices:
    """The cached matrices of ``params`` (blade, material, shroud, N, torsion); the beam's disk is rigid."""
    params.disk.check_rigid()
    return beam_matrices(params.blade, params.material, tip_body(params), params.reduced.N,
                         params.reduced.torsion, params.shroud if params.blade.step else None)
