"""The ring over speed by harmonic balance: tuned by one sector, mistuned as a whole (docs/ring.md).

The travelling wave of a tuned ring has U_{j+1,h} = exp(i h phi) U_{j,h}
(phi = 2 pi ke / N), so blade 0 carries the ring: its linear part is the
single blade's (shroud.analysis.hb.SpeedModel: condensed on its contact
coordinates, at any speed), and its contact is interface 0 seen through
the sector projection (shroud.core.cyclic.sector_projection): the relative
coordinates S2 y_0(tau) - S1 y_0(tau + phi), forces back through the
transpose. The branch is continued in speed by the single blade's own
continuation (shroud.analysis.hb.follow_branch: corners passed forward,
folds located and recorded, never retracing).

Stability: against perturbations of every nodal diameter, not only the
travelling wave's: the whole ring linearized about the wave
(shroud.core.floquet on the N blades, interface j's states and friction
being interface 0's shifted by j phi / (ke Omega) in time), its monodromy
over one period, built from g / N of it (g = gcd(N, ke)) by the wave's own
symmetry: relabelling the blades by r (r ke = g mod N) and shifting time
by T g / N maps the linearized ring onto itself (:func:`ring_symmetry`,
floquet.symmetric_monodromy). (A sector-size Bloch decomposition is not
exact here: the relabelling alone is no symmetry, only with the time
shift, so one Bloch wave's perturbation is a delay equation on the
sector.)

A mistuned ring (or any ring, :func:`whole_ring_at`) is solved as a whole:
every blade condensed on its own contact coordinates
(shroud.core.ring.ring_harmonics), the interfaces on their relative
coordinates, continued by shroud.analysis.hb.run_hb itself (RingOverSpeed
is its ``build``), stability from the same ring's monodromy; its linear
solves by a banded LU with pivoting (:func:`whole_ring`,
shroud.core.cyclic_banded: blade j couples only to blades j - 1, j + 1).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, replace
from typing import Any, Callable

import numpy as np

from shroud.analysis.hb import (DEFAULT_HARMONICS, REFINED_ITERATIONS, SpeedModel, branch_result, branch_scale,
                                check_inputs, follow_branch, model_at_speed, point_details, run_hb, speed_step)
from shroud.analysis.ring import RING_MODELS, blade_parameters, pairing
from shroud.analysis.transient import contact_law_for
from shroud.base.errors import InputError, RunDiverged
from shroud.core import floquet
from shroud.core import harmonic_balance as hb
from shroud.core.contact import KN, KT, N0, ContactLaw, contact_law
from shroud.core.continuation import continue_branch
from shroud.core.cyclic_banded import CyclicBanded, harmonic_major_blocks
from shroud.core.cyclic import Faces, ring_shifts, sector_balance
from shroud.core.results import HBResult
from shroud.core.ring import (assembled_system, face_selectors, interface_elements, ring_harmonics, ring_of,
                              with_rayleigh)
from shroud.core.system import StructuralSystem
from shroud.params import Parameters


@dataclass(frozen=True)
class Sector:
    """What the sector's balance needs besides the blade's linear part."""

    N: int
    ke: int
    faces: Faces | None        # interface 0 seen from the sector; None: the unknowns are the law's coordinates
    law: ContactLaw            # interface 0's points on its relative coordinates (or every interface's)
    banded: CyclicBanded | None = None   # the structure of a whole ring's Jacobian (None: dense solves)

    def solve(self, A: np.ndarray, b: np.ndarray) -> np.ndarray:
        """x with A x = b for a Newton step or a start: banded where the structure is declared."""
        return np.linalg.solve(A, b) if self.banded is None else self.banded(A, b)

    @property
    def phi(self) -> float:
        return 2.0 * math.pi * self.ke / self.N


def ring_model_at_speed(params: Parameters, model: str) -> Callable[[float], StructuralSystem]:
    """rpm -> ``model``'s blade at that speed with its faces paired for the ring (ring.pairing)."""
    pair, at = pairing(params, model), model_at_speed(params, model)
    return lambda rpm: pair(at(rpm))


