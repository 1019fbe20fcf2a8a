"""The 3D solid blade on DOLFINx 0.11: mesh, space, clamp and rotating-frame operators.

Linear elasticity in the rotating frame O-XYZ (rotation Omega about +Z),
root face X = R_d clamped. With u the displacement relative to the disk,
virtual work gives (paper Eq. 1, term by term)

    M u'' + G u' + (K_e + K_sigma + K_spin) u = f_c + F_e(t) f_aero

    M        int rho u . v                                   mass
    K_e      int sigma(u) : eps(v)                           elastic stiffness
    f_c      int rho Omega^2 (X, Y, 0) . v                   centrifugal load  (= -rho Om x (Om x x))
    K_sigma  int sigma0 : (grad(u)^T grad(v))                stress stiffening (centrifugal)
    K_spin   -int rho (Om x u) . (Om x v)                    spin softening    (= -rho Om^2 on X, Y)
    G        int 2 rho (Om x u) . v                          Coriolis          (skew-symmetric)
    f_aero   int_blade e_v(x) / A(x) . v                     F_e = 1 N/m along e_v(x) over the blade

sigma0 is the prestress of the linear static solve K_e u0 = f_c. Index
check of K_sigma: (grad(u)^T grad(v))_ij = sum_k du_k/dX_i dv_k/dX_j, so the
form is sigma0_ij du_k,i v_k,j: the second variation of the Green strain
under sigma0. Every rotation term is a power of Omega times a unit-speed
operator (linear prestress): K(Omega) = K_e + Omega^2 (K_sigma1 + K_spin1),
G(Omega) = Omega G1. The unit operators are assembled once per mesh and
material; a speed only rescales them.

Contract (used by engineer D's transient and CMS; names are stable)
------------------------------------------------------------------
``solid_model(params) -> SolidModel``
    mesh, vector space ``V`` (Lagrange, degree ``fe.order``), ``cell_tags``
    (meshes.blade.BLADE / SHROUD), ``facet_tags`` (ROOT, CONTACT_SIDE1,
    CONTACT_SIDE2), ``contact_tags``, ``bcs`` (root clamp),
    ``clamped_dofs`` (local unrolled indices), ``tip_dofs`` (unrolled
    indices of the embedded tip nodes: centre, centre -/+ c(L)/4 e_w(L); -1 on
    ranks that do not own them). Built once per process for a mesh/material.
``rotating_operators(params, rpm) -> RotatingOperators``
    ``M``, ``K`` (= K_e + K_sigma + K_spin), ``G`` (Coriolis) as PETSc Mats
    (clamped rows: diag 1 on K, 0 on M and G, so they add no finite
    eigenvalue), ``K_e``, the load vectors ``f_c`` and ``f_aero`` (PETSc Vecs,
    zero on clamped rows) and ``u0`` (the prestatic displacement, a Function).
``RotatingOperators.free() -> FreeOperators``
    ``M, K, G`` on the free DOFs (scipy CSR serially; under mpirun
    reference_fe.distributed matrices acting on replicated vectors) and
    arrays ``f_c, f_aero``; ``free`` (free -> global unrolled index),
    ``free_index`` (global unrolled -> free, -1 when clamped).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from typing import Any

import dolfinx_solver  # noqa: F401  (must precede dolfinx / petsc4py)
import numpy as np
import scipy.sparse as sp
import ufl
from dolfinx import fem
from dolfinx.fem import petsc as fem_petsc
from dolfinx.io import gmsh as gmshio
from mpi4py import MPI
from petsc4py import PETSc

from meshes.blade import (BLADE, CONTACT_SIDE1, CONTACT_SIDE2, ROOT, MeshSpec, check_geometry,
                          mesh_file, tip_points)
from meshes.spec import SweptBlade
from reference_fe.distributed import global_offset
from shroud.base.errors import InputError
from shroud.base.log import info
from shroud.base.parallel import in_task, task_comm
from shroud.params import Material, Parameters


@dataclass(frozen=True, eq=False)      # identity hash: one per process and mesh
class FEModel:
    """What the solid and the shell (reference_fe.shell) share: the geometry, the mesh, the space and
    its clamp, the tip nodes (and their values), the contact faces' tags."""

    spec: SweptBlade             # meshes.spec.MeshSpec (solid) or meshes.shell.ShellSpec
    material: Material
    mesh: Any
    V: Any
    cell_tags: Any               # BLADE / SHROUD
    facet_tags: Any              # ROOT, CONTACT_SIDE1 / 2 (the shell: TIP too)
    bcs: tuple                   # the root clamp
    clamped_dofs: np.ndarray     # local unrolled indices of clamped DOFs (owned and ghost)
    tip_dofs: np.ndarray         # (3, 3) indices in V of the displacement at the tip centre and at
                                 # centre -/+ (b/4) e_w(L); -1 on ranks that do not own them
    contact_tags = (CONTACT_SIDE1, CONTACT_SIDE2)

    @property
    def comm(self):
        return self.mesh.comm

    @property
    def global_dofs(self) -> int:
        imap = self.V.dofmap.index_map
        return imap.size_global * self.V.dofmap.index_map_bs

    @property
    def owned_dofs(self) -> int:
        return self.V.dofmap.index_map.size_local * self.V.dofmap.index_map_bs

    def gather_tip(self, xr, xi=None) -> np.ndarray:
        """(3, 3) displacements (X, Y, Z) of the three tip nodes in the shape xr + i xi (PETSc Vecs), every rank."""
        values = np.zeros((3, 3), dtype=complex)
        owned = self.tip_dofs[:, 0] >= 0
        for part, scale in ((xr, 1.0), (xi, 1j)):
            if part is None:
                continue
            values[owned] += scale * part.getArray(readonly=True)[self.tip_dofs[owned]]
        return self.comm.allreduce(values, op=MPI.SUM)


