"""Modes per nodal diameter of the solid sector of blade and flexible disk (docs/disk.md).

The sector (meshes.disk: blade, shroud, disk annulus of angle 2 pi / N, bore
clamped) is assembled once with real PETSc as the clamped blade is
(reference_fe.solid: paper Eq. 1 term by term, the rotating-frame forms at
1 rad/s) and then reduced per nodal diameter k by the cyclic constraint of
geometry.md, "The disk": each node h of the side theta = +pi/N is the node l
of the side -pi/N turned by phi = 2 pi / N, and

    u_h = exp(i k phi) R(phi) u_l,        u = T_k q,   q = (interior, low side) DOFs,

T_k sparse (identity on q's DOFs, the 3 x 3 blocks exp(i k phi) R on the
high side's rows, zero rows on the clamped bore). The sector's operators of
nodal diameter k are T_k^H A T_k (Hermitian for K, M; skew-Hermitian for
the Coriolis G), complex; with T_k = T_I + exp(i k phi) T_H they are
P + cos(k phi) S + i sin(k phi) D with P, S, D real and reduced once for
every k (CyclicParts), D only on the rows coupled to the high side. Real
PETSc factors their real 2-copy form [[Re, -Im], [Im, Re]] (MUMPS, one
symbolic analysis for every 0 < k < N/2: the pattern is the same); the
modes come from SLEPc for the real k = 0, N/2 and from ARPACK on the complex
Hermitian pencil for the others (each frequency once). (scipy's complex
SuperLU and ARPACK on the complex form took 170-210 s and 11 GB per nodal
diameter on the 87 447-DOF N = 4 sector, order 2, size 3.5 mm.)

Prestress: the static centrifugal state of the whole sector, disk included,
is the k = 0 one, K_e,0 q0 = T_0^T f_c (T_0 real); sigma0 of u0 = T_0 q0
gives the geometric stiffness K_sigma, so K(Omega) = K_e + Omega^2
(K_sigma1 + K_spin1) exactly as the clamped blade's (linear prestress).
With Coriolis, per k the gyroscopic modes come by Rayleigh-Ritz on
[Phi_k, K_k^-1 G_k Phi_k] (reference_fe.modal's basis; the same factor of
K_k serves both), frequencies lambda = i omega with omega > 0 (the mirror
nodal diameter N - k has the others, shroud.core.cyclic.modes).

Modes are labelled by the tip section's motion (|flap|, |chord|,
|torsion b/2|, |axial| of the complex shape). ``disk.E_factor`` scales the
disk's E (and its prestress) only: 1000 is the rigid-disk limit. One
process: the sector is assembled and solved on MPI.COMM_SELF, T_k^H A T_k
by scipy (under mpirun every rank solves it alone). SI units.
"""

from __future__ import annotations

import functools
import math
import time
from dataclasses import dataclass

import dolfinx_solver  # noqa: F401  (must precede dolfinx / petsc4py)
import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
import ufl
from dolfinx import fem
from mpi4py import MPI
from petsc4py import PETSc
from scipy.spatial import cKDTree

from meshes.disk import CYCLIC_HIGH, CYCLIC_LOW, DISK, DiskSpec, rotation_z, sector_mesh_file
from meshes.spec import CONTACT_SIDE1, CONTACT_SIDE2, ROOT, shroud_frame, tip_points
from reference_fe.contact_faces import face_nodes
from reference_fe.modal import GYROSCOPIC_EXTRA, lowest_vibration_modes, tip_components, undamped_modes
from reference_fe.solid import (SolidModel, _dx, _tip_dofs, _unit_forms, assemble_matrix, assemble_vector,
                                epsilon, lu_solver, read_mesh, sigma)
from shroud.base.log import Progress, info
from shroud.core.cyclic import modes as gyroscopic_modes
from shroud.core.cyclic import nodal_diameters
from shroud.core.modes import label_modes
from shroud.core.results import ModalResult, Mode
from shroud.params import Material, Parameters


