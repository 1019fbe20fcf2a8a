"""The beam model as a shroud.core.system.StructuralSystem at one speed (paper Eqs. 1-12).

    M q'' + (D + G) q' + (K_e + K_c + K_s [+ K_acc]) q
        = F_1 [+ acceleration loads] + f_aero F0 sin(ke Omega t) + W^T lambda(W q)

D is Rayleigh damping (Eq. 2) on the first two undamped frequencies at the
run's speed, computed without Coriolis and with K = K_e + K_c + K_s (the
stiffness the blade has at that speed). The contact acts on the shroud
coordinates y = (v_s, w_s) = R(alpha) (v_L, w_L) (Eq. 7); the tip forces
of Eq. 8 return through W^T, which is Eq. 10's F_y phi(L), F_z phi(L).
With the rigid shroud (``reduced.shroud = "rigid"``) each side acts on its
face instead, centred at p = (t_s / 2) e_X -/+ (b_s / 2) e_vs from the tip
centre, through two points spread along the face (face_points); a point's
displacement U + r x p carries the tip rotations times its arm, y holds
(v_s, w_s) of each point, and the contact forces load bending and torsion
through W^T. The contact law (shroud.core.contact) is the same; so is the
friction direction e_ws. This beam vibrates about its steady centrifugal
state (no constant load), as the solid does: the static untwist would
otherwise move the face points against neighbours that untwist alike.
With ``reduced=True`` everything is projected on the nr lowest free-interface
modes (reduced_model.reduction, Eq. 12).
"""

from __future__ import annotations

import dataclasses
import math
import time

import numpy as np
from numba import njit

from reduced_model.beam import E_X, BeamMatrices, for_parameters
from reduced_model.reduction import ModesOverSpeed, interpolated, project, undamped_modes
from shroud.core.damping import rayleigh, rayleigh_coefficients
from shroud.core.harmonic_balance import LinearHarmonics, condensation, condenses, from_condensation
from shroud.core.system import ContactElements, StructuralSystem
from shroud.params import Parameters


def shroud_frame(alpha_deg: float) -> np.ndarray:
    """(v_s, w_s) from (v_L, w_L): Eq. 7's rotation by the shroud inclination alpha."""
    a = math.radians(alpha_deg)
    return np.array([[math.cos(a), math.sin(a)], [-math.sin(a), math.cos(a)]])


def face_points(params: Parameters) -> list[tuple[int, np.ndarray]]:
    """(side, p): the contact points of the rigid shroud, p from the tip centre (m).

    Each face (side 1 at v_s = -b_s/2, side 2 at +b_s/2; t_s along X from
    the tip, l_s along e_ws) carries the two Gauss points of its length at
    mid-height, p = (t_s / 2) e_X -/+ (b_s / 2) e_vs -/+ l_s / (2 sqrt 3) e_ws,
    each with half of the side's kn, kt and N0: their resultant acts at the
    face centre, and a face turning about X compresses them unevenly with
    the stiffness kn l_s^2 / 12 of the solid's area-weighted face nodes
    (1333 N m/rad for the default shroud, against G J / L = 2100 N m/rad of
    the blade). The spread over the height (kn t_s^2 / 12 = 41 N m/rad about
    e_ws) is left out: the 2 x 2 points of the face's area moved the Fig. 8
    amplitudes and peaks by less than 0.2 % and the slip share by 0.012, at
    1.28 times the cost of a transient (benchmarks/bench_transient.py).
    """
    sh = params.shroud
    gamma = params.blade.beta(params.blade.length) + math.radians(params.contact.alpha_deg)
    e_vs = np.array([0.0, math.cos(gamma), math.sin(gamma)])
    e_ws = np.array([0.0, -math.sin(gamma), math.cos(gamma)])
    g = 0.5 / math.sqrt(3.0)
    return [(side, 0.5 * sh.thickness * E_X + sign * 0.5 * sh.width * e_vs + b * sh.length * e_ws)
            for side, sign in ((1, -1.0), (2, 1.0)) for b in (-g, g)]


def contact_elements(params: Parameters, beam: BeamMatrices) -> ContactElements | None:
    """The two shroud faces as contact elements on y = W q (None without contact)."""
    if not params.contact.enabled or params.shroud.thickness == 0:
        return None
    if params.reduced.shroud == "point":        # both sides act at the tip centre (Eq. 7)
        return ContactElements(W=shroud_frame(params.contact.alpha_deg) @ beam.tip,
                               normal_row=np.array([0, 0]), tangent_row=np.array([1, 1]),
                               side=np.array([1, 2]), weight=np.array([1.0, 1.0]))
    gamma = params.blade.beta(params.blade.length) + math.radians(params.contact.alpha_deg)
    frame = np.array([[0.0, math.cos(gamma), math.sin(gamma)], [0.0, -math.sin(gamma), math.cos(gamma)]])
    points = face_points(params)
    n = len(points)
    return ContactElements(W=np.vstack([frame @ beam.point_rows(p) for _, p in points]),
                           normal_row=2 * np.arange(n), tangent_row=2 * np.arange(n) + 1,
                           side=np.array([side for side, _ in points]), weight=np.full(n, 2.0 / n))


