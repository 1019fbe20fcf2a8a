"""Natural frequencies of the rotating solid blade, with and without Coriolis.

Without Coriolis (paper Eq. 1 with G = 0, D = 0), the generalized symmetric
problem

    (K_e + K_sigma + K_spin) phi = omega^2 M phi

is solved by SLEPc (Krylov-Schur, shift-invert about 0, MUMPS L D L^T of
K: the pencil is symmetric). With Coriolis, the gyroscopic quadratic problem

    (lambda^2 M + lambda G + K) x = 0,   G^T = -G,   lambda = +/- i omega

is solved by Rayleigh-Ritz on the undamped modes enriched with their
static Coriolis responses, V = [Phi, K^-1 G Phi] (M-orthonormalized): the
reduced problem (lambda^2 I + lambda V^T G V + V^T K V) y = 0 is small and
dense, x = V y. Phi holds GYROSCOPIC_EXTRA undamped modes above the asked
ones, so that a mode's Coriolis partner just above the asked range is in
the basis with its dynamics, not only statically; K^-1 G Phi carries the
coupling through the modes far above (the axial ones, through which
Coriolis softens the in-plane bending). The same factor of K serves the
shift-invert and K^-1 G Phi: one factorization for both problems. Against
SLEPc's full gyroscopic solve (PEP, TOAR, shift-invert, tolerance 1e-10):
8 modes of the default blade at 10000 r/min within 5e-8, at a third of its
solves (tests/test_fe_modal.py holds a second method to 1e-7). Clamped
rows carry diag 1 on K and 0 on M and G: they only add infinite
eigenvalues, far from the shift, and stay zero in every basis vector.

Modes are named by the kinematics of the tip section (shroud.core.modes): flap =
displacement of the tip-section centre along e_v(L), chord = along e_w(L),
axial = along X, torsion = rotation about X times b/2 (the chord-edge
displacement it causes). The tip-section centre (x = L on the blade axis) is
where the beam model's v_L, w_L live; the shroud box above it (t_s/2
further out) is part of the solid. Each gyroscopic mode inherits the label
of the undamped mode it is paired with (MAC, one-to-one: an optimal
assignment, shroud.core.modes.pair_by_mac), so the Coriolis shift of every
mode is reported by name.

Everything is PETSc/SLEPc-native: the same code runs serially or under
``mpirun -n P``; rank-local tip values are summed over ranks.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np
from mpi4py import MPI
from slepc4py import SLEPc

from meshes.blade import section_frame
from reference_fe.factor import block_solve, dense_on
from reference_fe.solid import FEModel, RotatingOperators, lu_solver
from shroud.base.log import Progress, info
from shroud.core.modes import label_modes, pair_by_mac
from shroud.params import Parameters
from shroud.core.results import ModalResult, Mode

GYROSCOPIC_EXTRA = 4     # undamped modes above the asked ones in the gyroscopic Ritz basis


@dataclass(frozen=True)
class SolidModes:
    """Modes of the solid at one speed, in frequency order of the undamped problem."""

    rpm: float
    dofs: int
    f_undamped: np.ndarray          # (k,) Hz, G = 0
    f_coriolis: np.ndarray | None   # (k,) Hz of the gyroscopic mode matched to each, or None
    damping_coriolis: np.ndarray | None  # (k,) its damping ratio -Re lambda / |lambda|
    mac_coriolis: np.ndarray | None  # (k,) MAC of that match
    labels: tuple[str, ...]
    participation: tuple[dict[str, float], ...]
    tip: np.ndarray                 # (k, 4) tip components [flap, chord, torsion*b/2, axial], m
    vectors: tuple                  # undamped mode shapes (PETSc Vecs, mass-normalized)
    operators: RotatingOperators
    solve_s: float                  # wall time of operators + eigen-solves, s

    @property
    def coriolis_shift(self) -> np.ndarray | None:
        """Relative frequency change due to Coriolis, (f_cor - f) / f."""
        if self.f_coriolis is None:
            return None
        return self.f_coriolis / self.f_undamped - 1.0


def tip_components(model: FEModel, xr, xi=None) -> np.ndarray:
    """[flap, chord, torsion * c(L)/2, axial] of one (possibly complex) shape, m.

    Nodal values at the tip nodes (FEModel.tip_dofs): centre c and
    c -/+ (c(L)/4) e_w(L) (c(L) the tip chord, b for the rectangle).
    A twist theta about X moves c +/- d e_w by
    -/+ theta d e_v (X x e_w = -e_v), so theta = -(u_+ - u_-).e_v / (2 d).
    """
    spec = model.spec
    e_v, e_w = section_frame(spec.beta_tip)
    centre, minus, plus = model.gather_tip(xr, xi)
    d = 0.25 * spec.tip_chord
    theta = -((plus - minus) @ e_v) / (2.0 * d)
    return np.array([centre @ e_v, centre @ e_w, theta * 2.0 * d, centre[0]])


def _undamped(ops: RotatingOperators, n_modes: int, ksp):
    """(f Hz, mass-normalized shapes) of the ``n_modes`` lowest undamped modes; ``ksp`` factors K."""
    return undamped_modes(ops.K, ops.M, ops.model.comm, n_modes, ksp)


def undamped_modes(K, M, comm, n_modes: int, ksp):
    """(f Hz, mass-normalized shapes) of the ``n_modes`` lowest modes of the symmetric pencil (K, M)
    (PETSc Mats); ``ksp`` factors K."""
    eps = SLEPc.EPS().create(comm)
    eps.setOptionsPrefix("shroud_modal_")
    eps.setOperators(K, M)
    eps.setProblemType(SLEPc.EPS.ProblemType.GHEP)
    eps.setType(SLEPc.EPS.Type.KRYLOVSCHUR)
    eps.setDimensions(nev=n_modes)
    eps.setTarget(0.0)
    eps.setWhichEigenpairs(SLEPc.EPS.Which.TARGET_REAL)
    eps.setTolerances(tol=1e-8, max_it=200)     # relative residual: omega^2 to ~1e-16 (symmetric)
    st = eps.getST()
    st.setType(SLEPc.ST.Type.SINVERT)
    st.setShift(0.0)
    st.setKSP(ksp)             # K - 0 M = K: the factor made once serves
    eps.setFromOptions()
    eps.solve()
    nconv = eps.getConverged()
    pairs = []
    for i in range(nconv):
        x = M.createVecRight()
        pairs.append((eps.getEigenpair(i, x).real, x))
    eps.destroy()
    keep = lowest_vibration_modes([lam for lam, _ in pairs], n_modes, "SLEPc EPS")
    pairs = [pairs[i] for i in keep]
    vectors = []
    for _, x in pairs:       # mass-normalize: x^T M x = 1
        Mx = M.createVecLeft()
        M.mult(x, Mx)
        x.scale(1.0 / np.sqrt(x.dot(Mx)))
        vectors.append(x)
    return np.sqrt([p[0] for p in pairs]) / (2 * np.pi), vectors


def lowest_vibration_modes(omega2, n_modes: int, solver: str) -> list[int]:
    """Indices of the ``n_modes`` lowest finite, positive omega^2 (rad^2/s^2) among a solver's pairs.

    Counted after the filtering, so a solve that converged enough pairs but
    too few vibration modes among them fails here instead of returning fewer.

    >>> lowest_vibration_modes([4.0, -1e-9, 1.0, float("inf")], 2, "EPS")
    [2, 0]
    >>> lowest_vibration_modes([4.0, -1e-9, float("inf")], 2, "EPS")
    Traceback (most recent call last):
    ...
    RuntimeError: EPS converged 3 eigenpairs but only 1 vibration modes (finite omega^2 > 0) of the 2 asked
    """
    good = [i for i, lam in enumerate(omega2) if np.isfinite(lam) and lam > 0]
    if len(good) < n_modes:
        raise RuntimeError(f"{solver} converged {len(omega2)} eigenpairs but only {len(good)} vibration modes "
                           f"(finite omega^2 > 0) of the {n_modes} asked")
    return sorted(good, key=lambda i: omega2[i])[:n_modes]


def _stiffness_factor(ops: RotatingOperators):
    """(KSP, factor Mat): MUMPS L D L^T of K (symmetric: K_e + K_sigma + K_spin, clamped rows diag 1).

    The factor Mat is held apart: the eigen-solver's spectral transformation
    resets the KSP when it is destroyed, the factor lives on for K^-1 G Phi.
    """
    ksp = lu_solver(ops.K, ops.model.comm, "shroud_modal_k_", symmetric=True)
    ksp.setUp()
    return ksp, ksp.getPC().getFactorMatrix()


def _block_product(A, V: np.ndarray) -> np.ndarray:
    """This rank's rows of A V for this rank's rows (rows, k) of a dense block V: one pass over A
    (MatMatMult) instead of k products with vectors, each of which reads all of A's entries."""
    rows, k = V.shape
    D = dense_on(np.asfortranarray(V).copy(), ((rows, A.getSize()[1]), (k, k)), A.getComm())
    AD = A.matMult(D)
    out = AD.getDenseArray().copy()
    D.destroy()
    AD.destroy()
    return out


