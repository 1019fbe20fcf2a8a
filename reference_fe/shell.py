"""The blade as a Reissner-Mindlin shell of its mid-surface on DOLFINx 0.11 (gdim 3, tdim 2).

Kinematics (J. Bleyer's linear shell tour; Campello, Pimenta & Wriggers
2003, linearized): a point zeta e_3 off the mid-surface moves by
u + zeta theta x e_3, with u the mid-surface displacement and theta the
infinitesimal rotation vector, both in global (X, Y, Z) components. With
(e_1, e_2, e_3) an orthonormal frame of the (flat) cell, e_3 its normal,
P = [e_1 e_2] and the tangential gradient grad_t w = grad(w) P:

    membrane   eps   = sym(P^T grad_t u)
    bending    kappa = sym(P^T grad_t (e_3 x theta))
    shear      gamma = grad_t (u . e_3) - P^T (e_3 x theta)
    drilling   varpi = (P^T grad_t u)_12 / 2 - (P^T grad_t u)_21 / 2 + theta . e_3

and the stress resultants of a plane-stress isotropic plate of thickness h

    N = h C : eps,   M = h^3/12 C : kappa,   Q = (5/6) G h gamma,

C the plane-stress Hooke tensor (lambda_ps = 2 lambda mu / (lambda + 2 mu)).
The drilling rotation, which a shell does not resist, is held by
``drilling`` E h^3 / h_K^2 varpi^2 (h_K the cell diameter): small against
the membrane stiffness E h, and it moves the frequencies by < 0.1 % over
``drilling`` = 0.1 .. 10 (docs/shell.md; tests/test_shell.py). Every term
is invariant under a change of the in-plane frame, so e_1 is simply the
first edge direction of the cell's Jacobian.

Locking: P2 displacements with Crouzeix-Raviart (facet-midpoint)
rotations. The P1 shear strain grad_t u_3 of the P2 deflection can match the
discontinuous P1 rotation of CR, so the Kirchhoff limit gamma -> 0 does
not lock (tested on NAFEMS FV16, a/h = 200, and on a clamped plate down
to a/h = 1000 against a full-Lagrange P2/P2 discretization that locks).

Mass: rho h u . v plus the rotary inertia rho h^3/12 (e_3 x theta) . (e_3 x eta)
of the director (the drilling rotation carries none).

Rotation about +Z at Omega (docs/geometry.md, as the solid, reference_fe.solid):
centrifugal load rho h Omega^2 (X, Y, 0), spin softening
-rho h (Om x u) . (Om x v), Coriolis 2 rho h (Om x u) . v, and the
geometric stiffness of the membrane forces N0 of the centrifugal state
(K_e u0 = f_c): int N0 : (grad_t u^T grad_t v), the shell's form of the
solid's int sigma0 : (grad u^T grad v) through the thickness, and on the
shroud plate that of its offset material turned on its arm t_s/2 e_X
(arm_stiffness: the radial tension of the solid's box, which the plate
carries in bending, not as a membrane force). The bending moments of the
prestatic state add to it at order h^2 / L^2 and are left out; so are the
rotary terms of spin softening and Coriolis.

The shroud (meshes.shell) is a plate of thickness t_s carried by the same
forms: the thickness is a cell-wise (DG0) field there, and on the blade
too where it is uniform (the untapered rectangle). Where it varies (a
thickness taper, the NACA profile: meshes.shell.ShellSpec.mid_thickness,
h = 2 c(x) y_t(s)) it is the UFL expression of x and of the chord fraction
s, a P2 field interpolated from the nodes (s is smooth; h ~ sqrt(s) at the
leading edge is evaluated at the quadrature points, QUADRATURE_DEGREE).
Membrane ~h, bending ~h^3, shear ~h, mass ~h and rotary inertia ~h^3 all
read it there.

The operators come out as the solid's (reference_fe.solid.RotatingOperators),
so the modal solver, the reduction and the system serve both models.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass
from typing import Any

import dolfinx_solver  # noqa: F401  (must precede dolfinx / petsc4py)
import basix.ufl
import numpy as np
import ufl
from dolfinx import fem

from meshes.shell import TIP, ShellSpec, check_geometry, mesh_file
from meshes.spec import BLADE, ROOT, SHROUD, tip_points
from reference_fe.solid import (FEModel, RotatingOperators, UnitOperators, assemble_vector, read_mesh,
                                unit_operators_from)
from shroud.base.log import info
from shroud.base.parallel import in_task, task_comm
from shroud.params import Material, Parameters

SHEAR_CORRECTION = 5.0 / 6.0
DRILLING = 1.0      # drilling stiffness / (E h^3 / h_K^2)
QUADRATURE_DEGREE = 4   # of a varying thickness's forms (UFL's estimate of h^3 with a sqrt is far higher)


@dataclass(frozen=True, eq=False)      # identity hash: one per process and mesh
class ShellModel(FEModel):
    """Mesh, mixed space (u: P2, theta: CR) and clamp of one mid-surface (spec: a ShellSpec; one per process
    and mesh), and the fields the shell's forms read."""

    thickness: Any               # DG0 field (t_s on the plate, a uniform blade's t) or a UFL expression of it
    offset: Any                  # DG0 field: how far out (along +X) the material sits from the cell: t_s/2 on the plate
    drilling: float = DRILLING
    quadrature_degree: int | None = None     # of every form (None: UFL's estimate)


