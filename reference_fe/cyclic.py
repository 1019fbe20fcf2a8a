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
the Coriolis G), complex; real PETSc/SLEPc solves their real 2-copy form
(diameter_modes): option (b) of issue 35. (scipy's complex SuperLU and
ARPACK on the complex form, half the size, took 170-210 s and 11 GB per
nodal diameter on the 87 447-DOF N = 4 sector, order 2, size 3.5 mm, on
the loaded machine.)

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
import ufl
from dolfinx import fem
from mpi4py import MPI
from petsc4py import PETSc
from scipy.spatial import cKDTree

from meshes.disk import CYCLIC_HIGH, CYCLIC_LOW, DISK, DiskSpec, rotation_z, sector_mesh_file
from meshes.spec import CONTACT_SIDE1, CONTACT_SIDE2, ROOT, shroud_frame, tip_points
from reference_fe.contact_faces import face_nodes
from reference_fe.modal import GYROSCOPIC_EXTRA, tip_components, undamped_modes
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
        return transformation(self.M.shape[0], self.clamped, self.low, self.high, self.pitch, nd)


def transformation(n: int, clamped: np.ndarray, low: np.ndarray, high: np.ndarray, pitch: float,
                   nd: int) -> sp.csr_matrix:
    """T_k (n, n_reduced) of nodal diameter ``nd``: identity on the kept DOFs (neither ``clamped`` nor on the
    ``high`` nodes), u_h = exp(i k pitch) R(pitch) u_l on each high node h paired with the low node l."""
    eliminated = np.zeros(n, dtype=bool)
    eliminated[clamped] = True
    eliminated[(3 * high[:, None] + np.arange(3)).ravel()] = True
    kept = np.flatnonzero(~eliminated)
    column = np.full(n, -1, dtype=np.int64)
    column[kept] = np.arange(kept.size)
    block = np.exp(1j * nd * pitch) * rotation_z(pitch)
    rows = (3 * high[:, None, None] + np.arange(3)[None, :, None]).repeat(3, axis=2)
    cols = column[3 * low[:, None, None] + np.arange(3)[None, None, :]].repeat(3, axis=1)
    values = np.broadcast_to(block, rows.shape)
    T = sp.coo_matrix((np.concatenate([np.ones(kept.size), values.ravel()]),
                       (np.concatenate([kept, rows.ravel()]), np.concatenate([np.arange(kept.size), cols.ravel()]))),
                      shape=(n, kept.size))
    return T.tocsr()


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
    T0 = transformation(M.shape[0], clamped, low, high, spec.pitch, 0).real    # the prestress: the k = 0 state
    u0 = fem.Function(V, name="prestatic_displacement_1rad_s")
    prestress = _Factor(_reduced(T0, K_e), copies=1)
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


def real_form(A: sp.spmatrix, copies: int) -> sp.csr_matrix:
    """The real operator of the complex A on (Re q, Im q): A itself (``copies`` 1: A real, k = 0 or N/2)
    or [[Re A, -Im A], [Im A, Re A]] (2), symmetric when A is Hermitian, each eigenvalue twice."""
    if copies == 1:
        return sp.csr_matrix(A.real)
    return sp.bmat([[A.real, -A.imag], [A.imag, A.real]], format="csr")


class _Factor:
    """A MUMPS L D L^T of the real form of the Hermitian K_k, solving K_k x = b for complex columns b."""

    def __init__(self, K: sp.spmatrix, copies: int):
        self.copies, self.n = copies, K.shape[0]
        self.K = _petsc(real_form(K, copies))
        self.ksp = lu_solver(self.K, MPI.COMM_SELF, "shroud_cyclic_k_", symmetric=True)
        self.ksp.setUp()
        self.F = self.ksp.getPC().getFactorMatrix()     # held apart: the eigen-solver resets the KSP

    def solve(self, B: np.ndarray) -> np.ndarray:
        B = np.asarray(B, dtype=complex).reshape(self.n, -1)
        rhs = [np.concatenate([b.real, b.imag]) for b in B.T] if self.copies == 2 else \
            [part for b in B.T for part in (b.real, b.imag)]
        x, y = self.K.createVecs()
        out = []
        for r in rhs:
            y.setArray(r)
            self.F.solve(y, x)
            out.append(x.getArray().copy())
        if self.copies == 2:
            return np.column_stack([u[:self.n] + 1j * u[self.n:] for u in out])
        return np.column_stack([out[2 * j] + 1j * out[2 * j + 1] for j in range(B.shape[1])])

    def destroy(self) -> None:
        self.ksp.destroy()
        self.F.destroy()
        self.K.destroy()


