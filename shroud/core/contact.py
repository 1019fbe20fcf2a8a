"""Impact and stick/slip friction between the shroud and its neighbours (paper Eqs. 3-8).

The law is written once, here, as small compiled pure functions on arrays,
and serves every model: the reduced and full beam (two elements, one per
side, on the rows [v_s, w_s] of Eq. 7) and the solid FE models (one element
per contact-face node, weighted by its area share).

Each element j acts on two projected coordinates of ``y = W q``: its normal
displacement ``v = y[normal_row[j]]`` (along e_vs) and its tangential
displacement ``w = y[tangent_row[j]]`` (along e_ws). With ``s = -1`` on side 1
and ``s = +1`` on side 2 (docs/geometry.md):

* normal force, Eq. 3: ``N = max(0, N0 + s kn v)``; it pushes the blade along
  ``-s e_vs`` (side 1 pushes +e_vs), so Eq. 8's ``N1 - N2`` is the sum of
  ``-s N`` over both sides;
* friction, Eqs. 4-6, as a return mapping on the slider (the contact point
  ``z``, z_s2 / z_s3 of the paper): trial ``F = kt (z - w)``; stick if
  ``|F| <= mu N`` (slider stays), else slip with ``F = mu N sign(z - w)`` and
  the slider dragged to ``z = w + F / kt``; separated: ``F = 0``, ``z = w``.
  ``F`` is the force on the blade along e_ws, so friction opposes relative
  slip and dissipates (CONTRIBUTING.md sign note; Eq. 4 printed literally
  would be a negative stiffness).

The law's derivatives in each state, its tangent (:func:`tangent`), are
written here too: the harmonic balance's Jacobian and the Floquet monodromy
(shroud.core.harmonic_balance, shroud.core.floquet) both use it.

Forces back on the projected coordinates: ``lam[normal_row] += -s N`` and
``lam[tangent_row] += F``; the generalized force is ``W^T lam`` (Eq. 8 for the
beam, where ``W`` carries the rotation by alpha).

The implicit step needs ``y`` such that ``y = y_pred + Cc lam(y)`` (``Cc`` the
contact compliance of the factorized Newmark operator). The law is piecewise
linear, so for a fixed set of element states ``lam`` is affine in ``y`` and
the equation is solved exactly; :func:`solve_contact` iterates over the
states (a semi-smooth Newton / active-set method) until they reproduce
themselves, with a residual line search as a guard against cycling. When
the compliance has low rank, Cc = Wc P with r < m (a modal model with
fewer modes than face coordinates: the reduced solid), the affine solve
works in the r-dimensional space instead.

Units: N, m, N/m.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numba import njit

from shroud.core.cyclic_blocks import cyclic_factor, cyclic_solve, lu_factor, lu_solve
from shroud.core.system import ContactElements

from shroud.core.states import SEPARATE, SLIP, STICK

# Columns of ContactLaw.props.
SIGN, KN, KT, MU, N0 = range(5)

# The law's functions never allocate. Compiled without numba's reference
# counting (the _nrt flag) a call skips two atomic operations per array
# argument: that was half the cost of a step with contact
# (benchmarks/bench_transient.py). Only for functions that allocate nothing.
leaf = njit(cache=True, _nrt=False)

_PLAIN_ITERATIONS = 25     # full Newton (active-set) steps before the line search guard
_MAX_ITERATIONS = 200


@dataclass(frozen=True)
class ContactLaw:
    """Per-element contact data in the compiled functions' layout.

    rows[j] = (normal_row, tangent_row); props[j] = (s, kn, kt, mu, N0) with
    s = -1 (side 1) or +1 (side 2), and kn, kt (N/m), N0 (N) the element's
    weight times the side's totals; side[j] in {1, 2}; m the number of
    projected coordinates.
    """

    rows: np.ndarray
    props: np.ndarray
    side: np.ndarray
    weight: np.ndarray
    m: int

    @property
    def count(self) -> int:
        return int(self.side.size)


def contact_law(elements: ContactElements | None, kn: float = 0.0, kt: float = 0.0, mu: float = 0.0,
                N0: float = 0.0, m: int | None = None) -> ContactLaw:
    """Element data from a model's contact points and the side totals (paper Eqs. 3-6).

    ``kn``, ``kt`` (N/m) and ``N0`` (N) are each side's totals, shared over
    its elements by their weights; ``mu`` is the Coulomb coefficient.
    ``elements=None`` gives the empty law (free blade) on ``m`` coordinates.
    """
    if elements is None:
        return ContactLaw(rows=np.zeros((0, 2), np.int64), props=np.zeros((0, 5)),
                          side=np.zeros(0, np.int64), weight=np.zeros(0), m=int(m or 0))
    side = np.asarray(elements.side, dtype=np.int64)
    weight = np.asarray(elements.weight, dtype=float)
    props = np.empty((side.size, 5))
    # columns SIGN, KN, KT, MU, N0 (the module constants)
    props[:] = np.column_stack([np.where(side == 1, -1.0, 1.0), weight * kn, weight * kt,
                                np.full(side.size, mu), weight * N0])
    rows = np.column_stack([np.asarray(elements.normal_row, np.int64),
                            np.asarray(elements.tangent_row, np.int64)])
    return ContactLaw(rows=rows, props=props, side=side, weight=weight, m=int(elements.W.shape[0]))


@leaf
def normal_force(v, N0, kn, s):
    """Eq. 3: N = max(0, N0 + s kn v_s), N (s = -1 side 1, +1 side 2)."""
    N = N0 + s * kn * v
    return N if N > 0.0 else 0.0


@leaf
def friction_return_map(w, z, N, kt, mu):
    """Eqs. 4-6 as a return mapping: (F on the blade along e_ws, new slider z, state)."""
    if N <= 0.0:
        return 0.0, w, SEPARATE
    trial = kt * (z - w)
    limit = mu * N
    if abs(trial) <= limit:
        return trial, z, STICK
    F = limit if trial > 0.0 else -limit
    return F, w + F / kt, SLIP          # kt > 0 here: |trial| > limit >= 0


@leaf
def tangent(state, F, s, kn, kt, mu):
    """The law's derivatives in one state (Eqs. 3-6 linearized; the law is piecewise linear).

    For the outputs (N, F, new slider z) of :func:`normal_force` and
    :func:`friction_return_map` with respect to their inputs (v, w, old
    slider z), in the state reached and with the friction F reached there
    (its sign is the slip direction sigma):

        separate: N = 0, F = 0, z = w;
        stick:    dN/dv = s kn, F = kt (z - w), z held;
        slip:     dN/dv = s kn, F = sigma mu N, z = w + F / kt.

    Returns (dN/dv, dF/dv, dF/dw, dF/dz, dz/dv, dz/dw, dz/dz): N/m for the
    force derivatives, 1 for the slider's.
    """
    if state == SEPARATE:
        return 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0
    if state == STICK:
        return s * kn, 0.0, -kt, kt, 0.0, 0.0, 1.0
    dF_dv = (mu if F > 0.0 else -mu) * s * kn
    return s * kn, dF_dv, 0.0, 0.0, dF_dv / kt, 1.0, 0.0


@njit(cache=True)
def tangents(state, F, props):
    """:func:`tangent` of every element (states ``state``, frictions ``F``): a (k, 7) array, same columns."""
    out = np.empty((state.size, 7))
    for j in range(state.size):
        d = tangent(state[j], F[j], props[j, SIGN], props[j, KN], props[j, KT], props[j, MU])
        for c in range(7):
            out[j, c] = d[c]
    return out


@leaf
def evaluate(y, z_old, rows, props, lam, N, F, z, state):
    """The law at projected displacements ``y`` from sliders ``z_old``.

    Fills per element N, F, z (new slider), state, and the forces ``lam`` on
    the projected coordinates.
    """
    for i in range(lam.size):
        lam[i] = 0.0
    for j in range(rows.shape[0]):
        nr, tr = rows[j, 0], rows[j, 1]
        s = props[j, SIGN]
        N[j] = normal_force(y[nr], props[j, N0], props[j, KN], s)
        F[j], z[j], state[j] = friction_return_map(y[tr], z_old[j], N[j], props[j, KT], props[j, MU])
        lam[nr] -= s * N[j]
        lam[tr] += F[j]


@leaf
def copy_into(dst, src):
    for i in range(src.size):          # explicit loops: slice assignment costs more than the law
        dst[i] = src[i]


@leaf
def _compliance_times(Cb, v, out):
    """out = Cc v from the cyclic blocks Cb (N, 3, c, c) of a ring's compliance (shroud.core.cyclic_blocks):
    interface j's rows see interfaces j-1, j, j+1 only."""
    N, c = Cb.shape[0], Cb.shape[2]
    for j in range(N):
        for i in range(c):
            acc = 0.0
            for t in range(3):
                o = ((j - 1 + t) % N) * c
                for l in range(c):
                    acc += Cb[j, t, i, l] * v[o + l]
            out[j * c + i] = acc


