"""Monte Carlo statistics against exact laws: percentile intervals cover as claimed; Whitehead's bound."""

import math

import numpy as np
import pytest

from shroud.core.statistics import order_statistics, percentile_interval, whitehead_bound


def test_whitehead_bound_of_known_rings():
    assert whitehead_bound(4) == 1.5                 # (1 + 2) / 2
    assert whitehead_bound(24) == pytest.approx(2.949, abs=1e-3)
    with pytest.raises(ValueError):
        whitehead_bound(1)


@pytest.mark.parametrize("n, q", [(200, 0.95), (200, 0.5), (1000, 0.99)])
def test_percentile_intervals_cover_the_true_quantile_as_often_as_they_say(n, q):
    """4000 samples of size n from the exponential law, whose q quantile is -ln(1 - q) exactly."""
    rng = np.random.default_rng(1)
    truth = -math.log(1 - q)
    l, u, coverage = order_statistics(n, q, 0.95)
    assert 1 <= l < u <= n and coverage >= 0.95
    x = np.sort(rng.exponential(size=(4000, n)), axis=1)
    rate = np.mean((x[:, l - 1] <= truth) & (truth <= x[:, u - 1]))
    assert abs(rate - coverage) < 4 * math.sqrt(coverage * (1 - coverage) / 4000)
    iv = percentile_interval(x[0], q)                 # the interval of one sample: those order statistics
    assert (iv.lower, iv.upper) == (x[0, l - 1], x[0, u - 1])


def test_a_sample_too_small_leaves_the_far_side_open():
    """The 99th percentile of 50 values: P(all 50 below it) = 0.99^50 = 0.605 > 2.5 %, so no upper bound."""
    iv = percentile_interval(np.arange(50.0), 0.99)
    assert iv.upper is None and iv.lower is not None