@dataclass(frozen=True, eq=False)      # identity hash: one per process and mesh
class Sector:
    """The sector's solid and its unit-speed operators as scipy CSR on all DOFs (clamped rows included)."""

    model: SolidModel
    low: np.ndarray        # (p,) node (block) of the side -pi/N paired with
    high: np.ndarray       # (p,) the node of the side +pi/N it turns into, both unclamped
    clamped: np.ndarray    # unrolled DOFs of the bore
    M: sp.csr_matrix
    K_e: sp.csr_matrix
    K_rot1: sp.csr_matrix  # K_sigma + K_spin at 1 rad/s (k = 0 prestress)
    G1: sp.csr_matrix      # Coriolis at 1 rad/s
    f_c1: np.ndarray       # centrifugal load at 1 rad/s, N (zero on the bore)
    contact: "ShroudPairs | None" = None   # the contact faces' nodes, side 2 paired with side 1
    stiffness: object = None   # DG0 Function: E / material.E per cell (disk.E_factor on the disk)

    @property
    def pitch(self) -> float:
        return self.model.spec.pitch

    def transformation(self, nd: int) -> sp.csr_matrix:
        """T_k (n_all, n_reduced), complex: u = T_k q under the constraint of nodal diameter ``nd``."""
        T_I, T_H = self.transformation_parts
        return (T_I + np.exp(1j * nd * self.pitch) * T_H).tocsr()

    @functools.cached_property
    def transformation_parts(self) -> tuple[sp.csr_matrix, sp.csr_matrix]:
        """(T_I, T_H), real: T_k = T_I + exp(i k pitch) T_H (:func:`transformation_parts`)."""
        return transformation_parts(self.M.shape[0], self.clamped, self.low, self.high, self.pitch)

    @functools.lru_cache(maxsize=2)
    def stiffness_parts(self, omega2: float) -> "CyclicParts":
        """K_e + omega2 K_rot1 (omega2 in rad^2/s^2) split as :class:`CyclicParts`, kept for the sweep over k."""
        return self.reduced["K_e"].plus(self.reduced["K_rot1"], omega2)

    @functools.cached_property
    def reduced(self) -> dict[str, "CyclicParts"]:
        """K_e, K_rot1, M, G1 split once for every nodal diameter (:class:`CyclicParts`)."""
        T_I, T_H = self.transformation_parts
        return {name: CyclicParts.of(getattr(self, name), T_I, T_H) for name in ("K_e", "K_rot1", "M", "G1")}


def transformation_parts(n: int, clamped: np.ndarray, low: np.ndarray, high: np.ndarray,
                         pitch: float) -> tuple[sp.csr_matrix, sp.csr_matrix]:
    """(T_I, T_H), both (n, n_reduced) and real, of T_k = T_I + exp(i k pitch) T_H: T_I the identity on the
    kept DOFs (neither ``clamped`` nor on the ``high`` nodes), T_H the blocks R(pitch) taking each low node l
    to the high node h paired with it (u_h = exp(i k pitch) R(pitch) u_l)."""
    eliminated = np.zeros(n, dtype=bool)
    eliminated[clamped] = True
    eliminated[(3 * high[:, None] + np.arange(3)).ravel()] = True
    kept = np.flatnonzero(~eliminated)
    column = np.full(n, -1, dtype=np.int64)
    column[kept] = np.arange(kept.size)
    rows = (3 * high[:, None, None] + np.arange(3)[None, :, None]).repeat(3, axis=2)
    cols = column[3 * low[:, None, None] + np.arange(3)[None, None, :]].repeat(3, axis=1)
    values = np.broadcast_to(rotation_z(pitch), rows.shape)
    T_I = sp.csr_matrix((np.ones(kept.size), (kept, np.arange(kept.size))), shape=(n, kept.size))
    T_H = sp.csr_matrix((values.ravel(), (rows.ravel(), cols.ravel())), shape=(n, kept.size))
    return T_I, T_H


