"""Campbell diagram of the beam model: frequencies over speed, tracked by MAC.

At each speed the modes are computed once (5N or 6N DOF, a few ms) and matched to
the previous speed's by the modal assurance criterion with an optimal
one-to-one assignment, so a track follows one mode shape through veerings
and crossings instead of following an index. Each track keeps the label it
has at the first speed. Resonance candidates are the speeds where a track
crosses an excitation line f = k_e * rpm / 60.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np
from scipy.optimize import linear_sum_assignment

from reduced_model.beam import for_parameters
from reduced_model.modal import modes_at
from shroud.base.log import Progress
from shroud.core.modes import label_modes, mac
from shroud.params import Parameters

EXTRA_CANDIDATES = 4   # modes computed beyond the tracked ones, so a track can swap order


@dataclass(frozen=True)
class CampbellResult:
    rpm: np.ndarray            # (s,) r/min
    f_hz: np.ndarray           # (s, k) tracked frequencies, Hz
    labels: tuple[str, ...]    # (k,) label of each track at the first speed
    coriolis: bool
    elapsed_s: float

    def crossings(self, order: int) -> list[tuple[str, float, float]]:
        """(label, rpm, f_hz) where a track meets the line f = order * rpm / 60."""
        out = []
        line = order * self.rpm / 60.0
        for j, label in enumerate(self.labels):
            d = self.f_hz[:, j] - line
            for i in np.flatnonzero(np.sign(d[:-1]) * np.sign(d[1:]) < 0):
                t = d[i] / (d[i] - d[i + 1])
                rpm = self.rpm[i] + t * (self.rpm[i + 1] - self.rpm[i])
                out.append((label, float(rpm), float(order * rpm / 60.0)))
        return out


def campbell(params: Parameters, rpms: np.ndarray, n_modes: int, coriolis: bool) -> CampbellResult:
    """Track the ``n_modes`` lowest modes of the full beam model over ``rpms`` (ascending)."""
    t0 = time.perf_counter()
    beam = for_parameters(params)
    rpms = np.asarray(rpms, dtype=float)
    count = min(n_modes + EXTRA_CANDIDATES, beam.dofs)
    f = np.empty((rpms.size, n_modes))
    progress = Progress("Campbell", rpms.size)
    previous = None
    for i, rpm in enumerate(rpms):
        modes = modes_at(beam, 2.0 * np.pi * rpm / 60.0, count, coriolis)
        if previous is None:
            pick = np.arange(n_modes)
            labels, _ = label_modes(beam.tip_kinematics(modes.shapes[:, :n_modes]))
        else:
            _, pick = linear_sum_assignment(-mac(previous, modes.shapes))
        f[i] = modes.f_hz[pick]
        previous = modes.shapes[:, pick]
        progress.update(i + 1)
    progress.done()
    return CampbellResult(rpm=rpms, f_hz=f, labels=tuple(labels), coriolis=coriolis,
                          elapsed_s=time.perf_counter() - t0)
