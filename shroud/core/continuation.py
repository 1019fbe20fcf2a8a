"""Pseudo-arclength continuation of R(x, p) = 0 in one parameter p (predictor-corrector, step control).

The branch is followed in the scaled unknowns u = (x / x_scale, p / p_scale):
a tangent predictor u + ds t, then Newton on the extended system

    R(x, p) = 0,    t . (u - u_pred) = 0

(Keller's pseudo-arclength condition), so a fold in p is passed like any
other point: p may go back, it is never jumped. The step grows after an
easy corrector (few iterations) and shrinks after a hard one, and a step
whose tangent turns by more than ``max_turn`` is retried shorter, so that
folds are resolved. When the corrector fails at the smallest step the
branch so far is returned, marked incomplete with where and why.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable, Protocol

import numpy as np

GROW_ITERATIONS, GROW = 4, 1.5   # a corrector this quick lets the next step grow by this factor (2 stopped
                                 # the 1 um gap's branch at mu 0.3 at a corner before its peak)
CONVERGED = 1e-8         # a Newton step this small (scaled, relative to 1 + |u|) ends a corrector
STALL_FROM, STALL = 4, 1e-3   # from this iteration on, a corrector still moving this much (scaled): cycling

# residual(x, p) -> (R, dR/dx, () -> dR/dp): the parameter derivative is asked for only where it is used
Residual = Callable[[np.ndarray, float], tuple[np.ndarray, np.ndarray, Callable[[], np.ndarray]]]


class Factor(Protocol):
    """A factorization of dR/dx (e.g. shroud.core.cyclic_banded.BandedLU): solves with it and its transpose."""

    def solve(self, rhs: np.ndarray, transposed: bool = False) -> np.ndarray: ...


Factorize = Callable[[np.ndarray], Factor]   # dR/dx -> its factorization: a structured solve (None: dense)


def _bordered(factorize: Factorize, J: np.ndarray, c: np.ndarray, d: np.ndarray, rhs: np.ndarray) -> np.ndarray:
    """u with [[J, c], [d]] u = rhs (J n x n, c (n,), d (n + 1,)) by mixed block elimination (BEM,
    Govaerts & Pryce 1993) on one factorization of J: stable where J is nearly singular (a fold) as long as
    the bordered matrix is not, which plain bordering is not."""
    n = J.shape[0]
    lu = factorize(J)
    e, f, g = d[n], rhs[:n], rhs[n]
    v = lu.solve(d[:n], transposed=True)
    y1 = (g - v @ f) / (e - c @ v)
    w = lu.solve(c)
    xi = lu.solve(f - c * y1)
    y2 = (g - e * y1 - d[:n] @ xi) / (e - d[:n] @ w)
    return np.append(xi - w * y2, y1 + y2)


@dataclass
class Branch:
    """Points of a continued branch in continuation order."""

    x: list[np.ndarray] = field(default_factory=list)
    p: list[float] = field(default_factory=list)
    iterations: list[int] = field(default_factory=list)
    complete: bool = True
    stopped: str | None = None          # where and why an incomplete branch stopped
    kinks: list[dict] = field(default_factory=list)   # {"p", "turn_rad"}: corners stepped over, not resolved


def _tangent(J: np.ndarray, Rp: np.ndarray, previous: np.ndarray | None,
             factorize: Factorize | None = None) -> np.ndarray:
    """Unit tangent of the branch: null vector of [J, R_p] (oriented along ``previous``)."""
    n = J.shape[0]
    last = previous if previous is not None else np.r_[np.zeros(n), 1.0]
    rhs = np.zeros(n + 1)
    rhs[n] = 1.0
    if factorize is None:
        A = np.zeros((n + 1, n + 1))
        A[:n, :n], A[:n, n], A[n] = J, Rp, last
        t = np.linalg.solve(A, rhs)
    else:
        t = _bordered(factorize, J, Rp, last, rhs)
    t /= np.linalg.norm(t)
    if previous is not None and t @ previous < 0:
        t = -t
    return t


def continue_branch(residual: Residual, x0: np.ndarray, p0: float, p_end: float, x_scale: float,
                    ds: float = 0.02, ds_min: float = 1e-5, ds_max: float = 0.1, max_points: int = 2000,
                    dp_max: float | None = None, max_turn: float = 0.5, ds_kink: float = 2e-3,
                    on_point: Callable[[np.ndarray, float], None] | None = None,
                    p_scale: float | None = None, stop_on_retrace: bool = False,
                    factorize: Factorize | None = None) -> Branch:
    """Follow R(x, p) = 0 from (x0, p0) until p passes ``p_end`` (p0 < p_end).

    ``x0`` needs only be near the solution at p0 (Newton at fixed p first).
    ``ds`` is the arclength step in the scaled unknowns (x / x_scale, p / p0);
    ``dp_max`` bounds the parameter's advance per step. A step whose tangent
    turns by more than ``max_turn`` (rad) is retried shorter, down to
    ``ds_kink``: below it the turn is a kink of the branch (the contact law
    is piecewise linear: grazing, the onset of stick) and is stepped over,
    recorded in ``Branch.kinks`` (its parameter value and the turn). The last point is
    put exactly at p_end. ``on_point(x, p)`` is called for every accepted point.
    With ``stop_on_retrace``, a branch that comes back onto its own path,
    going the same way (a closed loop, or a cycle between kinks), stops
    there, incomplete, saying so (:func:`_retraced`): past that point it
    would only repeat itself up to ``max_points``. Off by default: near a
    sharp peak the test also fires on branches that do not retrace (the
    full hb_friction scene's 300 um gap stopped after 10 points at its
    8089 r/min kink), so only branches seeded away from the continued one
    (shroud.analysis.hb.run_hb_through), where runaways were seen, use it.
    ``p_scale`` scales the parameter in the arclength (default |p0|; give it
    where p0 may be 0, e.g. a preload continued from N0 = 0). ``factorize``: a structured
    factorization of dR/dx for every linear solve (Newton's, the tangent's and the corrector's bordered
    systems, :func:`_bordered`); None: numpy.linalg.solve of the dense systems.
    """
    p_scale = abs(p0) if p_scale is None else p_scale
    branch = Branch()
    shortened = False          # the step was cut since the last point: it is not lengthened at the next

    def scaled(x, p):
        return np.r_[x / x_scale, p / p_scale]

    def newton_fixed_p(x, p):
        for it in range(1, 41):
            R, J, Rp = residual(x, p)
            dx = np.linalg.solve(J, -R) if factorize is None else factorize(J).solve(-R)
            if np.linalg.norm(dx) <= CONVERGED * x_scale * (1.0 + np.linalg.norm(x) / x_scale):
                return x, it, True, (J, Rp())
            x = x + dx
        return x, 40, False, (J, Rp())

    x, it, ok, (J, Rp) = newton_fixed_p(np.asarray(x0, float), p0)
    if not ok:
        branch.complete, branch.stopped = False, f"no solution found at the first speed p = {p0:g}"
        return branch
    branch.x.append(x), branch.p.append(p0), branch.iterations.append(it)
    if on_point:
        on_point(x, p0)
    t = _tangent(J * x_scale, Rp * p_scale, None, factorize)
    if t[-1] < 0:
        t = -t
    u = scaled(x, p0)
    path, count = np.empty((64, u.size)), 1       # the accepted points, scaled (the first count rows)
    path[0] = u
    while len(branch.p) < max_points:
        if dp_max is not None and abs(t[-1]) * ds * p_scale > dp_max:
            ds = dp_max / (abs(t[-1]) * p_scale)
        u_pred = u + ds * t
        u_new, it, ok, R, J, Rp = _corrector(residual, u_pred, t, x_scale, p_scale, factorize=factorize)
        turn = 0.0
        if ok:
            t_new = _tangent(J * x_scale, Rp() * p_scale, t, factorize)
            turn = math.acos(min(1.0, max(-1.0, float(t_new @ t))))
            ok = turn <= max_turn or ds <= ds_kink     # a kink (grazing, stick onset) is passed, not resolved
        if not ok:
            ds, shortened = 0.5 * ds, True
            if ds < ds_min:
                branch.complete = False
                branch.stopped = (f"the corrector did not converge beyond p = {u[-1] * p_scale:g} "
                                  f"(step below {ds_min:g} in scaled arclength)")
                return branch
            continue
        p_new = u_new[-1] * p_scale
        if p_new < p0 - 0.05 * (p_end - p0):
            branch.complete = False
            branch.stopped = f"the branch turned back below the first parameter value p = {p0:g}"
            return branch
        if p_new >= p_end:                     # last point exactly at p_end
            s = (p_end / p_scale - u[-1]) / (u_new[-1] - u[-1])
            xe, it_e, ok_e, _ = newton_fixed_p((u[:-1] + s * (u_new[:-1] - u[:-1])) * x_scale, p_end)
            if ok_e:
                branch.x.append(xe), branch.p.append(p_end), branch.iterations.append(it_e)
                if on_point:
                    on_point(xe, p_end)
            else:
                branch.complete = False
                branch.stopped = f"no solution found at the last parameter value p = {p_end:g}"
            return branch
        if turn > max_turn:
            branch.kinks.append({"p": float(p_new), "turn_rad": float(turn)})
        back = _retraced(path[:count], u_new, u_new - u) if stop_on_retrace else None
        if back is not None:
            branch.complete = False
            branch.stopped = (f"the branch came back onto its own path at p = {p_new:g} (its point {back}, "
                              f"p = {path[back][-1] * p_scale:g}): a closed loop or a cycle between kinks")
            return branch
        u, t = u_new, t_new
        if count == len(path):
            path = np.vstack([path, np.empty_like(path)])
        path[count] = u
        count += 1
        x = u[:-1] * x_scale
        branch.x.append(x), branch.p.append(p_new), branch.iterations.append(it)
        if on_point:
            on_point(x, p_new)
        grow = GROW if it <= GROW_ITERATIONS and not shortened else 1.0 if it <= 6 else 0.6
        ds, shortened = min(ds_max, ds * grow), False
    branch.complete = False
    branch.stopped = f"{max_points} points reached at p = {branch.p[-1]:g} before p = {p_end:g}"
    return branch


RETRACE = 0.1    # a new point this close to an earlier chord (share of the longer of it and the step): above
                 # the sag of a chord whose tangent turns by max_turn = 0.5 rad (0.06 of its length)


def _retraced(path: np.ndarray, u: np.ndarray, step: np.ndarray) -> int | None:
    """The index of the earlier point whose segment the new point ``u`` lies on, going the same way, or None.

    ``path``: the accepted points (scaled), the last the one ``step`` leads from. A point of a branch
    that retraces itself lies on an earlier chord (within RETRACE of the chord's and the step's length,
    the chords' sag where the path curves) and moves along it, not across: a fold's two sides or a
    crossing of two stretches (a figure eight) come close only across each other. The last two
    segments, the step's own neighbours, are left out.
    """
    if len(path) < 4:
        return None
    P = path[:-2]
    seg = P[1:] - P[:-1]
    length = np.linalg.norm(seg, axis=1)
    s = np.clip(np.einsum("ij,ij->i", u - P[:-1], seg) / np.maximum(length, 1e-300) ** 2, 0.0, 1.0)
    dist = np.linalg.norm(u - (P[:-1] + s[:, None] * seg), axis=1)
    h = float(np.linalg.norm(step))
    along = seg @ step > 0.5 * length * h            # within 60 degrees of the earlier chord's direction
    near = (dist <= RETRACE * np.maximum(length, h)) & along
    return int(np.flatnonzero(near)[0]) if near.any() else None


def _corrector(residual: Residual, u_pred: np.ndarray, t: np.ndarray, x_scale: float, p_scale: float,
               max_iterations: int = 10, factorize: Factorize | None = None):
    """Newton on [R(u); t . (u - u_pred)] = 0 from the predictor: (u, iterations, converged, R, J, R_p).

    Converged when the next Newton step would move u by less than
    ``CONVERGED`` (scaled): the point returned is the one that step was
    solved at, so it lies that close to the branch (the law is piecewise
    linear, so once the contact states settle the steps shrink by orders of
    magnitude each), and R, J, R_p (a callable) are its own: the tangent
    needs no evaluation of its own, nor what the caller records at the
    point (1e-8 against 1e-10: 432 evaluations instead of 457 on the 0.1 mm
    gap branch, 748 instead of 1010 on the 10 um one; 1e-7 saved more, but
    the 10 um gap's branch at mu 0.3 then stopped at a corner near
    4423 r/min). A corrector whose steps stay above ``STALL`` and
    do not halve over two iterations from the ``STALL_FROM``-th on is
    cycling between sets of contact states and is given up (measured on the
    0.1 mm gap branches: such a corrector never converged within 10
    iterations, every converging one had halved).
    """
    u = u_pred.copy()
    n = u.size - 1
    A = np.zeros((n + 1, n + 1)) if factorize is None else None
    steps = []
    for it in range(1, max_iterations + 1):
        R, J, Rp = residual(u[:-1] * x_scale, u[-1] * p_scale)
        if not np.all(np.isfinite(R)):
            return u, it, False, R, J, Rp
        rhs = -np.append(R, t @ (u - u_pred))
        if factorize is None:
            np.multiply(J, x_scale, out=A[:n, :n])
            A[:n, n], A[n] = Rp() * p_scale, t
            du = np.linalg.solve(A, rhs)
        else:
            du = _bordered(factorize, J * x_scale, Rp() * p_scale, t, rhs)
        steps.append(np.linalg.norm(du) / (1.0 + np.linalg.norm(u)))
        if steps[-1] <= CONVERGED:
            return u, it, True, R, J, Rp
        u = u + du
        if it >= STALL_FROM and steps[-1] > STALL and steps[-1] > 0.5 * steps[-3]:
            break
    return u, it, False, R, J, Rp