@leaf
def _residual_norm(y, y_pred, Cc, Cb, lam, scratch):
    """|y - y_pred - Cc lam| (Cc dense, or from its cyclic blocks Cb when there are any)."""
    r = 0.0
    if Cb.shape[0] > 0:
        _compliance_times(Cb, lam, scratch)
        for i in range(y.size):
            ri = y[i] - y_pred[i] - scratch[i]
            r += ri * ri
        return np.sqrt(r)
    for i in range(y.size):
        ri = y[i] - y_pred[i]
        for l in range(y.size):
            ri -= Cc[i, l] * lam[l]
        r += ri * ri
    return np.sqrt(r)


@leaf
def _state_keys_changed(rows, state, F, key):
    """Whether any element's state key (2 state, +1 for a slip along +e_ws) differs from ``key``; updates it."""
    changed = False
    for j in range(rows.shape[0]):
        kj = 2 * state[j] + (1 if state[j] == SLIP and F[j] > 0.0 else 0)
        if kj != key[j]:
            changed = True
            key[j] = kj
    return changed


@leaf
def _affine_load(z_old, rows, props, state, F, e):
    """e of lam = D y + e for fixed states (see :func:`_affine_solution`)."""
    for i in range(e.size):
        e[i] = 0.0
    for j in range(rows.shape[0]):
        if state[j] == SEPARATE:
            continue
        nr, tr = rows[j, 0], rows[j, 1]
        s, kt, mu, n0 = props[j, SIGN], props[j, KT], props[j, MU], props[j, N0]
        e[nr] -= s * n0
        if state[j] == STICK:
            e[tr] += kt * z_old[j]
        else:
            e[tr] += mu * (1.0 if F[j] > 0.0 else -1.0) * n0