def shell_model(params: Parameters, drilling: float = DRILLING) -> ShellModel:
    """The (cached) shell of ``params``' blade, shroud, shell mesh and material."""
    return model_of(ShellSpec.from_params(params), params.material, drilling)


def model_of(spec: ShellSpec, material: Material, drilling: float = DRILLING) -> ShellModel:
    """The shell of a mid-surface ``spec`` (the blade's, or a benchmark's strip)."""
    check_geometry(spec)
    return _shell_model(spec, material, float(drilling), in_task())


@functools.lru_cache(maxsize=4)
def _shell_model(spec: ShellSpec, material: Material, drilling: float, alone: bool) -> ShellModel:
    comm = task_comm()
    path = comm.bcast(mesh_file(spec) if comm.rank == 0 else None, root=0)
    data = read_mesh(path, comm, max_facet_to_cell_links=3)     # the shroud joins the tip line: a T
    msh = data.mesh
    cell = msh.basix_cell()
    V = fem.functionspace(msh, basix.ufl.mixed_element([basix.ufl.element("P", cell, 2, shape=(3,)),
                                                        basix.ufl.element("CR", cell, 1, shape=(3,))]))
    fdim = msh.topology.dim - 1
    msh.topology.create_connectivity(fdim, msh.topology.dim)
    root = data.facet_tags.find(ROOT)
    bcs, clamped = [], []
    for i in range(2):
        Vi, _ = V.sub(i).collapse()
        dofs = fem.locate_dofs_topological((V.sub(i), Vi), fdim, root)
        bcs.append(fem.dirichletbc(fem.Function(Vi), dofs, V.sub(i)))
        clamped.append(dofs[0])
    DG0 = fem.functionspace(msh, ("DG", 0))
    thickness, offset = fem.Function(DG0, name="thickness"), fem.Function(DG0, name="offset")
    uniform = spec.section == "rectangle" and spec.thickness_taper == 1.0
    thickness.x.array[:] = spec.thickness if uniform else 0.0
    if spec.has_shroud:
        plate = data.cell_tags.find(SHROUD)
        thickness.x.array[plate] = spec.shroud_thickness
        offset.x.array[plate] = 0.5 * spec.shroud_thickness
    h = thickness if uniform else thickness + _blade_share(DG0, data.cell_tags) * _mid_thickness(msh, spec)
    info(f"shell: {comm.allreduce(msh.topology.index_map(2).size_local)} triangles, "
         f"{V.dofmap.index_map.size_global} DOF (P2/CR, size {spec.size:g} m)")
    return ShellModel(spec=spec, material=material, mesh=msh, V=V, cell_tags=data.cell_tags,
                      facet_tags=data.facet_tags, bcs=tuple(bcs), clamped_dofs=np.unique(np.concatenate(clamped)),
                      tip_dofs=nodal_dofs(V, 0, tip_points(spec), spec.size), thickness=h, offset=offset,
                      drilling=drilling, quadrature_degree=None if uniform else QUADRATURE_DEGREE)


def _blade_share(DG0, cell_tags):
    """1 on the blade's cells, 0 on the plate's (DG0)."""
    share = fem.Function(DG0)
    share.x.array[cell_tags.find(BLADE)] = 1.0
    return share


