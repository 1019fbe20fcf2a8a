"""The extended beam (reduced.torsion, reduced.shroud = "rigid") against exact solutions,
one term at a time: torsion with a tip inertia, warping held at the root, the tension of
twisted fibres, the propeller moment, the extension-twist coupling of pretwist, a
Timoshenko cantilever carrying an offset rigid body, and the contact arms."""

import math
import subprocess
import sys

import numpy as np
import pytest
import scipy.linalg
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from reduced_model.beam import for_parameters
from reduced_model.modal import modal_analysis
from reduced_model.reduction import undamped_modes
from reduced_model.section import rectangle
from reduced_model.system import build_system
from shroud.core.modes import label_modes
from shroud.params import Parameters

RHO, E, NU = 7800.0, 200e9, 0.3
G = E / (2 * (1 + NU))


def bar(L, b, h, shroud=None, N=12, stagger=0.0, twist=0.0, torsion=True, kind="rigid", alpha=0.0, Rd=0.0):
    """A straight (or pretwisted) blade; shroud = (l_s, b_s, t_s) or None for none."""
    dims = {"thickness": 0.0} if shroud is None else dict(zip(("length", "width", "thickness"), shroud))
    return Parameters.from_mapping({
        "blade": {"length": L, "width": b, "thickness": h, "stagger_deg": stagger, "twist_deg": twist,
                  "disk_radius": Rd},
        "material": {"E": E, "rho": RHO, "nu": NU}, "shroud": dims,
        "contact": {"enabled": shroud is not None, "alpha_deg": alpha},
        "reduced": {"N": N, "nr": 0, "torsion": torsion, "shroud": kind}})


def sign_changes(fn, lo, hi, steps):
    grid = np.linspace(lo, hi, steps)
    vals = np.array([fn(g) for g in grid])
    return [brentq(fn, grid[i], grid[i + 1], xtol=1e-12)
            for i in np.flatnonzero(np.sign(vals[:-1]) != np.sign(vals[1:]))]


def torsion_frequencies(beam, K):
    """Frequencies (Hz) of the modes labelled torsion, in order."""
    modes = undamped_modes(beam.M, K)
    labels, _ = label_modes(beam.tip_kinematics(modes.shapes))
    return np.array([f for f, lab in zip(modes.f_hz, labels) if lab.startswith("torsion")])


def vlasov_determinant(L, EGamma, k, m, I_tip):
    """Frequency function of E Gamma theta'''' - (k(x) theta')' = omega^2 m theta on [0, L]:
    theta(0) = theta'(0) = 0 (warping held), at L bimoment E Gamma theta'' = 0 and torque
    k theta' - E Gamma theta''' = omega^2 I_tip theta. State y = (theta, theta', B, T), an exact
    solve from the root (independent of the Galerkin code): the matrix exponential for a
    constant k (a number), an ODE integration for k(x) (a function)."""
    def det(f):
        om2 = (2 * math.pi * f) ** 2

        def system(kx):
            return np.array([[0, 1, 0, 0], [0, 0, 1 / EGamma, 0], [0, kx, 0, -1], [-om2 * m, 0, 0, 0]])
        y0 = np.array([[0, 0], [0, 0], [1, 0], [0, 1]], float)
        if callable(k):
            yL = solve_ivp(lambda x, y: (system(k(x)) @ y.reshape(4, 2)).ravel(), (0, L), y0.ravel(),
                           method="DOP853", rtol=1e-12, atol=1e-14).y[:, -1].reshape(4, 2)
        else:
            yL = scipy.linalg.expm(system(k) * L) @ y0
        rows = np.array([yL[2], yL[3] - om2 * I_tip * yL[0]])
        return np.linalg.det(rows / np.abs(rows).max(axis=1, keepdims=True))
    return det


def saint_venant_tip_inertia(L, GJ, rho_Ip, I_tip, count):
    """Roots of x tan x = rho Ip L / I_tip, x = omega L sqrt(rho Ip / G J): the free-warping
    torsion frequencies (Hz) of a cantilever with a tip inertia (x_k in ((k-1) pi, (k-1/2) pi))."""
    ratio = rho_Ip * L / I_tip
    xs = [brentq(lambda x: x * math.sin(x) - ratio * math.cos(x), j * math.pi, (j + 0.5) * math.pi, xtol=1e-14)
          for j in range(count)]
    return np.array(xs) / (L * math.sqrt(rho_Ip / GJ)) / (2 * math.pi)