@leaf
def _affine_solution_cyclic(y_pred, Cb, z_old, rows, props, state, F, y_out, e, T, R, G, piv, col, key, cache):
    """The affine solve of :func:`_affine_solution` for a ring's cyclic block-tridiagonal Cc (blocks Cb).

    (I - Cc D) y = y_pred + Cc e over every coordinate (an inactive one has
    an identity column) is cyclic block-tridiagonal too, D being block
    diagonal by interface (the law's elements of interface k act on its own
    c coordinates): factored by shroud.core.cyclic_blocks in O(N c^3) when
    the states change, solved in O(N c^2) a step, where the dense path costs
    O(m^2) a step and O(|A|^3) a change (m = N c).
    """
    N, c = Cb.shape[0], Cb.shape[2]
    if _state_keys_changed(rows, state, F, key) or cache[0] == 0:
        for j in range(N):
            for t in range(3):
                for i in range(c):
                    for l in range(c):
                        T[j, t, i, l] = 1.0 if (t == 1 and i == l) else 0.0
        for p in range(rows.shape[0]):
            if state[p] == SEPARATE:
                continue
            k = rows[p, 0] // c                      # the element's interface; its local rows
            nl, tl = rows[p, 0] - k * c, rows[p, 1] - k * c
            s, kn, kt, mu = props[p, SIGN], props[p, KN], props[p, KT], props[p, MU]
            slip = mu * (1.0 if F[p] > 0.0 else -1.0) * s * kn
            for t in range(3):                       # block (j, k) of row j = k + 1 - t
                j = (k + 1 - t) % N
                for i in range(c):
                    T[j, t, i, nl] += kn * Cb[j, t, i, nl]
                    if state[p] == STICK:
                        T[j, t, i, tl] += kt * Cb[j, t, i, tl]
                    else:
                        T[j, t, i, nl] -= slip * Cb[j, t, i, tl]
        cyclic_factor(T, R, G, piv, col)
        cache[0] = 1
    _affine_load(z_old, rows, props, state, F, e)
    _compliance_times(Cb, e, y_out)
    for i in range(y_out.size):
        y_out[i] += y_pred[i]
    cyclic_solve(T, R, G, piv, y_out, col)


