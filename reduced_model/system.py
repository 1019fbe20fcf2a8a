"""The beam model as a shroud.core.system.StructuralSystem at one speed (paper Eqs. 1-12).

    M q'' + (D + G) q' + (K_e + K_c + K_s [+ K_acc]) q
        = F_1 [+ acceleration loads] + f_aero F0 sin(ke Omega t) + W^T lambda(W q)

D is Rayleigh damping (Eq. 2) on the first two undamped frequencies at the
run's speed, computed without Coriolis and with K = K_e + K_c + K_s (the
stiffness the blade has at that speed). The contact acts on the shroud
coordinates y = (v_s, w_s) = R(alpha) (v_L, w_L) (Eq. 7); the tip forces
of Eq. 8 return through W^T, which is Eq. 10's F_y phi(L), F_z phi(L).
With ``reduced=True`` everything is projected on the nr lowest free-interface
modes (reduced_model.reduction, Eq. 12).
"""

from __future__ import annotations

import math
import time

import numpy as np

from reduced_model.beam import for_parameters
from reduced_model.reduction import project, undamped_modes
from shroud.core.damping import rayleigh
from shroud.params import Parameters
from shroud.core.system import ContactElements, StructuralSystem


def shroud_frame(alpha_deg: float) -> np.ndarray:
    """(v_s, w_s) from (v_L, w_L): Eq. 7's rotation by the shroud inclination alpha."""
    a = math.radians(alpha_deg)
    return np.array([[math.cos(a), math.sin(a)], [-math.sin(a), math.cos(a)]])


def contact_elements(params: Parameters, tip: np.ndarray) -> ContactElements | None:
    """The two shroud faces as contact elements on y = W q (None without contact)."""
    if not params.contact.enabled or params.shroud.thickness == 0:
        return None
    return ContactElements(W=shroud_frame(params.contact.alpha_deg) @ tip,
                           normal_row=np.array([0, 0]), tangent_row=np.array([1, 1]),
                           side=np.array([1, 2]), weight=np.array([1.0, 1.0]))


def build_system(params: Parameters, reduced: bool) -> StructuralSystem:
    """The beam at ``params.speed.rpm``: full (5N DOF) or reduced to ``params.reduced.nr`` modes."""
    omega_dot = 2.0 * math.pi * params.speed.rpm_per_s / 60.0
    return _system(params, for_parameters(params), params.speed.omega, omega_dot, reduced)


def at_speed(params: Parameters, reduced: bool):
    """rpm -> the beam's system at that constant speed (what build_system makes there, without
    revalidating the parameters: continuation in speed asks for many speeds)."""
    beam = for_parameters(params)
    return lambda rpm: _system(params, beam, 2.0 * math.pi * rpm / 60.0, 0.0, reduced)


def _system(params: Parameters, beam, omega: float, omega_dot: float, reduced: bool) -> StructuralSystem:
    t0 = time.perf_counter()
    K = beam.stiffness(omega)
    modes = undamped_modes(beam.M, K)
    alpha, beta = rayleigh(modes.f_hz[0], modes.f_hz[1], params.damping.xi1, params.damping.xi2)
    C = alpha * beam.M + beta * K + beam.gyroscopic(omega)
    f_const = beam.centrifugal_load(omega)
    if omega_dot != 0.0:
        K = K + omega_dot * beam.K_acc1
        f_const = f_const + omega_dot * beam.f_acc1
    M, f_aero, tip = beam.M, params.load.F0 * beam.f_aero1, beam.tip

    nr = params.reduced.nr if reduced else 0
    if nr:
        basis = modes.truncated(nr)
        M, C, K = (project(basis, X) for X in (beam.M, C, K))
        f_const, f_aero, tip = basis.T @ f_const, basis.T @ f_aero, tip @ basis
    return StructuralSystem(
        model="reduced" if nr else "full", M=M, C=C, K=K, f_const=f_const, f_aero=f_aero,
        omega_e=params.load.ke * omega, tip=tip, contact=contact_elements(params, tip),
        build_s=time.perf_counter() - t0)
