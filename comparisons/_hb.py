"""Reading time-domain points against harmonic-balance branches (shared by the hb_* studies)."""

from __future__ import annotations

import numpy as np


def crossings(branch, rpm: float, stable: bool) -> list[float]:
    """Amplitudes (m) where stretches of ``branch`` with the given stability cross ``rpm`` (interpolated)."""
    out = []
    for i in range(len(branch.rpm) - 1):
        r0, r1 = branch.rpm[i], branch.rpm[i + 1]
        if (r0 != r1 and min(r0, r1) <= rpm <= max(r0, r1) and branch.stable[i] == stable
                and branch.stable[i + 1] == stable):
            t = (rpm - r0) / (r1 - r0)
            out.append(float((1 - t) * branch.amplitude_v_L[i] + t * branch.amplitude_v_L[i + 1]))
    return sorted(out)


def landed_on(branch, rpm: float, amplitude: float, period, match: float) -> str:
    """Name of the branch a time-domain point landed on."""
    if not np.isfinite(amplitude):
        return "diverged"
    stable = crossings(branch, rpm, True)
    names = (["lower stable", "upper stable"] if len(stable) == 2 else
             [f"stable {i + 1} of {len(stable)}" for i in range(len(stable))] if len(stable) > 2 else
             ["stable"])
    if stable:
        i = int(np.argmin([abs(a / amplitude - 1) for a in stable]))
        if abs(stable[i] / amplitude - 1) <= match:
            return names[i]
    if period not in (None, 1):
        return f"P{period} (no P1 branch holds it)"
    if crossings(branch, rpm, False) and not stable:
        return "beside an unstable P1 branch (quasi-periodic or drifting)"
    return "off the P1 branches"


def on_stable(name: str) -> bool:
    """Whether a name from :func:`landed_on` is a stable P1 branch."""
    return name.endswith("stable") or name.startswith("stable")