def sector_of(system: StructuralSystem, params: Parameters, H: int) -> Sector:
    """The sector of ``system``'s blade in a ring of ``params.ring.blades`` at engine order ``load.ke``."""
    S1, S2, weight = face_selectors(system.contact)
    c = params.contact
    law = contact_law(interface_elements(weight, np.eye(S1.shape[0])), kn=c.kn, kt=c.kt, mu=c.mu, N0=c.N0)
    N, ke = params.ring.blades, params.load.ke
    return Sector(N=N, ke=ke, faces=Faces(S1, S2, 2.0 * math.pi * ke / N), law=law)


def _residual(speeds: SpeedModel, sector: Sector, basis: hb.Fourier):
    """R(X, rpm), dR/dX and, on demand, dR/drpm (the law does not depend on the speed)."""
    def residual(X, rpm):
        lin, L, F = speeds.linear(rpm)
        b = sector_balance(X, lin, sector.law, basis, sector.faces, L, F.reshape(basis.nh, lin.nx))
        residual.last = (X, rpm, b)

        def d_rpm():
            dL, dF = speeds.derivative(rpm)
            return dL @ X - dF
        return b.R, b.J, d_rpm
    residual.last = None
    return residual


def _projected(sector: Sector, lin: hb.LinearHarmonics, H: int) -> np.ndarray:
    """Pa (nh c, nh nx), dense: the relative coordinates' harmonics from the unknowns' (the whole ring's:
    I (x) Wx), for the one-off uses (Newton's linear starts, the orbit for the stability)."""
    if sector.faces is None:
        return np.kron(np.eye(2 * H + 1), lin.Wx)
    return sector.faces.projection(H, lin.Wx)


def with_springs(lin: hb.LinearHarmonics, sector: Sector, basis: hb.Fourier, share: float) -> np.ndarray:
    """A start for Newton: the linear sector with every interface as springs of ``share`` times the law's kn
    and kt (0: contact-free; 1: stuck; 0.5: the mean of open and closed)."""
    nh = basis.nh
    D = np.zeros(sector.law.m)
    D[sector.law.rows[:, 0]] += share * sector.law.props[:, 1]
    D[sector.law.rows[:, 1]] += share * sector.law.props[:, 2]
    Pa = _projected(sector, lin, basis.H)
    return sector.solve(lin.L + Pa.T @ (np.tile(D, nh)[:, None] * Pa), lin.Fr.ravel())


STARTS = (0.5, 1.0, 0.1, 0.0)   # shares of the springs of the linear starts tried, in order
MOST_POINTS = 300               # of the continuation in the contact's stiffness (96 reach 24 tuned blades)


def sector_newton(X: np.ndarray, lin: hb.LinearHarmonics, sector: Sector, basis: hb.Fourier, tol: float = 1e-10,
                  max_iterations: int = 60) -> tuple[np.ndarray, bool]:
    """Newton on the sector's balance at one speed (the core's damped Newton, with the sector's structured
    solve), accepted at |R| <= 1e-6 |F|."""
    X, _, _, residual, _ = hb.damped_newton(
        lambda X, jacobian: sector_balance(X, lin, sector.law, basis, sector.faces, jacobian=jacobian),
        X, np.linalg.norm(lin.Fr) + 1e-300, tol, max_iterations, solve=sector.solve, shortest_step=1e-4)
    return X, residual <= hb.ACCEPT


def stiffened(law: ContactLaw, share: float) -> ContactLaw:
    """``law`` with kn, kt and N0 times ``share`` (the same gap or interference N0 / kn, softer springs)."""
    props = law.props.copy()
    props[:, [KN, KT, N0]] *= share
    return replace(law, props=props)


