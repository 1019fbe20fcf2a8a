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
sector.) The relabelling by N / g blades alone is one (ke / g whole
periods); where g is even, so is the relabelling by N / 2, and the ring's
perturbations split exactly into its periodic and antiperiodic halves,
each a ring of N / 2 blades (:func:`ring_blocks`).

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

from shroud.analysis.hb import (DEFAULT_HARMONICS, NOT_ASKED, NOT_CONVERGED, REFINED_ITERATIONS,
                                Checkpoint, SpeedModel, branch_result, branch_scale, check_inputs, follow_branch,
                                model_at_speed, point_details, run_hb, speed_step)
from shroud.analysis.ring import RING_MODELS, blade_parameters, pairing
from shroud.analysis.transient import contact_law_for
from shroud.base.errors import InputError, RunDiverged
from shroud.core import floquet
from shroud.core import harmonic_balance as hb
from shroud.core.contact import ContactLaw, contact_law
from shroud.core.cyclic_banded import CyclicBanded, harmonic_major_blocks
from shroud.core.cyclic import Faces, ring_shifts, sector_balance
from shroud.core.linear_solvers import dense
from shroud.core.results import HBResult
from shroud.core.ring import (assembled_system, face_selectors, interface_elements, ring_harmonics, ring_of,
                              with_rayleigh)
from shroud.core.starts import SECTOR_TOLERANCE, Sector, projected, sector_newton, sector_solve
from shroud.core.system import StructuralSystem
from shroud.params import Parameters


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


def _ring_samples(sector: Sector, samples: int) -> int:
    """The least multiple of N / gcd(N, ke) at or above ``samples``: interface j's states are then interface
    0's shifted by a whole number of samples (j ke / N of the period)."""
    unit = sector.N // math.gcd(sector.N, sector.ke)
    return unit * math.ceil(samples / unit)


def _ring_orbit(sector: Sector, lin: hb.LinearHarmonics, X: np.ndarray, basis: hb.Fourier, samples: int,
                interfaces: int | None = None):
    """(state, F, y_rate) of the ring's first ``interfaces`` interfaces (all N: None) on the travelling wave
    X, the law sampled at ``samples`` instants (a multiple of N / gcd(N, ke)): interface 0's, shifted for
    interface j."""
    fine = hb.fourier(basis.H, samples)
    nh = basis.nh
    Y = (projected(sector, lin, basis.H) @ X).reshape(nh, -1)
    ch = hb.contact_harmonics(Y, np.eye(Y.shape[1]), sector.law, fine, jacobian=False)
    rate = fine.rates(Y, lin.omega)                          # (samples, c)
    shifts = ring_shifts(samples, sector.N, sector.ke)[:interfaces]
    return (np.vstack([np.roll(ch.state, -s, axis=1) for s in shifts]),
            np.vstack([np.roll(ch.F, -s, axis=1) for s in shifts]),
            np.hstack([np.roll(rate, -s, axis=0) for s in shifts]))


