"""Rayleigh damping D = alpha M + beta K on two modes (paper Eq. 2).

A mode of circular frequency w = 2 pi f gets the damping ratio
xi(f) = alpha / (4 pi f) + beta pi f. Asking xi(f1) = xi1 and xi(f2) = xi2
gives

    alpha = 4 pi f1 f2 (f1 xi2 - f2 xi1) / (f1^2 - f2^2)      (as printed)
    beta  = (f2 xi2 - f1 xi1) / (pi (f2^2 - f1^2))            (printed with
                                                               the sign flipped)
"""

from __future__ import annotations

import math


def rayleigh(f1: float, f2: float, xi1: float, xi2: float) -> tuple[float, float]:
    """(alpha in 1/s, beta in s) giving damping ratios xi1, xi2 at f1 != f2 (Hz).

    Examples
    --------
    The ratios come back at both frequencies, xi(f) = alpha / (4 pi f) + beta pi f:

    >>> alpha, beta = rayleigh(280.0, 1120.0, 0.02, 0.04)
    >>> [round(alpha / (4 * math.pi * f) + beta * math.pi * f, 12) for f in (280.0, 1120.0)]
    [0.02, 0.04]
    """
    if not (f1 > 0 and f2 > 0) or math.isclose(f1, f2):
        raise ValueError(f"Rayleigh damping needs two distinct positive frequencies, got {f1}, {f2} Hz")
    return rayleigh_coefficients(f1, f2, xi1, xi2)


def rayleigh_coefficients(f1: float, f2: float, xi1: float, xi2: float) -> tuple[float, float]:
    """:func:`rayleigh` without its checks (plain arithmetic: a model's compiled kernel may compile it)."""
    alpha = 4.0 * math.pi * f1 * f2 * (f1 * xi2 - f2 * xi1) / (f1**2 - f2**2)
    beta = (f2 * xi2 - f1 * xi1) / (math.pi * (f2**2 - f1**2))
    return alpha, beta

