# # Harmonic balance of a model of one's own: Den Hartog's friction oscillator
#
# The workbench's harmonic balance (shroud.api.harmonic_balance) serves any
# model of the one shape every model here has: a linear part M, C, K with
# its loads, plus contact elements acting on projected coordinates y = W q
# through the one contact law (normal penalty, Jenkins friction). This
# example registers a model of its own, a 1-DOF oscillator rubbing on a
# preloaded friction contact,
#
#     m x'' + k x + F sgn(x') = P0 sin(w t),
#
# and holds its steady state against the exact solution Den Hartog (1931)
# built for continuous sliding: over the half period in which x' > 0 the
# motion is linear with the force -F, starting at x = -X, x' = 0 and ending
# at x = +X, x' = 0. Those two end conditions give the amplitude X.
#
# The model follows the workbench's conventions: its excitation is the
# engine order k_e times the rotation speed, so the speed given to the
# analysis sets w; its friction force is mu N0 with the contact's preload.

import math

import numpy as np
import scipy.optimize

from shroud import api

MASS, STIFF, P0, FRICTION = 1.0, 1e4, 10.0, 2.0     # kg, N/m, N, N (w_n = 100 rad/s)
MU = 0.2

# ## The model
#
# One DOF; one contact element whose normal coordinate never moves (W's
# normal row is zero, so the normal force stays at the preload N0 = F / mu)
# and whose tangential coordinate is x, with a tangential penalty 10^4 k:
# Coulomb friction for all practical purposes.


def oscillator(params: api.Parameters) -> api.StructuralSystem:
    contact = api.ContactElements(W=np.array([[0.0], [1.0]]), normal_row=np.array([0]),
                                  tangent_row=np.array([1]), side=np.array([1]), weight=np.array([1.0]))
    return api.StructuralSystem(model="den-hartog", M=np.eye(1) * MASS, C=np.zeros((1, 1)),
                                K=np.array([[STIFF]]), f_const=np.zeros(1), f_aero=np.array([P0]),
                                omega_e=params.load.ke * params.speed.omega, tip=np.array([[1.0], [0.0]]),
                                contact=contact)


api.register_model(api.ModelEntry("den-hartog", build_system=oscillator,
                                  description="1-DOF oscillator with Coulomb friction (Den Hartog 1931)"))
params = api.parameters({"contact.mu": MU, "contact.N0": FRICTION / MU, "contact.kn": 1e6,
                         "contact.kt": 1e4 * STIFF, "load.ke": 1})

# ## Den Hartog's exact amplitude
#
# x(s) over the sliding half period from x = -X at the forcing phase phi:
# the free motion plus the particular solutions of the load and of -F.


def exact_amplitude(w: float) -> float:
    wn, half, Pd = math.sqrt(STIFF / MASS), math.pi / w, P0 / (STIFF - MASS * w * w)

    def end_of_half(u):
        X, phi = u
        A, B = -X - Pd * math.sin(phi) + FRICTION / STIFF, -Pd * w * math.cos(phi) / wn
        x = A * math.cos(wn * half) + B * math.sin(wn * half) + Pd * math.sin(w * half + phi) - FRICTION / STIFF
        v = -A * wn * math.sin(wn * half) + B * wn * math.cos(wn * half) + Pd * w * math.cos(w * half + phi)
        return [x - X, v]

    X, _ = scipy.optimize.fsolve(end_of_half, [abs(Pd), -math.pi / 2 if w < wn else math.pi / 2], xtol=1e-14)
    return X


# ## The steady state by harmonic balance
#
# Below and above the resonance (w_n = 100 rad/s), where the mass slides
# all the time. 25 harmonics resolve the corners of the friction force.

print(f"{'w (rad/s)':>10} {'HB X (mm)':>11} {'exact X (mm)':>13} {'error':>8}")
for w in (70.0, 150.0):
    rpm = w * 60.0 / (2 * math.pi)                       # k_e = 1: the speed is the forcing frequency
    point = api.harmonic_balance(params, "den-hartog", rpm=rpm, harmonics=25, samples=1024)
    exact = exact_amplitude(w)
    error = point.amplitude_v_L / exact - 1
    print(f"{w:10.0f} {point.amplitude_v_L * 1e3:11.4f} {exact * 1e3:13.4f} {error:8.2%}")
    assert point.converged and abs(error) < 5e-3, (w, point.amplitude_v_L, exact)