@leaf
def _affine_solution(y_pred, Cc, z_old, rows, props, state, F, y_out, G, e, active, A, b, key, piv, cache):
    """Exact y of ``y = y_pred + Cc lam(y)`` with the element states held fixed.

    For fixed states lam = D y + e (D: -kn on contacting normals, -kt on
    sticking tangents, mu sign(F) s kn coupling a slipping tangent to its
    normal). D has non-zero columns only on the active coordinates A, so
    (I - Cc D)[A, A] y_A = y_pred_A + (Cc e)_A is solved, then
    y = y_pred + Cc e + (Cc D)[:, A] y_A.

    G = Cc D and the LU of (I - Cc D)[A, A] depend on the states (and slip
    directions) only: they are kept in the workspace (``key`` the state set
    they belong to, ``cache`` = (valid, size of A)) and reused while the
    states repeat, as they do over the many steps of a stick or slip phase.
    A step then costs O(m |A|) instead of O(|A|^3): what makes hundreds of
    contact nodes (the solid FE faces) affordable.
    """
    m = y_pred.size
    same = not _state_keys_changed(rows, state, F, key) and cache[0] == 1
    _affine_load(z_old, rows, props, state, F, e)
    is_active = active                  # flags first, compacted below
    if not same:
        for i in range(m):              # G = Cc D, built column by column
            is_active[i] = 0
            for l in range(m):
                G[i, l] = 0.0
    for j in range(rows.shape[0]):
        if same or state[j] == SEPARATE:
            continue
        nr, tr = rows[j, 0], rows[j, 1]
        s, kn, kt, mu = props[j, SIGN], props[j, KN], props[j, KT], props[j, MU]
        for i in range(m):
            G[i, nr] -= kn * Cc[i, nr]
        is_active[nr] = 1
        if state[j] == STICK:
            for i in range(m):
                G[i, tr] -= kt * Cc[i, tr]
            is_active[tr] = 1
        else:
            sigma = 1.0 if F[j] > 0.0 else -1.0
            for i in range(m):
                G[i, nr] += mu * sigma * s * kn * Cc[i, tr]
    if not same:
        na = 0
        for i in range(m):
            if is_active[i]:
                active[na] = i
                na += 1
        for a in range(na):
            for c in range(na):
                A[a, c] = (1.0 if a == c else 0.0) - G[active[a], active[c]]
        lu_factor(A, piv, na)
        cache[0], cache[1] = 1, na
    na = cache[1]
    for i in range(m):                  # y_out = y_pred + Cc e
        acc = y_pred[i]
        for l in range(m):
            acc += Cc[i, l] * e[l]
        y_out[i] = acc
    for a in range(na):
        b[a] = y_out[active[a]]
    lu_solve(A, piv, b, na)
    for i in range(m):
        acc = y_out[i]
        for c in range(na):
            acc += G[i, active[c]] * b[c]
        y_out[i] = acc


@leaf
def _element_compliance(H, P, Wc, nr, tr, s, kn, kt, mu, key, sign):
    """H += sign P D_j Wc: element j's share of P D Wc for its state key (see _affine_solution_low_rank).

    key = 2 state + (1 if a slip pushes along +e_ws): 0 separate, 2 stick, 4/5 slip -/+.
    """
    if key == 0:
        return
    r = H.shape[0]
    for a in range(r):                  # normal spring, D[nr, nr] = -kn
        pa = -sign * kn * P[a, nr]
        for b in range(r):
            H[a, b] += pa * Wc[nr, b]
    if key == 2:                        # sticking tangent, D[tr, tr] = -kt
        for a in range(r):
            pa = -sign * kt * P[a, tr]
            for b in range(r):
                H[a, b] += pa * Wc[tr, b]
    else:                               # slip: D[tr, nr] = mu sigma s kn
        sigma = 1.0 if key == 5 else -1.0
        for a in range(r):
            pa = sign * mu * sigma * s * kn * P[a, tr]
            for b in range(r):
                H[a, b] += pa * Wc[nr, b]


