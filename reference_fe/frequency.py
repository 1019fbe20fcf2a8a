"""The reduced solid over a speed range, for harmonic balance with continuation in speed.

The solid's operators are exact polynomials in the speed (reference_fe.solid):
K(Omega) = K_e + Omega^2 K_rot1 (linear prestress and spin softening, both
in Omega^2) and G(Omega) = Omega G_1. Projected on ONE free-interface basis
T (reference_fe.cms, built at ``params.speed.rpm``: its normal modes plus
the residual attachment modes of the contact and the load) they stay exact
polynomials,

    K_r(Omega) = T^T K_e T + Omega^2 T^T K_rot1 T,    G_r(Omega) = Omega T^T G_1 T,    M_r = I,

so a curve over speed needs no rebuild of the basis per speed; Rayleigh
damping (paper Eq. 2) is recomputed at each speed from the two lowest
frequencies of (K_r(Omega), I), as the time-domain model does with its own.
The time-domain "fe-reduced" model instead builds its basis at every
speed; :func:`basis_error` measures what the one basis costs against it.
"""

from __future__ import annotations

import math
import time
from pathlib import Path
from typing import Callable

import numpy as np

from shroud.base.cache import cached
from shroud.base.parallel import on_rank_zero
from shroud.core.damping import rayleigh
from shroud.core.system import ContactElements, StructuralSystem
from shroud.params import Parameters


def _build(params: Parameters, path: Path, kind: str = "fe") -> None:
    from reference_fe.cms import free_interface_basis, project
    from reference_fe.factor import MumpsFactor
    from reference_fe.system import _kept, _solid, check_reduction_sizes
    from shroud.base.log import info

    t0 = time.perf_counter()
    rpm = params.speed.rpm
    omega = 2.0 * math.pi * rpm / 60.0
    solid, at_rest = _solid(params, rpm, kind), _solid(params, 0.0, kind)
    modes, patterns = _kept(params, kind)
    contact = solid.contact
    W = contact.W if contact is not None else np.zeros((0, solid.M.shape[0]))
    check_reduction_sizes(params, solid.M.shape[0], W.shape[0], kind)
    basis = free_interface_basis(solid.K, solid.M, modes, solid.f_aero[:, None],
                                 lu=MumpsFactor(solid.K), W=W, interface_modes=patterns)
    K0 = project(basis, at_rest.K)                     # T^T K_e T
    K2 = (np.diag(basis.omega2) - K0) / omega**2       # T^T K_rot1 T
    G1 = project(basis, solid.G) / omega
    T = basis.T
    info(f"{kind} speed-range basis at {rpm:g} r/min: {basis.size} vectors in {time.perf_counter() - t0:.1f} s")
    with open(path, "wb") as fh:
        np.savez(fh, K0=0.5 * (K0 + K0.T), K2=0.5 * (K2 + K2.T), G1=0.5 * (G1 - G1.T),
                 f_aero=T.T @ solid.f_aero, tip=np.asarray(solid.tip @ T), W=np.asarray(W @ T),
                 normal_row=contact.normal_row if contact else np.zeros(0, int),
                 tangent_row=contact.tangent_row if contact else np.zeros(0, int),
                 side=contact.side if contact else np.zeros(0, int),
                 weight=contact.weight if contact else np.zeros(0), rpm=rpm)


def speed_range_operators(params: Parameters, kind: str = "fe") -> Path:
    """Path of the cached .npz of the one-basis operators (K0, K2, G1, loads, W) built at params.speed.rpm
    for the solid (``kind = "fe"``) or the shell."""
    from reference_fe.system import REDUCTION_SOURCES, reduction_inputs
    # Built serially, as the per-speed bases: under mpirun rank 0 builds it into the cache for all. Keyed on
    # the code that shapes it too, as they are (an edited form must not reuse an old basis).
    return on_rank_zero(lambda: cached(f"{kind}_speed_range", {**reduction_inputs(params, params.speed.rpm, kind),
                                                               "polynomial": 1}, ".npz",
                                       lambda path: _build(params, path, kind), what=f"{kind} speed-range basis",
                                       sources=(*REDUCTION_SOURCES[kind], __name__)))


def at_speed(params: Parameters, kind: str = "fe") -> Callable[[float], StructuralSystem]:
    """rpm -> the reduced solid (shell: ``kind``) at that speed on the one basis of :func:`speed_range_operators`."""
    with np.load(speed_range_operators(params, kind)) as data:
        d = {k: data[k] for k in data.files}
    contact = None
    if d["side"].size and params.contact.enabled:
        contact = ContactElements(W=d["W"], normal_row=d["normal_row"], tangent_row=d["tangent_row"],
                                  side=d["side"], weight=d["weight"])
    r = d["K0"].shape[0]
    eye = np.eye(r)

    def system(rpm: float) -> StructuralSystem:
        omega = 2.0 * math.pi * rpm / 60.0
        K = d["K0"] + omega**2 * d["K2"]
        w2 = np.linalg.eigvalsh(K)[:2]
        a, b = rayleigh(*(np.sqrt(w2) / (2 * math.pi)), params.damping.xi1, params.damping.xi2)
        return StructuralSystem(model=f"{kind}-reduced", M=eye, C=a * eye + b * K + omega * d["G1"], K=K,
                                f_const=np.zeros(r), f_aero=params.load.F0 * d["f_aero"],
                                omega_e=params.load.ke * omega, tip=d["tip"], contact=contact,
                                rayleigh=(float(a), float(b)))
    return system


def basis_error(params: Parameters, rpms) -> list[dict]:
    """The one basis against the per-speed basis of the time-domain model, at each speed in ``rpms``.

    Per speed: the largest relative difference of the 6 lowest frequencies,
    and of the contact-free tip response v_L to the load at ke Omega
    (|tip Z^-1 f_aero| with Z = K - w^2 M + i w C), both models' own damping.
    """
    from reference_fe.system import build_system
    one = at_speed(params)
    out = []
    for rpm in rpms:
        per = build_system(params.updated({"speed.rpm": float(rpm)}), reduced=True)
        rng = one(float(rpm))
        f_per, f_rng = (np.sqrt(np.linalg.eigvalsh(np.asarray(s.K))[:6]) for s in (per, rng))
        resp = [abs((np.asarray(s.tip) @ np.linalg.solve(s.K - s.omega_e**2 * s.M + 1j * s.omega_e * s.C,
                                                         s.f_aero))[0]) for s in (per, rng)]
        out.append({"rpm": float(rpm), "frequency_error": float(np.max(np.abs(f_rng / f_per - 1))),
                    "response_error": float(abs(resp[1] / resp[0] - 1))})
    return out

