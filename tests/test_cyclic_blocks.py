"""The periodic block-tridiagonal solve (shroud.core.cyclic_blocks) against LAPACK's dense solve."""

import numpy as np
import pytest

from shroud.core.cyclic_blocks import cyclic_factor, cyclic_solve


def _assemble(T):
    """The dense N b x N b matrix of cyclic blocks T (N, 3, b, b): row j holds A(j, j-1), A(j, j), A(j, j+1)."""
    N, b = T.shape[0], T.shape[2]
    A = np.zeros((N * b, N * b))
    for j in range(N):
        for k, m in enumerate((j - 1, j, j + 1)):
            A[j * b:(j + 1) * b, (m % N) * b:(m % N + 1) * b] += T[j, k]
    return A


@pytest.mark.parametrize("N,b", [(3, 1), (3, 4), (4, 2), (24, 4), (96, 2)])
def test_the_cyclic_block_solve_is_the_dense_solve(N, b):
    """Random blocks, the corners as large as the band, pivoting needed inside the diagonal blocks
    (their rows permuted): x within 1e-12 of numpy.linalg.solve, for several right-hand sides."""
    rng = np.random.default_rng(N * 10 + b)
    T = rng.uniform(-1.0, 1.0, (N, 3, b, b))
    for j in range(N):
        T[j, 1] = (T[j, 1] + 3.0 * b * np.eye(b))[rng.permutation(b)]
    A = _assemble(T)
    assert np.abs(A[:b, -b:]).max() > 0.1 and np.abs(A[-b:, :b]).max() > 0.1   # the corners count
    R, G = np.empty((N, b, b)), np.empty((N, b, b))
    piv, col = np.empty((N, b), dtype=np.int64), np.empty(b)
    F = T.copy()
    cyclic_factor(F, R, G, piv, col)
    for _ in range(3):
        rhs = rng.standard_normal(N * b)
        x = rhs.copy()
        cyclic_solve(F, R, G, piv, x, col)
        truth = np.linalg.solve(A, rhs)
        assert np.abs(x - truth).max() <= 1e-12 * np.abs(truth).max()


def test_dropping_the_corner_blocks_is_seen():
    """The same solve with A(0, N-1) and A(N-1, 0) zeroed is a different answer: the test above can fail."""
    rng = np.random.default_rng(7)
    N, b = 5, 2
    T = rng.uniform(-1.0, 1.0, (N, 3, b, b))
    T[:, 1] += 3.0 * b * np.eye(b)
    rhs = rng.standard_normal(N * b)
    Tc = T.copy()
    Tc[0, 0] = 0.0
    Tc[N - 1, 2] = 0.0
    assert np.abs(np.linalg.solve(_assemble(T), rhs) - np.linalg.solve(_assemble(Tc), rhs)).max() > 1e-3


def test_the_dense_lu_with_row_swaps_is_the_dense_solve():
    """lu_factor / lu_solve (the contact's dense and low-rank paths) on random matrices that need
    row swaps at several columns: within 1e-10 of numpy.linalg.solve (before the swaps were made
    LINPACK's, 164 of these 200 solves were wrong)."""
    from shroud.core.cyclic_blocks import lu_factor, lu_solve

    rng = np.random.default_rng(0)
    for _ in range(200):
        n = int(rng.integers(2, 9))
        A, rhs = rng.standard_normal((n, n)), rng.standard_normal(n)
        F, piv, x = A.copy(), np.empty(n, dtype=np.int64), rhs.copy()
        lu_factor(F, piv, n)
        lu_solve(F, piv, x, n)
        truth = np.linalg.solve(A, rhs)
        assert np.abs(x - truth).max() <= 1e-10 * np.abs(truth).max() * np.linalg.cond(A)
