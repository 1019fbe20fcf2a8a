"""The contact's linear limits: modes with the interfaces free or stuck (``modal --interface``; docs/ring.md).

``free``: the model without contact springs. ``stuck``: every contact point
as linear springs, kn on its normal and kt on its tangent (its share of the
side's totals), against the fixed neighbours (ring.blades = 0) or, with
ring.blades = N, between neighbouring blades, one nodal diameter at a time
(shroud.core.cyclic: the tuned ring by one sector). The modes are those of
the model's own system (the reduced beam: its nr-mode basis), with Coriolis
unless told otherwise; they are labelled by the tip's v_L, w_L (flap,
chord).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from shroud.analysis.ring import build_ring
from shroud.base.errors import InputError
from shroud.core import registry
from shroud.core.contact import contact_law
from shroud.core.cyclic import Modes, modes, nodal_diameters, sector_stiffness
from shroud.core.linear_solvers import dense
from shroud.core.modes import label_modes
from shroud.core.newmark import stuck_stiffness
from shroud.core.results import Mode, ModalResult
from shroud.core.system import StructuralSystem
from shroud.params import Parameters

INTERFACES = ("free", "stuck")


def gyroscopic(system: StructuralSystem) -> np.ndarray:
    """G = C - alpha M - beta K: the Coriolis part of the system's C (Rayleigh's coefficients known)."""
    if system.rayleigh is None:
        raise InputError("--interface", f"the {system.model} model does not say which Rayleigh damping its C "
                                        "holds; allowed: --no-coriolis")
    a, b = system.rayleigh
    return dense(system.C) - a * dense(system.M) - b * dense(system.K)


def _labelled(system: StructuralSystem, found: Modes) -> tuple[Mode, ...]:
    tip = dense(system.tip) @ found.shapes
    components = np.column_stack([np.abs(tip[0]), np.abs(tip[1]), np.zeros((2, tip.shape[1])).T])
    labels, shares = label_modes(components)
    return tuple(Mode(f_hz=float(f), label=lab, participation=part)
                 for f, lab, part in zip(found.f_hz, labels, shares))


@dataclass(frozen=True)
class InterfaceModal:
    """The blade's modes at the interface limit, and with a ring every nodal diameter's."""

    interface: str
    blade: ModalResult
    nodal_diameters: list[dict[str, Any]] | None

    def to_json(self) -> dict[str, Any]:
        out = {**self.blade.to_json(), "interface": self.interface}
        if self.nodal_diameters is not None:
            out["nodal_diameters"] = self.nodal_diameters
        return out


def interface_modal(params: Parameters, model: str, rpm: float, n_modes: int, coriolis: bool,
                    interface: str) -> InterfaceModal:
    """Modes of ``model`` at ``rpm`` with the contact ``interface`` ("free" or "stuck")."""
    t0 = time.perf_counter()
    if interface not in INTERFACES:
        raise InputError("--interface", f"{interface!r} is unknown; allowed: {', '.join(INTERFACES)}")
    params = params.updated({"speed.rpm": rpm})
    ring = params.ring.blades
    if ring and not params.ring.tuned:
        raise InputError("ring.mistuning", "nodal diameters belong to a tuned ring; allowed: all d_j = 0 with "
                                           "modal --interface")
    if params.disk.thickness > 0:
        return _disk_modal(params, model, rpm, n_modes, coriolis, interface, t0)
    system = registry.model(model).build_system(params)
    if not 1 <= n_modes <= system.dofs:
        raise InputError("--modes", f"{n_modes} is out of range; allowed: 1..{system.dofs} (the model's DOFs)")
    M, K = dense(system.M), dense(system.K)
    G = gyroscopic(system) if coriolis and rpm > 0 else None
    c = params.contact
    stuck = interface == "stuck" and system.contact is not None and c.enabled
    K_blade = K
    if stuck and not ring:                   # springs to the fixed neighbours
        W = dense(system.contact.W)
        K_blade = K + W.T @ stuck_stiffness(contact_law(system.contact, kn=c.kn, kt=c.kt, mu=c.mu, N0=c.N0)) @ W
    blade = ModalResult(model=system.model, rpm=float(rpm), dofs=system.dofs, elapsed_s=0.0, coriolis=G is not None,
                        modes=_labelled(system, modes(M, K_blade, n_modes, G)))
    diameters = None
    if ring:
        rg = build_ring(params, model)
        springs = np.zeros(rg.rows_per_interface)
        if stuck:
            springs[0::2], springs[1::2] = c.kn * rg.weight, c.kt * rg.weight
        diameters = [{"nd": n, "modes": [{"f_hz": m.f_hz, "label": m.label} for m in _labelled(
                          system, modes(M, sector_stiffness(K, springs, rg.side1[0], rg.side2[0], ring, n),
                                        n_modes, G))]}
                     for n in nodal_diameters(ring)]
    blade = replace(blade, elapsed_s=time.perf_counter() - t0)
    return InterfaceModal(interface=interface, blade=blade, nodal_diameters=diameters)


def _disk_modal(params: Parameters, model: str, rpm: float, n_modes: int, coriolis: bool, interface: str,
                t0: float) -> InterfaceModal:
    """The cyclic sector of blade and flexible disk per nodal diameter (docs/disk.md); its nodal
    diameter 0 stands for the blade's own modes."""
    sector = registry.model(model).disk_sector
    if sector is None:
        with_disk = [name for name in registry.names("modal") if registry.model(name).disk_sector is not None]
        raise InputError("disk.thickness", f"{params.disk.thickness!r}: the {model} model has a rigid disk only; "
                                           f"allowed: 0, or --model {' or '.join(with_disk)}")
    if n_modes < 1:
        raise InputError("--modes", f"{n_modes} is out of range; allowed: an integer >= 1")
    found = sector(params, rpm, n_modes, coriolis, interface)
    diameters = [{"nd": nd, "modes": [{"f_hz": m.f_hz, "label": m.label} for m in result.modes]}
                 for nd, result in found]
    blade = replace(found[0][1], elapsed_s=time.perf_counter() - t0)
    return InterfaceModal(interface=interface, blade=blade, nodal_diameters=diameters)