@leaf
def _affine_solution_low_rank(y_pred, Wc, P, z_old, rows, props, state, F, y_out, H, A, u, key, piv, cache):
    """The affine solve of :func:`_affine_solution` when Cc = Wc P has rank r < m.

    With y = y_pred + Wc u and u = P lam, fixed states (lam = D y + e) give
    the r x r system (I - P D Wc) u = P (D y_pred + e): for the reduced
    solid (r = 33 modes, m = 482 face coordinates) a step's solve costs
    O(m r) instead of O(m |A|), and a change of states updates H = P D Wc
    element by element, O(r^2) each, instead of rebuilding and refactoring
    an |A| x |A| matrix. H is rebuilt from scratch once as many element
    updates as there are elements have accumulated, so round-off cannot
    drift.
    """
    k, r = rows.shape[0], H.shape[0]
    changed = 0
    if cache[0] == 1:
        for j in range(k):
            kj = 2 * state[j] + (1 if state[j] == SLIP and F[j] > 0.0 else 0)
            if kj != key[j]:
                changed += 1
                cache[2] += 1
                nr, tr = rows[j, 0], rows[j, 1]
                s, kn, kt, mu = props[j, SIGN], props[j, KN], props[j, KT], props[j, MU]
                _element_compliance(H, P, Wc, nr, tr, s, kn, kt, mu, key[j], -1.0)
                _element_compliance(H, P, Wc, nr, tr, s, kn, kt, mu, kj, 1.0)
                key[j] = kj
    if cache[0] == 0 or cache[2] > k:
        for a in range(r):
            for b in range(r):
                H[a, b] = 0.0
        for j in range(k):
            key[j] = 2 * state[j] + (1 if state[j] == SLIP and F[j] > 0.0 else 0)
            _element_compliance(H, P, Wc, rows[j, 0], rows[j, 1], props[j, SIGN], props[j, KN],
                                props[j, KT], props[j, MU], key[j], 1.0)
        cache[0], cache[2] = 1, 0
        changed = 1
    if changed:
        for a in range(r):
            for b in range(r):
                A[a, b] = (1.0 if a == b else 0.0) - H[a, b]
        lu_factor(A, piv, r)
    for a in range(r):
        u[a] = 0.0
    for j in range(k):                  # u = P g with g = D y_pred + e (the affine law at y_pred)
        if state[j] == SEPARATE:
            continue
        nr, tr = rows[j, 0], rows[j, 1]
        s, kn, kt, mu, n0 = props[j, SIGN], props[j, KN], props[j, KT], props[j, MU], props[j, N0]
        g_n = -s * n0 - kn * y_pred[nr]
        if state[j] == STICK:
            g_t = kt * (z_old[j] - y_pred[tr])
        else:
            g_t = mu * (1.0 if F[j] > 0.0 else -1.0) * (n0 + s * kn * y_pred[nr])
        for a in range(r):
            u[a] += P[a, nr] * g_n + P[a, tr] * g_t
    lu_solve(A, piv, u, r)
    for i in range(y_out.size):         # y = y_pred + Wc u
        acc = y_pred[i]
        for b in range(r):
            acc += Wc[i, b] * u[b]
        y_out[i] = acc


