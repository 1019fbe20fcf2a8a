"""Pseudo-arclength continuation (shroud.core.continuation) through corners at which the branch folds.

Each residual below has an exact, piecewise analytic branch with one corner at which dp/ds changes sign
(a fold at the corner). With the orientation rule before issue 32 (the new tangent oriented along the
previous one, t . previous > 0, and no restart past a corner) each of these tests fails: that code's
corrector finds no point past the corner at any step (it stops incomplete at the corner, "the corrector
did not converge", checked on commit fd23feb), and with the restart past the corner but that orientation
the branch walks back from the far arm onto the near one (checked by patching the secant's orientation
back to the previous tangent's); the one of 82 degrees fails with the rule its docstring names.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from shroud.core.continuation import continue_branch


def no_point_repeats(branch, tol=1e-9):
    u = np.column_stack([np.array(branch.x), branch.p])
    gaps = np.linalg.norm(u[:, None] - u[None], axis=-1) + np.eye(len(u))
    return gaps.min() > tol


def scalar(R, dR_dx, dR_dp):
    """residual(x, p) of one unknown from R(x, p) and its derivatives."""
    return lambda x, p: (np.array([R(x[0], p)]), np.array([[dR_dx(x[0], p)]]), lambda: np.array([dR_dp(x[0], p)]))


def passed_forward(branch, near, far, corner_p, p0, p_end, min_turn=math.pi / 2):
    """Every point on the exact branch: the near arm up to the corner, then the far arm beyond it (x past the
    corner's and never back), the corner's fold recorded where it lies, the branch leaving the range below p0
    (the far arm turns back there), no point twice."""
    x, p = np.array(branch.x)[:, 0], np.array(branch.p)
    assert not branch.complete and "turned back below the first parameter value" in branch.stopped
    first_far = int(np.argmax([not near(xi, pi) for xi, pi in zip(x, p)]))
    assert first_far > 0
    assert all(near(xi, pi) for xi, pi in zip(x[:first_far], p[:first_far]))
    assert all(far(xi, pi) for xi, pi in zip(x[first_far:], p[first_far:]))
    assert len(x) - first_far >= 5                                      # down the far arm, not one point
    assert p[-1] < p0                                  # all the way down, to where it leaves the range
    assert no_point_repeats(branch)
    assert [f["kind"] for f in branch.folds] == ["corner"]
    assert branch.folds[0]["p"] == pytest.approx(corner_p, abs=1e-6)
    assert len(branch.kinks) == 1 and branch.kinks[0]["p"] == pytest.approx(corner_p, abs=1e-6)
    assert branch.kinks[0]["turn_rad"] > min_turn


def test_a_v_shaped_fold_is_passed_forward_down_its_far_arm():
    """R(x, p) = p - c + a |x| (a = 2, c = 1): the branch p = c - a |x| rises to its apex (0, c) and comes down
    the other arm; in the scaled unknowns (x, p) the corner turns by acos((1 - a^2) / (1 + a^2)) = 127 degrees.
    Continued upwards from x = -0.2 (p = 0.6) it must pass the apex and come down x > 0 until it leaves the
    range below p = 0.6."""
    a, c = 2.0, 1.0
    residual = scalar(lambda x, p: p - c + a * abs(x), lambda x, p: a * np.sign(x), lambda x, p: 1.0)
    branch = continue_branch(residual, np.array([-0.2]), 0.6, 1.2, 1.0, ds=0.05, ds_max=0.1, p_scale=1.0)
    exact = lambda x, p: abs(p - (c - a * abs(x))) < 1e-7
    passed_forward(branch, lambda x, p: x <= 0 and exact(x, p), lambda x, p: x > 0 and exact(x, p), c, 0.6, 1.2)
    assert branch.kinks[0]["turn_rad"] == pytest.approx(math.acos((1 - a * a) / (1 + a * a)), abs=1e-6)


def test_a_fold_at_a_corner_of_less_than_90_degrees_is_passed_where_the_far_arm_lands_far_off_the_predictor():
    """The V of the test above with a = 0.87: the corner turns by acos((1 - a^2) / (1 + a^2)) = 82 degrees (as
    the 1 um gap's beam branch at H 7 at 7669 r/min, scenes/hb_fig7.toml). A step past the corner lands on the
    far arm tan(82 deg) = 7 times further off the predictor than the corner lies short of it: a corrector
    moving further than its step, once taken only from the predictor's side (a jump to a neighbouring arm,
    else), so no step short enough for it came before the smallest and the branch stopped at the apex ("the
    corrector did not converge beyond p = 0.999995", checked with the rule before). The corner lies within
    the step, so the point is the far arm's and the branch goes down it."""
    a, c = 0.87, 1.0
    residual = scalar(lambda x, p: p - c + a * abs(x), lambda x, p: a * np.sign(x), lambda x, p: 1.0)
    branch = continue_branch(residual, np.array([-0.2]), c - 0.2 * a, 1.2, 1.0, ds=0.05, ds_max=0.1, p_scale=1.0)
    exact = lambda x, p: abs(p - (c - a * abs(x))) < 1e-7
    passed_forward(branch, lambda x, p: x <= 0 and exact(x, p), lambda x, p: x > 0 and exact(x, p), c,
                   c - 0.2 * a, 1.2, min_turn=0.0)
    assert branch.kinks[0]["turn_rad"] == pytest.approx(math.acos((1 - a * a) / (1 + a * a)), abs=1e-6)


def test_the_onset_of_slip_of_a_stuck_contact_is_passed_forward():
    """A mass on a spring k softened by the spin (k - p, p = m Omega^2, N/m), pushed by F against a
    Jenkins contact (tangential spring kt in series with a Coulomb slider of limit mu N; F < mu N):
    (k - p) x + clip(kt x, -mu N, mu N) = F. Stuck, x = F / (k + kt - p); the slider slips at
    x_s = mu N / kt, at p_s = k + kt (1 - F / mu N); slipping, x = (mu N - F) / (p - k), p falling as x
    grows: a fold at the stick/slip switch (k = 1, kt = 4, mu N = 1, F = 0.5: p_s = 3, x_s = 0.25, the
    corner turning by 166 degrees)."""
    k, kt, muN, F = 1.0, 4.0, 1.0, 0.5
    residual = scalar(lambda x, p: (k - p) * x + np.clip(kt * x, -muN, muN) - F,
                      lambda x, p: k - p + (kt if abs(kt * x) < muN else 0.0), lambda x, p: -x)
    branch = continue_branch(residual, np.array([F / (k + kt - 2.0)]), 2.0, 4.0, 1.0, ds=0.05, ds_max=0.1,
                             p_scale=1.0)
    x_s, p_s = muN / kt, k + kt * (1 - F / muN)
    stuck = lambda x, p: x <= x_s + 1e-12 and abs(x - F / (k + kt - p)) < 1e-7
    slipping = lambda x, p: x > x_s and abs(x - (muN - F) / (p - k)) < 1e-7
    passed_forward(branch, stuck, slipping, p_s, 2.0, 4.0)


def test_a_grazing_touch_is_passed_forward():
    """A 1-DOF spring-mass beside a stop (gap g, contact stiffness kc), at rest in the rotating frame beyond
    its static divergence (net stiffness k - p < 0, p = m Omega^2) under a load F: (k - p) x - F -
    kc max(-g - x, 0) = 0. Free, x = -F / (p - k); it first touches the stop (x = -g) at p_c = k + F / g,
    and in contact p = k + kc - (kc g - F) / |x| rises again: the speed has a minimum at the touch. Followed
    with the speed going down (parameter q = -p, as shroud.analysis.hb.run_hb_through does) from p = 3
    (k = F = g = 1, kc = 4: p_c = 2, a corner of 117 degrees), it must pass the touch and go back up in
    speed in contact."""
    k, F, g, kc = 1.0, 1.0, 1.0, 4.0
    residual = scalar(lambda x, q: (k + q) * x - F - kc * max(-g - x, 0.0),
                      lambda x, q: k + q + (kc if x < -g else 0.0), lambda x, q: x)
    branch = continue_branch(residual, np.array([-0.5]), -3.0, -1.5, 1.0, ds=0.05, ds_max=0.1, p_scale=1.0)
    free = lambda x, q: x >= -g - 1e-12 and abs(x + F / (-q - k)) < 1e-7
    touching = lambda x, q: x < -g and abs(-q - (k + kc - (kc * g - F) / abs(x))) < 1e-7
    passed_forward(branch, free, touching, -(k + F / g), -3.0, -1.5)


def test_a_branch_whose_steps_add_up_to_its_end_does_not_repeat_its_last_point():
    """x = 1e-9 p from 7900 to 14000 with steps of exactly dp_max = (14000 - 7900) / 29: the 29th lands
    1.5e-11 short of 14000 by rounding; it is the last point, put at 14000, not followed by 14000 again
    (the 6-blade ring's branch, 7900-14000 r/min, ended 13999.9999975, 14000)."""
    residual = scalar(lambda x, p: x - 1e-9 * p, lambda x, p: 1.0, lambda x, p: -1e-9)
    branch = continue_branch(residual, np.array([7.9e-6]), 7900.0, 14000.0, 1.0, ds=0.05, ds_max=0.5,
                             dp_max=6100.0 / 29)
    assert branch.complete and branch.p[-1] == 14000.0 and len(branch.p) == 30
    assert np.allclose(np.diff(branch.p), 6100.0 / 29)
