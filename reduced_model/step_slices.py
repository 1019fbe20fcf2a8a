"""The user's STEP blade (``blade.step``) cut into cross-sections for the beams.

shared/spec/geometry.md, "Airfoil blades and the user's own CAD": X radial
with the root face in the plane X = R_d (``blade.disk_radius``), Z the
rotation axis, metres after gmsh's OpenCASCADE reader converts the file's
declared unit. The solid is cut by the planes X = R_d + x_k at
:func:`slice_stations` (gmsh's ``occ.intersect`` of the solid with a plane
face), each cut's boundary curves sampled into closed polygons (edges
turning at most :data:`TURN_DEG` and no longer than the section mesh's
size), and the polygons, written in the section frame of the blade.* keys
(e_v = (0, cos beta, sin beta), e_w = (0, -sin beta, cos beta), beta(x) =
beta_1 + beta_t x / L), go to reduced_model.section_mesh: area, centroid,
principal axes, J, shear centre, Cowper's coefficients by P2 triangles on
the slice itself (no staircase). reduced_model.airfoil.span_sections joins
the stations as it joins the NACA profile's.

The keys describe the blade; the file must agree with them, or the beam
would be another blade's (each an InputError, one line, exit 2):
* the solid spans X = R_d .. R_d + L + t_s (``blade.length``,
  ``shroud.thickness``), its shroud cut half-way up has the area l_s b_s
  of the shroud keys (the beam's shroud body is theirs);
* every slice's centroid lies on the X axis (the beam stacks its sections
  on their centroids) within :data:`CENTROID_SLACK` of its chord;
* the twist: each slice's principal axes give its angle; their turn from
  the first station to the last is the keys' beta_t (x_last - x_first) / L
  within :data:`TWIST_SLACK_DEG` (the pretwist rate enters the beam's
  extension-twist coupling). The stagger itself is not held to the axes: a
  cambered profile's principal axes are turned from its chord (0.17 deg
  for the spec's NACA root, tens of degrees for a turbine profile), and
  the frame's choice changes nothing of the section (I_vw carries it).

gmsh is imported here only when a file is sliced: importing reduced_model
never loads it. The file is read by :func:`read_solid`, which meshes.step
shares (its refusals of a file gmsh cannot read, holds no solid, or whose
units are off by 1000).
"""

from __future__ import annotations

import dataclasses
import functools
import hashlib
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from shroud.base.cache import cached
from shroud.base.errors import InputError
from shroud.base.log import info
from shroud.params import Blade, Shroud
from reduced_model.section import SectionProperties
from reduced_model.section_mesh import inside_polygon, section_on_mesh

STEP_STATIONS = 5          # slices along the span: a file's sections may change shape more than a NACA taper
SLICE_INSET = 1e-3         # the first and last slices this share of L inside root and tip (off the faces there)
TURN_DEG = 3.0             # a polygon edge turns the sampled curve by at most this (sagitta 3.4e-4 x radius)
SAMPLES = 2001             # points per curve parameter range from which the polygon's vertices are drawn
MESH_CELLS_THICK = 11      # P2 triangles' size: the mean thickness (area / chord) over this (NACA: t / 16, as airfoil)
CENTROID_SLACK = 2e-3      # a slice's centroid may lie this share of its chord off the X axis
TWIST_SLACK_DEG = 1.0      # the slices' principal axes may turn this much more or less than the keys' twist
SHROUD_AREA_SLACK = 0.01   # the file's shroud section against l_s b_s, relative
UNIT_SLACK = 2.0           # lengths whose root lies this close to 1000 or 1/1000 times R_d: a unit mix-up
LENGTH_SLACK = 1e-3        # the solid's outer end against R_d + L + t_s, share of L
# OpenCASCADE's boolean cut of a B-spline loft fails now and then with a plane near one of the loft's own
# sections (no face, or a curve that does not close): such a cut is made again this share of L away
NUDGE = 1e-3
NUDGES = (0, 1, -1, 2, -2, 3, -3)
PAD = 0.1                  # the cutting plane's face reaches this share of the solid's width beyond it
CLOSURE = 2e-4             # a cut's curves join where their ends meet within this share of the solid's width


def _refuse(path: str, message: str) -> InputError:
    return InputError("blade.step", f"{path!r} {message}")


