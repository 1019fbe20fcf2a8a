# # A two-degree-of-freedom impact oscillator from raw matrices
#
# This example shows the one shape every model of the workbench takes,
#
#     M q'' + C q' + K q = f_const + f_aero sin(omega_e t) + W^T lambda(W q),
#
# built by hand for a point mass that moves in a plane: q = (u, w), u along
# the contact normal, w along the contact face. A spring couples the two
# directions, so a force along u alone also moves the mass along w. One
# contact element (shroud.core.system.ContactElements) presses on the mass
# with the paper's law (Eqs. 3-6: a normal penalty spring kn that acts only
# in contact, N = max(0, N0 - kn u), and stick/slip friction kt, mu), and
# shroud.core.newmark integrates it, the same integrator the beam and the
# 3D solid use.
#
# Two cases have an exact answer, and the last step asserts both:
#
# 1. a gap the mass never reaches: the contact does nothing, and the steady
#    response is the linear harmonic one, |(K - omega^2 M + i omega C)^-1 F|;
# 2. a preload so large, with so much friction, that the contact never opens
#    nor slips: the contact is then two linear springs, kn along u and kt
#    along w, and the steady response is the linear one of K + diag(kn, kt).
#
# Units: SI (kg, N/m, N, s, m).

import math

import numpy as np

from shroud.core.contact import contact_law
from shroud.core.newmark import NewmarkScheme, integrate
from shroud.core.signals import amplitude
from shroud.core.system import ContactElements, StructuralSystem

# ## The structure
#
# A 0.1 kg mass on springs of 4e5 N/m (along u) and 9e5 N/m (along w),
# coupled by 1e5 N/m, with stiffness-proportional damping of 1 % at the
# first natural frequency.

m = 0.1
M = np.diag([m, m])
K = np.array([[4.0e5, 1.0e5],
              [1.0e5, 9.0e5]])
omega_n = np.sqrt(np.linalg.eigvalsh(np.linalg.solve(M, K)))
beta = 2 * 0.01 / omega_n[0]            # C = beta K: damping ratio beta omega / 2
C = beta * K
print("natural frequencies:", np.round(omega_n / (2 * math.pi), 2), "Hz")

# The load: 50 N along u at 0.8 times the first natural frequency.

F = np.array([50.0, 0.0])
omega_e = 0.8 * omega_n[0]

# ## The contact element
#
# The projection W picks the contact's coordinates out of q: y = W q with
# y[0] the normal displacement u and y[1] the tangential one w. The element
# sits on side 1 (it pushes the mass along +u when u < -gap) with all of
# the side's stiffness (weight 1).

W = np.eye(2)
element = ContactElements(W=W, normal_row=np.array([0]), tangent_row=np.array([1]),
                          side=np.array([1]), weight=np.array([1.0]))


def system() -> StructuralSystem:
    return StructuralSystem(model="impact oscillator", M=M, C=C, K=K, f_const=np.zeros(2), f_aero=F,
                            omega_e=omega_e, tip=np.eye(2), contact=element)


# ## The time integration
#
# Average-acceleration Newmark, 256 steps per excitation period (the
# paper's), 200 periods from rest: the free transient has decayed by
# exp(-0.01 * 200 * 2 pi / 0.8) ~ 1e-7 by the end. The contact is solved
# implicitly at each step's end.

steps_per_period = 256
periods = 200
scheme = NewmarkScheme(dt=2 * math.pi / omega_e / steps_per_period)


def steady_amplitudes(kn: float, kt: float, mu: float, N0: float) -> np.ndarray:
    law = contact_law(element, kn=kn, kt=kt, mu=mu, N0=N0)
    run = integrate(system(), law, scheme, steps_per_period * periods, energy_window=10 * steps_per_period)
    assert run.diverged is None
    return np.array([amplitude(run.tip[:, i], steps_per_period) for i in range(2)])


def linear_amplitudes(K_total: np.ndarray) -> np.ndarray:
    """|(K - omega^2 M + i omega C)^-1 F|: the exact steady harmonic response."""
    return np.abs(np.linalg.solve(K_total - omega_e**2 * M + 1j * omega_e * C, F))


kn = kt = 2.0e6

# ## Case 1: a gap never reached
#
# N0 = -kn * gap is the paper's way of writing a gap. The gap is ten times
# the linear amplitude.

free = linear_amplitudes(K)
gap = 10 * free[0]
gapped = steady_amplitudes(kn, kt, mu=0.3, N0=-kn * gap)
print(f"gap {1e6 * gap:.1f} um: u, w amplitude {1e6 * gapped} um; exact {1e6 * free} um")

# ## Case 2: a contact that neither opens nor slips
#
# A preload N0 far above kn times any displacement keeps N > 0, and with
# mu = 10 the friction force stays inside the cone. The contact's springs
# act in parallel with the structure's; the constant preload shifts the
# mean, not the amplitude.

stuck = steady_amplitudes(kn, kt, mu=10.0, N0=1.0e3)
exact_stuck = linear_amplitudes(K + np.diag([kn, kt]))
print(f"stuck: u, w amplitude {1e6 * stuck} um; exact {1e6 * exact_stuck} um")

# ## The check
#
# Newmark's average acceleration keeps amplitudes (no numerical damping)
# and shifts frequencies by about (omega dt)^2 / 12 = 5e-5 at this step, so
# the integrated amplitudes agree with the exact ones to 1e-3.

np.testing.assert_allclose(gapped, free, rtol=1e-3)
np.testing.assert_allclose(stuck, exact_stuck, rtol=1e-3)
print("both cases agree with the exact harmonic response to 1e-3")
