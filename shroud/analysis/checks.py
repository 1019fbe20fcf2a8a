"""What a time integration (or a sweep of them) is refused before it starts, naming the bound.

Three limits no choice of parameters can get past:

* memory: a run records one row per step (tip displacements, contact forces,
  slider positions, states: :class:`shroud.core.newmark.Trajectory`) and its
  time-series CSV stacks those rows again before writing, so the records grow
  with ``time.periods * time.steps_per_period``;
* double precision: a contact spring of stiffness k_c in parallel with the
  structure's own stiffness k at the contact point enters every sum as
  k + k_c. Where k_c > k / eps (eps = 2.2e-16) the sum is k_c to the last
  digit: the structure has vanished from the contact problem and the run
  diverges or returns noise. k here is the structure's stiffness along each
  contact coordinate, w K w^T for the row w of the projection W (SI: N/m).
  It is at least the static stiffness 1 / (w K^-1 w^T) that the contact
  really meets, so the bound is where the structure is certainly lost;
  below it the contact forces keep about -log10(eps k_c / k_static) digits
  (the energy balance of the run shows what is left);
* memory, again: a sweep holds a task, a result row and its results.json
  entries for every speed it is asked for (or, by harmonic balance, every
  point its branch must have at least), so its size grows with the count.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse

from shroud.base.errors import InputError
from shroud.base.resources import in_words, physical_memory
from shroud.core.system import StructuralSystem
from shroud.params import Contact, Parameters

# Per step: tip, normal, friction and tangential pairs (float64) and the two states (int8) ...
RECORD_BYTES_PER_STEP = 4 * 2 * 8 + 2
# ... and the time-series CSV's 11 float64 columns, stacked before writing
# (shroud.core.results.write_trajectory_csv).
CSV_BYTES_PER_STEP = 11 * 8
# Per speed of a sweep: its task, result row, SweepResult entries and their JSON text (tracemalloc
# peak 610 B a speed for 200 000 speeds, the worker processes' copies not counted).
SWEEP_BYTES_PER_SPEED = 600
# Share of the machine's memory one run's records may take: the model, its
# solver and the other processes of a sweep or campaign need the rest.
MEMORY_SHARE = 0.5


def record_bytes(params: Parameters) -> int:
    """Bytes a run of ``params.time`` records, its CSV staging included.

    >>> from shroud.base.resources import in_words
    >>> in_words(record_bytes(Parameters().updated({"time.periods": 100_000_000})))
    '3.6 TiB'
    """
    steps = params.time.periods * params.time.steps_per_period
    return (steps + 1) * (RECORD_BYTES_PER_STEP + CSV_BYTES_PER_STEP)


def check_records(params: Parameters) -> None:
    """Refuse a run at rest (speed.rpm, by Parameters.time_step) or whose records this machine cannot hold."""
    params.time_step
    need, limit = record_bytes(params), MEMORY_SHARE * physical_memory()
    if need <= limit:
        return
    spp = params.time.steps_per_period
    most = int(limit // ((RECORD_BYTES_PER_STEP + CSV_BYTES_PER_STEP) * spp))
    if most < 1:                    # not one period fits: the steps are what is too many
        fits = int(limit // (RECORD_BYTES_PER_STEP + CSV_BYTES_PER_STEP))
        raise InputError("time.steps_per_period", f"{spp} steps per period would record {in_words(need / params.time.periods)} "
                         f"a period, more than {MEMORY_SHARE:.0%} of this machine's {in_words(physical_memory())}; "
                         f"allowed: at most {fits} steps per period here")
    raise InputError("time.periods", f"{params.time.periods} periods of {spp} steps would record "
                     f"{in_words(need)} (one row of {RECORD_BYTES_PER_STEP + CSV_BYTES_PER_STEP} bytes per step, "
                     f"CSV included), more than {MEMORY_SHARE:.0%} of this machine's {in_words(physical_memory())}; "
                     f"allowed: at most {most} periods here")


def check_speed_count(count: int, key: str) -> None:
    """Refuse (InputError on ``key``) a sweep of ``count`` speeds whose results this machine cannot hold.

    >>> check_speed_count(10**12, "--rpm-count")
    Traceback (most recent call last):
    ...
    shroud.base.errors.InputError: --rpm-count: 1000000000000 speeds would hold 545.7 TiB of results (600 B a speed), ...
    """
    need, limit = count * SWEEP_BYTES_PER_SPEED, MEMORY_SHARE * physical_memory()
    if need > limit:
        raise InputError(key, f"{count} speeds would hold {in_words(need)} of results ({SWEEP_BYTES_PER_SPEED} B a "
                              f"speed), more than {MEMORY_SHARE:.0%} of this machine's {in_words(physical_memory())}; "
                              f"allowed: at most {int(limit // SWEEP_BYTES_PER_SPEED)} speeds here")


def structural_stiffness(system: StructuralSystem, rows) -> dict[int, float]:
    """w K w^T (N/m) of each row w of the contact projection W named in ``rows``.

    One product of K with the rows' block (K dense, scipy.sparse or row-distributed).
    """
    W = system.contact.W
    index = sorted({int(r) for r in rows})
    block = W[index]
    dense = block.toarray() if scipy.sparse.issparse(block) else np.asarray(block, dtype=float)
    KWt = np.asarray(system.K @ dense.T)
    return dict(zip(index, np.einsum("ij,ji->i", dense, KWt).tolist()))


def contact_stiffness_bounds(system: StructuralSystem) -> dict[str, float]:
    """Largest side totals (N/m) of kn and kt whose share per element, k_c weight_j, stays within k / eps."""
    elements = system.contact
    k = structural_stiffness(system, np.concatenate([elements.normal_row, elements.tangent_row]))
    eps = np.finfo(float).eps
    return {key: min(k[int(r)] / (eps * w) for r, w in zip(rows, elements.weight) if w > 0)
            for key, rows in (("contact.kn", elements.normal_row), ("contact.kt", elements.tangent_row))}


def check_contact_stiffness(system: StructuralSystem, contact: Contact) -> None:
    """Refuse contact.kn or contact.kt beyond what double precision resolves against ``system``."""
    elements = system.contact
    if elements is None or not contact.enabled or elements.count == 0:
        return
    bounds = contact_stiffness_bounds(system)
    for key, value in (("contact.kn", contact.kn), ("contact.kt", contact.kt)):
        name = key.split(".")[1]
        if value > bounds[key]:
            raise InputError(key, f"{value:g} N/m is beyond what double precision resolves against the "
                             f"{system.model} model's own stiffness k at its contact points ({name} + k rounds to "
                             f"{name} once {name} > k / 2.2e-16 per point); allowed: at most {bounds[key]:.3g} N/m here")


def check_run(system: StructuralSystem, params: Parameters) -> None:
    """Both checks, before a time integration of ``system`` as ``params`` say."""
    check_records(params)
    check_contact_stiffness(system, params.contact)
