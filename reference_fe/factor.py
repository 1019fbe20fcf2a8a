"""A serial MUMPS factorization of a scipy sparse matrix, solving many right-hand sides.

The reduction basis of the solid (reference_fe.cms) needs K^-1 applied to
hundreds of force directions (one per contact-node direction) and to the
shift-invert iterations of the eigen-solve. MUMPS (through PETSc) factorizes
the symmetric stiffness as L D L^T in about a quarter of SuperLU's LU time
and solves a block of right-hand sides at once (MatMatSolve, BLAS-3): on the
default blade mesh (36888 DOF) 40 right-hand sides take 0.46 s against
1.7 s with SuperLU.

The Newmark step operator of "fe" is not symmetric (Coriolis): there MUMPS
LU with METIS ordering keeps 21.1 M factor entries against SuperLU's 32 M
(COLAMD), factorizes in 1.1 s against 3.8 s, back-substitutes in 36 ms
against 43 ms, and condenses the 482 contact coordinates as one block in
1.7 s against 22 s column by column (SuperLU's own block solve: 56 s), on
the Fig. 8 case's step operator. The whole run with it:
benchmarks/bench_fe_transient.py --models fe --mumps.
"""

from __future__ import annotations

import dolfinx_solver  # noqa: F401  (must precede petsc4py)
import numpy as np
import scipy.sparse as sp
from petsc4py import PETSc


METIS_ORDERING = 5          # MUMPS ICNTL(7)


class MumpsFactor:
    """``solve(b)`` with ``A x = b`` for b of shape (n,) or (n, k).

    ``symmetric``: A symmetric positive definite (L D L^T); otherwise LU.
    """

    def __init__(self, A, symmetric: bool = True):
        A = sp.csr_matrix(A)
        self.n = A.shape[0]
        self._A = PETSc.Mat().createAIJ(size=A.shape, csr=(A.indptr, A.indices, A.data),
                                        comm=PETSc.COMM_SELF)
        self._A.assemble()
        self._A.setOption(PETSc.Mat.Option.SYMMETRIC, symmetric)
        self._ksp = PETSc.KSP().create(PETSc.COMM_SELF)
        self._ksp.setOperators(self._A)
        self._ksp.setType("preonly")
        pc = self._ksp.getPC()
        pc.setType("cholesky" if symmetric else "lu")
        pc.setFactorSolverType("mumps")
        pc.setFactorSetUpSolverType()
        pc.getFactorMatrix().setMumpsIcntl(7, METIS_ORDERING)
        self._ksp.setUp()
        self._factor = pc.getFactorMatrix()
        self._x, self._b = self._A.createVecs()

    def solve(self, b: np.ndarray) -> np.ndarray:
        b = np.asarray(b, dtype=float)
        if b.ndim == 1:
            self._b.setArray(b)
            self._ksp.solve(self._b, self._x)
            return self._x.getArray().copy()
        B = PETSc.Mat().createDense(b.shape, array=np.asfortranarray(b).copy(), comm=PETSc.COMM_SELF)
        X = PETSc.Mat().createDense(b.shape, comm=PETSc.COMM_SELF)
        X.setUp()
        B.assemble()
        X.assemble()
        self._factor.matSolve(B, X)
        out = X.getDenseArray().copy()
        B.destroy()
        X.destroy()
        return out


def mumps_lu(A):
    """``solve`` of a MUMPS LU of ``A`` (METIS): the "fe" model's Newmark step operator."""
    return MumpsFactor(A, symmetric=False).solve