def test_torsion_of_a_cantilever_with_tip_inertia_matches_the_transcendental_equation():
    """Slender square bar (warping negligible: sqrt(E Gamma / G J) = 0.5 mm on 2 m, below what the
    basis resolves, so the root warps freely: beam.warping_held) with a
    rigid box at the tip: omega L sqrt(rho Ip / G J) tan(omega L sqrt(rho Ip / G J)) = rho Ip L / I_tip."""
    L, a = 2.0, 0.01
    box = (0.04, 0.03, 0.01)
    params = bar(L, a, a, box, N=14)
    beam = for_parameters(params)
    J, Ip = rectangle(a, a).J, a**4 / 6
    I_tip = RHO * math.prod(box) * (box[0] ** 2 + box[1] ** 2) / 12
    exact = saint_venant_tip_inertia(L, G * J, RHO * Ip, I_tip, 3)
    ours = torsion_frequencies(beam, beam.K_e)[:3]
    np.testing.assert_allclose(ours, exact, rtol=1e-5)
    # the tip inertia matters far beyond that tolerance: without it, f1 = sqrt(G J / rho Ip) / 4 L
    assert exact[0] < 0.8 * math.sqrt(G * J / (RHO * Ip)) / (4 * L)


def test_held_root_warping_matches_the_exact_vlasov_solution():
    """The blade's own 40 x 7 mm section, untwisted, with a rigid shroud: the warping held at
    the root (E Gamma) raises torsion by several per cent; the Galerkin beam follows the exact
    fourth-order equation to 1e-6."""
    L, b, h = 0.15, 0.04, 0.007
    box = (0.04, 0.02, 0.007)
    params = bar(L, b, h, box, N=14)
    beam = for_parameters(params)
    s = rectangle(b, h)
    I_tip = RHO * math.prod(box) * (box[0] ** 2 + box[1] ** 2) / 12
    ours = torsion_frequencies(beam, beam.K_e)[:2]
    det = vlasov_determinant(L, E * s.warping, G * s.J, RHO * s.I_p, I_tip)
    exact = [sign_changes(det, 0.97 * f, 1.03 * f, 13)[0] for f in ours]
    np.testing.assert_allclose(ours, exact, rtol=1e-6)
    free = saint_venant_tip_inertia(L, G * s.J, RHO * s.I_p, I_tip, 2)
    assert np.all(ours / free - 1 > 0.03)


def test_tension_of_twisted_fibres_matches_the_exact_variable_coefficient_solution():
    """K_e + Omega^2 K_c (no spin softening): the centrifugal tension P(x) stiffens the twist
    by P I_p / A: (G J + P(x) I_p / A) theta' in the exact equation."""
    L, b, h, Rd = 0.15, 0.04, 0.007, 0.15
    params = bar(L, b, h, N=14, Rd=Rd)
    beam = for_parameters(params)
    s = rectangle(b, h)
    omega = 2 * math.pi * 20000 / 60
    A = b * h
    P = lambda x: omega**2 * RHO * A * (Rd * (L - x) + 0.5 * (L**2 - x**2))
    ours = torsion_frequencies(beam, beam.K_e + omega**2 * beam.K_c1)[0]
    det = vlasov_determinant(L, E * s.warping, lambda x: G * s.J + P(x) * s.I_p / A, RHO * s.I_p, 0.0)
    exact = sign_changes(det, 0.995 * ours, 1.005 * ours, 3)[0]
    assert ours == pytest.approx(exact, rel=1e-6)
    at_rest = torsion_frequencies(beam, beam.K_e)[0]
    assert ours / at_rest - 1 > 0.01                     # the effect is resolved