def ring_blocks(system: StructuralSystem, sector: Sector, symmetric: bool = True) -> tuple[list[tuple], int]:
    """The whole tuned ring of ``system``'s blade linearized about the travelling wave, as invariant
    subspaces each with its own flow: ([(M, C, K, W, law, symmetry)], interfaces of a subspace's).

    Where N and ke are both even, blade j + N / 2 and interface j + N / 2 are blade j and interface j
    half a wave further on, ke / 2 whole periods: a relabelling by N / 2 with no shift in time maps the
    linearized ring onto itself at every instant, and its perturbations split exactly into the periodic
    ones (blade j + N / 2 moves as blade j) and the antiperiodic ones (as minus blade j). On either
    half the ring's equations are twice those of its first N / 2 blades and interfaces, the last
    interface's neighbour being blade 0 times +1 or -1 (its W's closing term); the monodromy is block
    diagonal in the halves, its multipliers theirs together (floquet.block_multipliers): 24 blades at
    ke 2, 2 x 156 states against 312, the ring's multipliers 3.9x cheaper (docs/performance.md).
    Otherwise one subspace, the whole ring. (For g =
    gcd(N, ke) > 2 the relabelling by N / g splits the ring into g subspaces, those of phase
    exp(2 pi i k / g) complex: not done, the monodromy's kernels are real.)

    ``symmetric``: each with the wave's symmetry (:func:`ring_symmetry`: the flow from g / N of the
    period); False: the whole ring integrated over the period, unsplit (the check of both)."""
    N = sector.N
    halves = symmetric and N % 2 == 0 and sector.ke % 2 == 0
    count = N // 2 if halves else N
    W_blade = dense(system.contact.W)
    S1, S2, weight = face_selectors(system.contact)
    side1, side2 = S1 @ W_blade, S2 @ W_blade                    # (c, nb) each
    c, nb = side1.shape
    ident = np.eye(count)
    M, C, K = (np.kron(ident, dense(A)) for A in (system.M, system.C, system.K))
    blocks = []
    for closure in ((1.0, -1.0) if halves else (1.0,)):
        W = np.zeros((count * c, count * nb))
        for j in range(count):
            k = (j + 1) % count
            W[j * c:(j + 1) * c, j * nb:(j + 1) * nb] += side2
            W[j * c:(j + 1) * c, k * nb:(k + 1) * nb] -= (closure if k == 0 else 1.0) * side1
        elements = interface_elements(weight, W)
        law = replace(sector.law, rows=np.column_stack([elements.normal_row, elements.tangent_row]),
                      props=np.tile(sector.law.props, (count, 1)), side=elements.side, weight=elements.weight,
                      m=W.shape[0])
        blocks.append((M, C, K, W, law, ring_symmetry(sector, nb, count, closure) if symmetric else None))
    return blocks, count