@dataclass(frozen=True)
class CyclicParts:
    """A real operator A of the sector (on all its DOFs) reduced for every nodal diameter at once:
    with T_k = T_I + e T_H (e = exp(i k pitch)),

        T_k^H A T_k = P + cos(k pitch) S + i sin(k pitch) D,
        P = T_I^T A T_I + T_H^T A T_H,   S = Q + Q',   D = Q - Q',   Q = T_I^T A T_H,   Q' = T_H^T A T_I,

    all real. D lives on the rows and columns coupled to the high side only, so the real 2-copy form
    [[Re, -Im], [Im, Re]] is two copies of the sector joined there (Im taken as T^H A T's imaginary part,
    every entry stored, coupled the copies everywhere: 14.2 M nonzeros and 59 M factor entries on the
    24-blade sector, 3.5 mm, against 7.3 M and 35 M)."""

    P: sp.csr_matrix
    S: sp.csr_matrix
    D: sp.csr_matrix

    @classmethod
    def of(cls, A: sp.csr_matrix, T_I: sp.csr_matrix, T_H: sp.csr_matrix) -> "CyclicParts":
        Q, Qt = T_I.T @ (A @ T_H), T_H.T @ (A @ T_I)
        return cls((T_I.T @ (A @ T_I) + T_H.T @ (A @ T_H)).tocsr(), (Q + Qt).tocsr(), (Q - Qt).tocsr())

    def plus(self, other: "CyclicParts", weight: float) -> "CyclicParts":
        """self + weight other."""
        return CyclicParts(self.P + weight * other.P, self.S + weight * other.S, self.D + weight * other.D)

    def at(self, nd: int, pitch: float) -> tuple[sp.csr_matrix, sp.csr_matrix]:
        """(Re, Im) of T_k^H A T_k for nodal diameter ``nd``; Im exactly zero for k = 0 and N/2 (sin = 0)."""
        if nd == 0:
            return self.P + self.S, None
        angle = nd * pitch
        if abs(math.sin(angle)) < 1e-12:         # k = N/2: cos = -1
            return self.P - self.S, None
        return self.P + math.cos(angle) * self.S, math.sin(angle) * self.D


@dataclass(frozen=True)
class ShroudPairs:
    """The nodes of the shroud's contact faces, side 2's node e facing side 1's node e (by position in
    the face plane), with the consistent area share ``weight`` of each (summing to 1 per face)."""

    side1: np.ndarray      # (P, 3) unrolled DOFs
    side2: np.ndarray      # (P, 3)
    weight: np.ndarray     # (P,)
    directions: np.ndarray  # (2, 3): e_vs (normal), e_ws (friction direction)

    def springs(self, n: int, nd: int, pitch: float, kn: float, kt: float) -> sp.csr_matrix:
        """B^H D B (n, n), Hermitian: the stuck springs kn, kt (N/m per face, by area shares) joining side 2
        to side 1 of the next sector, whose own-frame displacements are exp(i k pitch) this one's
        (geometry.md, "Moving neighbours": each blade in its own sector frame)."""
        P = self.weight.size

        def along(dofs):          # (2P, n): each node's displacement along e_vs, e_ws
            return sp.csr_matrix((np.tile(self.directions, (P, 1)).ravel(),
                                  (np.repeat(np.arange(2 * P), 3), np.repeat(dofs, 2, axis=0).ravel())), shape=(2 * P, n))
        B = along(self.side2) - np.exp(1j * nd * pitch) * along(self.side1)
        D = sp.diags(np.ravel(np.column_stack([kn * self.weight, kt * self.weight])))
        return (B.conj().T @ D @ B).tocsr()


def _shroud_pairs(V, facet_tags, spec: DiskSpec) -> ShroudPairs | None:
    """The contact faces' nodes (reference_fe.contact_faces.face_nodes) paired across the shroud's width."""
    if not spec.has_shroud:
        return None
    e_vs, e_ws = shroud_frame(spec)
    (dofs1, area1, x1), (dofs2, area2, x2) = (face_nodes(V, facet_tags, t) for t in (CONTACT_SIDE1, CONTACT_SIDE2))
    dist, match = cKDTree(x1).query(x2 - spec.shroud_width * e_vs)
    if dofs1.shape != dofs2.shape or dist.max() > 1e-8 * spec.size or np.unique(match).size != match.size:
        raise RuntimeError("the shroud's contact faces do not match node for node")
    return ShroudPairs(side1=dofs1[match], side2=dofs2, weight=area2 / area2.sum(), directions=np.vstack([e_vs, e_ws]))


def _csr(A) -> sp.csr_matrix:
    indptr, indices, data = A.getValuesCSR()
    return sp.csr_matrix((data, indices, indptr), shape=A.getSize())


def _reduced(T: sp.csr_matrix, A: sp.csr_matrix) -> sp.csc_matrix:
    """T^H A T."""
    return (T.conj().T @ (A @ T)).tocsc()