def step_digest(path: str) -> str:
    """sha256 of the STEP file's bytes; InputError on blade.step when it cannot be read."""
    try:
        return hashlib.sha256(Path(path).read_bytes()).hexdigest()
    except OSError as exc:
        raise InputError("blade.step", f"{path!r} cannot be read ({exc.strerror or exc}); "
                                       "allowed: a readable STEP file") from None


def read_solid(gmsh, path: str, disk_radius: float) -> list[int]:
    """Read the STEP file ``path`` into the current gmsh model (lengths converted to metres): its volumes'
    tags, made one conforming body; InputError on blade.step for a file gmsh cannot read, one without a
    solid, or one whose root lies 1000 times too far out or in (``disk_radius`` R_d, m)."""
    occ = gmsh.model.occ
    gmsh.option.setString("Geometry.OCCTargetUnit", "M")
    try:
        entities = occ.importShapes(path, highestDimOnly=False, format="step")
    except Exception as exc:            # gmsh raises Exception with its own message
        reason = str(exc).splitlines()[0] if str(exc) else "unreadable"
        raise _refuse(path, f"is not a STEP file gmsh can read ({reason}); allowed: a STEP (AP203/AP214) "
                            "file of blade and shroud") from None
    volumes = [(d, t) for d, t in entities if d == 3]
    if not volumes:
        raise _refuse(path, f"holds no solid ({len(entities)} curves and surfaces); allowed: a file of one "
                            "closed solid of blade and shroud")
    if len(volumes) > 1:
        volumes, _ = occ.fragment(volumes, [])       # one conforming body
    occ.synchronize()
    x_min = gmsh.model.getBoundingBox(-1, -1)[0]
    ratio = x_min / disk_radius
    for factor, words in ((1e3, "millimetres read as metres"), (1e-3, "metres read as millimetres")):
        if factor / UNIT_SLACK < ratio < factor * UNIT_SLACK:
            raise _refuse(path, f"has its root at X = {x_min:.4g} m, {ratio:.4g} x blade.disk_radius "
                                f"{disk_radius:g} m: its units are off by 1000 ({words}); allowed: "
                                "a file whose length unit matches its numbers (metres after conversion)")
    return [t for _, t in volumes]


def slice_stations(blade: Blade, count: int = STEP_STATIONS) -> np.ndarray:
    """Where the solid is cut, m from the root: ``count`` Chebyshev-Lobatto points on [d, L - d], d =
    SLICE_INSET L (a plane through the root face or the shroud's underside would cut a face, not a
    section); a cut OpenCASCADE fails is made again up to 3 NUDGE L away (inside [d, L - d])."""
    inset = SLICE_INSET * blade.length
    return inset + 0.5 * (blade.length - 2 * inset) * (1.0 - np.cos(np.pi * np.arange(count) / (count - 1)))


def _chained(pieces: list[np.ndarray], tol: float) -> list[np.ndarray]:
    """Closed loops (n, 2) from oriented polylines whose ends meet within ``tol`` (each loop's points once)."""
    loops, left = [], list(pieces)
    while left:
        loop = [left.pop(0)]
        while np.linalg.norm(loop[-1][-1] - loop[0][0]) > tol:
            gaps = [min(np.linalg.norm(p[0] - loop[-1][-1]), np.linalg.norm(p[-1] - loop[-1][-1])) for p in left]
            if not gaps or min(gaps) > tol:
                raise ValueError("a section's boundary curves do not close")
            k = int(np.argmin(gaps))
            piece = left.pop(k)
            loop.append(piece if np.linalg.norm(piece[0] - loop[-1][-1]) <= tol else piece[::-1])
        loops.append(np.concatenate([p[:-1] for p in loop]))
    return loops


def _thinned(points: np.ndarray, spacing: float) -> np.ndarray:
    """The vertices of the densely sampled polyline ``points`` (closed loop) kept so that each edge turns by
    about TURN_DEG at most and is about ``spacing`` long at most (to within one sample's share; corners,
    where the direction jumps by more than TURN_DEG, always kept)."""
    edge = np.roll(points, -1, axis=0) - points
    length = np.linalg.norm(edge, axis=1)
    heading = np.arctan2(edge[:, 1], edge[:, 0])
    turn = np.abs(np.angle(np.exp(1j * (heading - np.roll(heading, 1)))))
    budget = np.cumsum(turn / math.radians(TURN_DEG) + length / spacing)
    keep = np.flatnonzero(np.diff(np.floor(budget), prepend=-1.0) > 0)
    return points[np.union1d(keep, np.flatnonzero(turn > math.radians(TURN_DEG)))]