def sector_solve(lin: hb.LinearHarmonics, sector: Sector, basis: hb.Fourier, soft: float = 1e-3) -> np.ndarray:
    """The travelling wave at one speed by Newton from linear sectors with springs (:func:`with_springs`,
    STARTS in order), else by continuation in the contact's stiffness from ``soft`` times it (where the
    contact-free solution is Newton's start) up to all of it.

    The contact-free blade alone is a poor start: near its resonance it moves by tens of um where the
    ring's interfaces hold it to a few (6 blades at 10000 r/min: Newton stalls at |R| = |F| / 3 from it and
    converges in 10 steps from half springs). A continuation in the load cannot help where N0 = 0: the
    problem is then homogeneous in the load. 24 blades at 6000 r/min stall at |R| = |F| / 2 from every
    linear start, and the stiffness continuation reaches the wave in 96 points (0.24 s).
    """
    for share in STARTS:
        X, ok = sector_newton(with_springs(lin, sector, basis, share), lin, sector, basis)
        if ok:
            return X

    def residual(X, share):
        b = sector_balance(X, lin, stiffened(sector.law, share), basis, sector.faces)

        def d_share():
            h = 1e-6 * share
            return (sector_balance(X, lin, stiffened(sector.law, share + h), basis, sector.faces,
                                   jacobian=False).R - b.R) / h
        return b.R, b.J, d_share
    X0 = hb.linear_solution(lin)
    path = continue_branch(residual, X0, soft, 1.0, float(np.abs(X0).max()) + 1e-300, ds=0.05, ds_max=0.5,
                           p_scale=1.0, max_points=MOST_POINTS)
    if not (path.complete and path.p and path.p[-1] == 1.0):
        raise RunDiverged(f"no periodic state reached, neither by Newton from linear sectors with springs "
                          f"nor by continuation in the contact's stiffness: {path.stopped}")
    return path.x[-1]


def _ring_samples(sector: Sector, samples: int) -> int:
    """The least multiple of N / gcd(N, ke) at or above ``samples``: interface j's states are then interface
    0's shifted by a whole number of samples (j ke / N of the period)."""
    unit = sector.N // math.gcd(sector.N, sector.ke)
    return unit * math.ceil(samples / unit)


def _ring_orbit(sector: Sector, lin: hb.LinearHarmonics, X: np.ndarray, basis: hb.Fourier, samples: int):
    """(state, F, y_rate) of every interface of the ring on the travelling wave X, the law sampled at
    ``samples`` instants (a multiple of N / gcd(N, ke)): interface 0's, shifted for interface j."""
    fine = hb.fourier(basis.H, samples)
    nh = basis.nh
    Y = (_projected(sector, lin, basis.H) @ X).reshape(nh, -1)
    ch = hb.contact_harmonics(Y, np.eye(Y.shape[1]), sector.law, fine, jacobian=False)
    rate = fine.rates(Y, lin.omega)                          # (samples, c)
    shifts = ring_shifts(samples, sector.N, sector.ke)
    return (np.vstack([np.roll(ch.state, -s, axis=1) for s in shifts]),
            np.vstack([np.roll(ch.F, -s, axis=1) for s in shifts]),
            np.hstack([np.roll(rate, -s, axis=0) for s in shifts]))


def _ring_flow(system: StructuralSystem, sector: Sector) -> tuple:
    """(M, C, K, W, law) of the whole tuned ring of ``system``'s blade: every interface's points."""
    ring = ring_of([system] * sector.N, sector.ke)
    M, C, K = ring.assembled()
    elements = ring.contact()
    law = replace(sector.law, rows=np.column_stack([elements.normal_row, elements.tangent_row]),
                  props=np.tile(sector.law.props, (sector.N, 1)), side=elements.side, weight=elements.weight,
                  m=elements.W.shape[0])
    return M, C, K, elements.W, law