def _mid_thickness(msh, spec: ShellSpec):
    """The blade's thickness h(x, s), m, as UFL: spec.mid_thickness of x = X - R_d and of the chord
    fraction s, a P2 field of the nodes' own s (meshes.shell.ShellSpec.chord_fraction)."""
    S = fem.functionspace(msh, ("P", 2))
    nodes = S.tabulate_dof_coordinates()
    beta = spec.beta(nodes[:, 0])
    eta_w = -np.sin(beta) * nodes[:, 1] + np.cos(beta) * nodes[:, 2]
    s = fem.Function(S, name="chord_fraction")
    s.x.array[:] = np.clip(spec.chord_fraction(nodes[:, 0] - spec.disk_radius, eta_w), 0.0, 1.0)
    # s >= 0 at the quadrature points: the P2 field undershoots where its nodal values jump (the plate's,
    # where s means nothing and the blade's share is 0)
    return spec.mid_thickness(ufl.SpatialCoordinate(msh)[0] - spec.disk_radius, ufl.max_value(s, 0.0))


def nodal_dofs(V, sub: int, points: np.ndarray, size: float) -> np.ndarray:
    """(k, 3) indices in V of sub-space ``sub`` (0: u, 1: theta) at its nodes at ``points`` owned here, -1 elsewhere."""
    Vs, to_parent = V.sub(sub).collapse()
    to_parent = np.asarray(to_parent).reshape(-1, 3)
    owned = V.dofmap.index_map.size_local
    nodes = Vs.tabulate_dof_coordinates()
    out = np.full((len(points), 3), -1, dtype=np.int64)
    for i, p in enumerate(points):
        dist = np.linalg.norm(nodes - p, axis=1)
        j = int(np.argmin(dist))
        if dist[j] < 1e-8 * size and np.all(to_parent[j] < owned):
            out[i] = to_parent[j]
    return out


def local_frame(msh):
    """(e_1, e_2, e_3) of each flat cell: e_1 along the Jacobian's first column, e_3 the normal."""
    J = ufl.Jacobian(msh)
    t1 = ufl.as_vector([J[i, 0] for i in range(3)])
    t2 = ufl.as_vector([J[i, 1] for i in range(3)])
    e3 = ufl.cross(t1, t2)
    e3 = e3 / ufl.sqrt(ufl.dot(e3, e3))
    e1 = t1 / ufl.sqrt(ufl.dot(t1, t1))
    return e1, ufl.cross(e3, e1), e3


@dataclass(frozen=True)
class Kinematics:
    """The shell's strain measures as UFL functions of (u, theta) on one mesh."""

    P: Any       # (3, 2) tangent frame [e_1 e_2]
    e3: Any

    def tgrad(self, w):
        return ufl.dot(ufl.grad(w), self.P)

    def membrane(self, u):
        return ufl.sym(ufl.dot(self.P.T, self.tgrad(u)))

    def bending(self, theta):
        return ufl.sym(ufl.dot(self.P.T, self.tgrad(ufl.cross(self.e3, theta))))

    def shear(self, u, theta):
        return self.tgrad(ufl.dot(u, self.e3)) - ufl.dot(self.P.T, ufl.cross(self.e3, theta))

    def drilling(self, u, theta):
        g = ufl.dot(self.P.T, self.tgrad(u))
        return 0.5 * (g[0, 1] - g[1, 0]) + ufl.dot(theta, self.e3)


def kinematics(msh) -> Kinematics:
    e1, e2, e3 = local_frame(msh)
    return Kinematics(P=ufl.as_matrix([[e1[i], e2[i]] for i in range(3)]), e3=e3)


def plane_stress(e, material: Material):
    """C : e for a 2 x 2 strain e, Pa."""
    E, nu = material.E, material.nu
    lam = E * nu / ((1 + nu) * (1 - 2 * nu))
    mu = E / (2 * (1 + nu))
    return 2 * lam * mu / (lam + 2 * mu) * ufl.tr(e) * ufl.Identity(2) + 2 * mu * e


def _dx(model: ShellModel):
    """Area measure knowing the blade/shroud cell tags (one measure for every form of a model)."""
    metadata = {} if model.quadrature_degree is None else {"quadrature_degree": model.quadrature_degree}
    return ufl.Measure("dx", domain=model.mesh, subdomain_data=model.cell_tags, metadata=metadata)


