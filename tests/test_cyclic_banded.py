"""The periodic block-tridiagonal solve by banded LU with partial pivoting (shroud.core.cyclic_banded)
against LAPACK's dense solve, where the block elimination without pivoting across blocks fails."""

import numpy as np
import pytest

from shroud.core.cyclic_banded import CyclicBanded, harmonic_major_blocks, ring_order
from shroud.core.cyclic_blocks import cyclic_factor, cyclic_solve


def _needs_pivoting(rng, N, b):
    """Random cyclic blocks T (N, 3, b, b) whose diagonal blocks are singular (rank b - 1; zero for b = 1):
    no elimination that pivots only inside them can go through, the whole matrix is regular."""
    T = rng.uniform(-1.0, 1.0, (N, 3, b, b))
    for j in range(N):
        U, s, Vt = np.linalg.svd(T[j, 1])
        s[-1] = 0.0
        T[j, 1] = (U * s) @ Vt
    return T


def _assemble(T, blocks):
    """The dense matrix of cyclic blocks T, block j on the indices blocks[j]."""
    N = T.shape[0]
    n = blocks.size
    A = np.zeros((n, n))
    for j in range(N):
        for k, m in enumerate((j - 1, j, j + 1)):
            A[np.ix_(blocks[j], blocks[m % N])] += T[j, k]
    return A


def test_the_ring_order_puts_neighbours_at_most_two_apart():
    for N in range(3, 50):
        place = np.argsort(ring_order(N))
        assert sorted(ring_order(N)) == list(range(N))
        assert max(abs(place[j] - place[(j + 1) % N]) for j in range(N)) <= 2


@pytest.mark.parametrize("N,nh,m", [(3, 1, 1), (3, 3, 2), (4, 2, 1), (5, 1, 3), (24, 3, 2), (24, 21, 2)])
def test_the_banded_solve_is_the_dense_solve_where_pivoting_across_blocks_is_needed(N, nh, m):
    """Singular diagonal blocks, laid out harmonic-major as the ring's HB unknowns (blade j's coordinate l
    of harmonic h at h N m + j m + l): x within 1e-9 of numpy.linalg.solve relative to its size (1 and 2
    right-hand sides), while the block elimination of shroud.core.cyclic_blocks (blade-major, the same
    blocks) is off by orders of magnitude, not finite or
    stopped by a zero pivot."""
    rng = np.random.default_rng(100 * N + 10 * nh + m)
    b = nh * m
    T = _needs_pivoting(rng, N, b)
    blocks = harmonic_major_blocks(N, nh, m)
    A = _assemble(T, blocks)
    solve = CyclicBanded(blocks)
    for rhs in (rng.standard_normal(N * b), rng.standard_normal((N * b, 2))):
        truth = np.linalg.solve(A, rhs)
        x = solve(A, rhs)
        assert x.shape == rhs.shape
        assert np.abs(x - truth).max() <= 1e-9 * np.abs(truth).max()
    rhs = rng.standard_normal(N * b)
    truth = np.linalg.solve(_assemble(T, np.arange(N * b).reshape(N, b)), rhs)
    R, G = np.empty((N, b, b)), np.empty((N, b, b))
    piv, col = np.empty((N, b), dtype=np.int64), np.empty(b)
    F, y = T.copy(), rhs.copy()
    try:
        with np.errstate(all="ignore"):
            cyclic_factor(F, R, G, piv, col)
            cyclic_solve(F, R, G, piv, y, col)
    except ZeroDivisionError:           # an exactly zero pivot (compiled code raises)
        return
    assert not np.all(np.isfinite(y)) or np.abs(y - truth).max() > 1e-3 * np.abs(truth).max()


def test_a_singular_matrix_is_refused_as_numpy_does():
    blocks = harmonic_major_blocks(4, 2, 1)
    A = _assemble(np.ones((4, 3, 2, 2)), blocks)
    with pytest.raises(np.linalg.LinAlgError):
        CyclicBanded(blocks)(A, np.ones(8))


def test_the_transposed_solve_is_the_dense_transposed_solve():
    rng = np.random.default_rng(7)
    blocks = harmonic_major_blocks(6, 3, 2)
    A = _assemble(_needs_pivoting(rng, 6, 6), blocks)
    rhs = rng.standard_normal(36)
    truth = np.linalg.solve(A.T, rhs)
    assert np.abs(CyclicBanded(blocks).factor(A).solve(rhs, transposed=True) - truth).max() \
        <= 1e-10 * np.abs(truth).max()


def test_the_continuations_bordered_solve_is_the_dense_one_near_a_fold():
    """[[J, c], [d]] u = rhs by mixed block elimination on the banded LU of J
    (shroud.core.continuation._bordered) against numpy.linalg.solve of the bordered matrix, with one column
    of J scaled by 1e-13 (cond 1e15, a fold: J's null vector is the branch's tangent), the bordered
    matrix regular (measured: 1.4e-15 here, plain bordering 5.5e-6)."""
    from shroud.core.continuation import _bordered
    rng = np.random.default_rng(11)
    N, nh, m = 8, 3, 2
    blocks = harmonic_major_blocks(N, nh, m)
    A = _assemble(rng.uniform(-1.0, 1.0, (N, 3, nh * m, nh * m)), blocks)
    J = A.copy()
    J[:, blocks[3, 2]] *= 1e-13                        # one column nearly gone: the structure kept
    n = J.shape[0]
    c, d, rhs = rng.standard_normal(n), rng.standard_normal(n + 1), rng.standard_normal(n + 1)
    M = np.zeros((n + 1, n + 1))
    M[:n, :n], M[:n, n], M[n] = J, c, d
    truth = np.linalg.solve(M, rhs)
    u = _bordered(CyclicBanded(blocks).factor, J, c, d, rhs)
    assert np.abs(u - truth).max() <= 1e-8 * np.abs(truth).max()
    assert np.linalg.cond(J) > 1e12 and np.linalg.cond(M) < 1e8