def workspace(law: ContactLaw, Wc: np.ndarray | None = None, P: np.ndarray | None = None,
              blocks: np.ndarray | None = None):
    """Scratch arrays for :func:`solve_contact` (allocated once per run: they belong to one Cc).

    ``Wc, P``: factors of a low-rank compliance Cc = Wc P (m x r, r x m,
    r < m), solved in the r-dimensional space; ``blocks``: a ring's cyclic
    block-tridiagonal Cc as (N, 3, c, c) blocks (row j: its interfaces j-1,
    j, j+1; shroud.core.cyclic_blocks), solved block by block; neither: the
    dense m x m path.
    """
    m, k = law.m, law.count
    r = 0 if Wc is None else Wc.shape[1]
    dense_path = r == 0 and blocks is None
    Wc = np.zeros((m, 0)) if Wc is None else np.ascontiguousarray(Wc, dtype=float)
    P = np.zeros((0, m)) if P is None else np.ascontiguousarray(P, dtype=float)
    Cb = np.zeros((0, 3, 0, 0)) if blocks is None else np.ascontiguousarray(blocks, dtype=float)
    N, c = Cb.shape[0], Cb.shape[2]
    return (np.zeros((m, m)) if dense_path else np.zeros((0, 0)), np.zeros(m), np.zeros(m, np.int64),
            np.zeros((m, m)) if dense_path else np.zeros((0, 0)), np.zeros(m),
            np.zeros(m), np.zeros(m), np.zeros(k), np.zeros(k), np.zeros(k), np.zeros(k, np.int64),
            np.zeros(k, np.int64), np.zeros(k),
            np.full(k, -1, np.int64), np.zeros(max(m, r), np.int64), np.zeros(3, np.int64),  # LU reuse
            Wc, P, np.zeros((r, r)), np.zeros((r, r)), np.zeros(r),                      # low rank
            Cb, np.zeros((N, 3, c, c)), np.zeros((N, c, c)), np.zeros((N, c, c)),        # cyclic blocks
            np.zeros((N, c), np.int64), np.zeros(c), np.zeros(m))


@leaf
def solve_contact(y_pred, Cc, z_old, rows, props, y, lam, N, F, z, state, ws):
    """The implicit contact step: y with ``y = y_pred + Cc lam(y)``, to round-off.

    Starts from the predictor's states (the trial of a return mapping), then
    repeats: evaluate the states at y, solve the affine problem they define
    exactly, until the states reproduce themselves. A slip whose direction
    reverses between two iterations is tried as stick first (the stick range
    lies between the two slip directions; jumping across it makes plain
    Newton cycle). If the states still have not settled after a number of
    plain steps, each step is shortened until the residual decreases.
    Returns (iterations, converged).
    On return ``lam, N, F, z, state`` are the law evaluated at ``y``.
    """
    (G, e, active, A, b, y_try, lam_try, N_try, F_try, z_try, st_used, st_try, F_used, key, piv, cache,
     Wc, P, H, A_r, u, Cb, T, R, Gb, piv_b, col, scratch) = ws
    low_rank, cyclic = H.shape[0] > 0, Cb.shape[0] > 0
    copy_into(y, y_pred)
    evaluate(y, z_old, rows, props, lam, N, F, z, state)
    touching = False
    for j in range(state.size):
        touching = touching or state[j] != SEPARATE
    if not touching:                     # the predictor is free of contact: exact as it is
        return 1, True
    copy_into(st_used, state)
    copy_into(F_used, F)
    r = -1.0                             # residual at y, computed once an iteration fails
    for it in range(1, _MAX_ITERATIONS + 1):
        if low_rank:
            _affine_solution_low_rank(y_pred, Wc, P, z_old, rows, props, st_used, F_used, y_try, H, A_r,
                                      u, key, piv, cache)
        elif cyclic:
            _affine_solution_cyclic(y_pred, Cb, z_old, rows, props, st_used, F_used, y_try, e, T, R, Gb,
                                    piv_b, col, key, cache)
        else:
            _affine_solution(y_pred, Cc, z_old, rows, props, st_used, F_used, y_try, G, e, active, A, b,
                             key, piv, cache)
        full_step = True
        if it <= _PLAIN_ITERATIONS:      # plain active-set step: the law at y_try is the new iterate
            copy_into(y, y_try)
            evaluate(y, z_old, rows, props, lam, N, F, z, state)
        else:                            # guard: shorten the step until the residual drops
            evaluate(y_try, z_old, rows, props, lam_try, N_try, F_try, z_try, st_try)
            r_try = _residual_norm(y_try, y_pred, Cc, Cb, lam_try, scratch)
            t = 0.5
            while t > 1e-12 and r_try > r:
                full_step = False
                for i in range(y.size):
                    y_try[i] = y[i] + t * (y_try[i] - y[i])
                evaluate(y_try, z_old, rows, props, lam_try, N_try, F_try, z_try, st_try)
                r_try = _residual_norm(y_try, y_pred, Cc, Cb, lam_try, scratch)
                t *= 0.5
            copy_into(y, y_try)
            copy_into(lam, lam_try)
            copy_into(N, N_try)
            copy_into(F, F_try)
            copy_into(z, z_try)
            copy_into(state, st_try)
        same = full_step                 # y is the exact solution for the states used ...
        for j in range(state.size):      # ... and they reproduce themselves
            if state[j] != st_used[j] or (state[j] == SLIP and (F[j] > 0.0) != (F_used[j] > 0.0)):
                same = False
                break
        if same:
            return it, True
        r = _residual_norm(y, y_pred, Cc, Cb, lam, scratch)
        scale = 0.0
        for i in range(y.size):
            scale = max(scale, abs(y_pred[i]))
        if r <= 1e-13 * (scale + 1e-300):
            return it, True
        for j in range(state.size):      # next state set: the states at y, except that a slip
            if state[j] == SLIP and st_used[j] == SLIP and (F[j] > 0.0) != (F_used[j] > 0.0):
                st_used[j] = STICK       # that reversed passes through stick first
            else:
                st_used[j] = state[j]
            F_used[j] = F[j]
    return _MAX_ITERATIONS, False


