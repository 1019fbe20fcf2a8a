"""The beam model against exact solutions (non-rotating, rotating, static)."""

import math

import numpy as np
import pytest
import scipy.linalg
from scipy.optimize import brentq

from reduced_model.beam import for_parameters
from reduced_model.modal import modal_analysis
from shroud.params import Parameters

RHO, E, NU = 7800.0, 200e9, 0.3


def straight_beam(L, b, h, tip_mass_dims=None, N=12, disk_radius=0.0):
    """An untwisted blade at zero stagger: e_v = Y (thickness h), e_w = Z (chord b)."""
    shroud = {"thickness": 0.0}
    if tip_mass_dims:
        shroud = dict(zip(("length", "width", "thickness"), tip_mass_dims))
    return Parameters.from_mapping({
        "blade": {"length": L, "width": b, "thickness": h, "stagger_deg": 0.0,
                  "twist_deg": 0.0, "disk_radius": disk_radius},
        "material": {"E": E, "rho": RHO, "nu": NU}, "shroud": shroud,
        "reduced": {"N": N, "nr": 0}, "contact": {"enabled": False}})


def roots(fn, hi, count, steps=4000):
    """The first ``count`` sign changes of fn on (0, hi], refined by brentq."""
    grid = np.linspace(hi / steps, hi, steps)
    vals = np.array([fn(g) for g in grid])
    out = [brentq(fn, grid[i], grid[i + 1], xtol=1e-14)
           for i in np.flatnonzero(np.sign(vals[:-1]) != np.sign(vals[1:]))]
    return np.array(out[:count])


def euler_bernoulli_tip_mass(mu, count):
    """lambda_k of 1 + cos cosh + mu lambda (cos sinh - sin cosh) = 0 (clamped, tip mass ratio mu)."""
    def eq(lam):
        return (1 + math.cos(lam) * math.cosh(lam)
                + mu * lam * (math.cos(lam) * math.sinh(lam) - math.sin(lam) * math.cosh(lam))) / math.cosh(lam)
    return roots(eq, 12.0, count)


def timoshenko_tip_mass(L, A, I, k, m_tip, count, f_max):
    """Exact Timoshenko clamped-free frequencies (Hz) with a tip point mass, by transfer matrix.

    State y = (w, psi, M, Q), M = E I psi', Q = k G A (w' - psi):
    w' = psi + Q/kGA, psi' = M/EI, M' = -Q - rho I w^2 psi, Q' = -rho A w^2 w;
    y(0) = (0, 0, M0, Q0); at L: M = 0 and Q = m_tip w^2 w.
    """
    G = E / (2 * (1 + NU))
    kGA, EI = k * G * A, E * I

    def det(f):
        om2 = (2 * math.pi * f) ** 2
        Amat = np.array([[0, 1, 0, 1 / kGA], [0, 0, 1 / EI, 0],
                         [0, -RHO * I * om2, 0, -1], [-RHO * A * om2, 0, 0, 0]])
        T = scipy.linalg.expm(Amat * L)
        rows = np.array([T[2, 2:], T[3, 2:] - m_tip * om2 * T[0, 2:]])
        return np.linalg.det(rows) / np.abs(T).max() ** 2
    return roots(det, f_max, count, steps=600)


def frequencies_by_label(params, rpm=0.0, n=12):
    return modal_analysis(params, rpm=rpm, n_modes=n, coriolis=False).by_label()


def test_non_rotating_cantilever_with_tip_mass_matches_euler_bernoulli_equation():
    L, b, h = 1.0, 0.001, 0.0005                     # slender: L/h = 2000
    dims = (0.01, 0.001, 0.025)                       # m_s = 0.5 rho A L
    mu = math.prod(dims) / (b * h * L)
    params = straight_beam(L, b, h, dims)
    f = frequencies_by_label(params)
    lam = euler_bernoulli_tip_mass(mu, 3)
    scale = lambda I: np.sqrt(E * I / (RHO * b * h * L**4)) / (2 * math.pi)
    flap = lam**2 * scale(b * h**3 / 12)
    chord1 = lam[0] ** 2 * scale(h * b**3 / 12)
    ours = np.array([f["flap1"], f["flap2"], f["flap3"]])
    np.testing.assert_allclose(ours, flap, rtol=1e-5)
    assert f["chord1"] == pytest.approx(chord1, rel=1e-5)


