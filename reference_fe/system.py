"""The solid blade as a shroud.core.system.StructuralSystem: models "fe" and "fe-reduced".

    M q'' + (D + G) q' + (K_e + K_sigma + K_spin) q = f_aero F0 sin(ke Omega t) + W^T lam(W q)

(paper Eq. 9 for the 3D solid; operators from reference_fe.solid). ``q`` is
the displacement measured from the centrifugal equilibrium u0 about which
the stiffness is linearized (K_e u0 = f_c, linear prestress), so the
constant centrifugal load does not appear: the neighbours sit in the same
steady state (cyclic symmetry), and N0 is the preload at the running speed.
At 10000 r/min u0 moves the contact faces by 0.2 um along the contact
normal, against vibration amplitudes of tens of um.

D = alpha M + beta K is Rayleigh damping (Eq. 2) on the first two undamped
frequencies at the run's speed (without Coriolis, as the beam model).

Contact: one element per contact-face node with its area share of the
side's k_n, k_t and N_0 (reference_fe.contact_faces); the tip outputs
v_L, w_L are the shroud centre's displacement along e_v(L), e_w(L).

"fe-reduced" projects all of it on the free-interface basis of
reference_fe.cms: ``fe.cms_modes`` normal modes plus the residual
attachment modes of the aerodynamic load and of the contact forces: of
every contact-node direction, or (``fe.interface_modes = k > 0``) of the k
principal face-force patterns of the residual face flexibility. The basis
makes M = I and K diagonal; the reduced operators are cached on disk by
what shapes them (mesh, material, speed, kept modes and patterns), so a
second run at the same speed does not touch DOLFINx at all.

"fe" is scipy sparse on the free DOFs serially and row-distributed under
mpirun (reference_fe.distributed: MatMult and MUMPS over the ranks,
vectors replicated); the time loop of shroud.core.newmark factorizes the step
operator once (MUMPS LU) and condenses the contact onto the face nodes, so
a step is one back-substitution plus a small contact solve. The reduction
basis of "fe-reduced" is built serially: under mpirun rank 0 builds it into
the disk cache and every rank reads it.
"""

from __future__ import annotations

import dataclasses
import functools
import math
import time
from pathlib import Path

import numpy as np
import scipy.sparse as sp

from shroud.base.blas import single_threaded_blas
from shroud.base.cache import cached
from shroud.base.errors import InputError
from shroud.base.resources import in_words, physical_memory
from shroud.core.damping import rayleigh
from shroud.params import Parameters
from shroud.base.parallel import on_rank_zero
from shroud.core.system import ContactElements, StructuralSystem


@dataclasses.dataclass(frozen=True)
class _Solid:
    """The full solid at one speed on its free DOFs, with its contact and tip rows."""

    M: sp.csr_matrix
    K: sp.csr_matrix
    G: sp.csr_matrix
    f_aero: np.ndarray           # F_e = 1 N/m along e_v over the blade
    tip: sp.csr_matrix           # (2, n)
    contact: ContactElements | None


def _has_contact(params: Parameters) -> bool:
    return params.contact.enabled and params.shroud.thickness > 0


def _solid(params: Parameters, rpm: float, kind: str = "fe") -> _Solid:
    """The full model ``kind`` ("fe": the solid; "shell": reference_fe.shell) at ``rpm`` on its free DOFs."""
    from reference_fe.contact_faces import contact_elements, tip_frame, tip_rows
    from reference_fe.solid import tip_centre_dofs

    # F_e per unit span needs the section area along the span, which a STEP file does not name.
    params.blade.check_modelled(profile=True)
    if kind == "shell":
        from reference_fe.shell import contact_faces, rotating_operators, shell_model
        model = shell_model(params)
        faces = (lambda: contact_faces(model, params))
    else:
        from reference_fe.contact_faces import contact_faces
        from reference_fe.solid import rotating_operators, solid_model
        model = solid_model(params)
        faces = (lambda: contact_faces(model.V, model.facet_tags, model.contact_tags, params))
    ops = rotating_operators(params, rpm).free()
    frame = tip_frame(params)
    if params.shroud.thickness > 0:
        faces = faces()
        tip = tip_rows(faces, frame, ops.free_index, ops.n)
        contact = contact_elements(faces, frame, ops.free_index, ops.n) if _has_contact(params) else None
    else:                               # no shroud: the tip-centre node
        centre = ops.free_index[tip_centre_dofs(model)]
        tip = sp.csr_matrix((np.concatenate([frame.e_v, frame.e_w]),
                             (np.repeat([0, 1], 3), np.tile(centre, 2))), shape=(2, ops.n))
        contact = None
    return _Solid(M=ops.M, K=ops.K, G=ops.G, f_aero=ops.f_aero, tip=tip, contact=contact)