@leaf
def contact_energy(N, F, props):
    """Energy stored in the contact springs: sum N^2/(2 kn) + F^2/(2 kt), J."""
    E = 0.0
    for j in range(N.size):
        E += N[j] * N[j] / (2.0 * props[j, KN])
        if props[j, KT] > 0.0:
            E += F[j] * F[j] / (2.0 * props[j, KT])
    return E


@leaf
def friction_dissipation(F_old, F_new, z_old, z_new):
    """Work dissipated by the sliders over one step, -sum mean(F) dz, J (>= 0 in slip).

    With F = kt (z - w) at both ends of the step this closes the discrete
    energy balance exactly: mean(F) dw = mean(F) dz - d(F^2 / 2 kt).
    """
    D = 0.0
    for j in range(F_old.size):
        D -= 0.5 * (F_old[j] + F_new[j]) * (z_new[j] - z_old[j])
    return D


def harmonic_stiffness(kt: float, slip_force: float, amplitude: float) -> complex:
    """First-harmonic (describing-function) stiffness of one friction element, N/m.

    The tangential spring kt in series with the slider of limit ``slip_force``
    = mu N (constant N), driven by w = a cos(tau) with amplitude a (m) once
    the loop is periodic: the first harmonic of the force the element exerts,
    -F = (k' + i k'') w. It sticks over the angle beta after each reversal,
    cos beta = 1 - 2 mu N / (kt a), so

        k'  = kt / pi (beta - sin(2 beta) / 2),
        k'' = 4 mu N / (pi a) (1 - mu N / (kt a))   (pi a^2 k'' = the loop's area);

    for a <= mu N / kt it sticks throughout (k' = kt, k'' = 0). In gross slip
    (kt a >> mu N) k' = 16 / (3 pi) (mu N)^(3/2) / (kt^(1/2) a^(3/2)): a stiffer
    tangential spring makes the element softer, since the force tends to the
    square wave mu N sign(w'), all damping and no stiffness. At fixed a and
    mu N, k' rises with kt only while kt a < mu N / 0.769 (d k'/d kt = 0 at
    r = mu N / (kt a) = 0.769).
    """
    if amplitude <= 0.0 or kt * amplitude <= slip_force:
        return complex(kt, 0.0)
    r = slip_force / (kt * amplitude)
    beta = np.arccos(1.0 - 2.0 * r)
    return complex(kt / np.pi * (beta - 0.5 * np.sin(2.0 * beta)),
                   4.0 * slip_force / (np.pi * amplitude) * (1.0 - r))
