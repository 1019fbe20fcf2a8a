"""The MUMPS factorization of the solid's operators (dense and sparse right-hand sides), against scipy's direct solve."""

import numpy as np
import pytest
import scipy.sparse as sp
import scipy.sparse.linalg as spla

pytestmark = pytest.mark.fe

pytest.importorskip("dolfinx_solver")


def step_operator(n: int, seed: int):
    """K + a skew (gyroscopic) part: structurally symmetric, not symmetric, like K_eff with Coriolis."""
    rng = np.random.default_rng(seed)
    K = sp.diags([np.full(n, 4.0), -np.ones(n - 1), -np.ones(n - 1), -np.ones(n - 7), -np.ones(n - 7)],
                 [0, 1, -1, 7, -7])
    g = rng.normal(size=n - 7)
    G = sp.diags([g, -g], [7, -7])
    return sp.csr_matrix(K + 0.5 * G), sp.csr_matrix(K)


@pytest.mark.parametrize("symmetric", [False, True])
def test_vector_and_block_solves_match_a_direct_solve(symmetric):
    from reference_fe.factor import MumpsFactor
    A_eff, K = step_operator(400, 3)
    A = K if symmetric else A_eff
    rng = np.random.default_rng(4)
    B = rng.normal(size=(400, 5))
    direct = spla.spsolve(sp.csc_matrix(A), B)
    solver = MumpsFactor(A, symmetric=symmetric)
    np.testing.assert_allclose(solver.solve(B), direct, rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(solver.solve(B[:, 2]), direct[:, 2], rtol=1e-10, atol=1e-12)
    # sparse right-hand sides (unit nodal forces, as the contact directions W^T)
    S = sp.csc_matrix((np.ones(3), ([5, 200, 399], [0, 1, 2])), shape=(400, 3))
    np.testing.assert_allclose(solver.solve_sparse(S), spla.spsolve(sp.csc_matrix(A), S.toarray()),
                               rtol=1e-10, atol=1e-12)
