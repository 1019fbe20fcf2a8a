"""Harmonic balance against exact solutions, the linear limits, a second method and the time domain."""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.optimize

from comparisons._hb import crossings
from shroud.analysis.hb import checkpoint, run_hb
from shroud.analysis.transient import contact_law_for
from shroud.analysis.api import build_system
from shroud.core import floquet
from shroud.core import harmonic_balance as hb
from shroud.core.contact import SEPARATE, STICK, contact_law
from shroud.core.newmark import NewmarkScheme, integrate, stuck_stiffness
from shroud.core.signals import amplitude
from shroud.core.system import ContactElements, StructuralSystem
from shroud.params import Parameters

# --- Den Hartog (1931): one DOF with Coulomb friction, continuous sliding -----------------

MASS, STIFF, P0, FRICTION = 1.0, 1e4, 10.0, 2.0         # kg, N/m, N, mu N in N (w_n = 100 rad/s)


def den_hartog(w: float):
    """Exact steady state of m x'' + k x + F sign(x') = P0 sin(w t) without stops.

    Over the half period in which x' > 0 the motion is linear with the force
    -F: it starts at x = -X, x' = 0 at the forcing phase phi and ends at
    x = +X, x' = 0 half a period later (symmetry). The two end conditions
    give X and phi (Den Hartog's construction; solved here to round-off).
    Returns (X, phi, x(s)) with s the time since the start of the half.
    """
    wn, h, Pd = math.sqrt(STIFF / MASS), math.pi / w, P0 / (STIFF - MASS * w * w)

    def motion(s, X, phi):
        A, B = -X - Pd * math.sin(phi) + FRICTION / STIFF, -Pd * w * math.cos(phi) / wn
        x = A * np.cos(wn * s) + B * np.sin(wn * s) + Pd * np.sin(w * s + phi) - FRICTION / STIFF
        v = -A * wn * np.sin(wn * s) + B * wn * np.cos(wn * s) + Pd * w * np.cos(w * s + phi)
        return x, v

    def ends(u):
        x, v = motion(h, *u)
        return [x - u[0], v]

    X, phi = scipy.optimize.fsolve(ends, [abs(Pd), -math.pi / 2 if w < wn else math.pi / 2], xtol=1e-14)
    s = np.linspace(0, h, 2001)
    assert motion(s, X, phi)[1][1:-1].min() > 0          # it slides all the half period
    return X, phi, lambda s: motion(s, X, phi)[0]


def exact_fundamental(w: float) -> complex:
    """First harmonic a_1 - i b_1 of the exact motion (x = a_1 cos w t + b_1 sin w t + ...)."""
    X, phi, x_half = den_hartog(w)
    n, T = 8192, 2 * math.pi / w
    s = (np.arange(n) / n * T - phi / w) % T              # time since x was -X
    x = np.where(s < T / 2, x_half(np.minimum(s, T / 2)), -x_half(np.maximum(s - T / 2, 0.0)))
    return complex(np.fft.rfft(x)[1] / n * 2)


def friction_oscillator(w: float) -> tuple[StructuralSystem, object]:
    """The oscillator as a raw StructuralSystem: a preloaded contact whose normal coordinate never moves
    (W's normal row is zero) and a very stiff tangential spring (kt = 10^4 k): Coulomb friction mu N0."""
    contact = ContactElements(W=np.array([[0.0], [1.0]]), normal_row=np.array([0]), tangent_row=np.array([1]),
                              side=np.array([1]), weight=np.array([1.0]))
    system = StructuralSystem(model="sdof", M=np.eye(1) * MASS, C=np.zeros((1, 1)), K=np.array([[STIFF]]),
                              f_const=np.zeros(1), f_aero=np.array([P0]), omega_e=w, tip=np.array([[1.0], [0.0]]),
                              contact=contact)
    return system, contact_law(contact, kn=1e6, kt=1e8, mu=0.2, N0=FRICTION / 0.2)


