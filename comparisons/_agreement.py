"""How closely one transient follows a reference transient (Fig. 8, error against run time).

Both are compared over the reference's last ``periods`` excitation periods,
after interpolating the candidate onto the reference's time grid (runs at
other time steps then compare fairly). For each signal:

* NRMSE: RMS of the difference divided by the reference's peak-to-peak range;
* peak error: relative error of the largest absolute value.

The contact-state shares are the time (and, for a face of many nodes, area)
averages of the separate/stick/slip indicators of each side.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

SIGNALS = ("N1", "N2", "Ff1", "Ff2", "v_L", "w_L")


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


def nrmse(x: np.ndarray, ref: np.ndarray) -> float:
    span = float(np.ptp(ref))
    return float(np.sqrt(np.mean((x - ref) ** 2)) / span) if span > 0 else float(np.max(np.abs(x - ref)) > 0)


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
    errs, peaks = {}, {}
    for name in SIGNALS:
        x = np.interp(tw, t, signals[name])
        errs[name] = nrmse(x, reference[name][mask])
        peaks[name] = peak_error(x, reference[name][mask])
    return Agreement(nrmse=errs, peak_error=peaks)