def _gyroscopic(ops: RotatingOperators, shapes, factor):
    """Gyroscopic modes by Rayleigh-Ritz on [Phi, K^-1 G Phi]: (f Hz, damping ratio, MAC against Phi).

    ``shapes``: the undamped modes Phi (mass-normalized Vecs); ``factor``:
    the factored K (a MUMPS factor Mat). One mode per conjugate pair (Im
    lambda > 0), in ascending frequency; lambda = -zeta omega + i omega
    sqrt(1 - zeta^2): zeta = -Re lambda / |lambda| (0 to round-off: the
    reduced problem is gyroscopic too). MAC[i, j] between shape i and mode
    j (complex, xr + i xi), from this rank's rows summed over the ranks.
    """
    K, G, M = ops.K, ops.G, ops.M
    comm = ops.model.comm
    n = K.getSize()[0]
    Phi = np.column_stack([phi.getArray(readonly=True) for phi in shapes])   # this rank's rows
    V = np.hstack([Phi, block_solve(factor, n, _block_product(G, Phi), comm)])
    Mb, Kb, Gb = (comm.allreduce(V.T @ _block_product(A, V), op=MPI.SUM) for A in (M, K, G))
    scale = 1.0 / np.sqrt(np.diag(Mb))               # unit M-norm first: K^-1 G phi is ~1e-6 of phi
    Mb, Kb, Gb = (scale[:, None] * A * scale[None, :] for A in (Mb, Kb, Gb))
    w, U = np.linalg.eigh(Mb)
    independent = w > 1e-10 * w.max()
    T = U[:, independent] / np.sqrt(w[independent])   # V T is M-orthonormal
    Kr, Gr = T.T @ Kb @ T, T.T @ Gb @ T
    m = Kr.shape[0]
    lam, Y = np.linalg.eig(np.block([[np.zeros((m, m)), np.eye(m)], [-Kr, -Gr]]))
    up = np.flatnonzero(lam.imag > 0)
    up = up[np.argsort(lam[up].imag)]
    X = V @ (scale[:, None] * (T @ Y[:m, up]))          # this rank's rows of the complex shapes
    cross = comm.allreduce(Phi.T @ X, op=MPI.SUM)
    norms = np.outer(comm.allreduce(np.sum(Phi**2, axis=0), op=MPI.SUM),
                     comm.allreduce(np.sum(np.abs(X)**2, axis=0), op=MPI.SUM))
    return lam[up].imag / (2 * np.pi), -lam[up].real / np.abs(lam[up]), np.abs(cross)**2 / norms


