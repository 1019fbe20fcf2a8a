"""One transient run of a model with impact and friction (paper Sect. 2.1, Fig. 8).

``simulate(system, params, csv_path)`` integrates ``params.time.periods``
excitation periods from a zero state (Newmark, dt = 60 / (steps_per_period
ke rpm)) and reduces the response to what the paper reads off it: the
steady-state tip amplitudes, the detected period (P1 ... P10), the contact
states and peak forces, and the energy balance over the last periods.
"""

from __future__ import annotations

from pathlib import Path

from shroud.analysis.checks import check_run
from shroud.core import signals
from shroud.core.contact import ContactLaw, contact_law
from shroud.base.errors import RunDiverged
from shroud.base.log import info
from shroud.core.newmark import NewmarkScheme, Trajectory, integrate
from shroud.core.results import TransientResult, write_trajectory_csv
from shroud.params import Contact, Parameters
from shroud.core.system import StructuralSystem

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


def written(tr: Trajectory, csv_path: Path | None, what: str, rows: str = "") -> Trajectory:
    """``tr``'s time series in ``csv_path`` if asked (its status line says complete or where it stopped;
    ``rows`` names whose rows they are); raises RunDiverged naming ``what`` (the CSV so far kept) if the
    run was unbounded. The one writer of a transient's CSV, for the single blade and the ring."""
    if csv_path is not None:
        status = "complete" if tr.diverged is None else f"incomplete: {tr.diverged}"
        Path(csv_path).parent.mkdir(parents=True, exist_ok=True)
        write_trajectory_csv(Path(csv_path), tr, status)
        info(f"wrote {csv_path} ({tr.steps + 1} rows{rows})")
    if tr.diverged is not None:
        where = f"; time series so far in {csv_path}" if csv_path else ""
        raise RunDiverged(f"{what}: {tr.diverged}{where}")
    return tr


def simulate(system: StructuralSystem, params: Parameters, csv_path: Path | None = None,
             method: str = "auto") -> TransientResult:
    """One transient run; raises RunDiverged (CSV so far kept, marked incomplete) if unbounded."""
    spp = params.time.steps_per_period
    tr = run(system, params, method=method)
    written(tr, csv_path, f"{system.model} model at {params.speed.rpm:g} r/min")
    return TransientResult.from_trajectory(tr, model=system.model, rpm=params.speed.rpm, dofs=system.dofs,
                                           steps_per_period=spp, contact_treatment=params.time.contact,
                                           timeseries=str(csv_path) if csv_path else None)


def simulate_model(params: Parameters, model: str, csv_path: Path | None = None) -> TransientResult:
    """:func:`simulate` of the registered ``model``'s blade built at ``params.speed.rpm``."""
    from shroud.core import registry
    return simulate(registry.model(model).build_system(params), params, csv_path=csv_path)