@pytest.mark.parametrize("stagger", [0.0, 30.0, 90.0])
def test_propeller_moment_shifts_torsion_by_omega_squared_times_the_inertia_difference(stagger):
    """Spin softening alone on a uniform untwisted bar: omega^2 = omega_0^2 + Omega^2 (I_YY - I_ZZ) / I_p
    = omega_0^2 - Omega^2 (I_w - I_v) cos(2 beta) / I_p: the classic rotating flat plate (chord in
    the plane of rotation, beta = 90 deg: omega^2 = omega_0^2 + Omega^2 (I_w - I_v) / I_p), the
    section turning towards the plane of rotation (Bielawa, Rotary Wing Structural Dynamics, 6.6)."""
    L, b, h = 0.15, 0.04, 0.007
    beam = for_parameters(bar(L, b, h, N=12, stagger=stagger))
    s = rectangle(b, h)
    omega = 2 * math.pi * 12000 / 60
    f0 = torsion_frequencies(beam, beam.K_e)[:2]
    f = torsion_frequencies(beam, beam.K_e + omega**2 * beam.K_s1)[:2]
    shift = -omega**2 * (s.I_w - s.I_v) * math.cos(2 * math.radians(stagger)) / s.I_p
    np.testing.assert_allclose((2 * math.pi * f) ** 2, (2 * math.pi * f0) ** 2 + shift, rtol=1e-9)
    if stagger != 30.0:
        assert abs(f[0] / f0[0] - 1) > 1e-3


def test_pretwist_couples_extension_and_twist_as_in_rosen_theory():
    """A pretwisted strip pulled at the tip untwists: N = EA u' + E kappa Ip theta' = F, torque
    (G J + E kappa^2 I_rr) theta' + E kappa Ip u' - E Gamma theta''' = 0, theta'(0) = 0, theta''(L) = 0:
    theta(L) = -kappa Ip F / (A k) (L - lam tanh(L / lam)), k = G J + E kappa^2 (I_rr - Ip^2 / A),
    lam^2 = E Gamma / k (Rosen 1980; Vlasov for the held root)."""
    L, b, h, twist = 0.15, 0.04, 0.007, 40.0
    params = bar(L, b, h, N=16, stagger=30.0, twist=twist)
    beam = for_parameters(params)
    s = rectangle(b, h)
    F = 1000.0
    q = np.linalg.solve(beam.K_e, beam.tip_radial * F)
    kappa, A = math.radians(twist) / L, b * h
    k = G * s.J + E * kappa**2 * (s.I_rr - s.I_p**2 / A)
    lam = math.sqrt(E * s.warping / k)
    exact = -kappa * s.I_p * F / (A * k) * (L - lam * math.tanh(L / lam))
    assert beam.tip_body[3] @ q == pytest.approx(exact, rel=1e-8)
    assert exact < 0


def timoshenko_tip_body(L, A, I, k, m, d, J_c, count, f_max):
    """Exact Timoshenko clamped-free frequencies (Hz) with a rigid tip body: mass m, centroid d
    beyond the tip on the axis, rotary inertia J_c about its centroid. Transfer matrix of
    y = (w, psi, M, Q): w' = psi + Q/kGA, psi' = M/EI, M' = -Q - rho I w^2 psi, Q' = -rho A w^2 w;
    at L: Q = m w^2 (w + d psi), M = w^2 (m d w + (J_c + m d^2) psi)."""
    kGA, EI = k * G * A, E * I

    def det(f):
        om2 = (2 * math.pi * f) ** 2
        Amat = np.array([[0, 1, 0, 1 / kGA], [0, 0, 1 / EI, 0],
                         [0, -RHO * I * om2, 0, -1], [-RHO * A * om2, 0, 0, 0]])
        T = scipy.linalg.expm(Amat * L)[:, 2:]
        rows = np.array([T[2] - om2 * (m * d * T[0] + (J_c + m * d * d) * T[1]),
                         T[3] - om2 * m * (T[0] + d * T[1])])
        return np.linalg.det(rows / np.abs(rows).max(axis=1, keepdims=True))
    return np.array(sign_changes(det, f_max / 600, f_max, 600)[:count])