def build_system(params: Parameters, reduced: bool, kind: str = "fe") -> StructuralSystem:
    """The "fe" (``reduced=False``) or "fe-reduced" system at ``params.speed.rpm``; ``kind="shell"``: the shell's."""
    t0 = time.perf_counter()
    system = reduced_system(params, kind) if reduced else full_system(params, kind)
    return dataclasses.replace(system, build_s=time.perf_counter() - t0)


def full_system(params: Parameters, kind: str = "fe") -> StructuralSystem:
    """The solid (shell) FE model on its free DOFs (scipy sparse, or row-distributed under mpirun), SI units."""
    from reference_fe.cms import normal_modes
    from reference_fe.factor import METIS_ORDERING, PORD_ORDERING, MumpsFactor, mumps_lu

    solid = _solid(params, params.speed.rpm, kind)
    if kind == "shell":
        solid = _on_every_rank(solid)
    with MumpsFactor(solid.K) as lu:
        omega2, _ = normal_modes(solid.K, solid.M, 2, lu)
    f1, f2 = np.sqrt(omega2) / (2 * math.pi)
    a, b = rayleigh(f1, f2, params.damping.xi1, params.damping.xi2)
    n = solid.M.shape[0]
    return StructuralSystem(
        model=kind, M=solid.M, C=a * solid.M + b * solid.K + solid.G, K=solid.K,
        f_const=np.zeros(n), f_aero=params.load.F0 * solid.f_aero,
        omega_e=params.load.ke * params.speed.omega, tip=solid.tip, contact=solid.contact,
        factorize=functools.partial(mumps_lu, ordering=PORD_ORDERING if kind == "shell" else METIS_ORDERING),
        layout=getattr(solid.M, "layout", None), rayleigh=(float(a), float(b)))


def _on_every_rank(solid: _Solid) -> _Solid:
    """The whole model on every rank (scipy CSR): under mpirun each rank then integrates it alone.

    The shell's factor is small (2D: 10k DOF, 1.7 M entries, a 1.4-2 ms
    back-substitution on one process), and spread over the ranks its solve
    is mostly messages, each one a wait for the other rank's core: on 2
    ranks of the loaded machine a distributed solve took 2.6-7.2 ms of CPU
    and 10-38 ms of wall time, a rank solving alone 1.9-2.2 ms and 7-11 ms
    (docs/shell.md, "Cost"). Every rank computes the same trajectory, with
    no message per step; the solid's 3D factors stay spread over the ranks.
    """
    from reference_fe.distributed import DistributedMatrix
    if not isinstance(solid.M, DistributedMatrix):
        return solid
    return dataclasses.replace(solid, M=solid.M.whole(), K=solid.K.whole(), G=solid.G.whole())


def _kept(params: Parameters, kind: str) -> tuple[int, int]:
    """(normal modes, contact-face patterns; 0 = all) the reduction of ``kind`` keeps.

    The shell's contact points are few (shell.contact_points per face): all their patterns are kept.
    """
    return (params.shell.cms_modes, 0) if kind == "shell" else (params.fe.cms_modes, params.fe.interface_modes)


def reduction_inputs(params: Parameters, rpm: float, kind: str = "fe") -> dict:
    """Exactly what shapes the reduced operators (the cache key)."""
    if kind == "shell":
        from meshes.shell import ShellSpec as Spec
    else:
        from meshes.blade import MeshSpec as Spec
    modes, patterns = _kept(params, kind)
    return {"mesh": dataclasses.asdict(Spec.from_params(params)),
            "material": dataclasses.asdict(params.material), "rpm": float(rpm),
            "cms_modes": modes, "interface_modes": patterns, "contact": _has_contact(params)}


def reduced_operators(params: Parameters, rpm: float | None = None, kind: str = "fe") -> Path:
    """Path of the cached .npz of the reduced operators at ``rpm`` (built if missing)."""
    rpm = params.speed.rpm if rpm is None else float(rpm)
    # The basis is built serially (scipy): under mpirun rank 0 builds it into the cache for all.
    return on_rank_zero(lambda: cached(f"{'shell' if kind == 'shell' else 'fe'}_reduction",
                                       reduction_inputs(params, rpm, kind), ".npz",
                                       lambda path: _build_reduction(params, rpm, path, kind),
                                       what=f"{kind} reduction basis", sources=REDUCTION_SOURCES[kind],
                                       check=_check_npz))


# The code that shapes the reduced operators: editing any of it builds them anew.
_COMMON_SOURCES = ("reference_fe.contact_faces", "reference_fe.solid", "reference_fe.cms", __name__)
REDUCTION_SOURCES = {"fe": ("meshes.blade", *_COMMON_SOURCES),
                     "shell": ("meshes.shell", "reference_fe.shell", *_COMMON_SOURCES)}


def _check_npz(path: Path) -> None:
    """Read every array of the .npz (zip CRCs checked): raises if the file was cut short."""
    with np.load(path) as data:
        for name in data.files:
            data[name]


