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
import numpy as np

from reduced_model.beam import for_parameters
from reduced_model.modal import modes_at
from shroud.base.log import Progress
from shroud.core.modes import label_modes, mac, pair_by_mac
from shroud.core.results import CampbellResult
from shroud.params import Parameters

EXTRA_CANDIDATES = 4   # modes computed beyond the tracked ones, so a track can swap order


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
            pick = pair_by_mac(mac(previous, modes.shapes))
        f[i] = modes.f_hz[pick]
        previous = modes.shapes[:, pick]
        progress.update(i + 1)
    progress.done()
    return CampbellResult(rpm=rpms, f_hz=f, labels=tuple(labels), coriolis=coriolis,
                          elapsed_s=time.perf_counter() - t0)