def _plane(occ, X: float, box: tuple) -> tuple[int, int]:
    """A square face in the plane X, reaching PAD of the solid's width beyond its bounding ``box``."""
    _, y0, z0, _, y1, z1 = box
    pad = PAD * max(y1 - y0, z1 - z0)
    plane = occ.addRectangle(y0 - pad, z0 - pad, 0.0, y1 - y0 + 2 * pad, z1 - z0 + 2 * pad)
    occ.rotate([(2, plane)], 0, 0, 0, 1, 1, 1, 2 * math.pi / 3)       # (x, y, z) -> (z, x, y): the plane X = 0
    occ.translate([(2, plane)], X, 0, 0)
    return 2, plane


def _cut(gmsh, volumes: list[int], X: float, box: tuple) -> list[np.ndarray]:
    """Closed polygons (Y, Z), m, of the solid's section by the plane X (densely sampled): the common part of
    the solid and the plane, or where OpenCASCADE finds none (it fails so on some B-spline lofts: 25 of 60
    planes of a loft through closed splines), the plane's pieces inside the solid by the general fuse of a
    copy of the solid with the plane (2 of the same 60 fail); ValueError when both fail."""
    occ, model = gmsh.model.occ, gmsh.model
    crossing = [(3, v) for v in volumes if model.getBoundingBox(3, v)[0] < X < model.getBoundingBox(3, v)[3]]
    faces, _ = occ.intersect(crossing, [_plane(occ, X, box)], removeObject=False, removeTool=True)
    made = faces
    if not faces:
        made, parts = occ.fragment(occ.copy(crossing), [_plane(occ, X, box)])
        occ.synchronize()
        inside = box[1] - 0.5 * PAD * max(box[4] - box[1], box[5] - box[2])     # the outer piece reaches the pad
        faces = [piece for piece in parts[-1] if model.getBoundingBox(*piece)[1] > inside]
    occ.synchronize()
    pieces = []
    for _, curve in model.getBoundary(faces, oriented=True, combined=False):
        lo, hi = model.getParametrizationBounds(1, abs(curve))
        u = np.linspace(lo[0], hi[0], SAMPLES)
        xyz = np.reshape(model.getValue(1, abs(curve), u[::int(math.copysign(1, curve))]), (-1, 3))
        pieces.append(xyz[:, 1:])
    occ.remove(made, recursive=True)
    occ.synchronize()
    if not pieces:
        raise ValueError("the cut found no section")
    return _chained(pieces, tol=CLOSURE * max(box[4] - box[1], box[5] - box[2]))