def output_rows(params: Parameters, beam: BeamMatrices) -> np.ndarray:
    """(2, n): the transient's v_L, w_L (along e_v(L), e_w(L)).

    The point shroud sits at the tip centre, so they are the tip centre's.
    The rigid shroud's are taken at its centre, t_s / 2 above the tip, where
    the solid reports its transient (reference_fe.contact_faces: the mean of
    the two faces' displacements), so that both are compared at one point;
    the modes keep the tip centre's (BeamMatrices.tip_kinematics, as the
    solid's modal labels).
    """
    if params.reduced.shroud == "point":
        return beam.tip
    b = params.blade.beta(params.blade.length)
    frame = np.array([[0.0, math.cos(b), math.sin(b)], [0.0, -math.sin(b), math.cos(b)]])
    return frame @ beam.point_rows(0.5 * params.shroud.thickness * E_X)


def build_system(params: Parameters, reduced: bool) -> StructuralSystem:
    """The beam at ``params.speed.rpm``: full (5N or 6N DOF) or reduced to ``params.reduced.nr`` modes."""
    t0 = time.perf_counter()
    omega_dot = 2.0 * math.pi * params.speed.rpm_per_s / 60.0
    beam, omega, nr = for_parameters(params), params.speed.omega, params.reduced.nr if reduced else 0
    modes = undamped_modes(beam.M, beam.stiffness(omega))
    return _system(params, beam, omega, omega_dot, modes.f_hz, modes.truncated(nr) if nr else None,
                   contact_elements(params, beam), output_rows(params, beam), t0)


def at_speed(params: Parameters, reduced: bool) -> BeamOverSpeed:
    """The beam over a speed range (continuation in speed): rpm -> its system, and its harmonic-balance
    linear part without one (:class:`BeamOverSpeed`)."""
    return BeamOverSpeed(params, reduced)


class BeamOverSpeed:
    """What build_system makes at any constant speed, for continuation in speed (many speeds).

    The parameters are validated once, the speed-independent parts built
    once, and the modes (the reduction basis and the two lowest frequencies
    for Rayleigh damping) interpolated in Omega^2 on certified panels
    (reduced_model.reduction.ModesOverSpeed; ``modes.errors`` holds their
    errors against the exact modes). Called with a speed (r/min) it gives
    the system there; :meth:`harmonics` gives the system's linear part per
    harmonic, condensed on the contact coordinates, from one compiled call
    that builds and condenses (the continuation's corrector asks for it at
    every iterate, and needs the system itself only at converged points).
    """

    def __init__(self, params: Parameters, reduced: bool):
        self.params, self.beam = params, for_parameters(params)
        self.nr = params.reduced.nr if reduced else 0
        self.contact, self.tip = contact_elements(params, self.beam), output_rows(params, self.beam)
        self.rows = self.tip if self.contact is None else np.vstack([self.contact.W, self.tip])
        self.modes = modes_over_speed(self.beam, self.nr)

    def __call__(self, rpm: float) -> StructuralSystem:
        t0 = time.perf_counter()
        omega = 2.0 * math.pi * rpm / 60.0
        f_hz, basis = self.modes.at(omega)
        return _system(self.params, self.beam, omega, 0.0, f_hz, basis if self.nr else None, self.contact,
                       self.tip, t0, compiled=True)

    def harmonics(self, rpm: float, H: int) -> LinearHarmonics | None:
        """The linear part at ``rpm`` per harmonic 0..H condensed on the contact coordinates, as
        shroud.core.harmonic_balance.linear_harmonics makes it from this speed's system (the same
        arithmetic: _system's kernels and the core's condensation, in one compiled call); None where
        it does not condense (more contact coordinates than DOFs) or the modes are exact (no panel)."""
        omega = 2.0 * math.pi * rpm / 60.0
        m = 0 if self.contact is None else self.contact.W.shape[0]
        panel = self.modes.panel(omega)
        if panel is None or not condenses(m, self.nr or self.beam.dofs):
            return None
        p, d = self.params, self.params.damping
        return from_condensation(p.load.ke * omega, *_condensed_at(
            omega, *panel, self.beam.speed_terms, self.beam.f_c1,
            self.beam.f_aero1, self.rows, m, d.xi1, d.xi2, p.load.F0, p.load.ke,
            p.reduced.shroud == "point", H))


_MODES: dict[tuple[int, int], tuple[BeamMatrices, ModesOverSpeed]] = {}
MODES_KEPT = 16


def modes_over_speed(beam: BeamMatrices, nr: int) -> ModesOverSpeed:
    """The beam's nr lowest modes over speed, one object per beam and nr in a process (as the beam's
    matrices are one per parameter set: reduced_model.beam.beam_matrices): its panels are built once
    for every branch, and its modal coordinates mean the same in every one (the extended beam's)."""
    key = (id(beam), nr)                 # the entry holds the beam, so its id stays its own
    if key not in _MODES:
        if len(_MODES) >= MODES_KEPT:
            _MODES.pop(next(iter(_MODES)))
        _MODES[key] = (beam, ModesOverSpeed(beam.M, beam.stiffness, nr))
    return _MODES[key][1]