@dataclass(frozen=True, eq=False)      # identity hash: one per process and mesh
class SolidModel(FEModel):
    """Mesh, vector Lagrange space and clamp of one blade geometry (spec: a MeshSpec; one per process and mesh)."""


@dataclass(frozen=True)
class UnitOperators:
    """Speed-independent pieces: K_e, M, and the rotation operators at Omega = 1 rad/s."""

    M: Any
    K_e: Any
    K_rot1: Any        # K_sigma + K_spin at 1 rad/s (scales with Omega^2)
    G1: Any            # Coriolis at 1 rad/s (scales with Omega)
    f_c1: Any          # centrifugal load at 1 rad/s
    f_aero: Any
    u0_1: Any          # prestatic displacement at 1 rad/s


@dataclass(frozen=True)
class FreeOperators:
    """The operators on the free (unclamped) DOFs, SI units; arrays complete on every rank."""

    M: Any                    # scipy CSR (serial) or reference_fe.distributed.DistributedMatrix
    K: Any
    G: Any
    f_c: np.ndarray
    f_aero: np.ndarray
    free: np.ndarray          # (n_free,) global unrolled DOF index of each free DOF
    free_index: np.ndarray    # (n_all,) free index of each global unrolled DOF, -1 if clamped

    @property
    def n(self) -> int:
        return int(self.free.size)