def ring_symmetry(sector: Sector, blade_dofs: int, count: int | None = None,
                  closure: float = 1.0) -> floquet.Symmetry:
    """The travelling wave's symmetry of the linearized ring (floquet.Symmetry): interface j at time t is
    interface 0 at t + j T ke / N, so blade j + r at t - T g / N moves as blade j at t when r ke = g
    (mod N), g = gcd(N, ke); G relabels blade j - r as j (and interface j - r as j), q = N / g. On the
    first ``count`` blades of a subspace of :func:`ring_blocks` (blade j + count moving as ``closure``
    times blade j) a blade taken from beyond them carries that sign."""
    N, g = sector.N, math.gcd(sector.N, sector.ke)
    count = N if count is None else count
    r = pow(sector.ke // g, -1, N // g) if N > g else 0
    source = (np.arange(count) - r) % N                       # the ring's blade each of the first count takes
    sign = closure ** (source // count)
    e = sector.law.m // 2                                     # points of one interface

    def moved(size):
        return ((source % count)[:, None] * size + np.arange(size)).ravel()
    return floquet.Symmetry(dofs=moved(blade_dofs), elements=moved(e), q=N // g,
                            dof_signs=np.repeat(sign, blade_dofs), element_signs=np.repeat(sign, e))


def ring_multipliers(system: StructuralSystem, sector: Sector, lin: hb.LinearHarmonics, X: np.ndarray,
                     basis: hb.Fourier, symmetric: bool = True) -> np.ndarray:
    """Floquet multipliers of the whole ring about the travelling wave X (the sector's unknowns), every
    nodal diameter's perturbations included: interface j's states are interface 0's shifted by j ke / N of
    the period, sampled at a multiple of N / gcd(N, ke) instants (at least the AFT's). ``symmetric``: the
    monodromy from g / N of the period and the wave's symmetry (:func:`ring_symmetry`), split into the
    ring's periodic and antiperiodic halves where N and ke are even (:func:`ring_blocks`); False: the
    whole ring integrated over the whole period."""
    return _wave_multipliers(*ring_blocks(system, sector, symmetric), sector, lin, X, basis)


def _wave_multipliers(blocks: list[tuple], count: int, sector: Sector, lin: hb.LinearHarmonics, X: np.ndarray,
                      basis: hb.Fourier) -> np.ndarray:
    """The multipliers of the ring's subspaces ``blocks`` (:func:`ring_blocks`) about the wave X."""
    orbit = _ring_orbit(sector, lin, X, basis, _ring_samples(sector, basis.samples), count)
    return floquet.block_multipliers(blocks, *orbit[:2], lin.omega, orbit[2])[0]


def ring_stability(speeds: SpeedModel, sector: Sector, basis: hb.Fourier, X: np.ndarray,
                   rpm: float) -> floquet.Stability:
    """:func:`ring_multipliers` with the error the single blade's points carry (shroud.analysis.hb
    .point_details): the largest of floquet.MULTIPLIER_FLOOR, the change at half the samples and the change
    when the wave is solved again with twice the harmonics (Newton from X, at most
    REFINED_ITERATIONS; no state there: the error is infinite, the point undecided)."""
    system, lin, _, _ = speeds.at(rpm)
    samples = _ring_samples(sector, basis.samples)
    half = _ring_samples(sector, max(samples // 2, 2 * basis.H + 1))
    blocks, count = ring_blocks(system, sector)
    orbit, coarse = (_ring_orbit(sector, lin, X, basis, n, count) for n in (samples, half))
    st = floquet.blocks_stability(blocks, *orbit[:2], lin.omega, orbit[2], coarse)
    fine = speeds.refined()
    fine_basis = hb.fourier(fine.H, max(basis.samples, 4 * fine.H + 1))
    fine_lin = fine.linear(rpm)[0]
    X0 = np.zeros((fine_basis.nh, X.size // basis.nh))
    X0[:basis.nh] = X.reshape(basis.nh, -1)
    X2, ok = sector_newton(X0.ravel(), fine_lin, sector, fine_basis, max_iterations=REFINED_ITERATIONS)
    refined = float(np.abs(_wave_multipliers(blocks, count, sector, fine_lin, X2, fine_basis)).max()) if ok else None
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

    def plot(self, ax=None, label: str | None = None, scale: float = 1e3, **line):
        """Blade 0's branch as HBResult.plot draws it (stability by line style, bifurcations marked); a
        mistuned ring's every blade thin behind it (tuned: every blade is blade 0)."""
        from shroud.core.results import _axes
        ax = _axes(ax)
        colour = line.pop("colour", None)
        if self.amplitudes is not None:
            drawn = ax.plot(self.branch.rpm, np.asarray(self.amplitudes) * scale, lw=0.5, alpha=0.5, color=colour)
            colour = drawn[0].get_color()
        return self.branch.plot(ax, label=label or f"{self.branch.model}, {self.blades} blades", colour=colour,
                                scale=scale, **line)

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
    speeds, sector, basis = _ring_system(params, model, rpm, harmonics, samples, whole=False)
    X, _ = _ring_state(params, model, rpm, speeds, sector, basis, start)
    return {**_details(speeds, sector, basis, X, rpm, stability), "X": X}


def _ring_system(params: Parameters, model: str, rpm: float, harmonics: int, samples: int | None,
                 whole: bool) -> tuple[SpeedModel, Sector, hb.Fourier]:
    """(speeds, sector, basis) of the ring at ``rpm``: one sector of the tuned ring's travelling wave, or
    (``whole``) the whole ring on all its interfaces (:func:`whole_ring`)."""
    check_ring_hb(params, model)
    n = check_inputs(harmonics, samples, rpm * 0.5, rpm)
    basis = hb.fourier(harmonics, n)
    speeds = SpeedModel(RingOverSpeed(params, model) if whole else ring_model_at_speed(params, model), harmonics)
    system, lin, _, _ = speeds.at(rpm)
    sector = (whole_ring(params, lin, contact_law_for(system, params.contact), basis) if whole
              else sector_of(system, params, harmonics))
    return speeds, sector, basis


def _ring_state(params: Parameters, model: str, rpm: float, speeds: SpeedModel, sector: Sector,
                basis: hb.Fourier, start: np.ndarray | None, retry: bool = True) -> tuple[np.ndarray, str]:
    """(X, how it was reached) of the ring at ``rpm``: Newton from ``start`` (any number of harmonics), then
    (``retry``, or no ``start``) the linear starts (:func:`sector_solve`), then for a sector the waves at
    other numbers of harmonics (:func:`from_other_harmonics`); RunDiverged where none reaches a state."""
    lin = speeds.linear(rpm)[0]
    X, ok = (None, False) if start is None else sector_newton(resized(start, basis.nh), lin, sector, basis)
    if ok:
        return X, "given"
    if start is not None and not retry:
        raise RunDiverged("Newton did not converge from the state given")
    try:
        return sector_solve(lin, sector, basis), "linear ring with contact springs, or a continuation in the " \
                                                 "contact's stiffness"
    except RunDiverged as failed:
        if sector.faces is None:
            raise
        return (from_other_harmonics(params, model, rpm, lin, sector, basis, failed),
                "the wave at another number of harmonics")


def ring_checkpoint(params: Parameters, model: str, rpm: float, harmonics: int = DEFAULT_HARMONICS,
                    samples: int | None = None, start: np.ndarray | None = None, retry: bool = True,
                    multipliers: bool = True) -> Checkpoint:
    """The ring of ``params.ring.blades`` at ``rpm`` as a checkpoint (shroud.analysis.hb.Checkpoint, the same
    arguments): tuned, the travelling wave by one sector (:func:`sector_at`); mistuned, the whole ring
    (:func:`whole_ring_at`); with ``blades`` and every blade's v_L amplitude, the stability that of the whole
    ring's monodromy (every nodal diameter). Where no start reaches a state: ``converged`` False (the
    amplitudes nan, null in the JSON), ``start`` saying why."""
    t0 = time.perf_counter()
    whole = not params.ring.tuned
    speeds, sector, basis = _ring_system(params, model, rpm, harmonics, samples, whole)
    system, lin, _, _ = speeds.at(rpm)
    N = params.ring.blades
    t1 = time.perf_counter()
    try:
        X, how = _ring_state(params, model, rpm, speeds, sector, basis, start, retry)
    except RunDiverged as failed:
        X, how = None, f"no state reached: {failed}"
    t2 = time.perf_counter()
    details, blades, residual = {}, (), math.nan
    if X is not None:
        b = sector_balance(X, lin, sector.law, basis, sector.faces, jacobian=False)
        residual = float(np.linalg.norm(b.R) / (np.linalg.norm(lin.Fr) + 1e-300))
        if whole:
            details = point_details(speeds, sector.law, basis, X, rpm, stability=multipliers)
            blades = tuple(blade_amplitudes(lin, sector.law, basis, X))
        else:
            details = _details(speeds, sector, basis, X, rpm, multipliers)
            blades = (details["amplitude_v_L"],) * N
    largest = float(np.abs(details["multipliers"]).max()) if multipliers and details else None
    dofs = system.dofs if whole else N * system.dofs
    return Checkpoint(model=model, rpm=float(rpm), harmonics=harmonics, samples=basis.samples,
                      amplitude_v_L=details.get("amplitude_v_L", math.nan),
                      amplitude_w_L=details.get("amplitude_w_L", math.nan), converged=X is not None,
                      residual=residual, short=not residual <= SECTOR_TOLERANCE, tolerance=SECTOR_TOLERANCE,
                      iterations=None, spectral_tail=details.get("tail", math.nan), start=how,
                      start_amplitude_v_L=None, stable=details.get("stable"),
                      stability=(NOT_ASKED if not multipliers else NOT_CONVERGED if X is None
                                 else "Floquet multipliers of the whole ring (every nodal diameter)"),
                      largest_multiplier={} if largest is None else {dofs: largest},
                      multiplier_error=details.get("multiplier_error") if largest is not None else None,
                      dofs=dofs, condensed_on=lin.nx if lin.condensed else 0, linear_s=t1 - t0, start_s=0.0,
                      newton_s=t2 - t1, stability_s=time.perf_counter() - t2, X=X, blades=N,
                      blades_amplitude_v_L=blades)


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
    speeds, whole, basis = _ring_system(params, model, rpm, harmonics, samples, whole=True)
    X, _ = _ring_state(params, model, rpm, speeds, whole, basis, None)
    return {**(point_details(speeds, whole.law, basis, X, rpm) if stability else {}),
            "blades_amplitude_v_L": blade_amplitudes(speeds.linear(rpm)[0], whole.law, basis, X), "X": X}


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
