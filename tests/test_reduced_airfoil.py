"""The beams of any blade (issue 34): sections varying along the span and the shear centre off the
centroid, against independent truths: a second method for a tapered cantilever, the paper's
rectangle unchanged, and Banerjee's exact coupled bending-torsion frequencies."""

import dataclasses
import math

import numpy as np
import pytest
import scipy.linalg
from scipy.integrate import quad

from reduced_model.airfoil import SpanSections
from reduced_model.beam import TipBody, assemble, for_parameters
from shroud.analysis.api import modal
from shroud.params import Blade, Material, Parameters


def timoshenko_fe(L, EI, kGA, rhoA, rhoI, elements, P=None, soft_v=None, soft_psi=None, tip_mass=0.0,
                  tip_soft=0.0):
    """Cantilever frequencies (Hz) of a Timoshenko beam with properties f(x) by 2-node elements
    (linear v, psi; one-point shear, two-point bending, mass and prestress), an independent second
    method. Energy 1/2 int EI psi'^2 + kGA (v' - psi)^2 + P (v'^2 + rhoI / rhoA psi'^2)
    - soft_v v^2 - soft_psi psi^2 - tip_soft v(L)^2, kinetic 1/2 int rhoA v_t^2 + rhoI psi_t^2
    + 1/2 tip_mass v_t(L)^2."""
    zero = lambda x: 0.0                                    # noqa: E731
    P, soft_v, soft_psi = P or zero, soft_v or zero, soft_psi or zero
    nodes = np.linspace(0.0, L, elements + 1)
    n = 2 * (elements + 1)
    K, M = np.zeros((n, n)), np.zeros((n, n))
    g, w = np.polynomial.legendre.leggauss(2)
    for e in range(elements):
        a, b = nodes[e], nodes[e + 1]
        h, dofs = b - a, [2 * e, 2 * e + 1, 2 * e + 2, 2 * e + 3]      # v_a, psi_a, v_b, psi_b
        mid = 0.5 * (a + b)
        B = np.array([-1 / h, -0.5, 1 / h, -0.5])                       # v' - psi at the middle
        Ke = kGA(mid) * h * np.outer(B, B)
        Me = np.zeros((4, 4))
        for gk, wk in zip(g, w):
            x, s = mid + 0.5 * h * gk, 0.5 * (1 + gk)
            Nv, Np = np.array([1 - s, 0, s, 0]), np.array([0, 1 - s, 0, s])
            dv, dp = np.array([-1 / h, 0, 1 / h, 0]), np.array([0, -1 / h, 0, 1 / h])
            Ke += 0.5 * h * wk * (EI(x) * np.outer(dp, dp)
                                  + P(x) * (np.outer(dv, dv) + rhoI(x) / rhoA(x) * np.outer(dp, dp))
                                  - soft_v(x) * np.outer(Nv, Nv) - soft_psi(x) * np.outer(Np, Np))
            Me += 0.5 * h * wk * (rhoA(x) * np.outer(Nv, Nv) + rhoI(x) * np.outer(Np, Np))
        K[np.ix_(dofs, dofs)] += Ke
        M[np.ix_(dofs, dofs)] += Me
    M[-2, -2] += tip_mass
    K[-2, -2] -= tip_soft
    lam = scipy.linalg.eigh(K[2:, 2:], M[2:, 2:], eigvals_only=True, subset_by_index=[0, 2])
    return np.sqrt(lam) / (2 * math.pi)


