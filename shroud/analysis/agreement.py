"""How closely one transient follows a reference transient (used by the Fig. 8 and error-against-run-time studies).

Both are compared over the reference's last ``periods`` excitation periods,
after interpolating the candidate onto the reference's time grid (runs at
other time steps then compare fairly). For each signal:

* NRMSE: RMS of the difference divided by the reference's peak-to-peak range,
  or by ``FLAT_SHARE`` of the largest range among the signals of the same
  quantity (forces; tip displacements) in either run where that is larger.
  A reference that hardly moves (a face that never touches: N = 0 all
  window) is then measured against the size of its kind of signal: a small
  difference gives a small NRMSE instead of a jump to 1;
* peak error: relative error of the largest absolute value.

The contact-state shares are the time (and, for a face of many nodes, area)
averages of the separate/stick/slip indicators of each side.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

SIGNALS = ("N1", "N2", "Ff1", "Ff2", "v_L", "w_L")
QUANTITIES = (("N1", "N2", "Ff1", "Ff2"), ("v_L", "w_L"))   # signals of one unit share a scale
FLAT_SHARE = 0.01      # a reference range below 1 % of its quantity's largest range counts as flat


@dataclass(frozen=True)
class Agreement:
    nrmse: dict[str, float]
    peak_error: dict[str, float]

    @property
    def worst_nrmse(self) -> float:
        return max(self.nrmse.values())

    def to_json(self) -> dict:
        return {"nrmse": self.nrmse, "peak_error": self.peak_error, "worst_nrmse": self.worst_nrmse}


def signals_of(trajectory) -> dict[str, np.ndarray]:
    """The six compared signals of a shroud.core.newmark.Trajectory, by name."""
    tr = trajectory
    return {"v_L": tr.tip[:, 0], "w_L": tr.tip[:, 1], "N1": tr.normal[:, 0], "N2": tr.normal[:, 1],
            "Ff1": tr.friction[:, 0], "Ff2": tr.friction[:, 1]}


def window(t: np.ndarray, period: float, periods: int) -> np.ndarray:
    """Boolean mask of the last ``periods`` excitation periods of the time grid ``t``."""
    return t >= t[-1] - periods * period * (1 - 1e-9)


def nrmse(x: np.ndarray, ref: np.ndarray, scale: float = 0.0) -> float:
    """RMS of ``x - ref`` over the larger of ref's range and ``scale``.

    Two constant signals (no range, no scale) compare by their relative difference.

    >>> t = np.linspace(0.0, 2 * np.pi, 1001)
    >>> round(nrmse(np.sin(t) + 0.01, np.sin(t)), 9)             # range 2: 0.01 / 2
    0.005
    >>> nrmse(np.full(5, 1e-9), np.zeros(5), scale=0.5)         # a flat reference, a tiny difference
    2e-09
    """
    rms = float(np.sqrt(np.mean((x - ref) ** 2)))
    span = max(float(np.ptp(ref)), scale)
    if span == 0.0:
        span = max(float(np.max(np.abs(ref))), float(np.max(np.abs(x))))
    return rms / span if span > 0 else 0.0


def peak_error(x: np.ndarray, ref: np.ndarray) -> float:
    peak = float(np.max(np.abs(ref)))
    return abs(float(np.max(np.abs(x))) - peak) / peak if peak > 0 else float(np.max(np.abs(x)))


def agreement(t: np.ndarray, signals: dict[str, np.ndarray], t_ref: np.ndarray,
              reference: dict[str, np.ndarray], period: float, periods: int = 10) -> Agreement:
    """NRMSE and peak error of each of ``SIGNALS`` over the reference's last ``periods`` periods."""
    mask = window(t_ref, period, periods)
    tw = t_ref[mask]
    if tw[0] < t[0] or tw[-1] > t[-1] * (1 + 1e-9):
        raise ValueError("the candidate run does not cover the reference window")
    xs = {name: np.interp(tw, t, signals[name]) for name in SIGNALS}
    refs = {name: reference[name][mask] for name in SIGNALS}
    errs, peaks = {}, {}
    for group in QUANTITIES:
        scale = FLAT_SHARE * max(max(np.ptp(xs[n]), np.ptp(refs[n])) for n in group)
        for name in group:
            errs[name] = nrmse(xs[name], refs[name], scale)
            peaks[name] = peak_error(xs[name], refs[name])
    return Agreement(nrmse=errs, peak_error=peaks)
