"""The full solid in the frequency domain, condensed exactly on its contact coordinates per harmonic.

Harmonic k = 0..H of the solid's steady state (paper Eq. 9 for the 3D solid,
reference_fe.system) sees the complex dynamic stiffness

    Z_k = K - (k omega)^2 M + i k omega C,     C = alpha M + beta K + G,

with the very operators the time domain integrates at that speed (K with
K_sigma and K_spin in Omega^2, G in Omega, Rayleigh damping on the first two
undamped frequencies at the speed; omega = ke Omega). The contact acts only
on y = W q, so the harmonic balance needs of the solid only, per harmonic,

    R_k = W Z_k^-1 W^T      the receptance on the contact coordinates (m x m),
    W Z_k^-1 F_k            the load's motion of them (F_1 = -i f_aero, F_0 = f_const),
    tip Z_k^-1 [W^T, F_k]   the tip rows' response to both,

i.e. m + 1 right-hand sides per harmonic, exact (no modal truncation). The
core (shroud.core.harmonic_balance.condensed) turns these solved columns
into the condensed dynamic stiffness R_k^-1 on which the one Newton / AFT /
contact law runs unchanged.

PETSc here is built for real scalars, so Z_k x = b is solved in its real
block form

    [[A, -B], [B, A]] [x_r; x_i] = [b_r; b_i],   A = K - (k omega)^2 M,  B = k omega C,

factorized by MUMPS LU (reference_fe.factor.MumpsFactor, METIS); k = 0 is
the symmetric K alone (L D L^T). Under mpirun the block matrix keeps the
solid's row distribution: each rank holds its real rows followed by its
imaginary rows (the layout a PETSc MATNEST of the four blocks would have),
solves its rows of all right-hand sides at once, and the small products
W x, tip x are summed over the ranks; no vector of the solid is gathered.

Units: SI (m, N, rad/s).
"""

from __future__ import annotations

import dataclasses
import json
import time
from dataclasses import dataclass

import dolfinx_solver  # noqa: F401  (must precede petsc4py)
import numpy as np
import scipy.sparse as sp
from mpi4py import MPI
from petsc4py import PETSc

from reference_fe.distributed import DistributedMatrix, Layout
from reference_fe.factor import MumpsFactor
from shroud.base.errors import InputError
from shroud.base.log import info
from shroud.core import harmonic_balance as hb
from shroud.core.system import StructuralSystem
from shroud.params import Parameters


@dataclass(frozen=True)
class _Rows:
    """This rank's rows of the solid's operators and where every rank's rows lie."""

    M: sp.csr_matrix          # (rows, n)
    C: sp.csr_matrix
    K: sp.csr_matrix
    counts: np.ndarray        # (P,) rows of each rank
    rank: int
    comm: object              # petsc4py communicator of the operators
    layout: Layout | None     # the solid's row layout (None: one process)

    @property
    def start(self) -> int:
        return int(self.counts[:self.rank].sum())

    @property
    def stop(self) -> int:
        return self.start + int(self.counts[self.rank])

    @property
    def n(self) -> int:
        return int(self.counts.sum())

    def sum(self, part: np.ndarray) -> np.ndarray:
        """Sum over the ranks of each rank's (complex) ``part``."""
        if self.layout is None:
            return part
        return self.layout.sum(part.real) + 1j * self.layout.sum(part.imag)


def _rows(system: StructuralSystem) -> _Rows:
    layout = system.layout
    if layout is None:
        return _Rows(M=sp.csr_matrix(system.M), C=sp.csr_matrix(system.C), K=sp.csr_matrix(system.K),
                     counts=np.array([system.dofs]), rank=0, comm=PETSc.COMM_SELF, layout=None)
    return _Rows(M=system.M.row_block, C=system.C.row_block, K=system.K.row_block, counts=layout.counts,
                 rank=layout.comm.rank, comm=system.K.mat.getComm(), layout=layout)


def _block_operator(rows: _Rows, A: sp.csr_matrix, B: sp.csr_matrix) -> DistributedMatrix:
    """The real block form [[A, -B], [B, A]] of A + i B, rows spread as the solid's (real rows, then imaginary).

    Rank r holds block rows 2 start_r .. 2 stop_r: its real rows, then its
    imaginary rows; so column j (real part) sits at j + start_r(j) and its
    imaginary part at j + stop_r(j), r(j) the rank owning row j.
    """
    owner = np.repeat(np.arange(rows.counts.size), rows.counts)
    starts = np.concatenate([[0], np.cumsum(rows.counts)[:-1]])
    j = np.arange(rows.n)
    column = np.concatenate([j + starts[owner], j + starts[owner] + rows.counts[owner]])
    local = sp.vstack([sp.hstack([A, -B]), sp.hstack([B, A])], format="csr")
    local = sp.csr_matrix((local.data, column[local.indices], local.indptr), shape=local.shape)
    local.sort_indices()
    size = (local.shape[0], 2 * rows.n)
    mat = PETSc.Mat().createAIJ(size=(size, size), comm=rows.comm,
                                csr=(local.indptr.astype(PETSc.IntType), local.indices.astype(PETSc.IntType),
                                     local.data))
    mat.assemble()
    comm = rows.layout.comm if rows.layout is not None else MPI.COMM_SELF
    return DistributedMatrix(mat, Layout.of(comm, local.shape[0]))