def ring_symmetry(sector: Sector, blade_dofs: int) -> floquet.Symmetry:
    """The travelling wave's symmetry of the linearized ring (floquet.Symmetry): interface j at time t is
    interface 0 at t + j T ke / N, so blade j + r at t - T g / N moves as blade j at t when r ke = g
    (mod N), g = gcd(N, ke); G relabels blade j - r as j (and interface j - r as j), q = N / g."""
    N, g = sector.N, math.gcd(sector.N, sector.ke)
    r = pow(sector.ke // g, -1, N // g) if N > g else 0
    e = sector.law.m // 2                                     # points of one interface
    def moved(size):
        return (((np.arange(N) - r) % N)[:, None] * size + np.arange(size)).ravel()
    return floquet.Symmetry(dofs=moved(blade_dofs), elements=moved(e), q=N // g)


def ring_multipliers(system: StructuralSystem, sector: Sector, lin: hb.LinearHarmonics, X: np.ndarray,
                     basis: hb.Fourier, symmetric: bool = True) -> np.ndarray:
    """Floquet multipliers of the whole ring about the travelling wave X (the sector's unknowns), every
    nodal diameter's perturbations included: interface j's states are interface 0's shifted by j ke / N of
    the period, sampled at a multiple of N / gcd(N, ke) instants (at least the AFT's). ``symmetric``: the
    monodromy from g / N of the period and the wave's symmetry (:func:`ring_symmetry`); False: integrated
    over the whole period."""
    orbit = _ring_orbit(sector, lin, X, basis, _ring_samples(sector, basis.samples))
    return floquet.orbit_multipliers(*_ring_flow(system, sector), *orbit[:2], lin.omega, orbit[2],
                                     ring_symmetry(sector, system.dofs) if symmetric else None)


def ring_stability(speeds: SpeedModel, sector: Sector, basis: hb.Fourier, X: np.ndarray,
                   rpm: float) -> floquet.Stability:
    """:func:`ring_multipliers` with the error the single blade's points carry (shroud.analysis.hb
    .point_details): the largest of floquet.MULTIPLIER_FLOOR, the change at half the samples and the change
    when the wave is solved again with twice the harmonics (Newton from X, at most
    REFINED_ITERATIONS; no state there: the error is infinite, the point undecided)."""
    system, lin, _, _ = speeds.at(rpm)
    samples = _ring_samples(sector, basis.samples)
    half = _ring_samples(sector, max(samples // 2, 2 * basis.H + 1))
    orbit, coarse = (_ring_orbit(sector, lin, X, basis, n) for n in (samples, half))
    st = floquet.orbit_stability(*_ring_flow(system, sector), *orbit[:2], lin.omega, orbit[2], coarse,
                                 ring_symmetry(sector, system.dofs))
    fine = speeds.refined()
    fine_basis = hb.fourier(fine.H, max(basis.samples, 4 * fine.H + 1))
    fine_lin = fine.linear(rpm)[0]
    X0 = np.zeros((fine_basis.nh, X.size // basis.nh))
    X0[:basis.nh] = X.reshape(basis.nh, -1)
    X2, ok = sector_newton(X0.ravel(), fine_lin, sector, fine_basis, max_iterations=REFINED_ITERATIONS)
    refined = float(np.abs(ring_multipliers(system, sector, fine_lin, X2, fine_basis)).max()) if ok else None
    return st.truncated(refined)


def _details(speeds: SpeedModel, sector: Sector, basis: hb.Fourier, X: np.ndarray, rpm: float,
             stability: bool) -> dict:
    lin, L, F = speeds.linear(rpm)
    b = sector_balance(X, lin, sector.law, basis, sector.faces, L, F.reshape(basis.nh, lin.nx), jacobian=False)
    tip = lin.tip(X.reshape(basis.nh, lin.nx), b.Lam_y)
    amp = hb.amplitude_over_period(tip)
    st = ring_stability(speeds, sector, basis, X, rpm) if stability else None
    return {"amplitude_v_L": float(amp[0]), "amplitude_w_L": float(amp[1]),
            "tail": hb.spectral_tail(b.contact.lam, basis.H), "force_rms": float(np.std(b.contact.lam)),
            "multipliers": st.multipliers if st else np.array([np.nan]),
            "multiplier_error": st.error if st else math.nan, "stable": st.stable if st else None}


@dataclass(frozen=True)
class RingHBResult:
    """A ring's branch over speed: blade 0's (tuned: every blade alike) and every blade's amplitudes."""

    branch: HBResult
    blades: int
    stability: bool = True     # False: no multipliers computed (the JSON's stable and max_multiplier are null)
    amplitudes: list[list[float]] | None = None   # per point, every blade's v_L amplitude (None: tuned, alike)

    @property
    def complete(self) -> bool:
        return self.branch.complete

    @property
    def stopped(self) -> str | None:
        return self.branch.stopped

    def to_json(self) -> dict[str, Any]:
        out = self.branch.to_json()
        if not self.stability:
            out["stable"] = out["max_multiplier"] = [None] * len(out["rpm"])
            out["bifurcations"] = []
        every = self.amplitudes or [[float(a)] * self.blades for a in self.branch.amplitude_v_L]
        return {**out, "blades": self.blades, "blades_amplitude_v_L": every}


def check_ring_hb(params: Parameters, model: str) -> None:
    if model not in RING_MODELS:
        raise InputError("ring.blades", f"a ring of {model} blades is not solved by harmonic balance yet; "
                                        f"allowed: --model {', '.join(RING_MODELS)}")


def run_ring_hb(params: Parameters, model: str, rpm_from: float, rpm_to: float,
                harmonics: int = DEFAULT_HARMONICS, samples: int | None = None, min_points: int | None = None,
                stability: bool = True, stability_points: int | None = None,
                stability_at: tuple[float, ...] = ()) -> RingHBResult:
    """The ring's branch from ``rpm_from`` to ``rpm_to`` (r/min): tuned, the travelling wave by one sector
    (``stability=False``: without the ring's multipliers; ``stability_points``: the ring's stability at that
    many points spread over the branch, at both ends of every stretch crossing a speed of ``stability_at``
    and where it changes, :func:`located_changes`, instead of at every point); mistuned, the whole ring
    (run_whole_ring_hb)."""
    t0 = time.perf_counter()
    check_ring_hb(params, model)
    if not params.ring.tuned:
        return run_whole_ring_hb(params, model, rpm_from, rpm_to, harmonics, samples, min_points, stability)
    n = check_inputs(harmonics, samples, rpm_from, rpm_to)
    basis = hb.fourier(harmonics, n)
    speeds = SpeedModel(ring_model_at_speed(params, model), harmonics)
    system, lin, _, _ = speeds.at(rpm_from)
    sector = sector_of(system, params, harmonics)
    X0 = sector_solve(lin, sector, basis)
    branch, details = follow_branch(
        _residual(speeds, sector, basis), X0, rpm_from, rpm_to, branch_scale(params, hb.linear_solution(lin)),
        speed_step(rpm_from, rpm_to, min_points), f"HB ring of {sector.N} {model}",
        lambda X, rpm, previous: _details(speeds, sector, basis, X, rpm, stability and not stability_points))
    if stability and stability_points:
        ends = [j for rpm in stability_at for i, (a, b) in enumerate(zip(branch.p, branch.p[1:]))
                if a != b and min(a, b) <= rpm <= max(a, b) for j in (i, i + 1)]
        found = located_changes(lambda i: ring_stability(speeds, sector, basis, branch.x[i], branch.p[i]),
                                len(branch.p), stability_points, ends)
        for i, st in found.items():
            details[i].update(multipliers=st.multipliers, multiplier_error=st.error, stable=st.stable)
    result = branch_result(branch, details, model=model, harmonics=harmonics, samples=n, dofs=system.dofs,
                           condensed=lin.condensed, elapsed_s=time.perf_counter() - t0)
    return RingHBResult(branch=result, blades=params.ring.blades, stability=stability)


def located_changes(evaluate: Callable[[int], floquet.Stability], n: int, spread: int,
                    also: tuple[int, ...] | list[int] = ()) -> dict:
    """Stability at ``spread`` points of an ``n``-point branch (index 0, n - 1 and evenly between) and at the
    indices ``also``, then, between two neighbours whose verdicts differ (stable, unstable, undecided), at
    the middle point again and again until they are adjacent: every point not evaluated lies between two
    evaluated ones with one verdict. {index: evaluate(index)}; a branch of at most ``spread`` points is
    evaluated everywhere. A stretch of another verdict shorter than the spacing, between two of one
    verdict, is not seen (48 blades, 1 um: 12 spread points miss a stable stretch of 15 points at
    11290-12556 r/min, docs/ring-tuned.md)."""
    first = np.unique(np.r_[np.linspace(0, n - 1, min(spread, n)).round(), np.asarray(also, float)])
    done = {int(i): evaluate(int(i)) for i in first}
    pending = sorted(done)
    gaps = list(zip(pending, pending[1:]))
    while gaps:
        a, b = gaps.pop()
        if b - a > 1 and done[a].stable is not done[b].stable:
            m = (a + b) // 2
            done[m] = evaluate(m)
            gaps += [(a, m), (m, b)]
    return done


def sector_at(params: Parameters, model: str, rpm: float, harmonics: int = DEFAULT_HARMONICS,
              samples: int | None = None, stability: bool = True, start: np.ndarray | None = None) -> dict:
    """The travelling wave at one speed: its details (amplitudes, multipliers, stability) and X. ``start``:
    a wave's X at any number of harmonics, Newton's first start (cut or padded to ``harmonics``); then the
    linear starts (:func:`sector_solve`), then the waves at other numbers of harmonics
    (:func:`from_other_harmonics`)."""
    check_ring_hb(params, model)
    n = check_inputs(harmonics, samples, rpm * 0.5, rpm)
    basis = hb.fourier(harmonics, n)
    speeds = SpeedModel(ring_model_at_speed(params, model), harmonics)
    system, lin, _, _ = speeds.at(rpm)
    sector = sector_of(system, params, harmonics)
    X, ok = (None, False) if start is None else sector_newton(resized(start, basis.nh), lin, sector, basis)
    if not ok:
        try:
            X = sector_solve(lin, sector, basis)
        except RunDiverged as failed:
            X = from_other_harmonics(params, model, rpm, lin, sector, basis, failed)
    return {**_details(speeds, sector, basis, X, rpm, stability), "X": X}


def resized(X: np.ndarray, nh: int) -> np.ndarray:
    """``X`` (coefficients, m: harmonic-major) cut or padded with zeros to ``nh`` coefficients, flat."""
    Y = np.atleast_2d(X)
    out = np.zeros((nh, Y.shape[1]))
    out[:min(nh, Y.shape[0])] = Y[:nh]
    return out.ravel()


OTHER_HARMONICS = (1.5, 0.5)    # numbers of harmonics tried (times H) where no linear start reaches the wave


def from_other_harmonics(params: Parameters, model: str, rpm: float, lin: hb.LinearHarmonics, sector: Sector,
                         basis: hb.Fourier, failed: RunDiverged) -> np.ndarray:
    """The wave at H by Newton from the wave :func:`sector_solve` reaches with another number of harmonics
    (OTHER_HARMONICS times H in order), its coefficients cut or padded with zeros; ``failed`` re-raised where
    none does. The stiffness continuation from the linear start turns back at some H and not at others
    (12 blades, Fig. 11b contact, 1 um, 8000 r/min: reached at H = 5 and 30, not at 10, 15, 20)."""
    at = ring_model_at_speed(params, model)
    system = at(rpm)
    for factor in OTHER_HARMONICS:
        H = max(1, round(factor * basis.H))
        if H == basis.H:
            continue
        other = hb.fourier(H, hb.default_samples(H))
        try:
            Y = sector_solve(SpeedModel(at, H).linear(rpm)[0], sector_of(system, params, H), other)
        except RunDiverged:
            continue
        X, ok = sector_newton(resized(Y.reshape(other.nh, -1), basis.nh), lin, sector, basis)
        if ok:
            return X
    raise failed


def ring_state(system: StructuralSystem, lin: hb.LinearHarmonics, sector: Sector, basis: hb.Fourier,
               X: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(q, q') of every blade at t = 0 on the travelling wave X (N, nb each): blade j at tau = j phi of
    blade 0, whose DOFs' harmonics are Q_h = Z_h^-1 (F_h + W^T Lam_h) (for starting the ring in time on it)."""
    nh, H = basis.nh, basis.H
    if lin.condensed:
        b = sector_balance(X, lin, sector.law, basis, sector.faces, jacobian=False)
        W = np.asarray(system.contact.W)
        rhs = hb.load_harmonics(system, H) + hb._complex_coefficients(b.Lam_y) @ W
        Q = hb._real_coefficients(np.linalg.solve(hb.dynamic_stiffness(system, H), rhs[:, :, None])[:, :, 0])
    else:
        Q = X.reshape(nh, lin.nx)
    h = np.arange(1, H + 1)
    q, v = [], []
    for j in range(sector.N):
        tau = j * sector.phi
        c, s = np.cos(h * tau), np.sin(h * tau)
        q.append(Q[0] + c @ Q[1::2] + s @ Q[2::2])
        v.append(lin.omega * ((h * c) @ Q[2::2] - (h * s) @ Q[1::2]))
    return np.array(q), np.array(v)


# --- a mistuned ring: the whole ring condensed on its interfaces ------------------------------------

class RingOverSpeed:
    """The (mistuned) ring at any speed, for continuation (shroud.analysis.hb.SpeedModel's ``build``):
    called with a speed, the ring as one system (shroud.core.ring.assembled_system: its M, C, K and
    contact for the stability); :meth:`harmonics` its linear part condensed on the interfaces
    (shroud.core.ring.ring_harmonics, with the travelling wave's load). Each blade is its model at that
    speed (its own basis), with the tuned blade's Rayleigh coefficients."""

    def __init__(self, params: Parameters, model: str):
        self.model, self.ke = model, params.load.ke
        self.tuned = ring_model_at_speed(params, model)
        self.blades = [None if d == 0.0 else ring_model_at_speed(blade_parameters(params, j), model)
                       for j, d in enumerate(params.ring.deviations)]
        self._last: tuple[float, Any] | None = None

    def ring(self, rpm: float):
        if self._last is None or self._last[0] != rpm:
            tuned = self.tuned(rpm)
            blades = [tuned if b is None else with_rayleigh(b(rpm), tuned.rayleigh) for b in self.blades]
            self._last = (rpm, ring_of(blades, self.ke))
        return self._last[1]

    def __call__(self, rpm: float) -> StructuralSystem:
        return assembled_system(self.ring(rpm), self.model)

    def harmonics(self, rpm: float, H: int) -> hb.LinearHarmonics:
        return ring_harmonics(self.ring(rpm), H)


STRUCTURED = True   # the whole ring's linear solves banded (False: dense, for the benchmarks' comparison)


def whole_ring(params: Parameters, lin: hb.LinearHarmonics, law: ContactLaw, basis: hb.Fourier) -> Sector:
    """The whole ring as the "sector" of :func:`sector_solve` (no projection: every interface's points),
    its linear solves by the banded LU of shroud.core.cyclic_banded: blade j's unknowns (every harmonic of
    its contact coordinates) couple only to blades j - 1 and j + 1, so the Jacobian is cyclic
    block-tridiagonal in blade order (1008 x 1008 in 24 blocks of 42 at H = 10: 5.8 ms a solve against
    20 ms dense), with diagonal blocks far from dominant (the block elimination of
    shroud.core.cyclic_blocks breaks down on it)."""
    N = params.ring.blades
    banded = CyclicBanded(harmonic_major_blocks(N, basis.nh, lin.nx // N)) if N >= 3 and STRUCTURED else None
    return Sector(N=N, ke=params.load.ke, faces=None, law=law, banded=banded)


def whole_ring_at(params: Parameters, model: str, rpm: float, harmonics: int = DEFAULT_HARMONICS,
                  samples: int | None = None, stability: bool = True) -> dict:
    """The (mistuned) ring at one speed by harmonic balance on all its interfaces: every blade's
    amplitudes, the multipliers of the ring's monodromy, X."""
    check_ring_hb(params, model)
    n = check_inputs(harmonics, samples, rpm * 0.5, rpm)
    basis = hb.fourier(harmonics, n)
    speeds = SpeedModel(RingOverSpeed(params, model), harmonics)
    system, lin, _, _ = speeds.at(rpm)
    whole = whole_ring(params, lin, contact_law_for(system, params.contact), basis)
    X = sector_solve(lin, whole, basis)
    return {**(point_details(speeds, whole.law, basis, X, rpm) if stability else {}),
            "blades_amplitude_v_L": blade_amplitudes(lin, whole.law, basis, X), "X": X}


def blade_amplitudes(lin: hb.LinearHarmonics, law: ContactLaw, basis: hb.Fourier, X: np.ndarray) -> list[float]:
    """(max - min)/2 of each blade's v_L over the period (the ring's tip rows 2j)."""
    b = hb.balance(X, lin, law, basis, jacobian=False)
    return [float(a) for a in hb.amplitude_over_period(lin.tip(X.reshape(basis.nh, lin.nx), b.contact.Lam))[0::2]]


def run_whole_ring_hb(params: Parameters, model: str, rpm_from: float, rpm_to: float, harmonics: int,
                      samples: int | None, min_points: int | None, stability: bool = True) -> RingHBResult:
    """The mistuned ring's branch by shroud.analysis.hb.run_hb on the whole ring condensed on its
    interfaces (RingOverSpeed), started on the state :func:`sector_solve` reaches at ``rpm_from``."""
    n = check_inputs(harmonics, samples, rpm_from, rpm_to)
    build = RingOverSpeed(params, model)
    speeds = SpeedModel(build, harmonics)
    system, lin, _, _ = speeds.at(rpm_from)
    law = contact_law_for(system, params.contact)
    basis = hb.fourier(harmonics, n)
    whole = whole_ring(params, lin, law, basis)
    X0 = sector_solve(lin, whole, basis)
    branch = run_hb(params, model, rpm_from, rpm_to, harmonics=harmonics, samples=n, min_points=min_points,
                    build=build, start=X0, stability=stability,
                    factorize=None if whole.banded is None else whole.banded.factor)
    blades = [blade_amplitudes(speeds.linear(r)[0], law, basis, X) for r, X in zip(branch.rpm, branch.X)]
    return RingHBResult(branch=branch, blades=params.ring.blades, amplitudes=blades, stability=stability)


def stability_verdict(params: Parameters, model: str, rpm: float, harmonics: int = DEFAULT_HARMONICS):
    """Whether the tuned ring's travelling wave at ``rpm`` is stable, as a shroud.core.verdict.Verdict on
    the largest |multiplier| of the ring's monodromy (threshold 1) at 2 H harmonics, its margin the change
    from H (the orbit's impacts shift the multipliers by a few % with H: 24 blades at 10000 r/min,
    1.225 / 1.011 / 1.039 at H = 10 / 20 / 40); within it the verdict is "not decided"."""
    from shroud.core.verdict import Verdict
    largest, X = [], None
    for H in (harmonics, 2 * harmonics):
        d = sector_at(params, model, rpm, harmonics=H, samples=hb.default_samples(H),
                      start=None if X is None else X.reshape(2 * harmonics + 1, -1))
        X = d["X"]
        largest.append(float(np.abs(d["multipliers"]).max()))
    return Verdict.of(largest[1], threshold=1.0, margin=max(abs(largest[1] - largest[0]), floquet.UNIT_CIRCLE_TOL),
                      below=True, above=False,
                      reason=f"largest |multiplier| of the ring's monodromy at H = {2 * harmonics}, its margin the "
                             f"change from H = {harmonics} ({largest[0]:.4f})")