@pytest.mark.parametrize("rpm", [0.0, 10000.0])
def test_a_tapered_rotating_cantilever_has_the_frequencies_of_an_independent_timoshenko_solution(rpm):
    """Chord 40 -> 24 mm, thickness 7 -> 3.5 mm (the rectangle: A, I exact), staggered 90 deg (flap
    out of the plane of rotation, chord in it), untwisted, the shroud a tip mass: the paper's beam's
    first three flap and chord frequencies (each family decoupled from the others without Coriolis)
    against 2-node Timoshenko elements on the same A(x), I(x), with the axial force
    P(x) = Omega^2 (rho int_x^L A(s) (R_d + s) ds + m_s (R_d + L)) integrated by scipy's quad, the
    spin softening of the in-plane displacement and of both tilts (paper Eq. 1); Richardson on 200
    and 400 elements (O(h^2)), within 1e-7 (measured: at most 2.5e-8)."""
    L, c0, t0, ct, tt = 0.15, 0.04, 0.007, 0.6, 0.5
    params = Parameters.from_mapping({"blade": {"twist_deg": 0.0, "stagger_deg": 90.0, "chord_taper": ct,
                                                "thickness_taper": tt},
                                      "speed": {"rpm": rpm}, "contact": {"enabled": False},
                                      "reduced": {"N": 14}})
    beam, N = for_parameters(params), params.reduced.N
    mat, Rd, m_s, omega = params.material, params.blade.disk_radius, params.shroud_mass, params.speed.omega
    K = beam.stiffness(omega)
    c = lambda x: c0 * (1 + (ct - 1) * x / L)               # noqa: E731
    t = lambda x: t0 * (1 + (tt - 1) * x / L)               # noqa: E731
    A = lambda x: c(x) * t(x)                               # noqa: E731
    kappa = 10 * (1 + mat.nu) / (12 + 11 * mat.nu)          # Cowper's rectangle formula, as the paper's beam
    P = lambda x: omega**2 * (mat.rho * quad(lambda s: A(s) * (Rd + s), x, L)[0] + m_s * (Rd + L))  # noqa: E731
    # flap along Z (fields w_Z, psi_Z): no softening of the displacement; chord along -Y (v_Y, psi_Y) and
    # the shroud's mass moving with it: softened
    for family, I, soft_v, tip_soft in (((2, 4), lambda x: c(x) * t(x) ** 3 / 12, None, 0.0),
                                        ((1, 3), lambda x: c(x) ** 3 * t(x) / 12,
                                         lambda x: omega**2 * mat.rho * A(x), omega**2 * m_s)):
        dofs = np.concatenate([np.arange(f * N, (f + 1) * N) for f in family])
        f_beam = np.sqrt(scipy.linalg.eigh(K[np.ix_(dofs, dofs)], beam.M[np.ix_(dofs, dofs)], eigvals_only=True,
                                           subset_by_index=[0, 2])) / (2 * math.pi)
        coarse, fine = (timoshenko_fe(L, lambda x: mat.E * I(x), lambda x: kappa * mat.G * A(x),
                                      lambda x: mat.rho * A(x), lambda x: mat.rho * I(x), n, P=P, soft_v=soft_v,
                                      soft_psi=lambda x: omega**2 * mat.rho * I(x), tip_mass=m_s,
                                      tip_soft=tip_soft)
                        for n in (200, 400))
        reference = fine + (fine - coarse) / 3
        assert np.allclose(f_beam, reference, rtol=1e-7, atol=0), (family, f_beam, reference)


# the paper's rectangle as main had it before the beams took any section (commit 646f899,
# `shroud modal --model reduced|extended --rpm 10000 --modes 6`): the same numbers to round-off
MAIN_10000 = {"reduced": [306.5499717370849, 1127.6681289583714, 1535.6446385600423],
              "extended": [304.0556308170768, 1112.519561451023, 1481.0777614677127]}


@pytest.mark.parametrize("model", ["reduced", "extended"])
def test_the_rectangle_keeps_its_frequencies(model):
    f = [m.f_hz for m in modal(Parameters(), model, rpm=10000.0, n_modes=3, coriolis=True).modes]
    assert np.allclose(f, MAIN_10000[model], rtol=1e-12, atol=0)


# Banerjee, Int. J. Numer. Meth. Eng. 28 (1989) 1283, the cantilever wing coupled in bending and
# torsion: EI 9.75e6 N m^2, GJ 9.88e5 N m^2, m 35.75 kg/m, I_alpha 8.65 kg m about the elastic axis,
# the mass axis x_alpha = 0.18 m behind it, L = 6 m; his exact frequencies (rad/s)
BANERJEE = dict(EI=9.75e6, GJ=9.88e5, m=35.75, I_alpha=8.65, x_alpha=0.18, L=6.0)
BANERJEE_RAD_S = [49.6, 97.0, 248.9, 355.6, 451.5, 610.3]


