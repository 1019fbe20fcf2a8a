"""Natural frequencies of the rotating beam, with or without Coriolis.

Without Coriolis: the symmetric pencil (K_e + K_c + K_s, M).
With Coriolis: the gyroscopic problem (lambda^2 M + lambda G + K) x = 0
through a state-space form (in flexibility form, see gyroscopic_modes),
whose eigenvalues come in pairs lambda = +-i omega when G is skew and K
positive definite; the frequency is |Im lambda| / 2 pi and the real part
(zero up to round-off here) is reported as a damping ratio, a check.
Modes are labelled by tip kinematics (shroud.core.modes).
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np
import scipy.linalg

from reduced_model.beam import BeamMatrices, for_parameters
from reduced_model.reduction import stiffness_scaling, undamped_modes
from shroud.base.errors import InputError
from shroud.core.modes import label_modes
from shroud.params import Parameters
from shroud.core.results import Mode, ModalResult


@dataclass(frozen=True)
class Modes:
    f_hz: np.ndarray            # (k,) ascending
    shapes: np.ndarray          # (5N or 6N, k), complex with Coriolis
    damping_ratio: np.ndarray | None


def gyroscopic_modes(M: np.ndarray, G: np.ndarray, K: np.ndarray, count: int) -> Modes:
    """The ``count`` lowest modes of M x'' + G x' + K x = 0 by state space.

    In flexibility form (as reduction.undamped_modes), mu = 1 / lambda:
    [0, I; -K^-1 M, -K^-1 G] (x, mu x) = mu (x, mu x); the lowest modes have
    the largest |mu| and keep their digits.
    """
    n = M.shape[0]
    s = stiffness_scaling(K)
    S = np.outer(s, s)
    Kinv_M = np.linalg.solve(K * S, M * S)
    Kinv_G = np.linalg.solve(K * S, G * S)
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-Kinv_M, -Kinv_G]])
    mu, vec = scipy.linalg.eig(A)
    lam = 1.0 / mu
    # one of each conjugate pair; a tiny tolerance keeps modes whose Im is round-off negative
    keep = np.flatnonzero(lam.imag > -1e-9 * np.abs(lam))
    keep = keep[np.argsort(np.abs(lam[keep].imag))][:count]
    lam = lam[keep]
    return Modes(f_hz=np.abs(lam.imag) / (2.0 * np.pi), shapes=vec[:n, keep] * s[:, None],
                 damping_ratio=-lam.real / np.abs(lam))


def modes_at(beam: BeamMatrices, omega: float, count: int, coriolis: bool) -> Modes:
    """The ``count`` lowest modes of the full beam model at Omega (rad/s)."""
    K = beam.stiffness(omega)
    if coriolis and omega != 0.0:
        undamped_modes(beam.M, K)          # same stability check as the undamped path
        return gyroscopic_modes(beam.M, beam.gyroscopic(omega), K, count)
    basis = undamped_modes(beam.M, K)
    return Modes(f_hz=basis.f_hz[:count], shapes=basis.shapes[:, :count], damping_ratio=None)


def modal_analysis(params: Parameters, rpm: float, n_modes: int, coriolis: bool) -> ModalResult:
    """Frequencies and tip-kinematics labels of the beam model (5N or 6N DOF) at ``rpm``."""
    t0 = time.perf_counter()
    beam = for_parameters(params)
    if not 1 <= n_modes <= beam.dofs:
        raise InputError("--modes", f"{n_modes} is out of range; allowed: 1..{beam.dofs} (fields x reduced.N)")
    modes = modes_at(beam, 2.0 * np.pi * rpm / 60.0, n_modes, coriolis)
    labels, shares = label_modes(beam.tip_kinematics(modes.shapes))
    zeta = modes.damping_ratio if modes.damping_ratio is not None else [None] * len(labels)
    result_modes = tuple(
        Mode(f_hz=float(f), label=lab, participation=part,
             damping_ratio=None if z is None else float(z))
        for f, lab, part, z in zip(modes.f_hz, labels, shares, zeta))
    return ModalResult(model="reduced", rpm=float(rpm), dofs=beam.dofs,
                       elapsed_s=time.perf_counter() - t0, coriolis=coriolis,
                       modes=result_modes, shapes=modes.shapes)
