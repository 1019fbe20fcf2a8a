"""The blade and shroud from the user's STEP file (``blade.step``), tagged as meshes.blade tags its own.

shared/spec/geometry.md, "Airfoil blades and the user's own CAD": X radial
with the root face in the plane X = R_d (``blade.disk_radius``), Z the
rotation axis, lengths in metres (gmsh's OpenCASCADE reader converts the
file's declared length unit to metres). The root face is the face in that
plane; the two shroud contact faces are the planar faces whose outward
normals lie closest to -e_vs (side 1) and +e_vs (side 2), e_vs the tip
frame turned by alpha (paper Eq. 7, from blade.stagger_deg,
blade.twist_deg and contact.alpha_deg), within :data:`MAX_NORMAL_DEG`; or
the faces the file names ``root``, ``contact1``, ``contact2``. The whole
solid is the blade's volume (the file names no blade/shroud split), its
tip points (meshes.spec.tip_points, from the blade.* keys) embedded in it.

Everything wrong with the file is an InputError on ``blade.step``: no file
gmsh reads as STEP, no solid, lengths 1000 times off (a file in
millimetres declared as metres, or the reverse: these three by
reduced_model.step_slices.read_solid, which the beams' slices share), no
face in the root plane, no contact faces.
"""

from __future__ import annotations

import math

import numpy as np

from meshes.spec import BLADE, CONTACT_SIDE1, CONTACT_SIDE2, ROOT, MeshSpec, embed_tip_points, shroud_frame
from reduced_model.step_slices import read_solid
from shroud.base.errors import InputError

# A contact face's outward normal may turn this far from -/+ e_vs: the contact law acts along e_vs,
# so a face much further off is not the shroud face the keys describe.
MAX_NORMAL_DEG = 1.0


def _refuse(spec: MeshSpec, message: str) -> InputError:
    return InputError("blade.step", f"{spec.step!r} {message}")


def _named(gmsh, names: tuple[str, ...]) -> dict[str, list[int]]:
    """Faces the file names (entity labels, or physical groups of dimension 2), by name."""
    found: dict[str, list[int]] = {}
    model = gmsh.model
    for _, tag in model.getEntities(2):
        name = model.getEntityName(2, tag).split("/")[-1].strip().lower()
        if name in names:
            found.setdefault(name, []).append(tag)
    for dim, group in model.getPhysicalGroups(2):
        name = model.getPhysicalName(dim, group).strip().lower()
        if name in names:
            found.setdefault(name, []).extend(model.getEntitiesForPhysicalGroup(dim, group))
    return found


def _outward_normal(gmsh, tag: int, volumes: list[int], tol: float) -> tuple[np.ndarray, np.ndarray]:
    """A point of face ``tag`` and the face's outward unit normal there."""
    model = gmsh.model
    point, uv = model.getClosestPoint(2, tag, model.occ.getCenterOfMass(2, tag))
    normal = np.asarray(model.getNormal(tag, uv))
    probe = np.asarray(point) + tol * normal
    if any(model.isInside(3, v, list(probe)) for v in volumes):
        normal = -normal
    return np.asarray(point), normal


def _found_faces(gmsh, spec: MeshSpec, volumes: list[int]) -> tuple[list[int], list[int], list[int]]:
    """(root, side 1, side 2) face tags: named in the file, else found by position and normal."""
    model = gmsh.model
    named = _named(gmsh, ("root", "contact1", "contact2"))
    tol = 1e-3 * min(spec.thickness, spec.tip_thickness)    # far above OCC's box padding, below any feature
    root = named.get("root") or [tag for _, tag in model.getEntities(2)
                                 if abs(model.getBoundingBox(2, tag)[0] - spec.disk_radius) < tol
                                 and abs(model.getBoundingBox(2, tag)[3] - spec.disk_radius) < tol]
    if not root:
        raise _refuse(spec, f"has no face in the root plane X = blade.disk_radius = {spec.disk_radius:g} m "
                            f"(the solid spans X = {model.getBoundingBox(-1, -1)[0]:.4g} .. "
                            f"{model.getBoundingBox(-1, -1)[3]:.4g} m); allowed: a blade whose root face lies "
                            "in that plane, or a face named root")
    if model.getBoundingBox(-1, -1)[0] < spec.disk_radius - tol:
        raise _refuse(spec, f"reaches X = {model.getBoundingBox(-1, -1)[0]:.4g} m, inside the disk "
                            f"(blade.disk_radius {spec.disk_radius:g} m); allowed: a solid from its root plane out")
    if not spec.has_shroud:
        return root, [], []
    if "contact1" in named and "contact2" in named:
        return root, named["contact1"], named["contact2"]
    e_vs, _ = shroud_frame(spec)
    planes = []                                   # (e_vs . outward normal, e_vs . point, tag)
    for _, tag in model.getEntities(2):
        if tag not in root and model.getType(2, tag) == "Plane":
            point, normal = _outward_normal(gmsh, tag, volumes, tol)
            planes.append((float(normal @ e_vs), float(point @ e_vs), tag))
    least = math.cos(math.radians(MAX_NORMAL_DEG))
    sides = []
    for sign in (-1.0, 1.0):
        facing = [(sign * n, sign * p, tag) for n, p, tag in planes if sign * n >= least]
        if not facing:
            raise _refuse(spec, f"has no planar face whose outward normal lies within {MAX_NORMAL_DEG:g} deg of "
                                f"{'-+'[sign > 0]}e_vs = {np.round(sign * e_vs, 4).tolist()} (the shroud contact "
                                "faces, from blade.stagger_deg + blade.twist_deg + contact.alpha_deg); allowed: a "
                                "shroud with those faces, or faces named contact1 and contact2")
        outermost = max(p for _, p, _ in facing)                   # the face furthest out along its normal
        sides.append([tag for _, p, tag in facing if p > outermost - tol])
    return root, sides[0], sides[1]


def build_from_step(gmsh, spec: MeshSpec) -> float:
    """The STEP file's solid in the current gmsh model, with meshes.blade's physical groups; its
    volume, m^3 (for meshes.blade.check_mesh_size)."""
    volumes = read_solid(gmsh, spec.step, spec.disk_radius)
    root, side1, side2 = _found_faces(gmsh, spec, volumes)
    model = gmsh.model
    model.addPhysicalGroup(2, root, ROOT, name="root")
    if spec.has_shroud:
        model.addPhysicalGroup(2, side1, CONTACT_SIDE1, name="contact_side1")
        model.addPhysicalGroup(2, side2, CONTACT_SIDE2, name="contact_side2")
    model.addPhysicalGroup(3, volumes, BLADE, name="blade")
    embed_tip_points(model, spec)
    return sum(model.occ.getMass(3, v) for v in volumes)

