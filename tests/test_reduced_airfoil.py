"""The beams of any blade (issue 34): sections varying along the span and the shear centre off the
centroid, against independent truths: a second method for a tapered cantilever, the paper's
rectangle unchanged, and Banerjee's exact coupled bending-torsion frequencies."""

import dataclasses
import math

import numpy as np
import pytest
import scipy.linalg

from reduced_model.airfoil import SpanSections
from reduced_model.beam import TipBody, assemble, for_parameters
from shroud.analysis.api import modal
from shroud.params import Blade, Material, Parameters


def timoshenko_fe(L, EI, kGA, rhoA, rhoI, elements):
    """Cantilever frequencies (Hz) of a Timoshenko beam with properties f(x) by 2-node elements
    (linear v, psi; one-point shear, two-point bending and mass), an independent second method."""
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
            dp = np.array([0, -1 / h, 0, 1 / h])
            Ke += 0.5 * h * wk * EI(x) * np.outer(dp, dp)
            Me += 0.5 * h * wk * (rhoA(x) * np.outer(Nv, Nv) + rhoI(x) * np.outer(Np, Np))
        K[np.ix_(dofs, dofs)] += Ke
        M[np.ix_(dofs, dofs)] += Me
    lam = scipy.linalg.eigh(K[2:, 2:], M[2:, 2:], eigvals_only=True, subset_by_index=[0, 3])
    return np.sqrt(lam) / (2 * math.pi)


def test_a_tapered_cantilever_has_the_frequencies_of_an_independent_timoshenko_solution():
    """Chord 40 -> 24 mm, thickness 7 -> 3.5 mm (the rectangle: A, I exact), untwisted, no shroud, at
    rest: the paper's beam's flap and chord frequencies against 2-node Timoshenko elements on the same
    A(x), I(x) (Richardson on 400 and 800 elements, O(h^2)): 3e-9 apart, held to 1e-7."""
    L, c0, t0, ct, tt = 0.15, 0.04, 0.007, 0.6, 0.5
    params = Parameters.from_mapping({"blade": {"twist_deg": 0.0, "stagger_deg": 0.0, "chord_taper": ct,
                                                "thickness_taper": tt},
                                      "shroud": {"thickness": 0.0}, "contact": {"enabled": False},
                                      "reduced": {"N": 14}})
    beam = for_parameters(params)
    f_beam = np.sqrt(scipy.linalg.eigh(beam.K_e, beam.M, eigvals_only=True, subset_by_index=[0, 5])) / (2 * math.pi)
    mat = params.material
    kappa = 10 * (1 + mat.nu) / (12 + 11 * mat.nu)          # Cowper's rectangle formula, as the paper's beam
    c = lambda x: c0 * (1 + (ct - 1) * x / L)               # noqa: E731
    t = lambda x: t0 * (1 + (tt - 1) * x / L)               # noqa: E731
    reference = []
    for I in (lambda x: c(x) * t(x) ** 3 / 12, lambda x: c(x) ** 3 * t(x) / 12):     # flap, chord
        coarse, fine = (timoshenko_fe(L, lambda x: mat.E * I(x), lambda x: kappa * mat.G * c(x) * t(x),
                                      lambda x: mat.rho * c(x) * t(x), lambda x: mat.rho * I(x), n)
                        for n in (400, 800))
        reference.extend(fine + (fine - coarse) / 3)
    reference = np.sort(reference)[:4]                      # flap1, flap2, chord1, flap3 (the axial mode is higher)
    assert np.allclose(f_beam[:4], reference, rtol=1e-7, atol=0), (f_beam, reference)


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
        return SpanSections(area=A * one, I_v=I_v * one, I_w=(I_p - I_v) * one, I_vw=0 * one, I_rr=0 * one, I_rrv=0 * one, I_rrw=0 * one,
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


def test_the_beams_take_the_airfoil_and_the_solid_still_refuses_it(capsys):
    """`shroud modal --model extended` on the NACA blade answers (flap1 first); the STEP key stays refused."""
    from workbench.cli import main
    sets = [a for s in NACA_BLADE for a in ("--set", s)]
    assert main(["modal", "--model", "extended", "--modes", "2"] + sets) in (None, 0)
    out = capsys.readouterr().out
    assert "flap1" in out.splitlines()[1], out
    assert main(["modal", "--model", "extended", "--set", "blade.step=blade.step"] + sets) == 2
    assert "error: blade.step:" in capsys.readouterr().err