@pytest.mark.parametrize("offset", [(0.0, 0.18), (0.0, -0.18)])
def test_the_shear_centre_off_the_centroid_couples_bending_and_torsion_as_banerjee_finds(offset):
    """The extended beam's stiffness (fields at the centroid, the shear strain taken at the shear
    centre) on Banerjee's wing: a uniform section with the shear centre 0.18 m from the centroid along
    e_w, rho = 1 kg/m^3 and E = 1e11 Pa (bending rotary inertia r_g^2 / L^2 below 1e-7, Euler-Bernoulli
    as his), shear stiffness 1e5 times EI / L^2, the chord bending rigid. Within the rounding of his
    four digits (the exact determinant of his equations gives 49.6147, 97.0354, 248.874, 355.588,
    451.455, 610.317 rad/s; this beam at N = 16 is 1e-6 to 9e-5 below them). Without the offset the
    frequencies are 51.0, 95.1, 285.2 rad/s: 2.8 %, 2.0 %, 15 % off."""
    b = BANERJEE
    mat = Material(E=1e11, rho=1.0, nu=0.3)
    A = b["m"] / mat.rho
    I_v = b["EI"] / mat.E
    I_p = (b["I_alpha"] - b["m"] * b["x_alpha"] ** 2) / mat.rho          # about the centroid
    kappa = 1e5 * b["EI"] / b["L"] ** 2 / (mat.G * A)

    def sections(x):
        one = np.ones_like(x)
        return SpanSections(area=A * one, I_v=I_v * one, I_w=(I_p - I_v) * one, I_vw=0 * one, I_rr=0 * one,
                            I_rrv=0 * one, I_rrw=0 * one,
                            J=b["GJ"] / mat.G * one, warping=0 * one, shear_v=offset[0] * one,
                            shear_w=offset[1] * one, kappa_v=kappa * one, kappa_w=kappa * one)

    blade = dataclasses.replace(Blade(), length=b["L"], stagger_deg=0.0, twist_deg=0.0)
    beam = assemble(blade, mat, TipBody(mass=0.0), 16, True, sections)
    omega = np.sqrt(scipy.linalg.eigh(beam.K_e, beam.M, eigvals_only=True))
    # the coupled flap-torsion modes: the chord and axial ones are far above them
    coupled = omega[omega < 700]
    assert np.allclose(coupled, BANERJEE_RAD_S, rtol=6e-4, atol=0), coupled


NACA_BLADE = ["blade.section=naca4", "blade.chord_taper=0.75", "blade.thickness_taper=0.6", "contact.alpha_deg=15"]


def test_the_sections_between_stations_are_those_solved_there():
    """The spec's NACA blade (t/c from 0.175 at the root to 0.14 at the tip): every property the beam
    takes, carried from the four stations to points between them, against the profile solved at
    those points (measured: I_v 7.5e-5, kappa_v 1.2e-4, the rest below 2e-5; three stations: 2.2e-3)."""
    from reduced_model.airfoil import _station_values, blade_section, span_sections
    blade = Parameters().with_overrides(NACA_BLADE).blade
    x = np.array([0.02, 0.09, 0.13])
    between = span_sections(blade, x, nu=0.3)
    for k, xk in enumerate(x):
        for key, value in _station_values(blade_section(blade, float(xk)), 0.3).items():
            scale = blade.width if key.startswith("shear_") else abs(value)     # offsets: of the chord
            assert abs(getattr(between, key)[k] - value) <= 2e-4 * scale, (key, xk)


def test_the_beams_take_the_airfoil_and_refuse_a_step_file_they_cannot_read(capsys):
    """`shroud modal --model extended` on the NACA blade answers (flap1 first); a STEP file it cannot read is
    refused (the beams on a STEP file: tests/test_step_beam.py)."""
    from workbench.cli import main
    sets = [a for s in NACA_BLADE for a in ("--set", s)]
    assert main(["modal", "--model", "extended", "--modes", "2"] + sets) in (None, 0)
    out = capsys.readouterr().out
    assert "flap1" in out.splitlines()[1], out
    assert main(["modal", "--model", "extended", "--set", "blade.step=blade.step"] + sets) == 2
    assert "error: blade.step: 'blade.step' cannot be read" in capsys.readouterr().err