def test_timoshenko_cantilever_with_an_offset_rigid_shroud_matches_its_exact_equation():
    L, b, h = 0.5, 0.1, 0.05                          # thick: shear and rotary inertia matter
    box = (0.1, 0.06, 0.04)                           # l_s (along Z), b_s (along Y), t_s (along X)
    params = bar(L, b, h, box, N=16, torsion=False)
    f = modal_analysis(params, rpm=0.0, n_modes=8, coriolis=False).by_label()
    k = 10 * (1 + NU) / (12 + 11 * NU)
    m, d = RHO * math.prod(box), box[2] / 2
    flap = timoshenko_tip_body(L, b * h, b * h**3 / 12, k, m, d, m * (box[2] ** 2 + box[1] ** 2) / 12, 2, 3000.0)
    chord = timoshenko_tip_body(L, b * h, h * b**3 / 12, k, m, d, m * (box[2] ** 2 + box[0] ** 2) / 12, 1, 3000.0)
    np.testing.assert_allclose([f["flap1"], f["flap2"], f["chord1"]], [*flap, *chord], rtol=1e-5)
    # and the offset and rotary inertia are far beyond that tolerance (the point mass is stiffer)
    point = modal_analysis(params.updated({"reduced.shroud": "point"}), 0.0, 8, False).by_label()
    assert point["flap2"] / f["flap2"] - 1 > 0.02


def test_matrices_symmetric_positive_definite_and_gyroscopic_skew_with_torsion():
    params = Parameters.from_mapping({"reduced": {"torsion": True, "shroud": "rigid"}})
    beam = for_parameters(params)
    assert beam.dofs == 36
    K = beam.stiffness(2 * math.pi * 8500 / 60)
    for X in (beam.M, beam.K_e, K):
        np.testing.assert_allclose(X, X.T, rtol=0, atol=1e-12 * np.abs(X).max())
        assert np.linalg.eigvalsh(X).min() > 0
    np.testing.assert_array_equal(beam.G1, -beam.G1.T)
    np.testing.assert_array_equal(beam.K_acc1, -beam.K_acc1.T)
    TH, PZ = slice(30, 36), slice(24, 30)
    assert np.abs(beam.G1[TH, PZ]).max() > 0          # Coriolis couples the twist rate and the tilt rates
    result = modal_analysis(params, rpm=12000, n_modes=6, coriolis=True)
    assert max(abs(m.damping_ratio) for m in result.modes) < 1e-9
    assert "torsion1" in result.by_label()


def test_friction_at_the_rigid_shroud_faces_twists_the_blade_by_its_arm():
    """A tangential force F along e_ws on the side-2 face (its points at b_s/2 along e_vs) is a
    torque F b_s / 2 about X: tip twist T (L - lam tanh(L/lam)) / G J (warping held at the root);
    a normal force on the same face, whose centre lies on the e_vs axis, twists nothing."""
    L, b, h = 0.15, 0.04, 0.007
    box = (0.04, 0.02, 0.007)
    params = bar(L, b, h, box, N=16, stagger=30.0, alpha=15.0)
    system = build_system(params.updated({"speed.rpm": 0.0}), reduced=False)
    beam = for_parameters(params)
    c = system.contact
    s = rectangle(b, h)
    F = 10.0
    lam = np.zeros(c.W.shape[0])
    lam[c.tangent_row[c.side == 2]] = F * c.weight[c.side == 2]
    twist = beam.tip_body[3] @ np.linalg.solve(beam.K_e, c.W.T @ lam)
    lam_v = math.sqrt(E * s.warping / (G * s.J))
    assert twist == pytest.approx(F * box[1] / 2 * (L - lam_v * math.tanh(L / lam_v)) / (G * s.J), rel=1e-8)
    lam[:] = 0.0
    lam[c.normal_row[c.side == 2]] = F * c.weight[c.side == 2]
    assert abs(beam.tip_body[3] @ np.linalg.solve(beam.K_e, c.W.T @ lam)) < 1e-9 * abs(twist)


def test_point_shroud_without_torsion_is_the_papers_model():
    """The defaults build 5 fields and contact at the tip centre (Eq. 7), as before the switches."""
    beam = for_parameters(Parameters())
    assert beam.dofs == 30
    s = build_system(Parameters(), reduced=True)
    assert s.contact.W.shape == (2, 6)