def test_no_tip_mass_gives_the_classic_3_5160():
    L, b, h = 1.0, 0.004, 0.002
    f = frequencies_by_label(straight_beam(L, b, h))
    lam2 = 2 * math.pi * f["flap1"] / math.sqrt(E * b * h**3 / 12 / (RHO * b * h * L**4))
    assert lam2 == pytest.approx(3.5160, abs=1e-4)


def test_thick_cantilever_with_tip_mass_matches_exact_timoshenko():
    L, b, h = 0.5, 0.1, 0.05                         # L/h = 10: shear and rotary inertia matter
    dims = (0.1, 0.05, 0.02)
    params = straight_beam(L, b, h, dims, N=16)
    f = frequencies_by_label(params)
    k = 10 * (1 + NU) / (12 + 11 * NU)
    m_tip = RHO * math.prod(dims)
    exact = timoshenko_tip_mass(L, b * h, b * h**3 / 12, k, m_tip, 3, 3000.0)
    ours = [f["flap1"], f["flap2"], f["flap3"]]
    np.testing.assert_allclose(ours, exact, rtol=1e-5)
    # and the shear/rotary effect the test resolves is far larger than its tolerance
    lam = euler_bernoulli_tip_mass(m_tip / (RHO * b * h * L), 3)
    eb = lam**2 * np.sqrt(E * b * h**3 / 12 / (RHO * b * h * L**4)) / (2 * math.pi)
    assert np.all((eb - exact) / exact > np.array([1e-3, 1e-2, 3e-2]))


# Out-of-plane (flapwise) bending of a uniform rotating cantilever, no hub:
# omega / sqrt(EI / rho A L^4) at speed parameter gamma = Omega sqrt(rho A L^4 / EI)
# (Wright, Smith, Thresher, Wang, J. Appl. Mech. 1982; Hodges & Rutkowski, AIAA J. 1981).
PUBLISHED_OUT_OF_PLANE = {
    1.0: (3.6817, 22.1810),
    2.0: (4.1373, 22.6149),
    3.0: (4.7973, 23.3203),
    4.0: (5.5850, 24.2734),
    5.0: (6.4495, 25.4461),
}


@pytest.mark.parametrize("gamma", sorted(PUBLISHED_OUT_OF_PLANE))
def test_rotating_uniform_cantilever_matches_published_table(gamma):
    """Square slender section at zero stagger: Z bending is out of the plane of rotation
    (labelled chord here), Y bending is in it (flap) and is spin-softened:
    omega_in^2 = omega_out^2 - Omega^2 exactly for the uniform beam without hub."""
    L, a = 1.0, 0.0005
    params = straight_beam(L, a, a, N=14)
    unit = math.sqrt(E * a**4 / 12 / (RHO * a * a * L**4))      # rad/s per dimensionless unit
    rpm = gamma * unit * 60 / (2 * math.pi)
    f = frequencies_by_label(params, rpm=rpm)
    out = np.array([f["chord1"], f["chord2"]]) * 2 * math.pi / unit
    inp = np.array([f["flap1"], f["flap2"]]) * 2 * math.pi / unit
    published = np.array(PUBLISHED_OUT_OF_PLANE[gamma])
    np.testing.assert_allclose(out, published, atol=1.5e-4)
    np.testing.assert_allclose(inp, np.sqrt(published**2 - gamma**2), atol=2e-4)


