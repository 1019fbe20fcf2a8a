"""The solid's free-DOF operators spread over MPI ranks, acting on replicated vectors.

Under ``mpirun -n P`` DOLFINx assembles M, K and G row-distributed over the
ranks. A vector of the solid is 37k doubles (0.3 MB), so every rank keeps
all of it (replicated) and only the costly parts are spread: products with
the sparse operators and the back-substitutions of the factorized step
operator. ``A @ x`` (DistributedMatrix) takes the rank's rows of x, works on
them with PETSc (MatMult) and gathers the rows of every rank (MPI
Allgatherv): any code written for scipy matrices runs unchanged.

The Newmark loop (shroud.core.newmark) goes further, with one message of a
vector per step: each rank forms its rows of the step's right-hand side
from its ``row_block`` (its rows, every column) and the replicated state,
back-substitutes them with MUMPS (MumpsFactor.solve_rows), adds its rows of
the contact response, and gathers the end state; the contact coordinates
W q come from each rank's columns of W summed over the ranks (``sum``).

The free DOFs are numbered rank by rank (a rank's owned, unclamped DOFs in
their PETSc order); ``Layout`` knows which rows each rank owns. Serial runs
use scipy.sparse instead (reference_fe.solid.FreeOperators) and never come here.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass
from typing import Any

import dolfinx_solver  # noqa: F401  (must precede petsc4py)
import numpy as np
import scipy.sparse as sp
from mpi4py import MPI
from petsc4py import PETSc


def global_offset(V) -> int:
    """Global unrolled index of this rank's first owned DOF of the space ``V`` (DOLFINx/PETSc numbering)."""
    return V.dofmap.index_map_bs * V.dofmap.index_map.local_range[0]


@dataclass(frozen=True)
class Layout:
    """Rows of the free-DOF numbering owned by each rank (contiguous, rank by rank)."""

    comm: Any                  # mpi4py communicator
    counts: np.ndarray         # (P,) rows of each rank

    @classmethod
    def of(cls, comm, local_rows: int) -> "Layout":
        return cls(comm=comm, counts=np.asarray(comm.allgather(int(local_rows)), dtype=np.int64))

    @property
    def size(self) -> int:
        return int(self.counts.sum())

    @property
    def start(self) -> int:
        return int(self.counts[:self.comm.rank].sum())

    @property
    def stop(self) -> int:
        return self.start + int(self.counts[self.comm.rank])

    def sum(self, part: np.ndarray) -> np.ndarray:
        """The sum over the ranks of each rank's ``part`` (MPI Allreduce): W q from each rank's columns."""
        out = np.empty_like(part, dtype=float)
        self.comm.Allreduce(np.ascontiguousarray(part, dtype=float), out, op=MPI.SUM)
        return out

    def own(self, x: np.ndarray) -> np.ndarray:
        """This rank's rows of a replicated array (contiguous copy)."""
        return np.ascontiguousarray(x[self.start:self.stop], dtype=float)

    def gather(self, rows: np.ndarray) -> np.ndarray:
        """The replicated array from every rank's rows (1-D, or 2-D with rows first)."""
        rows = np.ascontiguousarray(rows, dtype=float)
        width = int(np.prod(rows.shape[1:], dtype=np.int64))
        out = np.empty((self.size, *rows.shape[1:]))
        counts = self.counts * width
        displs = np.concatenate([[0], np.cumsum(counts)[:-1]])
        self.comm.Allgatherv(rows, [out, counts, displs, MPI.DOUBLE])
        return out


class DistributedMatrix:
    """A row-distributed PETSc matrix acting on replicated vectors: ``A @ x``, ``A + B``, ``s * A``."""

    dtype = np.dtype(float)

    def __init__(self, mat: PETSc.Mat, layout: Layout):
        self.mat = mat
        self.layout = layout
        self._x, self._y = mat.createVecs()

    @property
    def shape(self) -> tuple[int, int]:
        return tuple(self.mat.getSize())

    @functools.cached_property
    def row_block(self) -> sp.csr_matrix:
        """This rank's rows with every column (scipy CSR): own rows of ``A x`` from a replicated x, no messages."""
        indptr, indices, data = self.mat.getValuesCSR()
        return sp.csr_matrix((data, indices, indptr), shape=(self.layout.stop - self.layout.start, self.shape[1]))

    def whole(self) -> sp.csr_matrix:
        """The complete matrix on every rank (scipy CSR, stored zeros dropped): the row blocks gathered once."""
        A = sp.vstack(self.layout.comm.allgather(self.row_block), format="csr")
        A.eliminate_zeros()
        return A

    def matvec(self, x: np.ndarray) -> np.ndarray:
        self._x.setArray(self.layout.own(np.ravel(x)))
        self.mat.mult(self._x, self._y)
        return self.layout.gather(self._y.getArray())

    def __matmul__(self, x: np.ndarray) -> np.ndarray:
        x = np.asarray(x, dtype=float)
        if x.ndim == 1:
            return self.matvec(x)
        return np.column_stack([self.matvec(x[:, i]) for i in range(x.shape[1])])

    def __add__(self, other: "DistributedMatrix") -> "DistributedMatrix":
        out = self.mat.copy()
        out.axpy(1.0, other.mat, structure=PETSc.Mat.Structure.DIFFERENT_NONZERO_PATTERN)
        return DistributedMatrix(out, self.layout)

    def __mul__(self, scale: float) -> "DistributedMatrix":
        out = self.mat.copy()
        out.scale(float(scale))
        return DistributedMatrix(out, self.layout)

    __rmul__ = __mul__

    def is_symmetric(self) -> bool:
        """Exactly symmetric (no Coriolis part)."""
        return bool(self.mat.isSymmetric(0.0))


def free_rows(A: PETSc.Mat, free_global: np.ndarray, layout: Layout) -> DistributedMatrix:
    """``A`` restricted to the free DOFs; ``free_global``: this rank's free rows in A's numbering."""
    index = PETSc.IS().createGeneral(np.asarray(free_global, dtype=PETSc.IntType), comm=layout.comm)
    return DistributedMatrix(A.createSubMatrix(index, index), layout)