def diameter_modes(sec: Sector, rpm: float, nd: int, n_modes: int, coriolis: bool,
                   stuck: tuple[float, float] | None = None) -> DiameterModes:
    """The ``n_modes`` lowest modes of nodal diameter ``nd`` at ``rpm`` (with Coriolis if asked and spinning);
    ``stuck`` (kn, kt), N/m: the shroud interfaces joined by those springs (ShroudPairs.springs), else free.

    SLEPc (Krylov-Schur, shift-invert about 0, MUMPS) on the real form of
    (K_k, M_k): for 0 < k < N/2 each frequency comes twice, its two
    eigenvectors (Re x, Im x) and (-Im x, Re x) being x and i x of one
    complex shape x = Re x + i Im x.
    """
    omega = 2.0 * math.pi * rpm / 60.0
    T = sec.transformation(nd)
    copies = 1 if nd == 0 or 2 * nd == sec.model.spec.blades else 2
    K_all = sec.K_e + omega**2 * sec.K_rot1
    if stuck is not None:
        K_all = K_all + sec.contact.springs(K_all.shape[0], nd, sec.pitch, *stuck)
    K = _reduced(T, K_all)
    M = _reduced(T, sec.M)
    factor = _Factor(K, copies)
    gyroscopic = coriolis and omega > 0
    count = n_modes + (GYROSCOPIC_EXTRA if gyroscopic else 0)
    Mr = _petsc(real_form(M, copies))
    f_all, vectors = undamped_modes(factor.K, Mr, MPI.COMM_SELF, copies * count, factor.ksp)
    n = K.shape[0]
    X = np.column_stack([v.getArray()[:n] + (1j * v.getArray()[n:] if copies == 2 else 0.0) for v in vectors])
    Mr.destroy()
    if gyroscopic:
        G = _reduced(T, omega * sec.G1)
        V = np.hstack([X, factor.solve(G @ X)])
        Mb, Kb, Gb = (V.conj().T @ (A @ V) for A in (M, K, G))
        w, U = np.linalg.eigh(0.5 * (Mb + Mb.conj().T))
        basis = U[:, w > 1e-10 * w.max()] / np.sqrt(w[w > 1e-10 * w.max()])      # V basis: M-orthonormal
        Kr, Gr = (basis.conj().T @ A @ basis for A in (Kb, Gb))
        found = gyroscopic_modes(np.eye(Kr.shape[0]), 0.5 * (Kr + Kr.conj().T), n_modes, 0.5 * (Gr - Gr.conj().T))
        f_hz, shapes = found.f_hz, V @ (basis @ found.shapes)
    else:
        f_hz, shapes = f_all[::copies][:n_modes], X[:, ::copies][:, :n_modes]
    factor.destroy()
    full = T @ shapes
    tip = np.array([np.abs(_tip(sec, full[:, j])) for j in range(full.shape[1])])
    labels, parts = label_modes(tip)
    return DiameterModes(nd=nd, f_hz=np.asarray(f_hz), labels=tuple(labels), participation=tuple(parts),
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
    out = []
    for nd in diameters:
        found = diameter_modes(sec, rpm, nd, n_modes, coriolis, stuck)
        out.append((nd, found.result(rpm, sec.model.global_dofs, time.perf_counter() - t0)))
        progress.update(nd + 1)
        info(f"nd {nd} done at {time.perf_counter() - t0:.2f} s: " + ", ".join(f"{l} {f:.2f} Hz" for l, f in zip(found.labels, found.f_hz)))
    progress.done()
    return out
