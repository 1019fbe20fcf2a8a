"""The converged thin-plate reference the shell is held to on NAFEMS FV16 (comparisons.shell_benchmarks).

Independent truths: at nu = 0 a cantilever plate's first bending modes are
the clamped-free beam's (their w_yy is 0, so the free edges' moment
vanishes): lambda = beta^2 with cos beta cosh beta = -1; at nu = 0.3 the
converged square cantilever plate's lambda_1 = 3.471 (Leissa 1969; Gorman's
superposition), and Barton's (1951) crossed-beam Ritz values (3.492, 8.525,
21.43, 27.33, 31.11, 54.44, as Code_Aster's SDLS01 quotes them) are upper
bounds the converged values lie below.
"""

import numpy as np

from comparisons.shell_benchmarks import RITZ_TERMS, cantilever_plate_lambdas

BEAM_ROOTS = (1.875104068711961, 4.694091132974174)     # cos b cosh b = -1, first two
BARTON = (3.492, 8.525, 21.43, 27.33, 31.11, 54.44)


def test_plate_without_poisson_coupling_has_the_cantilever_beams_bending_modes():
    lam = cantilever_plate_lambdas(RITZ_TERMS // 2, 0.0, 6)
    np.testing.assert_allclose(lam[[0, 2]], np.square(BEAM_ROOTS), rtol=1e-6)


def test_square_cantilever_plate_converges_below_bartons_upper_bounds():
    lam = cantilever_plate_lambdas(RITZ_TERMS, 0.3, 6)
    assert abs(lam[0] - 3.471) < 5e-4
    assert np.all(lam < BARTON)