def _solve_harmonic(rows: _Rows, system: StructuralSystem, k: int, omega: float, b: np.ndarray) -> np.ndarray:
    """This rank's rows of Z_k^-1 b (complex) from its rows of b (complex, (rows, c))."""
    if k == 0:                                          # Z_0 = K: real, symmetric; b real (W^T, f_const)
        with MumpsFactor(system.K, symmetric=True) as lu:
            return lu.solve_rows(b.real).astype(complex)
    w = k * omega
    Z = _block_operator(rows, rows.K - w**2 * rows.M, w * rows.C)
    try:
        with MumpsFactor(Z, symmetric=False) as lu:
            x = lu.solve_rows(np.vstack([b.real, b.imag]))
    finally:
        Z.mat.destroy()
    r = b.shape[0]
    return x[:r] + 1j * x[r:]


@dataclass(frozen=True)
class SolvedColumns:
    """Per harmonic k = 0..H: W Z_k^-1 [W^T, F_k] (H+1, m, m+1) and tip Z_k^-1 [W^T, F_k] (H+1, 2, m+1)."""

    WS: np.ndarray
    tipS: np.ndarray
    elapsed_s: float


def solved_columns(system: StructuralSystem, H: int) -> SolvedColumns:
    """The solid's responses on its contact coordinates and tip rows to unit contact forces and to the load.

    ``system``: the "fe" model at one speed (reference_fe.system.full_system),
    with contact elements; H >= 0 harmonics of omega = system.omega_e.
    """
    t0 = time.perf_counter()
    rows = _rows(system)
    W, tip = sp.csr_matrix(system.contact.W), sp.csr_matrix(system.tip)
    m = W.shape[0]
    F = hb.load_harmonics(system, H)
    Wc, tipc = W[:, rows.start:rows.stop], tip[:, rows.start:rows.stop]
    WTrows = Wc.T.toarray()
    WS = np.empty((H + 1, m, m + 1), complex)
    tipS = np.empty((H + 1, 2, m + 1), complex)
    for k in range(H + 1):
        b = np.hstack([WTrows, F[k, rows.start:rows.stop, None]])
        x = _solve_harmonic(rows, system, k, system.omega_e, b)
        WS[k] = rows.sum(Wc @ x)
        tipS[k] = rows.sum(tipc @ x)
        info(f"full solid, harmonic {k} of {H}: {m + 1} right-hand sides on {system.dofs} DOF "
             f"({2 if k else 1} x real), {time.perf_counter() - t0:.1f} s so far")
    return SolvedColumns(WS=WS, tipS=tipS, elapsed_s=time.perf_counter() - t0)


def linear_harmonics(system: StructuralSystem, H: int) -> hb.LinearHarmonics:
    """The full solid's linear part condensed on its contact coordinates (the core's LinearHarmonics)."""
    cols = solved_columns(system, H)
    return hb.condensed(system.omega_e, cols.WS, cols.tipS)


_KEPT: dict[str, tuple] = {}       # the last speeds' systems and condensations, by what shapes them
KEEP = 2


def condensed_at(params: Parameters, rpm: float, H: int,
                 kind: str = "fe") -> tuple[StructuralSystem, hb.LinearHarmonics]:
    """The "fe" (or "shell": ``kind``) model at ``rpm`` (r/min) and its linear part condensed on the
    contact coordinates.

    Kept in memory by exactly what shapes them (mesh, material, speed, damping,
    load, H; not the contact law's kn, kt, mu, N0, which act on the condensed
    coordinates only), so the cases of a study at one speed share one
    condensation. The model registry's ``linear_harmonics`` hook of "fe" and "shell".
    """
    from reference_fe.system import full_system, reduction_inputs
    at = params.updated({"speed.rpm": float(rpm)})
    inputs = reduction_inputs(at, rpm, kind)
    key = json.dumps({"kind": kind, "mesh": inputs["mesh"], "material": inputs["material"], "rpm": float(rpm),
                      "contact": inputs["contact"], "damping": dataclasses.asdict(params.damping),
                      "load": dataclasses.asdict(params.load), "H": int(H)}, sort_keys=True)
    if key not in _KEPT:
        if len(_KEPT) >= KEEP:
            _release(_KEPT.pop(next(iter(_KEPT)))[0])
        system = full_system(at, kind)
        if system.contact is None:
            raise InputError("contact.enabled", "the full solid is condensed on its contact coordinates; "
                                                "allowed: contact enabled on a shrouded blade")
        _KEPT[key] = (system, linear_harmonics(system, H))
    return _KEPT[key]


def _release(system: StructuralSystem) -> None:
    """Free a dropped system's PETSc objects: petsc4py leaves objects on a parallel communicator to an
    explicit, collective clean-up instead of freeing them when Python lets them go."""
    if system.layout is not None:
        comm = system.K.mat.getComm()
        del system
        PETSc.garbage_cleanup(comm)