def _forms(model: ShellModel):
    """UFL forms of the unit-speed operators (Omega = e_Z x 1 rad/s), and the kinematics."""
    msh, mat, spec = model.mesh, model.material, model.spec
    (du, dth), (v, eta) = ufl.TrialFunctions(model.V), ufl.TestFunctions(model.V)
    k = kinematics(msh)
    h, rho = model.thickness, mat.rho
    G = mat.E / (2 * (1 + mat.nu))
    X = ufl.SpatialCoordinate(msh)
    Om = ufl.as_vector((0.0, 0.0, 1.0))
    dx = _dx(model)
    beta = spec.beta(X[0])
    e_v = ufl.as_vector((0.0, ufl.cos(beta), ufl.sin(beta)))
    drill = model.drilling * mat.E * h**3 / ufl.CellDiameter(msh) ** 2
    k_e = (ufl.inner(h * plane_stress(k.membrane(du), mat), k.membrane(v))
           + ufl.inner(h**3 / 12 * plane_stress(k.bending(dth), mat), k.bending(eta))
           + SHEAR_CORRECTION * G * h * ufl.dot(k.shear(du, dth), k.shear(v, eta))
           + drill * k.drilling(du, dth) * k.drilling(v, eta)) * dx
    # The material of a cell sits ``offset`` out along +X from it (the shroud plate's, at the box's
    # centre plane): it moves with U = u + theta x (d e_X) and is spun at X + d.
    d = model.offset
    dU, V = carried(model, du, dth), carried(model, v, eta)
    m = (rho * h * ufl.dot(dU, V)
         + rho * h**3 / 12 * ufl.dot(ufl.cross(k.e3, dth), ufl.cross(k.e3, eta))) * dx
    return k, dict(
        m=m, k_e=k_e,
        k_spin=-rho * h * ufl.inner(ufl.cross(Om, dU), ufl.cross(Om, V)) * dx,
        g=2.0 * rho * h * ufl.inner(ufl.cross(Om, dU), V) * dx,
        f_c=rho * h * ufl.inner(ufl.as_vector((X[0] + d, X[1], 0.0)), V) * dx,
        f_aero=ufl.inner(e_v * h / spec.section_area(X[0] - spec.disk_radius), v) * dx(BLADE),
    )


def geometric_stiffness(model: ShellModel, k: Kinematics, u0: fem.Function):
    """The prestress stiffness of the state ``u0`` at 1 rad/s on the test pair: int N0 : (grad_t du^T grad_t v),
    the membrane forces N0 (N/m), plus that of the offset material's arm (:func:`arm_stiffness`)."""
    (du, dth), (v, eta) = ufl.TrialFunctions(model.V), ufl.TestFunctions(model.V)
    u0_disp = ufl.split(u0)[0]
    N0 = model.thickness * plane_stress(k.membrane(u0_disp), model.material)
    return (ufl.inner(ufl.dot(k.tgrad(du), N0), k.tgrad(v)) + arm_stiffness(model, dth, eta)) * _dx(model)


def arm_stiffness(model: ShellModel, theta, eta):
    """The centrifugal load f (1 rad/s) on material carried at the arm r = d e_X (the shroud plate's, d = t_s/2)
    turned by theta: its second-order displacement theta x (theta x r) / 2 does work
    (f.r)(theta.eta) - ((f.theta)(r.eta) + (f.eta)(r.theta)) / 2 (per unit area).

    The solid has it as the radial tension of its shroud box (sigma_XX falling from m Omega^2 X_c / A at the
    blade's tip to 0 outside) in int sigma0 : grad u^T grad u: m Omega^2 X_c d per radian^2 of the box
    turning about an axis across X; the plate, which carries that load in bending, has no membrane force for it.
    """
    X = ufl.SpatialCoordinate(model.mesh)
    d = model.offset
    f = model.material.rho * model.thickness * ufl.as_vector((X[0] + d, X[1], 0.0))
    r = d * ufl.as_vector((1.0, 0.0, 0.0))
    return (ufl.dot(f, r) * ufl.dot(theta, eta)
            - 0.5 * (ufl.dot(f, theta) * ufl.dot(r, eta) + ufl.dot(f, eta) * ufl.dot(r, theta)))