def operators_of(kind: str):
    """``(params, rpm) -> RotatingOperators`` of the FE model ``kind``: "fe" (the solid) or "shell"."""
    if kind == "shell":
        from reference_fe.shell import rotating_operators
    else:
        from reference_fe.solid import rotating_operators
    return rotating_operators


def solve_modes(params: Parameters, rpm: float | None = None, n_modes: int = 6,
                coriolis: bool = True, kind: str = "fe") -> SolidModes:
    """Undamped (and gyroscopic) modes of the prestressed solid (or shell: ``kind``) at ``rpm``."""
    rpm = params.speed.rpm if rpm is None else float(rpm)
    t0 = time.perf_counter()
    progress = Progress(f"FE modes at {rpm:g} r/min", 3)
    ops = operators_of(kind)(params, rpm)
    progress.update(1)
    gyroscopic = coriolis and ops.omega > 0
    ksp, factor = _stiffness_factor(ops)
    f0, shapes = _undamped(ops, n_modes + (GYROSCOPIC_EXTRA if gyroscopic else 0), ksp)
    f0, vectors = f0[:n_modes], shapes[:n_modes]
    progress.update(2)
    model = ops.model
    tip = np.array([tip_components(model, x) for x in vectors]).real
    labels, parts = label_modes(tip)
    f_cor = mac_cor = zeta_cor = None
    if gyroscopic:
        f_gyro, zeta_gyro, macs = _gyroscopic(ops, shapes, factor)
        macs = macs[:n_modes, :len(shapes)]
        pick = pair_by_mac(macs)
        f_cor, zeta_cor = f_gyro[pick], zeta_gyro[pick]
        mac_cor = macs[np.arange(n_modes), pick]
    elif coriolis:
        f_cor, mac_cor = f0.copy(), np.ones_like(f0)      # no rotation, no Coriolis
        zeta_cor = np.zeros_like(f0)
    ksp.destroy()
    factor.destroy()
    progress.update(3)
    elapsed = time.perf_counter() - t0
    progress.done()
    shown = f_cor if f_cor is not None else f0           # the variant a Coriolis-on result reports
    variant = "with Coriolis" if f_cor is not None else "without Coriolis"
    info(f"FE modes at {rpm:g} r/min, {variant}: " + ", ".join(f"{l} {f:.2f} Hz" for l, f in zip(labels, shown)))
    return SolidModes(rpm=rpm, dofs=model.global_dofs, f_undamped=f0, f_coriolis=f_cor,
                      damping_coriolis=zeta_cor, mac_coriolis=mac_cor, labels=tuple(labels), participation=tuple(parts),
                      tip=tip, vectors=tuple(vectors), operators=ops, solve_s=elapsed)


def modal_analysis(params: Parameters, rpm: float | None = None, n_modes: int = 6,
                   coriolis: bool = True, kind: str = "fe") -> ModalResult:
    """shroud.analysis.api entry: the solid's (shell's) modes as a ModalResult (Coriolis frequencies if asked)."""
    modes = solve_modes(params, rpm, n_modes, coriolis, kind)
    f = modes.f_coriolis if coriolis else modes.f_undamped
    order = np.argsort(f, kind="stable")
    return ModalResult(model=kind, rpm=modes.rpm, dofs=modes.dofs, elapsed_s=modes.solve_s,
                       coriolis=coriolis,
                       modes=tuple(Mode(f_hz=float(f[i]), label=modes.labels[i],
                                        participation=modes.participation[i],
                                        damping_ratio=float(modes.damping_coriolis[i]) if coriolis else None)
                                   for i in order))