@dataclass(frozen=True)
class RotatingOperators:
    """The solid's operators at one constant speed (PETSc, distributed)."""

    model: SolidModel
    rpm: float
    omega: float       # rad/s
    M: Any
    K: Any             # K_e + K_sigma + K_spin
    G: Any             # Coriolis
    K_e: Any
    f_c: Any
    f_aero: Any
    u0: Any            # prestatic displacement (fem.Function), m

    def free(self) -> FreeOperators:
        """The operators on the free DOFs: scipy CSR serially, row-distributed under mpirun.

        Free DOFs are numbered rank by rank (reference_fe.distributed); the
        index arrays, loads and coordinates are complete on every rank.
        """
        model = self.model
        comm = model.comm
        mine = np.setdiff1d(np.arange(model.owned_dofs), model.clamped_dofs)   # owned, unclamped
        offset = global_offset(model.V)
        free = np.concatenate(comm.allgather(offset + mine))
        free_index = np.full(model.global_dofs, -1, dtype=np.int64)
        free_index[free] = np.arange(free.size)
        if comm.size == 1:
            M, K, G = _free_csr((self.M, self.K, self.G), mine)
            # DOLFINx stores a 3 x 3 block per node pair; the mass fills only its diagonal, the Coriolis
            # operator two entries: M keeps a third of its entries, G two ninths (a product with M in
            # 0.40 ms against 1.65 ms, the same numbers; the eigen-solve of the reduction takes 189)
            M.eliminate_zeros()
            G.eliminate_zeros()
            gather = np.asarray
        else:
            from reference_fe.distributed import Layout, free_rows
            layout = Layout.of(comm, mine.size)
            M, K, G = (free_rows(A, offset + mine, layout) for A in (self.M, self.K, self.G))
            gather = layout.gather
        return FreeOperators(
            M=M, K=K, G=G, f_c=gather(self.f_c.getArray()[mine]),
            f_aero=gather(self.f_aero.getArray()[mine]), free=free, free_index=free_index)

    @classmethod
    def at(cls, model, unit: UnitOperators, rpm: float) -> "RotatingOperators":
        """The operators of ``model`` at ``rpm`` from its unit-speed ones: K_e + Omega^2 K_rot1, Omega G1."""
        omega = 2.0 * math.pi * float(rpm) / 60.0
        K = unit.K_e.copy()
        K.axpy(omega**2, unit.K_rot1, structure=PETSc.Mat.Structure.SUBSET_NONZERO_PATTERN)
        G = unit.G1.copy()
        G.scale(omega)
        f_c = unit.f_c1.copy()
        f_c.scale(omega**2)
        u0 = fem.Function(model.V, name="prestatic_displacement")
        u0.x.array[:] = omega**2 * unit.u0_1.x.array
        return cls(model=model, rpm=float(rpm), omega=omega, M=unit.M, K=K, G=G, K_e=unit.K_e,
                   f_c=f_c, f_aero=unit.f_aero, u0=u0)


def tip_centre_dofs(model: SolidModel) -> np.ndarray:
    """Global unrolled DOFs (x, y, z) of the embedded tip-centre node, on every rank."""
    mine = model.tip_dofs[0]
    found = model.comm.allgather(global_offset(model.V) + mine if mine[0] >= 0 else None)
    return next(d for d in found if d is not None)


def _free_csr(mats, keep: np.ndarray) -> list[sp.csr_matrix]:
    """Rows and columns ``keep`` (sorted) of each serial PETSc matrix, as scipy CSR.

    The operators of one space share a sparsity pattern: which entries stay,
    and where, is worked out once per distinct pattern and each matrix only
    picks its values (about 0.02 s, against 0.13-0.21 s of scipy's row and
    column slicing per matrix on the Fig. 8 solid). The result is entry for
    entry what the slicing gives.
    """
    out, pattern, selection = [], None, None
    for A in mats:
        indptr, indices, data = A.getValuesCSR()
        if pattern is None or not (np.array_equal(indptr, pattern[0]) and np.array_equal(indices, pattern[1])):
            pattern, selection = (indptr, indices), _kept_entries(indptr, indices, keep)
        kept_indptr, kept_indices, positions = selection
        out.append(sp.csr_matrix((data[positions], kept_indices, kept_indptr), shape=(keep.size, keep.size)))
    return out


def _kept_entries(indptr: np.ndarray, indices: np.ndarray, keep: np.ndarray):
    """(indptr, indices, positions in the old entries) of the CSR pattern restricted to ``keep`` x ``keep``."""
    new_of = np.full(indptr.size - 1, -1, dtype=np.int64)
    new_of[keep] = np.arange(keep.size)
    rows = new_of[np.repeat(np.arange(indptr.size - 1), np.diff(indptr))]
    cols = new_of[indices]
    positions = np.flatnonzero((rows >= 0) & (cols >= 0))
    counts = np.bincount(rows[positions], minlength=keep.size)
    kept_indptr = np.concatenate([[0], np.cumsum(counts)])
    return kept_indptr, cols[positions], positions


def epsilon(u):
    return ufl.sym(ufl.grad(u))


def sigma(u, material: Material):
    """Isotropic Hooke's law, Pa."""
    E, nu = material.E, material.nu
    lam = E * nu / ((1 + nu) * (1 - 2 * nu))
    mu = E / (2 * (1 + nu))
    return 2 * mu * epsilon(u) + lam * ufl.tr(epsilon(u)) * ufl.Identity(3)


