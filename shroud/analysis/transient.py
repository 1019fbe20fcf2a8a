"""One transient run of a model with impact and friction (paper Sect. 2.1, Fig. 8).

``simulate(system, params, csv_path)`` integrates ``params.time.periods``
excitation periods from a zero state (Newmark, dt = 60 / (steps_per_period
ke rpm)) and reduces the response to what the paper reads off it: the
steady-state tip amplitudes, the detected period (P1 ... P10), the contact
states and peak forces, and the energy balance over the last periods.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from shroud.analysis.checks import check_run
from shroud.core import signals
from shroud.core.contact import ContactLaw, contact_law
from shroud.base.errors import RunDiverged
from shroud.base.log import info
from shroud.core.newmark import EnergyBalance, NewmarkScheme, Trajectory, integrate
from shroud.params import Contact, Parameters
from shroud.core.system import StructuralSystem

CSV_COLUMNS = ("t", "v_L", "w_L", "w_s1", "w_s2", "N1", "N2", "Ff1", "Ff2", "state1", "state2")
CSV_UNITS = "s, m, m, m, m, N, N, N, N, 0 separate / 1 stick / 2 slip"


@dataclass(frozen=True)
class TransientResult:
    model: str
    rpm: float
    dofs: int
    steps: int
    steps_per_period: int
    elapsed_s: float
    amplitude: dict[str, float]          # v_L, w_L: (max - min)/2 over the last 10 periods, m
    peak: dict[str, float]               # N1, N2, Ff1, Ff2: largest |.| over the last 10 periods, N
    state_fraction: dict[str, dict[str, float]]
    period: int | None                   # in excitation periods (1 = P1), None if none up to P10
    energy: EnergyBalance | None
    contact_treatment: str
    timeseries: str | None
    trajectory: Trajectory

    def to_json(self) -> dict[str, Any]:
        return {
            "model": self.model, "rpm": self.rpm, "dofs": self.dofs, "steps": self.steps,
            "elapsed_s": round(self.elapsed_s, 6), "amplitude": self.amplitude, "peak": self.peak,
            "state_fraction": self.state_fraction, "period": self.period,
            "timeseries": self.timeseries, "contact_treatment": self.contact_treatment,
            "energy_balance": self.energy.to_json() if self.energy else None,
        }


def steady_state(trajectory: Trajectory, steps_per_period: int) -> dict[str, Any]:
    """Amplitudes, peaks, state fractions and period of a finished trajectory."""
    tr, spp = trajectory, steps_per_period
    return {
        "amplitude": {"v_L": signals.amplitude(tr.tip[:, 0], spp),
                      "w_L": signals.amplitude(tr.tip[:, 1], spp)},
        "peak": {"N1": signals.peak(tr.normal[:, 0], spp), "N2": signals.peak(tr.normal[:, 1], spp),
                 "Ff1": signals.peak(tr.friction[:, 0], spp), "Ff2": signals.peak(tr.friction[:, 1], spp)},
        "state_fraction": {f"side{s + 1}": signals.state_fractions(tr.state[:, s], spp) for s in range(2)},
        "period": signals.detect_period(tr.tip[:, 0], spp),
    }


def contact_law_for(system: StructuralSystem, contact: Contact) -> ContactLaw:
    """The contact law of ``system`` with the side totals of ``contact`` (empty when disabled)."""
    m = system.contact.W.shape[0] if system.contact is not None else 0
    if system.contact is None or not contact.enabled:
        return contact_law(None, m=m)
    return contact_law(system.contact, kn=contact.kn, kt=contact.kt, mu=contact.mu, N0=contact.N0)


def run(system: StructuralSystem, params: Parameters, method: str = "auto",
        energy_periods: int = signals.STEADY_PERIODS) -> Trajectory:
    """Integrate ``system`` as ``params.time`` and ``params.contact`` say (no output files).

    Refused up front (InputError) when the records would not fit in memory or
    the contact stiffness is beyond double precision (shroud.analysis.checks).
    """
    check_run(system, params)
    spp, periods = params.time.steps_per_period, params.time.periods
    law = contact_law_for(system, params.contact)
    return integrate(system, law, NewmarkScheme(dt=params.time_step), spp * periods,
                     implicit=params.time.contact == "implicit", method=method,
                     energy_window=min(energy_periods, periods) * spp, bound=params.blade.length,
                     label=f"transient {system.model} {params.speed.rpm:g} r/min")


def write_csv(path: Path, tr: Trajectory, status: str) -> Path:
    """The time series, one row per step; the header's first line gives the run's status."""
    data = np.column_stack([tr.t, tr.tip, tr.tangential, tr.normal, tr.friction, tr.state])
    fmt = ["%.9e"] * 9 + ["%d", "%d"]
    header = f"status: {status}\nunits: {CSV_UNITS}\n" + ",".join(CSV_COLUMNS)
    np.savetxt(path, data, delimiter=",", fmt=fmt, header=header)
    return path


def simulate(system: StructuralSystem, params: Parameters, csv_path: Path | None = None,
             method: str = "auto") -> TransientResult:
    """One transient run; raises RunDiverged (CSV so far kept, marked incomplete) if unbounded."""
    spp = params.time.steps_per_period
    tr = run(system, params, method=method)
    if csv_path is not None:
        status = "complete" if tr.diverged is None else f"incomplete: {tr.diverged}"
        Path(csv_path).parent.mkdir(parents=True, exist_ok=True)
        write_csv(Path(csv_path), tr, status)
        info(f"wrote {csv_path} ({tr.steps + 1} rows)")
    if tr.diverged is not None:
        where = f"; time series so far in {csv_path}" if csv_path else ""
        raise RunDiverged(f"{system.model} model at {params.speed.rpm:g} r/min: {tr.diverged}{where}")
    return TransientResult(model=system.model, rpm=params.speed.rpm, dofs=system.dofs, steps=tr.steps,
                           steps_per_period=spp, elapsed_s=tr.elapsed_s, energy=tr.energy,
                           contact_treatment=params.time.contact,
                           timeseries=str(csv_path) if csv_path else None, trajectory=tr,
                           **steady_state(tr, spp))