def _system(params: Parameters, beam: BeamMatrices, omega: float, omega_dot: float, f_hz: np.ndarray,
            basis: np.ndarray | None, contact: ContactElements | None, tip: np.ndarray,
            t0: float, compiled: bool = False) -> StructuralSystem:
    """The system at Omega (rad/s) from its lowest frequencies ``f_hz`` (Hz, Rayleigh damping) and
    reduction ``basis`` (None: the full beam); ``t0`` the build's start (perf_counter). ``compiled``:
    with the compiled kernels (where the harmonic balance has compiled them anyway), else numpy."""
    projected, combined = (_projected_compiled, _combined_compiled) if compiled else (_projected, _combined)
    alpha, beta = rayleigh(f_hz[0], f_hz[1], params.damping.xi1, params.damping.xi2)
    terms, f_c1, f_aero1 = beam.speed_terms, beam.f_c1, beam.f_aero1
    if basis is not None:
        m = 0 if contact is None else contact.W.shape[0]
        terms, f_c1, f_aero1, rows = projected(np.ascontiguousarray(basis), terms, f_c1, f_aero1,
                                               tip if contact is None else np.vstack([contact.W, tip]))
        tip = rows[m:]
        if contact is not None:
            contact = dataclasses.replace(contact, W=rows[:m])
    # the rigid shroud's contact points see the tip's rotations, so the beam vibrates about its steady
    # centrifugal state as the solid does (its neighbours, identical blades, untwist alike)
    M, C, K, f_const, f_aero = combined(terms, f_c1, f_aero1, omega, alpha, beta, params.load.F0,
                                        params.reduced.shroud == "point")
    if omega_dot != 0.0:
        K = K + omega_dot * (beam.K_acc1 if basis is None else project(basis, beam.K_acc1))
        f_const = f_const + omega_dot * (beam.f_acc1 if basis is None else basis.T @ beam.f_acc1)
    return StructuralSystem(
        model="full" if basis is None else "reduced", M=M, C=C, K=K, f_const=f_const, f_aero=f_aero,
        omega_e=params.load.ke * omega, tip=tip, contact=contact, build_s=time.perf_counter() - t0,
        rayleigh=(float(alpha), float(beta)))


def _projected(basis, terms, f_c1, f_aero1, rows):
    """N*^T [M, K_e, K_c1 + K_s1, G1] N* (Eq. 12) from ``terms`` (4, n, n), with N*^T f_c1, N*^T f_aero1
    and rows N*: projection is linear, so the reduced model at any speed combines its projected terms as
    the full one combines its own (:func:`_combined`)."""
    r = basis.shape[1]
    out = np.empty((4, r, r))
    for q in range(4):
        out[q] = basis.T @ (terms[q] @ basis)
    return out, basis.T @ f_c1, basis.T @ f_aero1, rows @ basis


def _combined(terms, f_c1, f_aero1, omega, alpha, beta, F0, centrifugal):
    """M, C = alpha M + beta K + G, K = K_e + K_c + K_s, f_const and f_aero at Omega (rad/s) from the
    speed-independent terms [M, K_e, K_c1 + K_s1, G1] (Eqs. 1-2, 10); ``centrifugal``: whether the
    blade carries its centrifugal load (the point shroud) or vibrates about its steady state."""
    M = terms[0]
    K = terms[1] + omega * omega * terms[2]
    C = alpha * M + beta * K + omega * terms[3]
    f_const = omega * omega * f_c1 if centrifugal else np.zeros_like(f_c1)
    return M, C, K, f_const, F0 * f_aero1


# The same arithmetic compiled for BeamOverSpeed.harmonics' kernel: _system runs the functions as numpy,
# so that a time-domain build compiles nothing (first build 0.06 s, against 5.8 s with the compilation).
_projected_compiled, _combined_compiled = njit(cache=True)(_projected), njit(cache=True)(_combined)
_rayleigh_compiled, _interpolated_compiled = njit(cache=True)(rayleigh_coefficients), njit(cache=True)(interpolated)


@njit(cache=True)
def _condensed_at(omega, x2, bary, f2, shapes, terms, f_c1, f_aero1, rows, m, xi1, xi2, F0, ke, centrifugal, H):
    """BeamOverSpeed.harmonics' compiled part: the modes interpolated on a panel (as ModesOverSpeed.at),
    Rayleigh damping on the two lowest frequencies, the system (as _system) and the core's condensation;
    the full beam's panel has shapes of no modes (no reduction)."""
    f_hz, basis = _interpolated_compiled(x2, bary, f2, shapes, omega * omega)
    alpha, beta = _rayleigh_compiled(f_hz[0], f_hz[1], xi1, xi2)
    if basis.shape[1]:
        terms, f_c1, f_aero1, rows = _projected_compiled(basis, terms, f_c1, f_aero1, rows)
    M, C, K, f_const, f_aero = _combined_compiled(terms, f_c1, f_aero1, omega, alpha, beta, F0, centrifugal)
    return condensation(M, C, K, rows, m, f_const, f_aero, ke * omega, H)