def solid_model(params: Parameters) -> SolidModel:
    """The (cached) solid for ``params``' geometry, mesh size, order and material."""
    spec = MeshSpec.from_params(params)
    check_geometry(spec)      # on every rank, before any gmsh work
    return _solid_model(spec, params.material, in_task())


@functools.lru_cache(maxsize=4)
def _solid_model(spec: MeshSpec, material: Material, alone: bool) -> SolidModel:
    # COMM_WORLD, or COMM_SELF for a rank working alone (an item of a spread campaign, or
    # serial work on rank 0): ``alone`` keys the cache so the two never share a model.
    comm = task_comm()
    # Rank 0 meshes; an input error it finds there (a STEP file the solid cannot use) stops every rank.
    path = error = None
    if comm.rank == 0:
        try:
            path = mesh_file(spec)
        except InputError as exc:
            error = exc
    path, error = comm.bcast((path, error), root=0)
    if error is not None:
        raise error
    data = read_mesh(path, comm)
    msh = data.mesh
    V = fem.functionspace(msh, ("Lagrange", spec.order, (3,)))
    fdim = msh.topology.dim - 1
    root_facets = data.facet_tags.find(ROOT)
    root_blocks = fem.locate_dofs_topological(V, fdim, root_facets)
    bc = fem.dirichletbc(np.zeros(3, dtype=PETSc.ScalarType), root_blocks, V)
    clamped = (3 * root_blocks[:, None] + np.arange(3)[None, :]).ravel()
    info(f"solid: {comm.allreduce(msh.topology.index_map(3).size_local)} cells, "
         f"{V.dofmap.index_map.size_global * 3} DOF (order {spec.order}, size {spec.size:g} m)")
    return SolidModel(spec=spec, material=material, mesh=msh, V=V, cell_tags=data.cell_tags,
                      facet_tags=data.facet_tags, bcs=(bc,), clamped_dofs=np.sort(clamped),
                      tip_dofs=_tip_dofs(V, tip_points(spec), spec.size))


