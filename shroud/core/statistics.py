"""Statistics of Monte Carlo studies: percentiles with their confidence, and Whitehead's bound.

A mistuning study draws blades' properties at random and reports how much
worse the worst blade gets than the tuned one. A percentile of a finite
sample is itself uncertain; :func:`percentile_interval` gives the
distribution-free (order-statistic) confidence interval for it, which needs
no assumption on the law of the amplification.

Whitehead (1966): for a bladed disk with one isolated mode family and
light, linear coupling, no blade's forced response can exceed the tuned one
by more than (1 + sqrt N) / 2 (:func:`whitehead_bound`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import stats


def whitehead_bound(blades: int) -> float:
    """Largest tuned-to-mistuned amplification of one blade, (1 + sqrt N) / 2 (Whitehead 1966)."""
    if blades < 2:
        raise ValueError(f"a ring has at least 2 blades (got {blades})")
    return (1.0 + math.sqrt(blades)) / 2.0


@dataclass(frozen=True)
class PercentileInterval:
    """The ``q`` quantile of a sample and a two-sided interval holding the true one with ``confidence``.

    ``lower``/``upper`` are order statistics; None where the sample is too
    small to bound that side at this confidence (``coverage`` is then the
    probability the sample does reach).
    """

    q: float
    estimate: float
    lower: float | None
    upper: float | None
    confidence: float
    coverage: float
    samples: int

    def to_json(self) -> dict:
        return {"q": self.q, "estimate": self.estimate, "lower": self.lower, "upper": self.upper,
                "confidence": self.confidence, "coverage": self.coverage, "samples": self.samples}


def order_statistics(n: int, q: float, confidence: float = 0.95) -> tuple[int, int, float]:
    """(l, u, coverage): the order statistics x_(l) <= x_(u) (1-based; l = 0 or u = n + 1 where that
    side cannot be bounded) of a confidence interval for the ``q`` quantile of n i.i.d. values.

    The number K of values below the true quantile is Binomial(n, q); the
    interval covers it when l <= K <= u - 1, with probability
    B(u - 1) - B(l - 1). l is the largest with P(K <= l - 1) <= (1 - confidence) / 2,
    u the smallest with P(K >= u) <= (1 - confidence) / 2.
    """
    if n < 1 or not 0.0 < q < 1.0 or not 0.0 < confidence < 1.0:
        raise ValueError(f"need n >= 1, 0 < q < 1 and 0 < confidence < 1 (got n={n}, q={q}, {confidence})")
    binom = stats.binom(n, q)
    tail = (1.0 - confidence) / 2.0
    l = int(binom.ppf(tail))                  # the smallest k with B(k) >= tail: B(l - 1) < tail
    u = int(binom.ppf(1.0 - tail)) + 1        # P(K >= u) = 1 - B(u - 1) <= tail
    l, u = max(l, 0), min(u, n + 1)
    coverage = float(binom.cdf(u - 1) - (binom.cdf(l - 1) if l >= 1 else 0.0))
    return l, u, coverage


def percentile_interval(sample, q: float, confidence: float = 0.95) -> PercentileInterval:
    """Distribution-free confidence interval of the ``q`` quantile (0 < q < 1) from i.i.d. ``sample``
    (:func:`order_statistics`), with the sample's own quantile as the estimate."""
    x = np.sort(np.asarray(sample, dtype=float))
    l, u, coverage = order_statistics(x.size, q, confidence)
    return PercentileInterval(q=q, estimate=float(np.quantile(x, q)),
                              lower=float(x[l - 1]) if l >= 1 else None,
                              upper=float(x[u - 1]) if u <= x.size else None,
                              confidence=confidence, coverage=coverage, samples=int(x.size))