@pytest.mark.parametrize("setting, key", [("reduced.shroud=beam", "reduced.shroud"),
                                          ("reduced.torsion=maybe", "reduced.torsion"),
                                          ("reduced.torsion=2", "reduced.torsion")])
def test_bad_switches_end_with_one_line_and_status_2(setting, key):
    proc = subprocess.run([sys.executable, "-m", "workbench.cli", "modal", "--set", setting],
                          capture_output=True, text=True)
    assert proc.returncode == 2
    assert proc.stdout == ""
    assert proc.stderr.count("\n") == 1 and proc.stderr.startswith(f"error: {key}:")


def test_a_number_for_torsion_in_a_scene_is_refused(tmp_path):
    scene = tmp_path / "s.toml"
    scene.write_text('study = "table1"\n[reduced]\ntorsion = 1\n')
    out = tmp_path / "out"
    proc = subprocess.run([sys.executable, "-m", "workbench.cli", "run", str(scene), "--out", str(out)],
                          capture_output=True, text=True)
    assert proc.returncode == 2 and proc.stderr.startswith("error: reduced.torsion:")
    assert proc.stderr.count("\n") == 1 and not out.exists()


@pytest.mark.parametrize("stagger", [30.0, -60.0])
def test_static_propeller_moment_turns_the_section_towards_the_plane_of_rotation(stagger):
    """The centrifugal field's moment on a turned section, -Omega^2 rho I_YZ per unit length,
    with its stiffness Omega^2 rho (I_YY - I_ZZ): E Gamma theta'''' - G J theta'' + s theta = m_t,
    theta(0) = theta'(0) = 0, bimoment and torque zero at the tip, solved exactly (matrix
    exponential of the state (theta, theta', B, T, 1)). The section turns towards the plane of
    rotation (the chord towards Y, beta towards +-90 deg)."""
    L, b, h = 0.15, 0.04, 0.007
    beam = for_parameters(bar(L, b, h, N=14, stagger=stagger))
    sec = rectangle(b, h)
    omega = 2 * math.pi * 15000 / 60
    beta = math.radians(stagger)
    I_YZ = (sec.I_v - sec.I_w) * math.cos(beta) * math.sin(beta)
    s = omega**2 * RHO * (sec.I_v - sec.I_w) * math.cos(2 * beta)
    m_t = -omega**2 * RHO * I_YZ
    A = np.zeros((5, 5))
    A[0, 1], A[1, 2], A[2, 1], A[2, 3], A[3, 0], A[3, 4] = 1, 1 / (E * sec.warping), G * sec.J, -1, s, -m_t
    T = scipy.linalg.expm(A * L)
    # unknown B(0), T(0): B(L) = T(L) = 0
    coef = np.linalg.solve(T[np.ix_([2, 3], [2, 3])], -T[[2, 3], 4])
    exact = T[0, [2, 3]] @ coef + T[0, 4]
    q = np.linalg.solve(beam.K_e + omega**2 * beam.K_s1, beam.centrifugal_load(omega))
    twist = beam.tip_body[3] @ q
    assert twist == pytest.approx(exact, rel=1e-8)
    assert np.sign(twist) == np.sign(math.sin(2 * beta))     # |beta| grows towards 90 deg