def read_mesh(path, comm, max_facet_to_cell_links: int = 2):
    """gmshio.read_from_msh without gmsh's console output (stdout is kept for --json).

    ``max_facet_to_cell_links``: 3 for a branching surface (the shell's shroud on its tip line).
    """
    import gmsh
    if comm.rank != 0:
        return gmshio.model_to_mesh(gmsh.model, comm, 0, gdim=3, max_facet_to_cell_links=max_facet_to_cell_links)
    gmsh.initialize(interruptible=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.merge(str(path))
        return gmshio.model_to_mesh(gmsh.model, comm, 0, gdim=3, max_facet_to_cell_links=max_facet_to_cell_links)
    finally:
        gmsh.finalize()


def _tip_dofs(V, points: np.ndarray, size: float) -> np.ndarray:
    """Unrolled DOFs (x, y, z) of the nodes at ``points`` owned by this rank (-1 elsewhere)."""
    owned = V.dofmap.index_map.size_local
    nodes = V.tabulate_dof_coordinates()[:owned]
    out = np.full((len(points), 3), -1, dtype=np.int64)
    for i, p in enumerate(points):
        dist = np.linalg.norm(nodes - p, axis=1) if owned else np.array([np.inf])
        j = int(np.argmin(dist))
        if dist[j] < 1e-8 * size:
            out[i] = 3 * j + np.arange(3)
    return out


def _dx(model: SolidModel):
    """Volume measure knowing the blade/shroud cell tags.

    Hexahedra (fe.cell = "hex") are integrated with Gauss points of degree
    2 * order per direction (3 x 3 x 3 for Q2: exact for the mass of an
    affine cell, the usual full rule of 27-node bricks); UFL's estimate for
    the curved Q2 cells (degree 10, 216 points) costs 6x the assembly for
    a 0.1 % change in the stiffness norm, well inside the discretization error.
    """
    metadata = {"quadrature_degree": 2 * model.spec.order} if model.spec.cell == "hex" else {}
    return ufl.Measure("dx", domain=model.mesh, subdomain_data=model.cell_tags, metadata=metadata)


def _unit_forms(model: SolidModel):
    """UFL forms of the unit-speed operators (Omega = e_Z x 1 rad/s)."""
    msh, V, mat = model.mesh, model.V, model.material
    spec = model.spec
    du, v = ufl.TrialFunction(V), ufl.TestFunction(V)
    X = ufl.SpatialCoordinate(msh)
    rho = mat.rho
    Om = ufl.as_vector((0.0, 0.0, 1.0))
    dx = _dx(model)
    beta = spec.stagger + spec.twist * (X[0] - spec.disk_radius) / spec.length
    e_v = ufl.as_vector((0.0, ufl.cos(beta), ufl.sin(beta)))
    return dict(
        m=rho * ufl.inner(du, v) * dx,
        k_e=ufl.inner(sigma(du, mat), epsilon(v)) * dx,
        k_spin=-rho * ufl.inner(ufl.cross(Om, du), ufl.cross(Om, v)) * dx,
        g=2.0 * rho * ufl.inner(ufl.cross(Om, du), v) * dx,
        f_c=rho * ufl.inner(ufl.as_vector((X[0], X[1], 0.0)), v) * dx,
        f_aero=ufl.inner(e_v / spec.section_area(X[0] - spec.disk_radius), v) * dx(BLADE),
    )


def assemble_matrix(form, bcs, diag: float):
    A = fem_petsc.assemble_matrix(fem.form(form), bcs=list(bcs), diag=diag)
    A.assemble()
    return A


def assemble_vector(form, bcs):
    """Load vector with clamped rows set to zero (the prescribed value)."""
    b = fem_petsc.assemble_vector(fem.form(form))
    b.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
    fem_petsc.set_bc(b, list(bcs))
    return b


def lu_solver(A, comm, prefix: str, symmetric: bool = True):
    """A direct (MUMPS) KSP on A, factorized once and reused; Cholesky (LDL^T) if symmetric."""
    ksp = PETSc.KSP().create(comm)
    ksp.setOptionsPrefix(prefix)
    ksp.setOperators(A)
    ksp.setType("preonly")
    ksp.getPC().setType("cholesky" if symmetric else "lu")
    ksp.getPC().setFactorSolverType("mumps")
    ksp.setFromOptions()
    return ksp


def unit_operators_from(model, forms: dict, k_sigma_of) -> UnitOperators:
    """Assemble the unit-speed operators of ``forms`` (m, k_e, k_spin, g, f_c, f_aero) on ``model``.

    ``k_sigma_of(u0)`` is the geometric-stiffness form of the prestatic
    state u0 (K_e u0 = f_c at 1 rad/s, clamped root), which is solved here.
    Clamped rows: diag 1 on K_e, 0 on the others (they add no finite eigenvalue).
    """
    bcs = model.bcs
    M = assemble_matrix(forms["m"], bcs, 0.0)
    K_e = assemble_matrix(forms["k_e"], bcs, 1.0)
    f_c1 = assemble_vector(forms["f_c"], bcs)
    f_aero = assemble_vector(forms["f_aero"], bcs)
    u0 = fem.Function(model.V, name="prestatic_displacement_1rad_s")
    ksp = lu_solver(K_e, model.comm, "shroud_prestress_")
    ksp.solve(f_c1, u0.x.petsc_vec)
    u0.x.scatter_forward()
    ksp.destroy()
    K_rot1 = assemble_matrix(k_sigma_of(u0) + forms["k_spin"], bcs, 0.0)
    G1 = assemble_matrix(forms["g"], bcs, 0.0)
    return UnitOperators(M=M, K_e=K_e, K_rot1=K_rot1, G1=G1, f_c1=f_c1, f_aero=f_aero, u0_1=u0)


@functools.lru_cache(maxsize=4)
def _unit_operators(model: SolidModel) -> UnitOperators:
    def k_sigma(u0):
        du, v = ufl.TrialFunction(model.V), ufl.TestFunction(model.V)
        return ufl.inner(sigma(u0, model.material), ufl.dot(ufl.grad(du).T, ufl.grad(v))) * _dx(model)
    return unit_operators_from(model, _unit_forms(model), k_sigma)


def rotating_operators(params: Parameters, rpm: float | None = None) -> RotatingOperators:
    """M, K(Omega), G(Omega), the loads and the prestatic displacement at ``rpm`` (SI)."""
    rpm = params.speed.rpm if rpm is None else float(rpm)
    model = solid_model(params)
    return RotatingOperators.at(model, _unit_operators(model), rpm)
