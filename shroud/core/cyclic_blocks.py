"""Dense LU and the periodic block-tridiagonal solve, compiled and allocation-free (docs/ring.md).

A ring's contact couples interface j only to j-1 and j+1 (through the
blades they share), so its matrices are cyclic block-tridiagonal: block row
j holds T[j, 0] = A(j, j-1), T[j, 1] = A(j, j), T[j, 2] = A(j, j+1), indices
mod N (N >= 3, so that the three blocks are distinct). :func:`cyclic_factor`
is block Gaussian elimination in order 0, 1, ..., N-1 with the corner
blocks carried along as a last block column (R_j: row j's coupling to
block N-1) and a last block row (G_j: row N-1's coupling to block j), the
bordered form of the periodic Thomas algorithm: O(N b^3) to factor and
O(N b^2) to solve, against O((N b)^3) and O((N b)^2) dense. Pivoting is
within the diagonal blocks only (the contact's I - Cc D is block
diagonally dominant enough: I plus a compliance times the springs).

Leaf functions as shroud.core.contact's law: compiled without numba's
reference counting (they allocate nothing).
"""

from __future__ import annotations

from numba import njit

leaf = njit(cache=True, _nrt=False)


@leaf
def lu_factor(A, piv, n):
    """LU of A[:n, :n] in place (partial pivoting; multipliers below the diagonal), row swaps in piv.

    LINPACK's layout: a swap at column c exchanges columns c.. only, leaving
    the earlier columns' multipliers where they were made, which is what
    :func:`lu_solve`'s interleaved swaps and eliminations read (LAPACK swaps
    whole rows and applies every swap before the elimination instead).
    """
    for c in range(n):
        p = c
        for i in range(c + 1, n):
            if abs(A[i, c]) > abs(A[p, c]):
                p = i
        piv[c] = p
        if p != c:
            for l in range(c, n):
                A[c, l], A[p, l] = A[p, l], A[c, l]
        for i in range(c + 1, n):
            f = A[i, c] / A[c, c]
            A[i, c] = f
            for l in range(c + 1, n):
                A[i, l] -= f * A[c, l]


@leaf
def lu_solve(A, piv, b, n):
    """Solve with the factors of :func:`lu_factor`; x returned in b[:n]."""
    for c in range(n):
        p = piv[c]
        if p != c:
            b[c], b[p] = b[p], b[c]
        for i in range(c + 1, n):
            b[i] -= A[i, c] * b[c]
    for c in range(n - 1, -1, -1):
        acc = b[c]
        for l in range(c + 1, n):
            acc -= A[c, l] * b[l]
        b[c] = acc / A[c, c]


@leaf
def _solve_columns(A, piv, B, col):
    """B <- A^-1 B for the b x b factors of :func:`lu_factor` (every column of B; ``col`` scratch (b,))."""
    b = B.shape[0]
    for k in range(B.shape[1]):
        for i in range(b):
            col[i] = B[i, k]
        lu_solve(A, piv, col, b)
        for i in range(b):
            B[i, k] = col[i]


@leaf
def _subtract_product(C, A, B):
    """C -= A B (b x b blocks)."""
    b = C.shape[0]
    for i in range(b):
        for k in range(b):
            a = A[i, k]
            if a != 0.0:
                for l in range(b):
                    C[i, l] -= a * B[k, l]


@leaf
def cyclic_factor(T, R, G, piv, col):
    """Factor the cyclic block-tridiagonal T (N, 3, b, b) in place (module docstring).

    On return T[j, 1] holds the LU of the j-th pivot block (swaps in piv[j]),
    T[j, 2] the eliminated D_j^-1 A(j, j+1) (j < N-2), R[j] D_j^-1 R_j (the
    last block column), G[j] row N-1's coupling to block j after
    elimination, T[j, 0] untouched: what :func:`cyclic_solve` needs.
    """
    N, b = T.shape[0], T.shape[2]
    for j in range(N):
        for i in range(b):
            for l in range(b):
                R[j, i, l] = 0.0
                G[j, i, l] = 0.0
    for i in range(b):
        for l in range(b):
            R[0, i, l] = T[0, 0, i, l]                  # A(0, N-1), the corner
            R[N - 2, i, l] += T[N - 2, 2, i, l]         # A(N-2, N-1) joins the last column
            G[0, i, l] = T[N - 1, 2, i, l]              # A(N-1, 0), the other corner
            G[N - 2, i, l] += T[N - 1, 0, i, l]         # A(N-1, N-2) joins the last row
    for j in range(N - 1):
        lu_factor(T[j, 1], piv[j], b)
        _solve_columns(T[j, 1], piv[j], R[j], col)
        if j < N - 2:
            _solve_columns(T[j, 1], piv[j], T[j, 2], col)
            _subtract_product(T[j + 1, 1], T[j + 1, 0], T[j, 2])
            _subtract_product(R[j + 1], T[j + 1, 0], R[j])
            _subtract_product(G[j + 1], G[j], T[j, 2])
        _subtract_product(T[N - 1, 1], G[j], R[j])
    lu_factor(T[N - 1, 1], piv[N - 1], b)


@leaf
def cyclic_solve(T, R, G, piv, x, col):
    """x <- A^-1 x with the factors of :func:`cyclic_factor` (x: (N b,), block j at j b .. (j+1) b - 1)."""
    N, b = T.shape[0], T.shape[2]
    last = (N - 1) * b
    for j in range(N):                                  # forward: eliminate below each pivot block
        o = j * b
        for i in range(b):
            col[i] = x[o + i]
        lu_solve(T[j, 1], piv[j], col, b)
        for i in range(b):
            x[o + i] = col[i]
        if j == N - 1:
            break
        if j < N - 2:
            for i in range(b):
                acc = 0.0
                for l in range(b):
                    acc += T[j + 1, 0, i, l] * col[l]
                x[o + b + i] -= acc
        for i in range(b):
            acc = 0.0
            for l in range(b):
                acc += G[j, i, l] * col[l]
            x[last + i] -= acc
    for j in range(N - 2, -1, -1):                      # back: the last block, then j + 1 into j
        o = j * b
        for i in range(b):
            acc = 0.0
            for l in range(b):
                acc += R[j, i, l] * x[last + l]
                if j < N - 2:
                    acc += T[j, 2, i, l] * x[o + b + l]
            x[o + i] -= acc