@pytest.mark.parametrize("w", [70.0, 150.0])
def test_den_hartog_steady_state(w):
    X, _, _ = den_hartog(w)
    c1 = exact_fundamental(w)
    system, law = friction_oscillator(w)
    sol = hb.solve(system, law, H=25, samples=1024)
    assert sol.converged
    h1 = sol.tip[1, 0] - 1j * sol.tip[2, 0]
    assert sol.amplitude_v_L == pytest.approx(X, rel=5e-3)
    assert abs(h1) == pytest.approx(abs(c1), rel=5e-3)
    assert abs(np.angle(h1 / c1)) < 5e-3 * math.pi
    spp = 1024                                            # the time domain on the same system
    tr = integrate(system, law, NewmarkScheme(2 * math.pi / w / spp), 150 * spp)
    assert amplitude(tr.tip[:, 0], spp) == pytest.approx(X, rel=5e-3)


# --- the analytic Jacobian ----------------------------------------------------------------

def test_jacobian_through_the_law_matches_finite_differences():
    """Impact, stick and slip on both sides of the reduced beam near its resonance (condensed form)."""
    p = Parameters().updated({"contact.gap": 2e-5, "speed.rpm": 9000.0})
    system = build_system(p, "reduced")
    law = contact_law_for(system, p.contact)
    basis = hb.fourier(4, 64)
    lin = hb.linear_harmonics(system, 4)
    X = hb.linear_solution(lin) * 3.0
    b = hb.balance(X, lin, law, basis)
    states = set(np.unique(b.contact.state))
    assert states == {0, 1, 2}                           # every branch of the law is exercised
    h = 1e-12
    J = np.column_stack([(hb.balance(X + h * e, lin, law, basis).R - hb.balance(X - h * e, lin, law, basis).R)
                         / (2 * h) for e in np.eye(X.size)])
    assert np.abs(J - b.J).max() <= 1e-5 * np.abs(b.J).max()


# --- the linear limits ----------------------------------------------------------------------

def test_a_gap_never_reached_gives_the_linear_solution():
    p = Parameters().updated({"contact.gap": 5e-3, "speed.rpm": 8000.0})
    system = build_system(p, "full")
    sol = hb.solve(system, contact_law_for(system, p.contact), H=5)
    assert not np.any(sol.contact.N)
    Z = system.K - system.omega_e ** 2 * system.M + 1j * system.omega_e * system.C
    q1 = np.linalg.solve(Z, -1j * system.f_aero)          # the linear harmonic response
    tip1 = system.tip @ q1
    v = sol.tip[1, 0] - 1j * sol.tip[2, 0]
    assert abs(v - tip1[0]) <= 1e-8 * abs(tip1[0])
    assert np.abs(sol.tip[3:]).max() <= 1e-8 * abs(tip1[0])   # no higher harmonics


def test_a_fully_stuck_contact_is_the_linear_blade_with_contact_springs():
    """A large preload and friction keep both shroud contacts stuck all period: harmonic 1 of the tip is
    that of K + W^T diag(kn, kt) W."""
    p = Parameters().updated({"contact.N0": 5e4, "contact.mu": 5.0, "speed.rpm": 12000.0})
    system = build_system(p, "reduced")
    law = contact_law_for(system, p.contact)
    sol = hb.solve(system, law, H=5)
    assert np.all(sol.contact.state == 1)
    W = np.asarray(system.contact.W)
    K = system.K + W.T @ stuck_stiffness(law) @ W
    w = system.omega_e
    tip1 = system.tip @ np.linalg.solve(K - w * w * system.M + 1j * w * system.C, -1j * system.f_aero)
    v = sol.tip[1:3, :].T @ np.array([1.0, -1j])
    assert np.abs(v - tip1).max() <= 1e-9 * np.abs(tip1).max()


# --- the beam over a speed range ------------------------------------------------------------