def test_static_centrifugal_stretch_matches_exact_bar_solution():
    """E A u'' + rho A Omega^2 (R_d + x + u) = 0, u(0) = 0, E A u'(L) = m_s Omega^2 (R_d + L + u(L)):
    F_1 of Eq. 10 on K_e + K_s (spin softening on u; the exact bar has no geometric stiffness)."""
    params = straight_beam(0.15, 0.04, 0.007, (0.04, 0.02, 0.007), N=12, disk_radius=0.15)
    beam = for_parameters(params)
    omega = 2 * math.pi * 30000 / 60
    q = np.linalg.solve(beam.K_e + omega**2 * beam.K_s1, beam.centrifugal_load(omega))
    L, Rd, m = 0.15, 0.15, params.shroud_mass
    EA, k = E * 0.04 * 0.007, omega * math.sqrt(RHO / E)
    # u = -(Rd + x) + Rd cos kx + C sin kx; the tip condition fixes C
    c, s = math.cos(k * L), math.sin(k * L)
    C = (EA * (1 + Rd * k * s) + m * omega**2 * Rd * c) / (EA * k * c - m * omega**2 * s)
    u_L = -(Rd + L) + Rd * c + C * s
    assert beam.tip_radial @ q == pytest.approx(u_L, rel=1e-9)


def test_tip_force_along_e_v_gives_exact_timoshenko_deflection():
    """Static tip load F along e_v(L) of a staggered untwisted blade:
    v_L = F L^3 / (3 E I_v) + F L / (k G A), w_L = 0."""
    params = Parameters.from_mapping({"blade": {"twist_deg": 0.0, "stagger_deg": 30.0},
                                      "reduced": {"N": 8}})
    beam = for_parameters(params)
    F = 1.0
    q = np.linalg.solve(beam.K_e, beam.tip.T @ np.array([F, 0.0]))
    b, h, L = 0.04, 0.007, 0.15
    k, G = 10 * (1 + NU) / (12 + 11 * NU), E / (2 * (1 + NU))
    exact = F * L**3 / (3 * E * b * h**3 / 12) + F * L / (k * G * b * h)
    v_L, w_L = beam.tip @ q
    assert v_L == pytest.approx(exact, rel=1e-12)
    assert abs(w_L) < 1e-12 * v_L


def test_matrices_symmetric_positive_definite_and_gyroscopic_skew():
    beam = for_parameters(Parameters())
    omega = 2 * math.pi * 8500 / 60
    K = beam.stiffness(omega)
    for X in (beam.M, beam.K_e, K):
        np.testing.assert_allclose(X, X.T, rtol=0, atol=1e-12 * np.abs(X).max())
        assert np.linalg.eigvalsh(X).min() > 0
    np.testing.assert_allclose(beam.K_c1, beam.K_c1.T, atol=1e-12 * np.abs(beam.K_c1).max())
    assert np.linalg.eigvalsh(beam.K_c1).min() > -1e-12 * np.abs(beam.K_c1).max()   # tension stiffens
    assert np.linalg.eigvalsh(beam.K_s1).max() <= 1e-12 * np.abs(beam.K_s1).max()   # spin softens
    for S in (beam.G1, beam.K_acc1):
        np.testing.assert_array_equal(S, -S.T)
        assert np.abs(S).max() > 0


def test_coriolis_modes_are_undamped_and_singular_points_of_the_hermitian_pencil():
    """G skew: the gyroscopic system conserves energy, so its eigenvalues are
    purely imaginary and K - w^2 M + i w G (Hermitian) is singular at each w."""
    params = Parameters()
    result = modal_analysis(params, rpm=12000, n_modes=6, coriolis=True)
    beam = for_parameters(params)
    omega = 2 * math.pi * 12000 / 60
    K, G = beam.stiffness(omega), beam.gyroscopic(omega)
    for mode in result.modes:
        assert abs(mode.damping_ratio) < 1e-9
        w = 2 * math.pi * mode.f_hz
        H = K - w**2 * beam.M + 1j * w * G
        eig = np.linalg.eigvalsh(H)
        assert np.abs(eig).min() < 1e-8 * np.abs(eig).max()
