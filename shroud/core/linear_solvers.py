"""Factorizations of the step operator and row shares, as the integrators see them.

Two small protocols let a model bring its own direct solver and its own
spreading of rows over MPI ranks without the core knowing PETSc:

* :class:`Factorization`: ``solve(b)`` with ``A x = b`` for ``b`` of shape
  (n,) or (n, k), ``solve_rows(b_rows)``: this process's rows of x from
  this process's rows of b (one process: all rows, the same as ``solve``),
  and ``close()``, called by whoever factorized once the solves are done.
* :class:`RowShare`: the rows ``start:stop`` this process holds, ``own(x)``
  its rows of a replicated array, ``gather(rows)`` the replicated array back,
  ``sum(part)`` the sum over the processes of each one's ``part``.

The core implements both for one process (:class:`DenseInverse`,
:class:`SparseLU`, :class:`AllRows`); reference_fe implements them with
MUMPS over MPI ranks (reference_fe.factor.MumpsFactor,
reference_fe.distributed.Layout).
"""

from __future__ import annotations

from typing import Protocol, runtime_checkable

import numpy as np
import scipy.sparse
import scipy.sparse.linalg


@runtime_checkable
class Factorization(Protocol):
    """A factorized square operator A (n x n)."""

    def solve(self, b: np.ndarray) -> np.ndarray:
        """x with A x = b; b of shape (n,) or (n, k), x of the same shape, every row."""
        ...

    def solve_rows(self, b_rows: np.ndarray) -> np.ndarray:
        """This process's rows of x from this process's rows of b (1-D)."""
        ...

    def close(self) -> None:
        """Release what the factorization holds (solver objects outside Python's memory)."""
        ...


@runtime_checkable
class RowShare(Protocol):
    """Which rows of the model's vectors this process holds (contiguous ``start:stop``)."""

    start: int
    stop: int

    def own(self, x: np.ndarray) -> np.ndarray: ...

    def gather(self, rows: np.ndarray) -> np.ndarray: ...

    def sum(self, part: np.ndarray) -> np.ndarray: ...


def dense(A) -> np.ndarray:
    """``A`` as a float ndarray (scipy.sparse made dense): for the small operators only.

    >>> dense(scipy.sparse.eye(2)).tolist()
    [[1.0, 0.0], [0.0, 1.0]]
    """
    return A.toarray() if scipy.sparse.issparse(A) else np.asarray(A, dtype=float)


class DenseInverse:
    """A small dense operator, inverted once.

    Dense step operators are small (n <= a few hundred) and the compiled
    Newmark kernel needs the inverse anyway to fold it into its products; a
    multi-column LU solve through scipy instead wakes the BLAS threads and
    costs milliseconds per speed of a sweep on a busy machine.

    >>> DenseInverse(np.array([[2.0, 0.0], [0.0, 4.0]])).solve(np.array([2.0, 2.0]))
    array([1. , 0.5])
    """

    def __init__(self, A):
        self.inverse = np.linalg.inv(np.asarray(A, dtype=float))

    def solve(self, b: np.ndarray) -> np.ndarray:
        return self.inverse @ b

    solve_rows = solve

    def close(self) -> None:
        """Nothing outside Python's memory."""


class SparseLU:
    """SuperLU of a scipy.sparse operator on one process.

    SuperLU is handed one column at a time: its multi-column solve goes
    through the threaded BLAS and measured slower on the 36888-DOF "fe"
    step operator with 482 contact columns (2 cores: 32-52 s as one block,
    21-23 s by columns; only with one BLAS thread, which the library does
    not control, the block wins: 23 s against 29-45 s).
    """

    def __init__(self, A):
        self._lu = scipy.sparse.linalg.splu(scipy.sparse.csc_matrix(A))

    def solve(self, b: np.ndarray) -> np.ndarray:
        b = np.asarray(b, dtype=float)
        if b.ndim == 1:
            return self._lu.solve(b)
        x = np.empty_like(b)
        for i in range(b.shape[1]):
            x[:, i] = self._lu.solve(np.ascontiguousarray(b[:, i]))
        return x

    solve_rows = solve

    def close(self) -> None:
        """Nothing outside Python's memory."""


def default_factorization(A) -> Factorization:
    """SuperLU for scipy.sparse, the inverse for a dense array."""
    return SparseLU(A) if scipy.sparse.issparse(A) else DenseInverse(A)


class AllRows:
    """One process holds every row: the trivial :class:`RowShare`."""

    def __init__(self, n: int):
        self.start, self.stop = 0, n

    @staticmethod
    def own(x: np.ndarray) -> np.ndarray:
        return x

    @staticmethod
    def gather(rows: np.ndarray) -> np.ndarray:
        return rows

    @staticmethod
    def sum(part: np.ndarray) -> np.ndarray:
        return part