def _build_reduction(params: Parameters, rpm: float, path: Path, kind: str = "fe") -> None:
    """The reduced operators into ``path``, on one BLAS thread (shroud.base.blas: the basis is a chain
    of small BLAS calls between MUMPS solves, which the process's four OpenBLAS pools slowed 2-4x in
    a third to a half of the runs on the 2-core machine)."""
    import reference_fe.solid  # noqa: F401  (DOLFINx and PETSc, and the OpenBLAS each brings, loaded first)

    with single_threaded_blas():
        _write_reduction(params, rpm, path, kind)


def check_reduction_sizes(params: Parameters, dofs: int, patterns: int, kind: str = "fe") -> None:
    """Refuse (InputError) kept counts this model does not have, once it is assembled, before any mode is solved.

    ``dofs``: the model's free DOF; ``patterns``: its contact-face coordinates (the face-force
    patterns the reduction chooses among). The basis is dense, dofs x (modes + patterns), and
    the eigensolver works on about twice the kept modes: 8 dofs (3 modes + 2 patterns) bytes.
    """
    modes, chosen = _kept(params, kind)
    section = "shell" if kind == "shell" else "fe"
    size = params.shell.mesh_size if kind == "shell" else params.fe.mesh_size
    if modes >= dofs:
        raise InputError(f"{section}.cms_modes", f"{modes} modes asked of a {kind} model with {dofs} DOF "
                         f"({section}.mesh_size {size:g} m); allowed: 1 .. {dofs - 1}")
    if chosen > patterns:
        raise InputError("fe.interface_modes", f"{chosen} is more than the {patterns} contact-face "
                         f"patterns of this mesh; allowed: 0 (all of them) .. {patterns}")
    kept = chosen or patterns
    need, memory = 8.0 * dofs * (3 * modes + 2 * kept), physical_memory()
    if need > memory:
        most = int((memory / (8.0 * dofs) - 2 * kept) / 3)
        raise InputError(f"{section}.cms_modes", f"{modes} modes of a {kind} model with {dofs} DOF need about "
                         f"{in_words(need)}; this machine has {in_words(memory)}; allowed: at most {max(most, 1)} here")


def _write_reduction(params: Parameters, rpm: float, path: Path, kind: str) -> None:
    from reference_fe.cms import free_interface_basis, project
    from reference_fe.factor import MumpsFactor
    from shroud.base.log import info

    solid = _solid(params, rpm, kind)
    modes, patterns = _kept(params, kind)
    W = solid.contact.W if solid.contact is not None else sp.csr_matrix((0, solid.M.shape[0]))
    check_reduction_sizes(params, solid.M.shape[0], W.shape[0], kind)
    t0 = time.perf_counter()
    with MumpsFactor(solid.K) as lu:
        basis = free_interface_basis(solid.K, solid.M, modes, solid.f_aero[:, None],
                                     lu=lu, W=W, interface_modes=patterns)
    info(f"{kind} reduction at {rpm:g} r/min: {solid.M.shape[0]} DOF -> {basis.n_modes} modes + "
         f"{basis.n_attachment} attachment modes ({patterns or 'all'} of {W.shape[0]} "
         f"contact-face patterns) in {time.perf_counter() - t0:.1f} s")
    T = basis.T
    contact = solid.contact
    with open(path, "wb") as fh:
        np.savez(fh, omega2=basis.omega2, n_modes=basis.n_modes, full_dofs=solid.M.shape[0],
                 G=project(basis, solid.G), f_aero=T.T @ solid.f_aero, tip=np.asarray(solid.tip @ T),
                 W=np.asarray(W @ T),
                 normal_row=contact.normal_row if contact else np.zeros(0, int),
                 tangent_row=contact.tangent_row if contact else np.zeros(0, int),
                 side=contact.side if contact else np.zeros(0, int),
                 weight=contact.weight if contact else np.zeros(0))


def reduced_system(params: Parameters, kind: str = "fe") -> StructuralSystem:
    """The solid (shell) projected on its free-interface basis (dense, M = I, K diagonal), SI units."""
    with np.load(reduced_operators(params, kind=kind)) as data:
        d = {k: data[k] for k in data.files}
    omega2 = d["omega2"]
    f1, f2 = np.sqrt(omega2[:2]) / (2 * math.pi)        # the two lowest normal modes lead the basis
    a, b = rayleigh(f1, f2, params.damping.xi1, params.damping.xi2)
    r = omega2.size
    contact = None
    if d["side"].size:
        contact = ContactElements(W=d["W"], normal_row=d["normal_row"], tangent_row=d["tangent_row"],
                                  side=d["side"], weight=d["weight"])
    return StructuralSystem(
        model=f"{kind}-reduced", M=np.eye(r), C=np.diag(a + b * omega2) + d["G"], K=np.diag(omega2),
        f_const=np.zeros(r), f_aero=params.load.F0 * d["f_aero"],
        omega_e=params.load.ke * params.speed.omega, tip=d["tip"], contact=contact, rayleigh=(float(a), float(b)))
