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
benchmarks/bench_fe_transient.py --models fe (--superlu compares).

What else was tried for that back-substitution (same operator, one right-hand
side, 2 MPI ranks, ms per solve; repeats vary by about 3 ms): METIS 19.9
(21.7 M factor entries), SCOTCH 19.2 (22.3 M), PORD 27.4 (20.0 M), QAMD 29.6
(25.2 M), parallel analysis with PT-SCOTCH 25.7 (23.5 M); block low-rank
factors (ICNTL(35) = 2) 18.7 at CNTL(7) = 1e-12 (residual 4e-10 instead of
1e-12) and 21.7 at 1e-14; SuperLU_DIST 32.4 (34.2 on one rank). On one
process MUMPS with METIS takes 27-31 ms. So METIS LU, without compression.

The shell's step operator (2D, 9993 DOF) is another matter: PORD keeps
1.37 M factor entries against METIS's 1.67 M and back-substitutes in
1.31 ms of CPU against 1.46 ms (one process, 7 alternated rounds of 200
solves, load 8; the solutions 4e-14 apart): :func:`mumps_lu` takes the
ordering, reference_fe.system picks it per model.
"""

from __future__ import annotations

import dolfinx_solver  # noqa: F401  (must precede petsc4py)
import numpy as np
import scipy.sparse as sp
from petsc4py import PETSc

from reference_fe.distributed import DistributedMatrix


METIS_ORDERING, PORD_ORDERING = 5, 4         # MUMPS ICNTL(7)


class MumpsFactor:
    """A MUMPS factorization: a shroud.core.linear_solvers.Factorization.

    ``solve(b)`` with ``A x = b`` for b of shape (n,) or (n, k). ``A``: scipy
    sparse (one process), or a reference_fe.distributed DistributedMatrix
    under mpirun: then MUMPS works on the ranks' rows and ``b`` and the
    solution are complete (replicated) on every rank. ``symmetric``: A
    symmetric positive definite (L D L^T); otherwise LU. ``close()`` (or a
    ``with`` block) destroys the PETSc objects, the factor among them: on
    the default solid that is 21 M entries, which would otherwise wait for
    the garbage collector.
    """

    def __init__(self, A, symmetric: bool = True, ordering: int = METIS_ORDERING):
        if isinstance(A, DistributedMatrix):
            self._A, self._layout, comm = A.mat, A.layout, A.mat.getComm()
        else:
            A = sp.csr_matrix(A)
            comm = PETSc.COMM_SELF
            self._A = PETSc.Mat().createAIJ(size=A.shape, csr=(A.indptr, A.indices, A.data), comm=comm)
            self._A.assemble()
            self._layout = None
        self.n = self._A.getSize()[0]
        self._owns_A = self._layout is None           # a distributed A belongs to the model
        self._A.setOption(PETSc.Mat.Option.SYMMETRIC, symmetric)
        self._ksp = PETSc.KSP().create(comm)
        self._ksp.setOperators(self._A)
        self._ksp.setType("preonly")
        pc = self._ksp.getPC()
        pc.setType("cholesky" if symmetric else "lu")
        pc.setFactorSolverType("mumps")
        pc.setFactorSetUpSolverType()
        pc.getFactorMatrix().setMumpsIcntl(7, ordering)
        self._ksp.setUp()
        self._factor = pc.getFactorMatrix()
        self._x, self._b = self._A.createVecs()

    def solve_rows(self, b_rows: np.ndarray) -> np.ndarray:
        """This rank's rows of x from this rank's rows of b, (rows,) or (rows, k) (no gather: the time
        loop's step; a block of right-hand sides is solved at once, MatMatSolve)."""
        if b_rows.ndim == 1:
            self._b.setArray(b_rows)
            self._ksp.solve(self._b, self._x)
            return self._x.getArray().copy()
        return block_solve(self._factor, self.n, b_rows, self._A.getComm())

    def _own(self, b: np.ndarray) -> np.ndarray:
        return b if self._layout is None else self._layout.own(b)

    def _gather(self, x: np.ndarray) -> np.ndarray:
        return x if self._layout is None else self._layout.gather(x)

    def close(self) -> None:
        """Destroy the solver, its factor and work vectors (and A when this object made it).

        The factor is destroyed by name: its Python handle holds a reference of its own, which petsc4py
        does not drop for objects on a parallel communicator until an explicit clean-up; destroying the
        solver alone left each factor alive under mpirun (0.45 GB per rank for each factorized harmonic
        of the full solid, reference_fe.harmonic).
        """
        for obj in (self._ksp, self._factor, self._x, self._b) + ((self._A,) if self._owns_A else ()):
            obj.destroy()

    def __enter__(self) -> "MumpsFactor":
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def solve(self, b: np.ndarray) -> np.ndarray:
        return self._gather(self.solve_rows(self._own(np.asarray(b, dtype=float))))


    def solve_sparse(self, B) -> np.ndarray:
        """``A^-1 B`` for a scipy sparse B (n, k), dense (n, k) out, on every rank.

        One process: MUMPS takes B as sparse right-hand sides (PETSc's
        transpose of the AIJ B^T), so the forward elimination skips the
        zeros: the 396 contact-force directions of the default solid in
        0.38 s of CPU against 1.42 s dense. Under mpirun: as ``solve`` of B dense.
        """
        if self._layout is not None:
            return self.solve(B.toarray())
        Bt = sp.csr_matrix(B.T)
        k = Bt.shape[0]
        Bt_mat = PETSc.Mat().createAIJ(size=Bt.shape, csr=(Bt.indptr, Bt.indices, Bt.data), comm=PETSc.COMM_SELF)
        Bt_mat.assemble()
        B_mat = PETSc.Mat().createTranspose(Bt_mat)
        out = np.empty((self.n, k), order="F")
        X = dense_on(out, (self.n, k), PETSc.COMM_SELF)
        self._factor.matSolve(B_mat, X)
        for obj in (Bt_mat, B_mat, X):
            obj.destroy()
        return out


def block_solve(factor: PETSc.Mat, n: int, b_rows: np.ndarray, comm) -> np.ndarray:
    """This rank's rows of A^-1 B from this rank's rows (rows, k) of a dense block B, with A (n x n)
    factored in ``factor`` (a MUMPS factor Mat): one MatMatSolve for the k right-hand sides."""
    rows, k = b_rows.shape
    sizes = ((rows, n), (k, k))
    B = dense_on(np.asfortranarray(b_rows, dtype=float).copy(), sizes, comm)
    out = np.empty((rows, k), order="F")
    X = dense_on(out, sizes, comm)
    factor.matSolve(B, X)
    B.destroy()
    X.destroy()
    return out


def dense_on(out: np.ndarray, sizes, comm) -> PETSc.Mat:
    """A PETSc dense Mat on the column-major array ``out`` itself, assembled: a block read from it
    or written into it with no copy (MUMPS's solutions land in the array returned: a copy of the 396
    contact directions' solutions cost 0.03-0.1 s of CPU)."""
    X = PETSc.Mat().createDense(sizes, array=out, comm=comm)
    X.assemble()
    return X


def mumps_lu(A, ordering: int = METIS_ORDERING) -> MumpsFactor:
    """A MUMPS LU of ``A`` (ICNTL(7) ``ordering``): a full model's Newmark step operator (called as ``solve``)."""
    return MumpsFactor(A, symmetric=False, ordering=ordering)
