# # Your own blade from a STEP file: the solid's modes and the beam cut from it
#
# This example draws a blade of its own with gmsh's OpenCASCADE kernel (a
# NACA four-digit profile of 2 % camber at 40 % chord, 40 mm chord and 7 mm
# thick, twisted 10 deg over its 150 mm span and stacked on its centroids,
# the paper's shroud box fused to its tip), writes it to a STEP file in millimetres as a CAD system would,
# and hands the file to the workbench with ``blade.step``:
#
# * the solid (``fe``) meshes the file's solid with quadratic tetrahedra,
#   finds its root face in the plane X = R_d and the shroud's contact faces
#   by their normals (shared/spec/geometry.md);
# * the beam (``extended``: torsion and the rigid shroud) cuts the solid
#   into sections at five stations along the span, solves each slice's
#   properties on P2 triangles (area, principal axes, torsion constant,
#   shear centre, shear coefficients: docs/sections.md) and joins them
#   along the span.
#
# The keys (``blade.*``, ``shroud.*``, ``contact.alpha_deg``) describe the
# blade the file holds: the workbench refuses a file that disagrees with
# them (span, shroud, twist, centroids off the axis) with one line and
# exit 2.

import math
import tempfile
from pathlib import Path

import gmsh
import numpy as np

from shroud.analysis.api import modal
from shroud.params import Parameters

params = Parameters().with_overrides(["blade.section=naca4", "blade.naca_m=0.02", "blade.naca_p=0.4",
                                      "fe.cell=tet", "fe.mesh_size=0.0035"])
b, s, alpha = params.blade, params.shroud, math.radians(params.contact.alpha_deg)

# ## The blade, drawn here
#
# The NACA four-digit outline from its textbook formula (Abbott & von
# Doenhoff, Sect. 6.4), 41 cosine-spaced points a surface, its area
# centroid moved to the origin; sections every 1.5 deg of twist, one
# closed spline each, lofted; the shroud box turned by the tip's angle
# plus alpha and fused on.

def outline(m, p, tau, chord, n=41):
    x = 0.5 * (1 - np.cos(np.linspace(0, np.pi, n)))
    yt = 5 * tau * (0.2969 * np.sqrt(x) - 0.1260 * x - 0.3516 * x**2 + 0.2843 * x**3 - 0.1036 * x**4)
    yc = np.where(x < p, m / p**2 * (2 * p * x - x**2), m / (1 - p) ** 2 * (1 - 2 * p + 2 * p * x - x**2))
    th = np.arctan(np.where(x < p, 2 * m / p**2 * (p - x), 2 * m / (1 - p) ** 2 * (p - x)))
    upper = np.column_stack([yc + yt * np.cos(th), x - yt * np.sin(th)])
    lower = np.column_stack([yc - yt * np.cos(th), x + yt * np.sin(th)])
    loop = chord * np.concatenate([upper[::-1], lower[1:-1]])        # (across, along the chord)
    a, c = loop, np.roll(loop, -1, axis=0)
    cross = a[:, 0] * c[:, 1] - c[:, 0] * a[:, 1]
    return loop - np.sum((a + c) * cross[:, None], axis=0) / (3 * np.sum(cross))


step = Path(tempfile.mkdtemp()) / "my_blade.step"
mm = 1e3
gmsh.initialize(interruptible=False)
gmsh.option.setNumber("General.Terminal", 0)
gmsh.option.setString("Geometry.OCCTargetUnit", "MM")
occ = gmsh.model.occ
wires = []
for x in np.linspace(0.0, b.length, 8):
    loop = outline(b.naca_m, b.naca_p, b.thickness / b.width, b.width)
    c, sn = math.cos(b.beta(x)), math.sin(b.beta(x))
    points = [occ.addPoint(mm * (b.disk_radius + x), mm * (v * c - w * sn), mm * (v * sn + w * c)) for v, w in loop]
    wires.append(occ.addWire([occ.addSpline(points + points[:1])]))
blade = occ.addThruSections(wires, makeSolid=True)
box = occ.addBox(mm * (b.disk_radius + b.length), -mm * s.width / 2, -mm * s.length / 2,
                 mm * s.thickness, mm * s.width, mm * s.length)
occ.rotate([(3, box)], 0, 0, 0, 1, 0, 0, b.beta(b.length) + alpha)
occ.fuse(blade, [(3, box)])
occ.synchronize()
gmsh.write(str(step))
gmsh.finalize()

# ## The workbench on the file
#
# The same calls as for the keys' own blade; ``blade.step`` swaps the
# geometry. The solid at rest; the beam at rest, from the file's slices
# and, for the check, from the keys' NACA profile (the workbench's own
# profile code, none of the drawing above).

on_file = params.updated({"blade.step": str(step)})
solid = modal(on_file, "fe", rpm=0, n_modes=4).by_label()
beam = modal(on_file, "extended", rpm=0, n_modes=4).by_label()
profile = modal(params, "extended", rpm=0, n_modes=4).by_label()
print("mode        solid    beam (slices)  beam (profile)   Hz")
for label in beam:
    print(f"  {label:9s} {solid.get(label, float('nan')):8.1f} {beam[label]:10.1f} {profile[label]:12.1f}")

# ## The checks
#
# The beam cut from the file is the beam of the profile the file was drawn
# from, to within the file's splines (0.5 %); and it has the solid's flap
# and chord frequencies within 3 % (the solid here is coarse: two cells
# through the thickness; docs/sections.md has the converged comparison).

for label in beam:
    assert abs(beam[label] / profile[label] - 1) < 5e-3, (label, beam[label], profile[label])
for label in ("flap1", "chord1"):
    print(f"{label}: the beam from the slices {100 * (beam[label] / solid[label] - 1):+.2f} % from the solid")
    assert abs(beam[label] / solid[label] - 1) < 0.03