def _side_pairs(V, facet_tags, pitch: float, size: float, clamped: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Nodes (blocks) of the two side faces paired by the turn by ``pitch``; bore nodes left out (clamped)."""
    low = fem.locate_dofs_topological(V, 2, facet_tags.find(CYCLIC_LOW))
    high = fem.locate_dofs_topological(V, 2, facet_tags.find(CYCLIC_HIGH))
    if low.size != high.size:
        raise RuntimeError(f"the side faces have {low.size} and {high.size} nodes: the mesh is not periodic")
    x = V.tabulate_dof_coordinates()
    dist, match = cKDTree(x[high]).query(x[low] @ rotation_z(pitch).T)
    if dist.max() > 1e-8 * size:
        raise RuntimeError(f"a side node has no partner within {dist.max():.3g} m: the mesh is not periodic")
    high = high[match]
    free = ~np.isin(3 * low, clamped)
    return low[free], high[free]


def sector(params: Parameters) -> Sector:
    """The (cached) sector for ``params``' geometry, disk, mesh and material."""
    return _sector(DiskSpec.from_params(params), params.material, params.disk.E_factor)


@functools.lru_cache(maxsize=2)
def _sector(spec: DiskSpec, material: Material, disk_E_factor: float) -> Sector:
    comm = MPI.COMM_SELF
    data = read_mesh(sector_mesh_file(spec), comm)
    msh = data.mesh
    V = fem.functionspace(msh, ("Lagrange", spec.order, (3,)))
    bore = fem.locate_dofs_topological(V, 2, data.facet_tags.find(ROOT))
    bc = fem.dirichletbc(np.zeros(3, dtype=PETSc.ScalarType), bore, V)
    clamped = np.sort((3 * bore[:, None] + np.arange(3)).ravel())
    model = SolidModel(spec=spec, material=material, mesh=msh, V=V, cell_tags=data.cell_tags,
                       facet_tags=data.facet_tags, bcs=(bc,), clamped_dofs=clamped,
                       tip_dofs=_tip_dofs(V, tip_points(spec), spec.size))
    low, high = _side_pairs(V, data.facet_tags, spec.pitch, spec.size, clamped)
    info(f"disk sector: {msh.topology.index_map(3).size_local} cells, {V.dofmap.index_map.size_global * 3} DOF, "
         f"{low.size} node pairs on the sides (N = {spec.blades}, order {spec.order}, size {spec.size:g} m)")
    # E on the disk's cells scaled by disk.E_factor (the rigid-disk limit), 1 elsewhere
    Q = fem.functionspace(msh, ("DG", 0))
    stiffness = fem.Function(Q)
    stiffness.x.array[:] = 1.0
    stiffness.x.array[data.cell_tags.find(DISK)] = disk_E_factor
    forms = _unit_forms(model)
    du, v = ufl.TrialFunction(V), ufl.TestFunction(V)
    dx = _dx(model)
    forms["k_e"] = stiffness * ufl.inner(sigma(du, material), epsilon(v)) * dx
    M = _csr(assemble_matrix(forms["m"], model.bcs, 0.0))
    K_e = _csr(assemble_matrix(forms["k_e"], model.bcs, 1.0))
    f_c1 = assemble_vector(forms["f_c"], model.bcs).getArray().copy()
    T_I, T_H = transformation_parts(M.shape[0], clamped, low, high, spec.pitch)
    T0 = (T_I + T_H).tocsr()                  # the prestress: the k = 0 state
    u0 = fem.Function(V, name="prestatic_displacement_1rad_s")
    prestress = _Factor((T0.T @ (K_e @ T0)).tocsr(), None)
    u0.x.array[:] = (T0 @ prestress.solve(T0.T @ f_c1)).real.ravel()
    prestress.destroy()
    G1 = _csr(assemble_matrix(forms["g"], model.bcs, 0.0))
    return Sector(model=model, low=low, high=high, clamped=clamped, M=M, K_e=K_e,
                  K_rot1=rotation_stiffness(model, stiffness, u0), G1=G1, f_c1=f_c1,
                  contact=_shroud_pairs(V, data.facet_tags, spec), stiffness=stiffness)


def rotation_stiffness(model: SolidModel, stiffness, u0) -> sp.csr_matrix:
    """K_sigma + K_spin at 1 rad/s (N/m): the geometric stiffness of the prestatic state ``u0`` (a Function,
    m, at 1 rad/s; sigma0 scaled by the cells' ``stiffness``, the disk's E_factor) and the spin softening."""
    du, v = ufl.TrialFunction(model.V), ufl.TestFunction(model.V)
    k_sigma = stiffness * ufl.inner(sigma(u0, model.material), ufl.dot(ufl.grad(du).T, ufl.grad(v))) * _dx(model)
    return _csr(assemble_matrix(k_sigma + _unit_forms(model)["k_spin"], model.bcs, 0.0))


@dataclass(frozen=True)
class DiameterModes:
    """The modes of one nodal diameter: frequencies (Hz, ascending), labels, participations, shapes."""

    nd: int
    f_hz: np.ndarray
    labels: tuple[str, ...]
    participation: tuple[dict[str, float], ...]
    coriolis: bool
    shapes: np.ndarray                    # (n_all, k) complex, on every DOF of the sector

    def result(self, rpm: float, dofs: int, elapsed_s: float) -> ModalResult:
        return ModalResult(model="fe", rpm=rpm, dofs=dofs, elapsed_s=elapsed_s, coriolis=self.coriolis,
                           modes=tuple(Mode(f_hz=float(f), label=lab, participation=part)
                                       for f, lab, part in zip(self.f_hz, self.labels, self.participation)))


def _petsc(A: sp.spmatrix):
    """A real scipy matrix as a serial PETSc AIJ Mat."""
    A = sp.csr_matrix(A)
    A.sort_indices()
    return PETSc.Mat().createAIJ(size=A.shape, csr=(A.indptr.astype(PETSc.IntType), A.indices.astype(PETSc.IntType),
                                                    A.data), comm=MPI.COMM_SELF)


def real_form(re: sp.spmatrix, im: sp.spmatrix | None) -> sp.csr_matrix:
    """The real operator of the complex re + i im on (Re q, Im q): ``re`` itself (``im`` None: k = 0 or
    N/2) or [[re, -im], [im, re]], symmetric when re + i im is Hermitian, each eigenvalue twice."""
    if im is None:
        return sp.csr_matrix(re)
    return sp.bmat([[re, -im], [im, re]], format="csr")


def _complex(re: sp.spmatrix, im: sp.spmatrix | None) -> sp.csr_matrix:
    return sp.csr_matrix(re) if im is None else (re + 1j * im).tocsr()


# MUMPS's fill-reducing ordering (ICNTL(7)) of the sector's forms: 4, PORD. Its default (7, automatic), METIS (5)
# and SCOTCH (3) took 7-12 % more CPU per complex k on the 24-blade sector graded from 2 mm, AMD (0) 40 % more
# (docs/disk.md, "The graded default"); the frequencies moved by 3e-11.
MUMPS_ORDERING = 4


class _Factor:
    """A MUMPS L D L^T of the real form of the Hermitian K_k = re + i im, solving K_k x = b for complex b.

    :meth:`update` refactors it for another nodal diameter: the real forms of every 0 < k < N/2 share one
    sparsity pattern (CyclicParts), so MUMPS keeps its ordering and symbolic analysis (a third of a factor's
    cost on the 24-blade sector) and redoes the numbers only."""

    def __init__(self, re: sp.spmatrix, im: sp.spmatrix | None):
        self.copies, self.n = (1 if im is None else 2), re.shape[0]
        self.A = _sorted(real_form(re, im))
        self.K = _petsc(self.A)
        self.ksp = lu_solver(self.K, MPI.COMM_SELF, "shroud_cyclic_k_", symmetric=True)
        pc = self.ksp.getPC()
        pc.setFactorSetUpSolverType()
        pc.getFactorMatrix().setMumpsIcntl(7, MUMPS_ORDERING)
        self.ksp.setUp()
        self.F = self.ksp.getPC().getFactorMatrix()     # held apart: the eigen-solver resets the KSP

    def update(self, re: sp.spmatrix, im: sp.spmatrix | None) -> "_Factor":
        """This factor refactored for re + i im if its real form has this one's pattern, else a new one."""
        A = _sorted(real_form(re, im))
        if (1 if im is None else 2) != self.copies or not (np.array_equal(A.indptr, self.A.indptr)
                                                          and np.array_equal(A.indices, self.A.indices)):
            self.destroy()
            return _Factor(re, im)
        self.A = A
        self.K.setValuesCSR(A.indptr.astype(PETSc.IntType), A.indices.astype(PETSc.IntType), A.data)
        self.K.assemble()
        self.ksp.setOperators(self.K)
        self.ksp.setUp()
        self.F = self.ksp.getPC().getFactorMatrix()
        return self

    def solve(self, B: np.ndarray) -> np.ndarray:
        """K_k^-1 B for the complex columns of B (n, m): one multi-column MUMPS solve (the factor read once)."""
        B = np.asarray(B, dtype=complex).reshape(self.n, -1)
        if self.copies == 2:
            rhs = np.vstack([B.real, B.imag])
        else:
            rhs = np.column_stack([B.real, B.imag])
        if rhs.shape[1] == 1:
            x, y = self.K.createVecs()
            y.setArray(rhs[:, 0])
            self.F.solve(y, x)
            out = x.getArray().copy()[:, None]
        else:
            Y, X = (PETSc.Mat().createDense(rhs.shape, array=np.asfortranarray(a), comm=MPI.COMM_SELF)
                    for a in (rhs, np.zeros_like(rhs)))
            self.F.matSolve(Y, X)
            out = X.getDenseArray().copy()
            Y.destroy()
            X.destroy()
        if self.copies == 2:
            return out[:self.n] + 1j * out[self.n:]
        m = B.shape[1]
        return out[:, :m] + 1j * out[:, m:]

    def destroy(self) -> None:
        self.ksp.destroy()
        self.F.destroy()
        self.K.destroy()


def _sorted(A: sp.csr_matrix) -> sp.csr_matrix:
    A.sort_indices()
    return A


def _hermitian_modes(factor: _Factor, M: sp.csr_matrix, count: int) -> tuple[np.ndarray, np.ndarray]:
    """(f Hz, M-normalized complex shapes) of the ``count`` lowest modes of the Hermitian pencil (K_k, M_k),
    by ARPACK (shift-invert about 0; K_k^-1 from ``factor``, one real solve of the 2-copy form per complex
    vector). Each frequency comes once: SLEPc on the real 2-copy form finds each twice, with twice the
    Krylov basis and solves (and twice the columns in the Coriolis basis after it)."""
    n = M.shape[0]
    inverse = spla.LinearOperator((n, n), matvec=lambda b: factor.solve(b).ravel(), dtype=complex)
    lam, X = spla.eigsh(M, k=count, M=M, sigma=0.0, which="LM", OPinv=inverse, tol=1e-10,
                        v0=np.full(n, 1.0 + 1.0j))      # M in place of K: unused by shift-invert with OPinv
    keep = lowest_vibration_modes(lam, count, "ARPACK")
    X = X[:, keep]
    X = X / np.sqrt(np.real(np.einsum("ij,ij->j", X.conj(), M @ X)))
    return np.sqrt(lam[keep]) / (2 * np.pi), X


def diameter_modes(sec: Sector, rpm: float, nd: int, n_modes: int, coriolis: bool,
                   stuck: tuple[float, float] | None = None, factors: dict | None = None) -> DiameterModes:
    """The ``n_modes`` lowest modes of nodal diameter ``nd`` at ``rpm`` (with Coriolis if asked and spinning);
    ``stuck`` (kn, kt), N/m: the shroud interfaces joined by those springs (ShroudPairs.springs), else free.
    ``factors``: {copies: _Factor} kept across the calls of one sweep over k (the caller destroys them),
    refactored in place where the pattern allows (:meth:`_Factor.update`); None: one factor, destroyed here.

    The operators of nodal diameter k from the sector's once-reduced parts
    (Sector.reduced, CyclicParts); K_k factored once (MUMPS L D L^T of its
    real form); its modes by SLEPc (Krylov-Schur, shift-invert about 0) for
    the real k = 0 and N/2, by ARPACK on the complex Hermitian pencil
    (:func:`_hermitian_modes`) for the others.
    """
    omega = 2.0 * math.pi * rpm / 60.0
    parts, pitch = sec.reduced, sec.pitch
    K_re, K_im = sec.stiffness_parts(omega**2).at(nd, pitch)
    M_re, M_im = parts["M"].at(nd, pitch)
    T = sec.transformation(nd)
    if stuck is not None:         # the springs on the contact faces' DOFs only: reduced by T_k itself
        Z = _reduced(T, sec.contact.springs(T.shape[0], nd, pitch, *stuck))
        K_re = K_re + sp.csr_matrix(Z.real)
        K_im = None if K_im is None else K_im + sp.csr_matrix(Z.imag)
    copies = 1 if K_im is None else 2
    held = factors if factors is not None else {}
    factor = held[copies] = held[copies].update(K_re, K_im) if copies in held else _Factor(K_re, K_im)
    gyroscopic = coriolis and omega > 0
    count = n_modes + (GYROSCOPIC_EXTRA if gyroscopic else 0)
    if K_im is None:              # real: SLEPc on (K_k, M_k) themselves
        Mr = _petsc(M_re)
        f_hz, vectors = undamped_modes(factor.K, Mr, MPI.COMM_SELF, count, factor.ksp)
        X = np.column_stack([v.getArray().astype(complex) for v in vectors])
        Mr.destroy()
    else:
        f_hz, X = _hermitian_modes(factor, _complex(M_re, M_im), count)
    if gyroscopic:
        K, M = _complex(K_re, K_im), _complex(M_re, M_im)
        G = omega * _complex(*parts["G1"].at(nd, pitch))
        V = np.hstack([X, factor.solve(G @ X)])
        Mb, Kb, Gb = (V.conj().T @ (A @ V) for A in (M, K, G))
        w, U = np.linalg.eigh(0.5 * (Mb + Mb.conj().T))
        basis = U[:, w > 1e-10 * w.max()] / np.sqrt(w[w > 1e-10 * w.max()])      # V basis: M-orthonormal
        Kr, Gr = (basis.conj().T @ A @ basis for A in (Kb, Gb))
        found = gyroscopic_modes(np.eye(Kr.shape[0]), 0.5 * (Kr + Kr.conj().T), n_modes, 0.5 * (Gr - Gr.conj().T))
        f_hz, shapes = found.f_hz, V @ (basis @ found.shapes)
    else:
        f_hz, shapes = f_hz[:n_modes], X[:, :n_modes]
    if factors is None:
        factor.destroy()
    full = T @ shapes
    tip = np.array([np.abs(_tip(sec, full[:, j])) for j in range(full.shape[1])])
    labels, participation = label_modes(tip)
    return DiameterModes(nd=nd, f_hz=np.asarray(f_hz), labels=tuple(labels), participation=tuple(participation),
                         coriolis=coriolis, shapes=full)


def _tip(sec: Sector, u: np.ndarray) -> np.ndarray:
    """[flap, chord, torsion b/2, axial] of the complex shape ``u`` (reference_fe.modal.tip_components)."""
    parts = [PETSc.Vec().createWithArray(np.ascontiguousarray(p), comm=MPI.COMM_SELF) for p in (u.real, u.imag)]
    return tip_components(sec.model, *parts)


def sector_modal(params: Parameters, rpm: float, n_modes: int, coriolis: bool,
                 interface: str = "free") -> list[tuple[int, ModalResult]]:
    """Registry entry (``disk_sector``): (nd, modes of nodal diameter nd) for nd = 0 .. N // 2 at ``rpm``,
    the shroud interfaces ``free`` or ``stuck`` (springs contact.kn, contact.kt)."""
    t0 = time.perf_counter()
    sec = sector(params)
    c = params.contact
    stuck = (c.kn, c.kt) if interface == "stuck" and sec.contact is not None and c.enabled else None
    diameters = nodal_diameters(params.ring.blades)
    progress = Progress(f"disk sector modes at {rpm:g} r/min", len(diameters))
    out, factors = [], {}
    for nd in diameters:
        found = diameter_modes(sec, rpm, nd, n_modes, coriolis, stuck, factors)
        out.append((nd, found.result(rpm, sec.model.global_dofs, time.perf_counter() - t0)))
        progress.update(nd + 1)
        info(f"nd {nd} done at {time.perf_counter() - t0:.2f} s: " + ", ".join(f"{l} {f:.2f} Hz" for l, f in zip(found.labels, found.f_hz)))
    progress.done()
    for factor in factors.values():
        factor.destroy()
    return out