@pytest.mark.parametrize("reduced", [True, False])
def test_the_beams_speed_range_systems_are_the_per_speed_builds(reduced):
    """The modes interpolated in Omega^2 (at_speed) against the eigenproblem solved at each speed
    (build_system, what the time domain uses): the contact receptance W Z^-1 W^T and the tip response at
    harmonics 1-3 of the excitation agree to 1e-8, off the interpolation nodes and across panels."""
    from reduced_model.system import at_speed
    p = Parameters().updated({"contact.gap": 1e-4})
    one = at_speed(p, reduced)
    for rpm in (5123.0, 9999.0, 13777.0, 19501.0):
        a, b = one(rpm), build_system(p.updated({"speed.rpm": rpm}), "reduced" if reduced else "full")
        for k in (1, 2, 3):
            w = k * b.omega_e
            ra, rb = (np.vstack([s.contact.W, s.tip]) @ np.linalg.solve(
                s.K - w * w * s.M + 1j * w * s.C, np.column_stack([s.contact.W.T, s.f_aero])) for s in (a, b))
            assert np.abs(ra - rb).max() <= 1e-8 * np.abs(rb).max()
    from reduced_model.reduction import PANEL_RPM
    assert all(one.modes.errors[int(rpm // PANEL_RPM)] <= 1e-7 for rpm in (5123.0, 9999.0, 13777.0, 19501.0))


@pytest.mark.parametrize("reduced", [True, False])
def test_the_beams_compiled_linear_part_is_the_condensation_of_their_system(reduced):
    """BeamOverSpeed.harmonics (interpolation, damping, assembly and condensation in one compiled call,
    what the continuation's corrector uses) against the core's condensation (with LAPACK's solves) of the
    system the same speed-range model builds there, off nodes, on a node and at a panel's end."""
    from reduced_model.system import at_speed
    one = at_speed(Parameters().updated({"contact.gap": 1e-4}), reduced)
    for rpm in (5000.0, 7777.7, 10000.0, 16543.2):
        a, s = one.harmonics(rpm, 6), one(rpm)
        W, tip = s.contact.W, s.tip
        b = hb.linear_harmonics(s, 6)
        assert np.abs(a.L - b.L).max() <= 1e-12 * np.abs(b.L).max()
        assert np.abs(a.Fr - b.Fr).max() <= 1e-12 * np.abs(b.Fr).max()
        for k in (0, 1, 2):                  # the receptance itself, solved by LAPACK
            w = k * s.omega_e
            Z = s.K - w * w * s.M + 1j * w * s.C
            R = W @ np.linalg.solve(Z, W.T)
            assert np.abs(np.linalg.inv(R) - a.Z[k]).max() <= 1e-10 * np.abs(a.Z[k]).max()
            assert np.abs(tip @ np.linalg.solve(Z, W.T) - a.tip_lam[k]).max() <= 1e-10 * np.abs(a.tip_lam[k]).max()


def test_the_extended_beams_modal_coordinates_mean_the_same_across_panels():
    """The extended beam has more contact coordinates (8) than modes (6), so its balance runs on modal
    coordinates: they must mean the same from one speed panel to the next (the continuation stopped at
    10000 r/min, a panel's end, when a mode's sign flipped there) and through the veering of flap2 and
    torsion1 near 13842 r/min, where the two eigenvectors turn within 1 r/min (it stopped there too)."""
    from reduced_model.models import EXTENDED
    from reduced_model.system import at_speed
    one = at_speed(Parameters().updated(EXTENDED), True)
    for edge in (7500.0, 10000.0, 12500.0, 13842.0):
        a, b = one.modes.at(2 * np.pi / 60 * (edge - 1e-3))[1], one.modes.at(2 * np.pi / 60 * (edge + 1e-3))[1]
        assert np.abs(a - b).max() <= 1e-5 * np.abs(a).max()


# --- stability: monodromy against Hill's method ------------------------------------------------

@pytest.mark.parametrize("rpm, mu", [(9000.0, 0.0), (8000.0, 0.3)])
def test_floquet_multipliers_by_monodromy_and_by_hill_agree(rpm, mu):
    p = Parameters().updated({"contact.gap": 1e-4, "contact.mu": mu, "speed.rpm": rpm})
    system = build_system(p, "reduced")
    law = contact_law_for(system, p.contact)
    H = 12
    sol = hb.solve(system, law, H=H, samples=1024)
    lin_full = hb.linear_harmonics(system, H, condense=False)
    _, _, Q = hb.state_vector(system, sol, hb.linear_harmonics(system, H))
    b = hb.balance(Q.ravel(), lin_full, law, sol.basis)
    assert np.linalg.norm(b.R) <= 1e-8 * np.linalg.norm(lin_full.Fr)   # the same solution on all DOFs
    assert np.any(b.contact.N > 0)
    Phi = floquet.monodromy(system.M, system.C, system.K, system.contact.W, law, b.contact.state,
                            b.contact.F, system.omega_e)
    mono = floquet.multipliers(Phi)
    s = floquet.hill_exponents(b.J, system.M, system.C, system.omega_e, H)
    hill = np.exp(s * 2 * math.pi / system.omega_e)
    # Hill's method takes the sliders' history derivative at s = 0 (the HB Jacobian's): a small
    # difference with friction, none without
    assert np.abs(hill).max() == pytest.approx(np.abs(mono).max(), abs=0.01 if mu == 0 else 0.03)


# --- against the time domain ----------------------------------------------------------------

def _time_domain(p: Parameters, model: str, rpm: float, periods: int = 150, q0=None, v0=None):
    q = p.updated({"speed.rpm": rpm})
    system = build_system(q, model)
    spp = q.time.steps_per_period
    tr = integrate(system, contact_law_for(system, q.contact), NewmarkScheme(q.time_step), spp * periods,
                   q0=q0, v0=v0)
    return tr, spp


@pytest.mark.parametrize("model", ["reduced", "full", "extended"])
def test_every_p1_time_domain_point_lies_on_a_stable_hb_branch(model):
    """Fig. 11a cases: where a run from rest settles on P1, a stable HB point is within 1 %."""
    from shroud.core.signals import detect_period
    p = Parameters().updated({"contact.gap": 1e-4})
    branch = run_hb(p, model, 6000.0, 18000.0, harmonics=12, samples=512)
    assert branch.complete
    checked = 0
    for rpm in (7000.0, 9000.0, 11000.0, 16000.0):
        tr, spp = _time_domain(p, model, rpm)
        if detect_period(tr.tip[:, 0], spp) != 1:
            continue
        a = amplitude(tr.tip[:, 0], spp)
        near = crossings(branch, rpm, stable=True)
        assert near and min(abs(x / a - 1) for x in near) < 0.01, (rpm, a, near)
        checked += 1
    assert checked >= 3


def test_a_time_run_leaves_an_unstable_hb_state_and_stays_on_a_stable_one():
    """At 12500 r/min (gap 0.1 mm) three P1 states coexist; a run started on the unstable one ends on a
    stable one, a run started on a stable one stays there."""
    p = Parameters().updated({"contact.gap": 1e-4})
    branch = run_hb(p, "reduced", 9000.0, 16000.0, harmonics=12, samples=512)
    rpm = 12500.0
    stable_amplitudes = crossings(branch, rpm, stable=True)
    assert len(stable_amplitudes) == 2 and len(crossings(branch, rpm, stable=False)) == 1
    for stable_wanted in (True, False):
        point = _hb_state_at(p, rpm, branch, stable_wanted)
        assert point.stable is stable_wanted
        system = build_system(p.updated({"speed.rpm": rpm}), "reduced")
        lin = hb.linear_harmonics(system, 12)
        sol = hb.solve(system, contact_law_for(system, p.contact), 12, 512, X0=point.X, lin=lin)   # its forces
        q0, v0, _ = hb.state_vector(system, sol, lin)
        tr, spp = _time_domain(p, "reduced", rpm, periods=200, q0=q0, v0=v0)
        a_end = amplitude(tr.tip[:, 0], spp)
        if stable_wanted:
            assert a_end == pytest.approx(sol.amplitude_v_L, rel=0.01)
        else:
            assert abs(a_end / sol.amplitude_v_L - 1) > 0.02
            assert min(abs(a_end / a - 1) for a in stable_amplitudes) < 0.01


def _hb_state_at(p, rpm, branch, stable):
    """An HB solution at ``rpm`` on a stretch of the branch with the wanted stability (Newton from it)."""
    for i in range(len(branch.rpm) - 1):
        r0, r1 = branch.rpm[i], branch.rpm[i + 1]
        if (min(r0, r1) <= rpm <= max(r0, r1) and r0 != r1 and branch.stable[i] is stable
                and branch.stable[i + 1] is stable):
            t = (rpm - r0) / (r1 - r0)
            X0 = (1 - t) * branch.X[i] + t * branch.X[i + 1]
            return checkpoint(p, "reduced", rpm, harmonics=12, samples=512, start=X0, retry=False)
    raise AssertionError(f"no {'stable' if stable else 'unstable'} stretch at {rpm}")


def test_an_orbit_that_sticks_from_the_touch_is_as_stable_as_the_time_domain_says():
    """Full beam, gap 0.1 mm, 12300 r/min on the upper branch: sampled at 512 instants the shroud's
    orbit sticks from the sample it touches at (its neighbours at 4096 samples slide first). Its slider
    holds z = w(t_c), which moves with the touch time t_c: without that term in the monodromy the point
    came out unstable (|multiplier| 1.03, a period-1 state that should leave within ~150 periods);
    a time run started on it stays on it for 400 periods."""
    p = Parameters().updated({"contact.gap": 1e-4})
    rpm = 12300.0
    branch = run_hb(p, "full", 6000.0, rpm, harmonics=10, samples=512)     # up the resonance to 12300
    sol = checkpoint(p, "full", rpm, harmonics=10, samples=512, start=branch.X[-1], retry=False)
    system = build_system(p.updated({"speed.rpm": rpm}), "full")
    law = contact_law_for(system, p.contact)
    lin = hb.linear_harmonics(system, 10)
    state = hb.balance(sol.X, lin, law, sol.basis, jacobian=False).contact.state[0]
    touch = np.flatnonzero((state != SEPARATE) & (np.roll(state, 1) == SEPARATE))
    assert touch.size == 1 and state[touch[0]] == STICK          # the case in point: stuck from the touch
    assert sol.stable and sol.largest_multiplier[sol.dofs] < 0.99
    q0, v0, _ = hb.state_vector(system, hb.solve(system, law, 10, 512, X0=sol.X, lin=lin), lin)   # its forces
    tr, spp = _time_domain(p, "full", rpm, periods=400, q0=q0, v0=v0)
    assert amplitude(tr.tip[:, 0], spp) == pytest.approx(sol.amplitude_v_L, rel=0.01)


def test_a_small_gap_whose_first_point_folds_in_the_load_runs_the_whole_range():
    """Fig. 11 contact (alpha 30 deg, kt 5e6 N/m), 10 um gap, mu 0.1: at 4000 r/min Newton fails from the
    linear solution and the solution folds back in the load (near 0.69 of it, down to 0.60, ...), so raising
    the load in fixed steps stopped there and the branch had no first point. Followed through the folds
    the first point is found; the branch runs 4000-60000 r/min, every point solves R = 0, and where the
    time domain settles on P1 (8000 and 30000 r/min) an HB state agrees with it within 1 %."""
    p = Parameters().updated({"contact.alpha_deg": 30.0, "contact.kt": 5e6, "contact.mu": 0.1,
                              "contact.gap": 1e-5})
    system = build_system(p.updated({"speed.rpm": 4000.0}), "reduced")
    law = contact_law_for(system, p.contact)
    lin = hb.linear_harmonics(system, 10)
    basis = hb.fourier(10, 512)
    assert not hb.newton(hb.linear_solution(lin), lin, law, basis)[3]      # the case in point
    first = hb.solve(system, law, 10, 512)
    assert first.converged and first.residual <= 1e-10
    branch = run_hb(p, "reduced", 4000.0, 60000.0, harmonics=10, samples=512, min_points=60)
    assert branch.complete and branch.rpm[0] == 4000.0 and branch.rpm[-1] == 60000.0
    for k in range(0, len(branch.rpm), 10):
        at = p.updated({"speed.rpm": float(branch.rpm[k])})
        s = build_system(at, "reduced")
        # Newton at the point's speed, on the system built afresh there, barely moves it: a corrector stops
        # within continuation.CONVERGED = 1e-8 (scaled) of the branch (measured at 1e-7: at most 2e-5 of the state,
        # beside a fold, where a fixed-speed correction is amplified); a point off the branch moves by its size
        X, _, _, ok, _, _ = hb.newton(branch.X[k], hb.linear_harmonics(s, 10), contact_law_for(s, at.contact), basis)
        assert ok and np.linalg.norm(X - branch.X[k]) <= 1e-4 * np.linalg.norm(branch.X[k])
    from shroud.core.signals import detect_period
    for rpm in (8000.0, 30000.0):
        tr, spp = _time_domain(p, "reduced", rpm)
        assert detect_period(tr.tip[:, 0], spp) == 1
        a = amplitude(tr.tip[:, 0], spp)
        near = [np.interp(rpm, branch.rpm[i:i + 2], branch.amplitude_v_L[i:i + 2]) for i in range(len(branch.rpm) - 1)
                if branch.rpm[i] <= rpm <= branch.rpm[i + 1]]               # every crossing, whatever its stability
        assert near and min(abs(x / a - 1) for x in near) < 0.01, (rpm, a, near)


# --- solvers that never overstate ---------------------------------------------------------------

def test_newton_that_stops_short_of_its_tolerance_says_so():
    """Asked for |R| / |F| <= 1e-30 (below round-off) Newton stalls: it is still accepted (within hb.ACCEPT)
    but says it stopped short, with the residual it reached; asked for 1e-6 it is not short."""
    system, law = friction_oscillator(70.0)
    lin = hb.linear_harmonics(system, 5)
    basis = hb.fourier(5, 256)
    tight = hb.newton(hb.linear_solution(lin), lin, law, basis, tol=1e-30)
    assert tight.converged and tight.short and 1e-30 < tight.residual <= hb.ACCEPT
    loose = hb.newton(hb.linear_solution(lin), lin, law, basis, tol=1e-6)
    assert loose.converged and not loose.short


def test_the_continuation_records_the_kink_it_steps_over():
    """x = |p - 1|: the tangent turns by 90 degrees at p = 1, more than any step resolves; the branch is
    followed through it (every point on x = |p - 1|) and the kink recorded there."""
    from shroud.core.continuation import continue_branch

    def residual(x, p):
        return x - abs(p - 1.0), np.eye(1), lambda: np.array([-np.sign(p - 1.0)])
    branch = continue_branch(residual, np.array([0.5]), 0.5, 1.5, 1.0, ds=0.05, ds_max=0.1)
    assert branch.complete and branch.p[-1] == 1.5
    assert np.allclose([x[0] for x in branch.x], np.abs(np.array(branch.p) - 1.0), atol=1e-9)
    assert len(branch.kinks) == 1 and branch.kinks[0]["p"] == pytest.approx(1.0, abs=0.01)
    assert branch.kinks[0]["turn_rad"] > 0.5


def test_the_1um_gap_beam_branch_passes_its_folds_at_corners_and_never_walks_back_down_its_path():
    """The beam of scenes/hb_fig7.toml (kn = kt = 1e7 N/m, alpha 15 deg, mu 0.3), 1 um gap, H 7, 256 samples:
    its branch folds back at a corner near 7755 r/min and forward again at an 82-degree corner near
    7669 r/min. It stopped there ("the corrector did not converge beyond p = 7668.69": its one point past
    the corner, 4.7 to 6.2 steps off the predictor, was taken for a jump to a neighbouring arm), and, passed
    there, it went on to a crowd of corners between 9119 and 9136 r/min, where a restart past one of them
    landed back on its own path and walked it down below 6000 r/min. Now both folds are passed and recorded
    and the branch, once beyond 9000 r/min, never comes back below the 7669 r/min fold."""
    p = Parameters().updated({"contact.kn": 1e7, "contact.kt": 1e7, "contact.alpha_deg": 15.0, "contact.mu": 0.3,
                              "contact.gap": 1e-6})
    br = run_hb(p, "reduced", 6000.0, 14000.0, harmonics=7, samples=256, stability=False)
    folds = [f["rpm"] for f in br.folds]
    assert any(abs(f - 7755) < 5 for f in folds) and any(abs(f - 7669) < 5 for f in folds)
    beyond = int(np.argmax(br.rpm > 9000.0))
    assert beyond > 0 and br.rpm[beyond:].min() > 7669.0, br.stopped
    # at 256 samples it stops among the saw-tooth's corners at 9119-9136 r/min, and says what passes them
    assert br.complete or "more samples (--samples)" in br.stopped
    # the default 512 samples of H 7 (hb.default_samples, scenes/hb_fig7.toml): the whole range, through folds
    fine = run_hb(p, "reduced", 6000.0, 14000.0, harmonics=7, samples=512, stability=False)
    assert fine.complete and fine.rpm[-1] == 14000.0 and len(fine.folds) >= 2, fine.stopped


def test_a_tail_target_never_met_is_flagged_in_the_result_and_its_json():
    """A tail of 1e-9 of the contact forces' spectrum is beyond H = 2 and 4 (the most allowed): the branch at
    H = 4 comes back with tail_met False, its tail above the target, and a note saying so."""
    from shroud.analysis.hb import run_hb_to_tail
    p = Parameters().updated({"contact.gap": 1e-4})
    br = run_hb_to_tail(p, "reduced", 8000.0, 10000.0, tail=1e-9, first=2, most=4, min_points=5)
    assert br.harmonics == 4 and br.tail_met is False and br.spectral_tail > 1e-9
    out = br.to_json()
    assert out["tail_met"] is False and out["tail_target"] == 1e-9
    assert any("spectral tail" in n for n in out["notes"])


def test_points_within_the_multipliers_error_are_undecided_and_the_resonance_is_never_an_unstable_point():
    """1 um gap (alpha 30 deg, kt 5e6 N/m, mu 0.3), 5000-9000 r/min: the branch has stable, unstable and
    undecided points; every undecided one has its largest |multiplier| within its error of 1 (or no state at
    2 H), every decided one beyond it, on its side; the JSON says null for them. The resonance is the largest
    amplitude over the points not shown unstable, and where an unstable point is larger it is reported
    beside it, never as the headline."""
    p = Parameters().updated({"contact.alpha_deg": 30.0, "contact.kt": 5e6, "contact.mu": 0.3, "contact.gap": 1e-6})
    br = run_hb(p, "reduced", 5000.0, 9000.0, harmonics=10, samples=512, min_points=30)
    verdicts = list(br.stable)
    assert True in verdicts and False in verdicts and None in verdicts
    for s, m, e in zip(br.stable, br.max_multiplier, br.multiplier_error):
        assert e >= floquet.MULTIPLIER_FLOOR
        if s is None:
            assert abs(m - 1) <= e or not np.isfinite(e)
        else:
            assert (m < 1 - e) if s else (m > 1 + e)
    assert br.to_json()["stable"] == [None if s is None else bool(s) for s in br.stable]
    res = br.resonance
    kept = [a for a, s in zip(br.amplitude_v_L, br.stable) if s is not False]
    assert res["amplitude"] == max(kept) and res["stable"] is not False
    unstable = [a for a, s in zip(br.amplitude_v_L, br.stable) if s is False]
    if max(unstable) > max(kept):
        assert res["unstable_peak"]["amplitude"] == max(unstable) and res["unstable_peak"]["stable"] is False
    else:
        assert res["unstable_peak"] is None


def test_an_unstable_peak_is_reported_beside_the_resonance_never_as_it():
    """Amplitudes 1, 3, 2, 1.5 mm with the 3 mm point unstable and the 2 mm one undecided: the resonance is
    2 mm (undecided, said so) with the 3 mm unstable peak beside it; all unstable: no resonance (nan)."""
    from shroud.core.results import HBResult

    def branch(stable):
        return HBResult(model="m", harmonics=1, samples=3, rpm=np.array([1.0, 2.0, 3.0, 4.0]),
                        amplitude_v_L=np.array([1.0, 3.0, 2.0, 1.5]), amplitude_w_L=np.zeros(4), stable=stable,
                        max_multiplier=np.array([0.5, 1.5, 1.0, 0.5]), bifurcations=(), spectral_tail=0.0,
                        iterations=0, complete=True, stopped=None, dofs=1, condensed=False, elapsed_s=0.0)
    res = branch([True, False, None, True]).resonance
    assert (res["rpm"], res["amplitude"], res["stable"]) == (3.0, 2.0, None)
    assert res["unstable_peak"]["rpm"] == 2.0 and res["unstable_peak"]["amplitude"] == 3.0
    res = branch([False] * 4).resonance
    assert np.isnan(res["amplitude"]) and res["unstable_peak"]["amplitude"] == 3.0
    assert branch([True] * 4).resonance["unstable_peak"] is None


def test_a_closed_loop_stops_where_it_comes_back_onto_itself():
    """R(x, p) = x^2 + (p - 10)^2 - 1: the solutions are the unit circle about p = 10, an isolated loop that
    never reaches p_end = 100 nor turns back below p0 (the check for a branch leaving its range). The
    continuation goes round once, covering the circle (p from 9 to 11, x from -1 to 1, every point on it),
    and stops where it comes back onto its path, saying so, instead of circling up to max_points. Its two
    smooth folds in p are located where they lie (p = 11, then 9)."""
    def residual(x, p):
        return np.array([x[0] ** 2 + (p - 10.0) ** 2 - 1.0]), np.array([[2 * x[0]]]), lambda: np.array([2 * (p - 10.0)])
    from shroud.core.continuation import continue_branch
    branch = continue_branch(residual, np.array([math.sqrt(0.75)]), 9.5, 100.0, 1.0, ds=0.02, ds_max=0.05)
    x, p = np.array(branch.x)[:, 0], np.array(branch.p)
    assert not branch.complete and "came back onto its own path" in branch.stopped
    assert np.allclose(x ** 2 + (p - 10.0) ** 2, 1.0, atol=1e-8)
    assert p.min() == pytest.approx(9.0, abs=1e-3) and p.max() == pytest.approx(11.0, abs=1e-3)
    assert x.min() == pytest.approx(-1.0, abs=1e-3) and x.max() == pytest.approx(1.0, abs=1e-3)
    turned = np.unwrap(np.arctan2(x, p - 10.0))
    assert 2 * math.pi - 0.2 <= abs(turned[-1] - turned[0]) < 2 * math.pi + 0.5    # once round (to a step), not twice
    assert len(branch.p) < 2000
    assert [f["kind"] for f in branch.folds] == ["smooth", "smooth"] and not branch.kinks
    assert np.allclose([f["p"] for f in branch.folds], [11.0, 9.0], atol=1e-4)