def test_body_terms_match_point_sums_and_the_exact_centrifugal_potential_of_a_turned_box():
    """The rigid-body formula in the moments (m, S, Q) against a second method: sums over the
    27 Gauss points of the box (exact for these quadratic integrands), with the potential
    V(s) = -1/2 Omega^2 sum m_i |Pi (R e_X + U + exp([r x]) p_i)|^2 of the exact rotation
    differentiated numerically: its gradient is -f_c1 and its Hessian K_s1 (per Omega^2)."""
    from reduced_model.beam import TipBody, body_terms, cross_matrix
    m, (l, w, t), angle, R = 0.05, (0.04, 0.02, 0.007), 0.7, 0.3
    box = TipBody.box(m, l, w, t, angle)
    terms = body_terms(box.mass, box.S, box.Q, R)
    g, gw = np.polynomial.legendre.leggauss(3)
    c, s = math.cos(angle), math.sin(angle)
    e_vs, e_ws = np.array([0, c, s]), np.array([0, -s, c])
    pts = [(0.5 + 0.5 * a) * t * np.eye(3)[0] + 0.5 * b * w * e_vs + 0.5 * d * l * e_ws
           for a in g for b in g for d in g]
    wts = [m * wa * wb * wd / 8 for wa in gw for wb in gw for wd in gw]
    B = [np.hstack([np.eye(3), -cross_matrix(p)]) for p in pts]
    Ez = cross_matrix(np.array([0.0, 0.0, 1.0]))
    np.testing.assert_allclose(terms.M[0], sum(wi * Bi.T @ Bi for wi, Bi in zip(wts, B)), atol=1e-15)
    np.testing.assert_allclose(terms.G1[0], sum(wi * Bi.T @ (2 * Ez) @ Bi for wi, Bi in zip(wts, B)), atol=1e-15)
    Pi = np.diag([1.0, 1.0, 0.0])

    def V(sv):
        rot = scipy.linalg.expm(cross_matrix(sv[3:]))
        return -0.5 * sum(wi * np.sum((Pi @ (R * np.eye(3)[0] + sv[:3] + rot @ p)) ** 2) for wi, p in zip(wts, pts))
    h = 1e-4
    E6 = np.eye(6) * h
    grad = np.array([(V(E6[i]) - V(-E6[i])) / (2 * h) for i in range(6)])
    hess = np.array([[(V(E6[i] + E6[j]) - V(E6[i] - E6[j]) - V(-E6[i] + E6[j]) + V(-E6[i] - E6[j])) / (4 * h * h)
                      for j in range(6)] for i in range(6)])
    np.testing.assert_allclose(-grad, terms.f_c1[0], rtol=1e-7, atol=1e-12)
    np.testing.assert_allclose(hess, terms.K_s1[0], rtol=1e-5, atol=1e-7 * np.abs(hess).max())


@pytest.mark.parametrize("stagger", [0.0, 30.0, 75.0])
def test_extended_beam_takes_the_sections_shear_coefficients_per_axis(monkeypatch, stagger):
    """Static tip forces along e_v(L) and e_w(L) of a staggered, untwisted blade give the exact
    Timoshenko deflections F L^3 / (3 E I) + F L / (kappa G A) with each axis' own kappa, and no
    cross deflection. The blade's rectangle has equal coefficients by Cowper's definition, so the
    section is asked here for the energy ones (0.41 for shear across the thickness, 0.83 along
    the chord at nu = 0.3), which differ: a shear stiffness turned wrongly with the section
    would couple the two axes."""
    from reduced_model.beam import beam_matrices
    from reduced_model.section import SectionProperties

    monkeypatch.setattr(SectionProperties, "shear_coefficients",
                        lambda self, nu: tuple(f.kappa(nu, "energy") for f in self.flexure))
    b, h, L = 0.04, 0.007, 0.15
    params = Parameters.from_mapping({"blade": {"twist_deg": 0.0, "stagger_deg": stagger, "length": L},
                                      "reduced": {"N": 8, "torsion": True}})
    beam_matrices.cache_clear()                     # built with the energy coefficients, and not kept
    beam = for_parameters(params)
    beam_matrices.cache_clear()
    kappa_v, kappa_w = (f.kappa(NU, "energy") for f in rectangle(b, h).flexure)
    assert kappa_v < 0.5 < 0.8 < kappa_w
    for axis, I, kappa in ((0, b * h**3 / 12, kappa_v), (1, h * b**3 / 12, kappa_w)):
        F = np.zeros(2)
        F[axis] = 1.0
        q = np.linalg.solve(beam.K_e, beam.tip.T @ F)
        deflection = beam.tip @ q
        assert deflection[axis] == pytest.approx(L**3 / (3 * E * I) + L / (kappa * G * b * h), rel=1e-10)
        assert abs(deflection[1 - axis]) < 1e-10 * deflection[axis]