@functools.lru_cache(maxsize=4)
def _unit_operators(model: ShellModel) -> UnitOperators:
    k, forms = _forms(model)
    return unit_operators_from(model, forms, lambda u0: geometric_stiffness(model, k, u0))


def rotating_operators(params: Parameters, rpm: float | None = None) -> RotatingOperators:
    """M, K(Omega), G(Omega), the loads and the prestatic state of the shell at ``rpm`` (SI)."""
    return operators_at(shell_model(params), params.speed.rpm if rpm is None else rpm)


def operators_at(model: ShellModel, rpm: float) -> RotatingOperators:
    return RotatingOperators.at(model, _unit_operators(model), rpm)


def carried(model: ShellModel, u, theta):
    """The displacement of the material a cell carries: u + theta x (d e_X), d = ``model.offset``
    (t_s/2 on the shroud plate, whose material sits at the box's centre plane; 0 on the blade)."""
    return u + model.offset * ufl.cross(theta, ufl.as_vector((1.0, 0.0, 0.0)))


def tip_load(model: ShellModel, force: np.ndarray):
    """The load vector of ``force`` (N, global X, Y, Z) spread evenly over the shroud plate's material
    (at the box's centre plane, as the solid's over its box), or over the tip line."""
    v = carried(model, *ufl.TestFunctions(model.V))
    msh = model.mesh
    if model.spec.has_shroud:
        measure = _dx(model)(SHROUD)
    else:
        measure = ufl.Measure("ds", domain=msh, subdomain_data=model.facet_tags)(TIP)
    one = fem.assemble_scalar(fem.form(fem.Constant(msh, 1.0) * measure))
    size = msh.comm.allreduce(one)
    F = fem.Constant(msh, np.asarray(force, dtype=float) / size)
    return assemble_vector(ufl.inner(F, v) * measure, model.bcs)


def contact_faces(model: ShellModel, params: Parameters):
    """The two contact faces (reference_fe.contact_faces.ContactFace), side 1 then side 2.

    A face of the solid's shroud box (l_s along e_ws, t_s along X) is here
    the plate's edge at v_s = -/+ b_s/2, cut into ``shell.contact_points``
    equal segments: a contact point at each segment's midpoint carries the
    segment's share of the face (1/n each), and sits on the face's centre
    line, t_s/2 out along X from the plate: it moves by u + theta x (t_s/2) e_X
    with u and theta the P2 and CR nodal values at the segment's midpoint.
    """
    from reference_fe.contact_faces import ContactFace, tip_frame

    spec, frame = model.spec, tip_frame(params)
    n = spec.contact_points
    w_s = (np.arange(n) + 0.5) / n * spec.shroud_length - 0.5 * spec.shroud_length
    faces = []
    for side, v_s in ((1, -0.5 * spec.shroud_width), (2, 0.5 * spec.shroud_width)):
        points = np.array([spec.tip_x, 0.0, 0.0]) + v_s * frame.e_vs + w_s[:, None] * frame.e_ws[None, :]
        faces.append(ContactFace(side=side, dofs=_global_nodes(model, 0, points, side),
                                 weight=np.full(n, 1.0 / n), area=spec.shroud_length * spec.shroud_thickness,
                                 coords=points + 0.5 * spec.shroud_thickness * np.array([1.0, 0.0, 0.0]),
                                 rotation_dofs=_global_nodes(model, 1, points, side),
                                 arm=np.array([0.5 * spec.shroud_thickness, 0.0, 0.0])))
    return tuple(faces)


def _global_nodes(model: ShellModel, sub: int, points: np.ndarray, side: int) -> np.ndarray:
    """(k, 3) global indices of sub-space ``sub`` (0: u, 1: theta) at the nodes at ``points``, on every rank."""
    from reference_fe.distributed import global_offset

    local = nodal_dofs(model.V, sub, points, model.spec.size)
    found = np.max(model.comm.allgather(np.where(local >= 0, local + global_offset(model.V), -1)), axis=0)
    if np.any(found < 0):
        raise RuntimeError(f"shell contact face {side}: {int(np.sum(found[:, 0] < 0))} points are not nodes "
                           f"of sub-space {sub}")
    return found