def _sample(path: str, blade: Blade, shroud: Shroud, stations: np.ndarray, out) -> None:
    """Write the polygons (in the keys' section frames) of the solid's sections at ``stations`` to ``out``,
    once they pass the checks against the keys (:func:`_slices`)."""
    import gmsh
    gmsh.initialize(interruptible=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add("step_slices")
        volumes = read_solid(gmsh, path, blade.disk_radius)
        box = gmsh.model.getBoundingBox(-1, -1)
        top = blade.disk_radius + blade.length + shroud.thickness
        tol = LENGTH_SLACK * blade.length
        if abs(box[0] - blade.disk_radius) > tol or abs(box[3] - top) > tol:
            raise _refuse(path, f"spans X = {box[0]:.5g} .. {box[3]:.5g} m; the keys make the blade and shroud "
                                f"span {blade.disk_radius:g} .. {top:.5g} m (blade.disk_radius, blade.length, "
                                "shroud.thickness); allowed: keys that describe the file")
        planes = [[x + j * NUDGE * blade.length for j in NUDGES] for x in stations]
        planes = [[x for x in near if stations[0] <= x <= stations[-1]] for near in planes]
        if shroud.thickness > 0:
            planes.append([blade.length + 0.5 * shroud.thickness])
        cuts, cut_at = [], []
        for near in planes:
            for x in near:
                try:
                    cuts.append(_cut(gmsh, volumes, blade.disk_radius + x, box))
                    break
                except ValueError as exc:
                    reason = str(exc)
            else:
                raise _refuse(path, f"gives no closed section at x = {near[0]:.4g} m from the root, nor "
                                    f"{len(near) - 1} planes up to {max(NUDGES) * NUDGE:g} L on either side "
                                    f"({reason}); allowed: one closed solid of blade and shroud")
            cut_at.append(x)
    finally:
        gmsh.finalize()
    slices = _slices(path, blade, shroud, np.array(cut_at[:len(stations)]), cuts)
    np.savez(out, stations=slices.stations, principal=slices.principal,
             **{f"slice{k}_loop{j}": loop for k, loops in enumerate(slices.loops) for j, loop in enumerate(loops)})


@dataclass(frozen=True)
class Slices:
    """The file's sections at ``stations`` (m from the root): each an outline and its holes, (eta_v, eta_w)
    m in the keys' section frame at that x, and the angle of its principal axis nearest e_w from the keys'
    e_w, turned about +X, rad (the section's own angle is beta(x) + principal)."""

    stations: np.ndarray
    loops: tuple
    principal: np.ndarray


def _polygon_area(loop: np.ndarray) -> float:
    a, b = loop, np.roll(loop, -1, axis=0)
    return 0.5 * float(np.sum(a[:, 0] * b[:, 1] - b[:, 0] * a[:, 1]))


def _moments(loops: list[np.ndarray]) -> tuple[float, np.ndarray, np.ndarray]:
    """Area, centroid (2,) and second moments [[I_v, I_vw], [I_vw, I_w]] about it of the region the loops
    bound (outline less holes; any orientation), m^2, m, m^4: Green's theorem, exact for the polygons."""
    area, first, second = 0.0, np.zeros(2), np.zeros((2, 2))
    for k, loop in enumerate(loops):
        sign = (1.0 if k == 0 else -1.0) * math.copysign(1.0, _polygon_area(loop))
        (v0, w0), (v1, w1) = loop.T, np.roll(loop, -1, axis=0).T
        cross = sign * (v0 * w1 - v1 * w0)
        area += 0.5 * cross.sum()
        first += np.array([np.sum(cross * (v0 + v1)), np.sum(cross * (w0 + w1))]) / 6.0
        vv = np.sum(cross * (v0 * v0 + v0 * v1 + v1 * v1)) / 12.0
        ww = np.sum(cross * (w0 * w0 + w0 * w1 + w1 * w1)) / 12.0
        vw = np.sum(cross * (2 * v0 * w0 + v0 * w1 + v1 * w0 + 2 * v1 * w1)) / 24.0
        second += np.array([[vv, vw], [vw, ww]])
    centroid = first / area
    return area, centroid, second - area * np.outer(centroid, centroid)


def _slices(path: str, blade: Blade, shroud: Shroud, stations: np.ndarray, cuts: list) -> Slices:
    """The cuts (polygons (Y, Z)) in the keys' section frames, checked against the keys (module docstring):
    InputError otherwise."""
    if shroud.thickness > 0:
        area = _moments(sorted(cuts[-1], key=lambda loop: -abs(_polygon_area(loop))))[0]
        if abs(area / (shroud.length * shroud.width) - 1.0) > SHROUD_AREA_SLACK:
            raise _refuse(path, f"has a shroud of section {area * 1e6:.4g} mm^2 half-way up; the keys' shroud is "
                                f"{shroud.length * shroud.width * 1e6:.4g} mm^2 (shroud.length x shroud.width), "
                                "the shroud the beam carries; allowed: keys that describe the file")
    framed, principal = [], []
    for x, loops in zip(stations, cuts):
        c, s = math.cos(blade.beta(x)), math.sin(blade.beta(x))
        loops = sorted(([np.column_stack([Y * c + Z * s, -Y * s + Z * c]) for Y, Z in (loop.T for loop in loops)]),
                       key=lambda loop: -abs(_polygon_area(loop)))             # the outline first
        if any(not np.all(inside_polygon(hole, [loops[0]])) for hole in loops[1:]):
            raise _refuse(path, f"cuts into {len(loops)} separate pieces at x = {x:.4g} m; allowed: a blade whose "
                                "sections are one piece (with holes)")
        _, centroid, (( I_v, I_vw), (_, I_w)) = _moments(loops)
        chord = float(np.ptp(loops[0][:, 1]))
        off = float(np.hypot(*centroid))
        if off > CENTROID_SLACK * chord:
            raise _refuse(path, f"has the centroid of its section at x = {x:.4g} m {off * 1e3:.3g} mm off the X "
                                f"axis ({off / chord:.2g} of its chord); allowed: sections stacked on their "
                                f"centroids on X (within {CENTROID_SLACK:g} of the chord)")
        framed.append(tuple(loops))
        principal.append(-0.5 * math.atan2(2.0 * I_vw, I_w - I_v))
    turn = math.degrees(principal[-1] - principal[0])
    keys = blade.twist_deg * (stations[-1] - stations[0]) / blade.length
    if abs(turn) > TWIST_SLACK_DEG:
        raise InputError("blade.twist_deg", f"{blade.twist_deg!r}: the sections of {path!r} turn by "
                                            f"{keys + turn:.3g} deg from x = {stations[0]:.3g} to {stations[-1]:.3g} m "
                                            f"(their principal axes), the key by {keys:.3g} deg; allowed: the file's "
                                            f"twist within {TWIST_SLACK_DEG:g} deg")
    return Slices(stations=stations, loops=tuple(framed), principal=np.array(principal))


def _read(file) -> Slices:
    with np.load(file) as data:
        stations = data["stations"]
        loops = tuple(tuple(data[f"slice{k}_loop{j}"] for j in range(sum(n.startswith(f"slice{k}_") for n in data.files)))
                      for k in range(len(stations)))
        return Slices(stations=stations, loops=loops, principal=data["principal"])


@dataclass(frozen=True)
class SlicedBlade:
    """The file's sections at ``stations`` (m from the root) in the keys' section frames, about their own
    centroids (SectionProperties, SI), with each slice's chord (its extent along e_w) and mean thickness
    (area / chord), m, and its principal axes' angle (Slices)."""

    stations: np.ndarray
    sections: tuple[SectionProperties, ...]
    chords: np.ndarray
    thicknesses: np.ndarray
    principal: np.ndarray


def _section(loops: tuple) -> tuple[SectionProperties, float, float]:
    """The slice from its polygons (outline first): (its properties by P2 triangles, chord, mean thickness)."""
    outline, holes = loops[0], loops[1:]
    chord = float(np.ptp(outline[:, 1]))
    thickness = _moments(list(loops))[0] / chord
    size = thickness / MESH_CELLS_THICK
    return section_on_mesh(_thinned(outline, size), tuple(_thinned(h, size) for h in holes), size=size), chord, thickness


@functools.lru_cache(maxsize=8)
def sliced_blade(blade: Blade, shroud: Shroud) -> SlicedBlade:
    """The file ``blade.step`` cut at slice_stations(blade), checked against the keys (module docstring).

    The polygons are cached on disk (by the file's bytes and the keys that place and check the cuts:
    0.2 s a cut with gmsh), once checked; the section solves (0.1 s a slice) run once a process.
    """
    path = blade.step
    stations = slice_stations(blade)
    inputs = dict(step=step_digest(path), disk_radius=blade.disk_radius, length=blade.length,
                  stagger_deg=blade.stagger_deg, twist_deg=blade.twist_deg, shroud=dataclasses.asdict(shroud),
                  stations=[round(float(x), 12) for x in stations])
    file = cached("step_slices", inputs, ".npz", lambda tmp: _sample(path, blade, shroud, stations, tmp),
                  what="slices of the STEP blade", sources=(__name__,))
    slices = _read(file)
    x, angle = slices.stations, np.degrees(slices.principal)
    info(f"slices of {path}: x = {', '.join(f'{v:.4g}' for v in x)} m; their principal axes lie "
         f"{', '.join(f'{a:.3g}' for a in angle)} deg from the keys' e_w: the file's twist "
         f"{blade.twist_deg * (x[-1] - x[0]) / blade.length + angle[-1] - angle[0]:.4g} deg from the first to "
         f"the last, the keys' {blade.twist_deg * (x[-1] - x[0]) / blade.length:.4g} deg")
    sections, chords, thicknesses = zip(*(_section(loops) for loops in slices.loops))
    return SlicedBlade(stations=slices.stations, sections=tuple(sections), chords=np.array(chords),
                       thicknesses=np.array(thicknesses), principal=slices.principal)
