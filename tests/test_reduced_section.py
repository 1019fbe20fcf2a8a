"""Section properties computed from the shape, against the rectangle's series solutions
(Timoshenko & Goodier, Theory of Elasticity, Sects. 104-109) and composite-area formulas."""

import math

import numpy as np
import pytest

from reduced_model.section import rectangle, section_properties


def torsion_series(b, h, terms=60):
    """St-Venant J of a b x h rectangle, b >= h: b h^3/3 [1 - 192 h/(pi^5 b) sum tanh(n pi b/2h)/n^5]."""
    n = np.arange(1, 2 * terms, 2, dtype=float)
    return b * h**3 / 3 * (1 - 192 * h / (math.pi**5 * b) * np.sum(np.tanh(n * math.pi * b / (2 * h)) / n**5))


def warping_series(b, h, terms=60, points=200):
    """Gamma = int omega^2 dA of the rectangle, y in [-b/2, b/2], z in [-h/2, h/2]:
    omega = -y z + sum_n A_n sin(k_n z) sinh(k_n y) / cosh(k_n b/2), k_n = n pi / h,
    A_n = 8 h^2 (-1)^((n-1)/2) / (pi^3 n^3) (n odd), the harmonic conjugate of Prandtl's series."""
    a, c = b / 2, h / 2
    t, w = np.polynomial.legendre.leggauss(points)
    Y, Z = np.meshgrid(a * t, c * t, indexing="ij")
    omega = -Y * Z
    for n in range(1, 2 * terms, 2):
        k = n * math.pi / (2 * c)
        A = 32 * c**2 * (-1) ** ((n - 1) // 2) / (math.pi**3 * n**3)
        # sinh(k y) / cosh(k a) without overflow
        ratio = np.sign(Y) * np.exp(k * (np.abs(Y) - a)) * (1 - np.exp(-2 * k * np.abs(Y))) / (1 + np.exp(-2 * k * a))
        omega += A * np.sin(k * Z) * ratio
    return float(np.einsum("i,j,ij->", w * a, w * c, omega**2))


@pytest.mark.parametrize("b, h, rtol_gamma", [(0.04, 0.007, 1e-4), (0.02, 0.01, 1e-3), (0.01, 0.01, 3e-3),
                                              (0.1, 0.005, 1e-4)])
def test_rectangle_torsion_and_warping_constants_match_their_series(b, h, rtol_gamma):
    s = rectangle(b, h)
    assert s.J == pytest.approx(torsion_series(b, h), rel=2e-5)
    assert s.warping == pytest.approx(warping_series(b, h), rel=rtol_gamma)
    # and neither is its thin-strip value (b h^3/3, b^3 h^3/144) for the blade's 40 x 7 mm
    if b / h < 6:
        assert abs(s.J / (b * h**3 / 3) - 1) > 0.05 and abs(s.warping / (b**3 * h**3 / 144) - 1) > 0.1


def test_rectangle_area_and_moments_are_exact():
    b, h = 0.04, 0.007
    s = rectangle(b, h)
    assert s.area == pytest.approx(b * h, rel=1e-13)
    assert s.I_v == pytest.approx(b * h**3 / 12, rel=1e-12)          # flap: along the thickness
    assert s.I_w == pytest.approx(h * b**3 / 12, rel=1e-12)
    assert s.I_rr == pytest.approx(b * h * (b**4 / 80 + b**2 * h**2 / 72 + h**4 / 80), rel=1e-12)
    assert abs(s.I_vw) < 1e-12 * s.I_w and s.principal_angle == pytest.approx(0.0, abs=1e-12)
    assert np.hypot(*s.shear_centre) < 1e-9 * b                        # doubly symmetric: the centroid


def test_shifted_rectangle_has_its_shear_centre_and_centroid_at_its_middle():
    """Nothing in the section depends on where the shape sits: an off-origin rectangle
    gives the same J and Gamma and its shear centre at its own middle."""
    b, h, cv, cw = 0.02, 0.01, 0.003, -0.006

    def inside(v, w):
        return (np.abs(v - cv) <= h / 2) & (np.abs(w - cw) <= b / 2)

    s = section_properties(inside, (cv - h / 2, cv + h / 2), (cw - b / 2, cw + b / 2))
    ref = rectangle(b, h)
    assert s.centroid == pytest.approx((cv, cw), abs=1e-12)
    assert s.shear_centre == pytest.approx((cv, cw), abs=1e-6 * b)
    assert s.J == pytest.approx(ref.J, rel=1e-9) and s.warping == pytest.approx(ref.warping, rel=1e-6)
    assert s.shear_coefficients(0.3, "energy") == pytest.approx(ref.shear_coefficients(0.3, "energy"), rel=1e-9)


def test_angle_section_moments_and_principal_angle_match_composite_areas():
    """An equal-leg angle (two t x a legs): its product of inertia and principal axes at 45 deg."""
    a, t = 0.03, 0.01

    def inside(v, w):
        return ((v <= t) | (w <= t)) & (v >= 0) & (w >= 0)

    s = section_properties(inside, (0.0, a), (0.0, a))
    # composite: leg 1 = a x t along v (w in [0, t]), leg 2 = (a - t) x t along w (v in [0, t])
    parts = [(a * t, a / 2, t / 2, t * a**3 / 12, a * t**3 / 12), ((a - t) * t, t / 2, t + (a - t) / 2,
                                                                     (a - t) * t**3 / 12, t * (a - t) ** 3 / 12)]
    A = sum(p[0] for p in parts)
    cv = sum(p[0] * p[1] for p in parts) / A
    cw = sum(p[0] * p[2] for p in parts) / A
    Ivv = sum(p[3] + p[0] * (p[1] - cv) ** 2 for p in parts)
    Iww = sum(p[4] + p[0] * (p[2] - cw) ** 2 for p in parts)
    Ivw = sum(p[0] * (p[1] - cv) * (p[2] - cw) for p in parts)
    assert s.area == pytest.approx(A, rel=1e-12)
    assert (s.I_v, s.I_w, s.I_vw) == pytest.approx((Ivv, Iww, Ivw), rel=1e-10)
    assert abs(s.principal_angle) == pytest.approx(math.pi / 4, abs=1e-9)


def cowper(nu):
    """Cowper's shear coefficient of the rectangle (J. Appl. Mech. 33, 1966, Table 1)."""
    return 10 * (1 + nu) / (12 + 11 * nu)


def flexure_stress_series(width, depth, nu, Y, Z, terms=60):
    """(tau_y, tau_z) I / Q of a rectangle sheared along its depth, from the series of its flexure
    function (y along the depth h, z across the width b, c = -nu / (2 (1 + nu))):
    chi = chi_0(y) - c y z^2 / 2 + sum_n A_n cos(k_n z) sinh(k_n y), k_n = 2 n pi / b,
    chi_0' = -(1 + c)(y^2 - h^2/4) / 2 - c h^2 / 8 + c b^2 / 12,
    A_n = c b^3 (-1)^n / (2 n^3 pi^3 cosh(k_n h / 2)) (the cosine series of z^2 on the width),
    tau I / Q = grad chi + c ((y^2 - z^2) / 2, y z): Timoshenko & Goodier, Sect. 124's problem."""
    b, h = width, depth
    c = -nu / (2 * (1 + nu))
    ty = -(1 + c) * (Y**2 - h**2 / 4) / 2 - c * h**2 / 8 + c * b**2 / 12 - c * Z**2 / 2 + c * (Y**2 - Z**2) / 2
    tz = -c * Y * Z + c * Y * Z
    for n in range(1, terms + 1):
        k = 2 * n * math.pi / b
        A = c * b**3 * (-1) ** n / (2 * n**3 * math.pi**3)
        # cosh(k y) / cosh(k h / 2) and sinh(k y) / cosh(k h / 2) without overflow
        ch = (np.exp(k * (np.abs(Y) - h / 2)) + np.exp(-k * (np.abs(Y) + h / 2))) / (1 + math.exp(-k * h))
        sh = np.sign(Y) * (np.exp(k * (np.abs(Y) - h / 2)) - np.exp(-k * (np.abs(Y) + h / 2))) / (1 + math.exp(-k * h))
        ty = ty + A * k * np.cos(k * Z) * ch
        tz = tz - A * k * np.sin(k * Z) * sh
    return ty, tz


def energy_shear_coefficient_series(width, depth, nu, points=120):
    """kappa = Q^2 / (A int |tau|^2 dA) of the rectangle from the series, by Gauss quadrature."""
    b, h = width, depth
    t, w = np.polynomial.legendre.leggauss(points)
    Y, Z = np.meshgrid(0.5 * h * t, 0.5 * b * t, indexing="ij")
    ty, tz = flexure_stress_series(b, h, nu, Y, Z)
    energy = np.einsum("i,j,ij->", w * h / 2, w * b / 2, ty**2 + tz**2)
    I = b * h**3 / 12
    return I**2 / (b * h * energy)


@pytest.mark.parametrize("ratio, edge, centre", [(2.0, 1.396, 0.856), (1.0, 1.126, 0.940),
                                                 (0.5, 1.033, 0.983), (0.25, 1.008, 0.996)])
def test_flexure_series_matches_timoshenko_and_goodiers_table(ratio, edge, centre):
    """The series itself against the published shear stresses on the neutral axis, at the edges
    and at the centre, over the elementary 3 Q / (2 A), for nu = 1/4 and b/h = 2 .. 1/4
    (Timoshenko & Goodier, Theory of Elasticity, Sect. 124, table)."""
    h = 0.01
    b = ratio * h
    elementary = 1.5 / (b * h) * (b * h**3 / 12)           # 3 Q / (2 A) in units of Q / I
    at_edge = flexure_stress_series(b, h, 0.25, np.array(0.0), np.array(b / 2), terms=400)[0]
    at_centre = flexure_stress_series(b, h, 0.25, np.array(0.0), np.array(0.0), terms=400)[0]
    assert at_edge / elementary == pytest.approx(edge, abs=1e-3)
    assert at_centre / elementary == pytest.approx(centre, abs=1e-3)


def test_energy_series_reaches_its_narrow_limit():
    """The series itself: a narrow rectangle has the elementary parabolic shear flow, kappa = 5/6."""
    assert energy_shear_coefficient_series(0.001, 0.05, 0.3) == pytest.approx(5 / 6, rel=1e-4)


@pytest.mark.parametrize("chord, thickness", [(0.04, 0.007), (0.01, 0.01), (0.1, 0.005)])
@pytest.mark.parametrize("nu", [0.0, 0.3, 0.49])
def test_rectangle_shear_coefficients_match_cowper_and_the_series(chord, thickness, nu):
    """Cowper's definition gives 10 (1 + nu)/(12 + 11 nu) for every aspect ratio (the narrow
    limit is where it is usually quoted); the energy definition the series' value, which falls
    well below 5/6 for a wide section when nu > 0 (0.41 for the blade's flap at nu = 0.3)."""
    s = rectangle(chord, thickness)
    kappa_v, kappa_w = s.shear_coefficients(nu)
    assert (kappa_v, kappa_w) == pytest.approx((cowper(nu), cowper(nu)), rel=2e-5)
    energy_v, energy_w = s.shear_coefficients(nu, "energy")
    # shear along e_v runs across the thickness (depth h, width b); along e_w across the chord
    assert energy_v == pytest.approx(energy_shear_coefficient_series(chord, thickness, nu), rel=5e-4)
    assert energy_w == pytest.approx(energy_shear_coefficient_series(thickness, chord, nu), rel=5e-4)


def circle_energy_coefficient(nu, points=120):
    """Q^2 / (A int |tau|^2 dA) of the circle from Timoshenko & Goodier's exact flexure stresses
    (Sect. 121): tau_xy = (3 + 2 nu) Q / (8 (1 + nu) I) (R^2 - y^2 - (1 - 2 nu) z^2 / (3 + 2 nu)),
    tau_xz = -(1 + 2 nu) Q y z / (4 (1 + nu) I); R = 1, by Gauss quadrature in polar coordinates."""
    t, w = np.polynomial.legendre.leggauss(points)
    r, wr = 0.5 * (t + 1), 0.5 * w
    th = np.linspace(0, 2 * np.pi, 4 * points, endpoint=False)
    Rg, Tg = np.meshgrid(r, th, indexing="ij")
    weight = np.outer(wr, np.full(th.size, 2 * np.pi / th.size)) * Rg
    y, z = Rg * np.cos(Tg), Rg * np.sin(Tg)
    I = math.pi / 4
    txy = (3 + 2 * nu) / (8 * (1 + nu) * I) * (1 - y**2 - (1 - 2 * nu) / (3 + 2 * nu) * z**2)
    txz = -(1 + 2 * nu) * y * z / (4 * (1 + nu) * I)
    return 1 / (math.pi * np.sum((txy**2 + txz**2) * weight))


@pytest.fixture(scope="module")
def circle():
    R = 0.01
    return section_properties(lambda v, w: v**2 + w**2 <= R**2, (-R, R), (-R, R), cells_v=CIRCLE_CELLS)


CIRCLE_CELLS = 100


@pytest.mark.parametrize("nu", [0.0, 0.3, 0.5])
def test_circle_shear_coefficients_match_cowper_and_the_exact_stresses(circle, nu):
    """The circle on a grid of 100 x 100 cells (a staircase outline, so 1e-3): Cowper's
    6 (1 + nu)/(7 + 6 nu) and the energy of the exact stresses; Hutchinson's
    6 (1 + nu)^2/(7 + 12 nu + 4 nu^2), a third definition, is 4 % and 9 % from them at nu = 0.3."""
    cow = 6 * (1 + nu) / (7 + 6 * nu)
    assert circle.shear_coefficients(nu) == pytest.approx((cow, cow), rel=1e-3)
    energy = circle_energy_coefficient(nu)
    assert energy == pytest.approx(6 * (1 + nu) ** 2 / (7 + 14 * nu + 8 * nu**2), rel=1e-12)
    assert circle.shear_coefficients(nu, "energy") == pytest.approx((energy, energy), rel=1e-3)
