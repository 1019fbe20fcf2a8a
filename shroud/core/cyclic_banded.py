"""Periodic block-tridiagonal systems by banded LU with partial pivoting (docs/ring.md).

A ring couples block j (a blade's unknowns) only to j-1 and j+1, indices
mod N: its matrices are cyclic block-tridiagonal. Taken in the order
0, N-1, 1, N-2, 2, ... every pair of ring neighbours is at most two
places apart (j, j+1 at 2j, 2j+2; N-k, N-k-1 at 2k-1, 2k+1; 0, N-1 at
0, 1), so the reordered matrix is banded with kl = ku = 3b - 1 for blocks
of b unknowns. LAPACK's banded LU (dgbsv) pivots by rows across the whole
band: O(N b^3) like the block elimination of shroud.core.cyclic_blocks,
but it does not need the diagonal blocks to be dominant (the harmonic
balance's Jacobian of a ring, where they are not: there the elimination
without pivoting across blocks breaks down).
"""

from __future__ import annotations

import numpy as np
import scipy.linalg.lapack as lapack



def ring_order(N: int) -> np.ndarray:
    """The blocks 0, N-1, 1, N-2, ...: ring neighbours at most two places apart.

    >>> ring_order(5).tolist()
    [0, 4, 1, 3, 2]
    """
    order = np.empty(N, dtype=int)
    order[0::2] = np.arange((N + 1) // 2)
    order[1::2] = N - 1 - np.arange(N // 2)
    return order


def harmonic_major_blocks(N: int, nh: int, m: int) -> np.ndarray:
    """(N, nh m) indices of each blade's unknowns in a harmonic-major vector of N m coordinates per
    harmonic (shroud.core.ring.ring_harmonics: coordinate l of blade j, harmonic h at h N m + j m + l).

    >>> harmonic_major_blocks(2, 2, 1).tolist()
    [[0, 2], [1, 3]]
    """
    h, j, l = np.meshgrid(np.arange(nh), np.arange(N), np.arange(m), indexing="ij")
    return (h * N * m + j * m + l).transpose(1, 0, 2).reshape(N, nh * m)


class BandedLU:
    """The banded LU (LAPACK dgbtrf) of a reordered matrix: solves with it or with its transpose."""

    def __init__(self, lu: np.ndarray, piv: np.ndarray, kl: int, ku: int, perm: np.ndarray):
        self.lu, self.piv, self.kl, self.ku, self.perm = lu, piv, kl, ku, perm

    def solve(self, rhs: np.ndarray, transposed: bool = False) -> np.ndarray:
        """x with A x = rhs (A^T x = rhs if ``transposed``); rhs (n,) or (n, k)."""
        x, info = lapack.dgbtrs(self.lu, self.kl, self.ku, np.asarray(rhs, dtype=float)[self.perm], self.piv,
                                trans=int(transposed), overwrite_b=True)
        out = np.empty_like(x)
        out[self.perm] = x
        return out


class CyclicBanded:
    """:meth:`factor` and ``solve(A, rhs)`` for a cyclic block-tridiagonal A whose block j is on the
    indices ``blocks[j]`` (N >= 3 blocks of b): numpy.linalg.solve's call and its LinAlgError where A is
    singular, rhs (n,) or (n, k).

    The gather from A into LAPACK's band storage (ab[kl + ku + i - j, j] = A_ij, reordered) is worked out
    once; every factorization is one gather and one dgbtrf. Entries of A outside the declared structure
    are not read: A must be cyclic block-tridiagonal in ``blocks``.
    """

    def __init__(self, blocks: np.ndarray):
        blocks = np.asarray(blocks)
        N, b = blocks.shape
        if N < 3:
            raise ValueError(f"a cyclic block-tridiagonal system needs N >= 3 blocks, not {N}")
        self.perm = blocks[ring_order(N)].ravel()
        n = self.perm.size
        self.kl = self.ku = min(3 * b - 1, n - 1)
        rows = 2 * self.kl + self.ku + 1                 # the first kl rows: room for the pivoting's fill
        j = np.repeat(np.arange(n), self.kl + self.ku + 1)
        i = j + np.tile(np.arange(-self.ku, self.kl + 1), n)
        inside = (i >= 0) & (i < n)
        i, j = i[inside], j[inside]
        self._dst = j * rows + self.kl + self.ku + i - j  # flat index into ab^T (n, rows): ab in Fortran order
        self._src = self.perm[i] * n + self.perm[j]      # flat index into A
        self._shape = (n, rows)

    def factor(self, A: np.ndarray) -> BandedLU:
        abT = np.zeros(self._shape)
        abT.flat[self._dst] = np.ravel(A)[self._src]
        lu, piv, info = lapack.dgbtrf(abT.T, self.kl, self.ku, overwrite_ab=True)
        if info != 0:
            raise np.linalg.LinAlgError(f"singular cyclic block-tridiagonal matrix (dgbtrf: info {info})")
        return BandedLU(lu, piv, self.kl, self.ku, self.perm)

    def __call__(self, A: np.ndarray, rhs: np.ndarray) -> np.ndarray:
        return self.factor(A).solve(rhs)
