"""Pseudo-arclength continuation of R(x, p) = 0 in one parameter p (predictor-corrector, step control).

The branch is followed in the scaled unknowns u = (x / x_scale, p / p_scale):
a tangent predictor u + ds t, then Newton on the extended system

    R(x, p) = 0,    t . (u - u_pred) = 0

(Keller's pseudo-arclength condition), so a fold in p is passed like any
other point: p may go back, it is never jumped. The step grows after an
easy corrector (few iterations) and shrinks after a hard one, and a step
whose tangent turns by more than ``max_turn`` is retried shorter, so that
folds are resolved. A corner (the contact law is piecewise linear) is passed
forward whatever its angle, folds are located by dp/ds changing sign, both
recorded, and a branch that comes back onto its own path stops there
rather than retrace it. When the corrector fails at the smallest step the
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
END = 1e-9               # a point this close to p_end (share of the range) is the last: else steps of exactly
                         # dp_max land 1e-15 short of it and p_end repeats the point (6 blades, 7900-14000 r/min)

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
    kinks: list[dict] = field(default_factory=list)   # {"p", "turn_rad"}: corners passed (not resolved), where
                                                      # the tangent lines either side meet and the turn
    folds: list[dict] = field(default_factory=list)   # {"p", "kind"}: where dp/ds changed sign, "smooth" or
                                                      # "corner" (a fold at a corner)


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
                    p_scale: float | None = None, factorize: Factorize | None = None,
                    forward: bool = False) -> Branch:
    """Follow R(x, p) = 0 from (x0, p0) until p passes ``p_end`` (p0 < p_end).

    ``x0`` needs only be near the solution at p0 (Newton at fixed p first).
    ``ds`` is the arclength step in the scaled unknowns (x / x_scale, p / p0);
    ``dp_max`` bounds the parameter's advance per step. A step whose tangent
    turns by more than ``max_turn`` (rad) is retried shorter, down to
    ``ds_kink``: below it the turn is a corner of the branch (the contact law
    is piecewise linear: grazing, the onset of stick) and is passed forward
    whatever its angle: the new tangent is oriented by the secant across the
    corner (u_new - u), not by the previous tangent (which, past a corner of
    more than 90 degrees, points back along the branch's far arm). Where the
    corrector finds no point past a corner at all, down to the step ``ds_min``
    (past more than 90 degrees the plane normal to the last tangent one step
    ahead meets neither arm), the branch is restarted past it
    (:func:`_past_corner`; not earlier: a fold that shorter steps resolve is
    left to them, measured on the 24-blade ring at 9335 r/min, where a restart
    at ``ds_kink`` took the arm it came along, backwards). Each corner is
    recorded in ``Branch.kinks`` (where it lies and the turn), each fold, a
    change of sign of dp/ds (smooth, or at a corner), in ``Branch.folds``.
    The last point is put exactly at p_end. ``on_point(x, p)`` is called for every accepted point.

    ``forward``: the branch is one point per parameter value (a resonance followed in the preload,
    shroud.analysis.peak.track_peak), so a corner is a junction of the law's pieces, never a fold: it is
    passed onto the arm that goes on along the previous tangent, wherever the corrector lands within
    ``ds_kink`` (the rule before the secant's). Where three arms meet, the secant's rule takes the one going
    back (the hb_friction scene's peak at mu 0.3, a 167-degree corner at 177.5 N, just below full stick at
    182.9 N).

    A branch never retraces itself: a point that lies on an earlier chord of
    the path, going the same way, is held back, and if the next one does too
    the branch stops there (incomplete, saying so, the held point dropped):
    a closed loop, or a cycle between corners (:func:`_retraced`). One such
    point alone is not a retrace: near a sharp peak a point can fall on the
    far end of a long earlier chord (the hb_friction scene's 300 um gap at
    its 8089 r/min corner, with the check's earlier form, which also took
    points beyond a chord's end as on it).
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

    def report(x, p, it, events):
        branch.x.append(x), branch.p.append(p), branch.iterations.append(it)
        for kind, event in events:
            getattr(branch, kind).append(event)
        if on_point:
            on_point(x, p)

    x, it, ok, (J, Rp) = newton_fixed_p(np.asarray(x0, float), p0)
    if not ok:
        branch.complete, branch.stopped = False, f"no solution found at the first speed p = {p0:g}"
        return branch
    report(x, p0, it, [])
    t = _tangent(J * x_scale, Rp * p_scale, None, factorize)
    if t[-1] < 0:
        t = -t
    u = scaled(x, p0)
    path, count = np.empty((64, u.size)), 1       # the points continued from (scaled; the first count rows)
    path[0] = u
    held = None         # (x, p, iterations, events) of a point on an earlier chord: reported if the next is not
    while len(branch.p) + (held is not None) < max_points:
        if dp_max is not None and abs(t[-1]) * ds * p_scale > dp_max:
            ds = dp_max / (abs(t[-1]) * p_scale)
        u_new, it, ok, R, J, Rp = _corrector(residual, u + ds * t, t, x_scale, p_scale, factorize=factorize)
        corner = False
        if ok:
            t_new = _tangent(J * x_scale, Rp() * p_scale, t, factorize)
            corner = math.acos(min(1.0, max(-1.0, float(t_new @ t)))) > max_turn
            # a corner is taken within ds_kink, and only from the predictor's side or across a corner that lies
            # within the step: a corrector that moved further from the predictor than the step (a secant more
            # than 45 degrees off t) may have jumped to a neighbouring arm (24 blades, 9336 r/min: from the
            # fold's upper arm onto the middle one), unless the corner explains it (past a corner of turn
            # theta the far arm meets the corrector's plane tan(theta) times further off than the corner's
            # distance from it: the 1 um gap's beam at H 7, a 82-degree fold at 7669 r/min, 4.7 to 6.2 steps)
            near = (forward or np.linalg.norm(u_new - u - ds * t) <= ds
                    or _corner_within(u, t, u_new, t_new, ds))
            ok = not corner or (ds <= ds_kink and near)
        elif 0.5 * ds < ds_min and not forward:   # the last resort before stopping: the corner lies within this step
            past = _past_corner(residual, u, t, ds, x_scale, p_scale, factorize, path[:count])
            if past is not None:
                (u_new, it, _, J, Rp), ok, corner = past, True, True
        if not ok:
            ds, shortened = 0.5 * ds, True
            if ds < ds_min:
                branch.complete = False
                branch.stopped = (f"the corrector did not converge beyond p = {u[-1] * p_scale:g} "
                                  f"(step below {ds_min:g} in scaled arclength)")
                return branch
            continue
        if corner and not forward:    # oriented by the secant across the corner (the border too: t may be
                                      # near normal to it)
            t_new = _tangent(J * x_scale, Rp() * p_scale, (u_new - u) / np.linalg.norm(u_new - u), factorize)
        p_new = u_new[-1] * p_scale
        if p_new < p0 - 0.05 * (p_end - p0):
            branch.complete = False
            branch.stopped = f"the branch turned back below the first parameter value p = {p0:g}"
            return branch
        at_end = p_new >= p_end - END * (p_end - p0)    # a step landing a hair short of p_end reaches it
        back = _retraced(path[:count], u_new, u_new - u) if not at_end else None
        if held is not None:
            if back is not None:
                branch.complete = False
                branch.stopped = (f"the branch came back onto its own path at p = {held[1]:g} and went on along "
                                  f"it (its point {back}, p = {path[back][-1] * p_scale:g}): a closed loop or a "
                                  "cycle between corners")
                return branch
            report(*held)
            held = None
        if at_end:                             # last point exactly at p_end
            s = (p_end / p_scale - u[-1]) / (u_new[-1] - u[-1])
            xe, it_e, ok_e, _ = newton_fixed_p((u[:-1] + s * (u_new[:-1] - u[:-1])) * x_scale, p_end)
            if ok_e:
                report(xe, p_end, it_e, [])
            else:
                branch.complete = False
                branch.stopped = f"no solution found at the last parameter value p = {p_end:g}"
            return branch
        events = []
        if corner:
            at = _corner_point(u, t, u_new, t_new)
            events.append(("kinks", {"p": float(at[-1] * p_scale),
                                     "turn_rad": math.acos(min(1.0, max(-1.0, float(t_new @ t))))}))
        if t_new[-1] * t[-1] < 0:              # the parameter turned: a fold, smooth or at the corner
            at = _corner_point(u, t, u_new, t_new) if corner else _fold_point(u, t, u_new, t_new)
            events.append(("folds", {"p": float(at[-1] * p_scale), "kind": "corner" if corner else "smooth"}))
        u, t = u_new, t_new
        if count == len(path):
            path = np.vstack([path, np.empty_like(path)])
        path[count] = u
        count += 1
        point = (u[:-1] * x_scale, p_new, it, events)
        if back is None:
            report(*point)
        else:
            held = point
        grow = GROW if it <= GROW_ITERATIONS and not shortened else 1.0 if it <= 6 else 0.6
        ds, shortened = min(ds_max, ds * grow), False
    branch.complete = False
    branch.stopped = f"{max_points} points reached at p = {branch.p[-1]:g} before p = {p_end:g}"
    return branch


def _tangent_lines(u: np.ndarray, t: np.ndarray, u_new: np.ndarray, t_new: np.ndarray):
    """Where the tangent lines at two points come closest (least squares: u + a t = u_new - b t_new):
    (a, b, the lines' distance there, the chord's length h)."""
    (a, b), *_ = np.linalg.lstsq(np.column_stack([t, t_new]), u_new - u, rcond=None)
    gap = float(np.linalg.norm(u + a * t - (u_new - b * t_new)))
    return float(a), float(b), gap, float(np.linalg.norm(u_new - u))


def _corner_within(u: np.ndarray, t: np.ndarray, u_new: np.ndarray, t_new: np.ndarray, ds: float) -> bool:
    """Whether the corrector's point ``u_new`` from ``u`` (step ``ds`` along ``t``) lies on the far arm of a
    corner within the step: the tangent lines meet (within RETRACE of the chord), the corner no further
    along t than the step, and ``u_new`` beyond it on its arm (``t_new`` taken along the secant). A jump to
    a neighbouring arm is not so explained: on the 24-blade ring at 9328 r/min its lines met 2.4 steps
    ahead, behind the new point."""
    t_new = t_new if t_new @ (u_new - u) >= 0 else -t_new
    a, b, gap, h = _tangent_lines(u, t, u_new, t_new)
    slack = RETRACE * h
    return gap <= slack and -slack <= a <= ds + slack and b >= 0.0


def _corner_point(u: np.ndarray, t: np.ndarray, u_new: np.ndarray, t_new: np.ndarray) -> np.ndarray:
    """The corner between two points either side of it: where the tangent lines at them come closest
    (:func:`_tangent_lines`), each within 10 steps behind its point (else ``u_new``: lines so near parallel
    that they place no corner)."""
    a, b, _, h = _tangent_lines(u, t, u_new, t_new)
    if not (-0.01 * h <= a <= 10 * h and -0.01 * h <= b <= 10 * h):
        return u_new
    return 0.5 * (u + a * t + u_new - b * t_new)


def _fold_point(u: np.ndarray, t: np.ndarray, u_new: np.ndarray, t_new: np.ndarray) -> np.ndarray:
    """The smooth fold between two points whose tangents' p components have opposite signs: dp/ds taken
    linear over the chord (length h), zero at s* = h t_p / (t_p - t_new_p), where p = p + t_p s* / 2."""
    h = float(np.linalg.norm(u_new - u))
    s = h * t[-1] / (t[-1] - t_new[-1])
    out = u + s * (u_new - u) / h
    out[-1] = u[-1] + 0.5 * t[-1] * s
    return out


def _past_corner(residual: Residual, u: np.ndarray, t: np.ndarray, h: float, x_scale: float, p_scale: float,
                 factorize: Factorize | None, path: np.ndarray):
    """A point of the branch a step ``h`` past a corner the corrector could not pass from ``u`` (tangent
    ``t``): (u, iterations, R, J, R_p) there, or None.

    Beyond a corner of more than 90 degrees the plane normal to t one step ahead meets neither arm (the
    near one ends at the corner, the far one leaves it backwards), so the corrector fails at any step. The
    point v = u + h t lies past the corner (the step failed there), and the residual's null direction d
    there is the far arm's (as a line: past a corner of nearly 180 degrees it differs little from t's). The
    far arm goes from the corner one way along d: from v + h d and from v - h d the corrector on the plane
    normal to d is run (and from PAST_CORNER times further where neither gives one); the point found
    farthest off the line the branch came along (u, t), by more than RETRACE of its distance from u, is
    the far arm's (one back on the near arm, or ahead where no corner
    lies and the corrector failed otherwise, lies on that line: None), unless it lies on the ``path``
    continued so far (scaled points), either way (:func:`_on_path`): where corners crowd, the line
    (u, t) is not the path, and the beam's 1 um gap branch at H 7 (scenes/hb_fig7.toml), restarted past
    a dozen corners between 9119 and 9136 r/min, was restarted at 9119.66 r/min back onto its own path and
    walked it down below 6000 r/min (to 5638).
    """
    v = u + h * t
    R, J, Rp = residual(v[:-1] * x_scale, v[-1] * p_scale)
    if not np.all(np.isfinite(R)):
        return None
    try:
        d = _tangent(J * x_scale, Rp() * p_scale, t, factorize)
    except np.linalg.LinAlgError:
        return None
    for reach in PAST_CORNER:
        best, off_best = None, 0.0
        for w in (v + reach * h * d, v - reach * h * d):
            found = _corrector(residual, w, d, x_scale, p_scale, factorize=factorize)
            if not found[2]:
                continue
            r = found[0] - u
            off = float(np.linalg.norm(r - (r @ t) * t))
            if (off > max(off_best, RETRACE * float(np.linalg.norm(r)))
                    and not _on_path(path, found[0], float(np.linalg.norm(r)))):
                best, off_best = found, off
        if best is not None:
            return best[0], best[1], *best[3:]
    return None


PAST_CORNER = (1, 4, 16)     # the far arm is sought this many steps from v (where the law's pieces crowd about a
                             # fold, 24 blades at 9344 r/min, the corrector from one step away cycles)


RETRACE = 0.1    # a new point this close to an earlier chord (share of its length): above the sag of a chord
                 # whose tangent turns by max_turn = 0.5 rad (0.06 of its length)


def _on_path(path: np.ndarray, v: np.ndarray, r: float) -> bool:
    """Whether ``v`` lies on the path already continued (scaled points, in order), either way along it:
    within RETRACE of ``r`` (its distance from the point restarted from) of one of its chords."""
    seg = path[1:] - path[:-1]
    s = np.einsum("ij,ij->i", v - path[:-1], seg) / np.maximum(np.einsum("ij,ij->i", seg, seg), 1e-300)
    dist = np.linalg.norm(v - (path[:-1] + np.clip(s, 0.0, 1.0)[:, None] * seg), axis=1)
    return bool(dist.size and dist.min() <= RETRACE * r)


def _retraced(path: np.ndarray, u: np.ndarray, step: np.ndarray) -> int | None:
    """The index of the earlier point whose chord the new point ``u`` lies on, going the same way, or None.

    ``path``: the points continued from (scaled), the last the one ``step`` leads from. A point of a
    branch that retraces itself lies on an earlier chord (within RETRACE of the chord's length: the chord's
    sag where the path curves; its foot inside the chord, not beyond an end: near a sharp peak the branch
    passes close by the far end of a long chord without retracing it) and moves along it, not across: a
    fold's two sides or a crossing of two stretches (a figure eight) come close only across each other.
    The last two chords, the step's own neighbours, are left out.
    """
    if len(path) < 4:
        return None
    P = path[:-2]
    seg = P[1:] - P[:-1]
    length = np.linalg.norm(seg, axis=1)
    s = np.einsum("ij,ij->i", u - P[:-1], seg) / np.maximum(length, 1e-300) ** 2
    dist = np.linalg.norm(u - (P[:-1] + s[:, None] * seg), axis=1)
    along = seg @ step > 0.5 * length * float(np.linalg.norm(step))   # within 60 degrees of the chord's way
    near = (dist <= RETRACE * length) & along & (s >= 0.0) & (s <= 1.0)
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