def test_the_pretwist_helix_couples_bending_and_twist_as_the_fibres_stretch():
    """The bending-twist term of pretwist, -int E kappa (T_Y psi_Y' + T_Z psi_Z') theta', against the
    stretch of the helical fibres of the twisted body computed point by point: each fibre of the
    cambered NACA section (stagger 30 deg, pretwist 10 deg over the span) displaced by the beam's
    kinematics (axial -Y psi_Y - Z psi_Z, transverse (v_Y, w_Z) + theta e_X x p) for psi = x with the
    deflection that keeps the shear strain zero (v' = psi: x^2 / 2) and theta = x, its strain
    P0' . U' / |P0'|^2 by central differences along the fibre, the cross energy int E eps_psi eps_theta
    over the section and the span: 1.2e-3 and 1.4e-3 apart, held to 2e-3 (the beam keeps the O(kappa)
    term; the fibre strain's 1 / |P0'|^2 = 1 - (kappa r)^2 + ..., kappa r up to 0.03, is the rest: without it
    the two agree to 1e-4)."""
    from reduced_model.airfoil import naca4_outline
    from reduced_model.section_mesh import p2_elements, triangulate

    points, triangles, _ = triangulate(naca4_outline(0.04, 0.4, 0.175, 0.04), size=0.0007)
    elements = p2_elements(points, triangles)
    eta, weight = elements.X.reshape(-1, 2), elements.weight.ravel()
    eta = eta - weight @ eta / weight.sum()                                 # about the centroid
    params = Parameters.from_mapping({"reduced": {"N": 4}})
    blade, mat, L = params.blade, params.material, params.blade.length
    r2 = np.sum(eta**2, axis=1)
    third = {key: np.sum(weight * r2 * eta[:, k]) for k, key in enumerate(("I_rrv", "I_rrw"))}

    def sections(x):
        one, big = np.ones_like(x), 1e3
        return SpanSections(area=weight.sum() * one, I_v=1e-9 * one, I_w=1e-8 * one, I_vw=0 * one, I_rr=0 * one,
                            J=1e-9 * one, warping=0 * one, shear_v=0 * one, shear_w=0 * one, kappa_v=big * one,
                            kappa_w=big * one, **{key: value * one for key, value in third.items()})

    K = assemble(blade, mat, TipBody(mass=0.0), params.reduced.N, True, sections).K_e
    N = params.reduced.N
    beam_cross = [L**2 * K[f * N, 5 * N] for f in (3, 4)]                  # psi_Y = x, psi_Z = x against theta = x

    def position(x):                                                       # (points, 3) on the fibres at x
        b = blade.beta(x)
        return np.column_stack([np.full(len(eta), x), eta[:, 0] * math.cos(b) - eta[:, 1] * math.sin(b),
                                eta[:, 0] * math.sin(b) + eta[:, 1] * math.cos(b)])

    def strain(x, field):
        h = 1e-5 * L
        P0 = lambda s: position(s)                                         # noqa: E731
        U = {"psi_Y": lambda P: np.column_stack([-P[:, 1] * P[:, 0], 0.5 * P[:, 0] ** 2, 0 * P[:, 0]]),
             "psi_Z": lambda P: np.column_stack([-P[:, 2] * P[:, 0], 0 * P[:, 0], 0.5 * P[:, 0] ** 2]),
             "theta": lambda P: np.column_stack([0 * P[:, 0], -P[:, 0] * P[:, 2], P[:, 0] * P[:, 1]])}[field]
        dP0 = (P0(x + h) - P0(x - h)) / (2 * h)
        dU = (U(P0(x + h)) - U(P0(x - h))) / (2 * h)
        return np.sum(dP0 * dU, axis=1) / np.sum(dP0**2, axis=1)

    g, w = np.polynomial.legendre.leggauss(6)
    fibre_cross = [sum(0.5 * L * wk * mat.E * np.sum(weight * strain(x, field) * strain(x, "theta"))
                       for x, wk in zip(0.5 * L * (g + 1), w)) for field in ("psi_Y", "psi_Z")]
    assert abs(third["I_rrv"]) > 0.1 * abs(third["I_rrw"])                  # the camber's share is not negligible
    assert np.allclose(beam_cross, fibre_cross, rtol=2e-3, atol=0), (beam_cross, fibre_cross)
