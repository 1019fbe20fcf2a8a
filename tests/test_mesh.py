"""The gmsh solid: its volume, faces and tags against the geometry, cache reuse, bad geometry."""

from __future__ import annotations

import dataclasses
import math
import subprocess
import sys

import numpy as np
import pytest

from meshes.blade import (CONTACT_SIDE1, CONTACT_SIDE2, ROOT, MeshSpec, check_geometry, mesh_file,
                          shroud_frame, tip_points)
from shroud.base.errors import InputError
from shroud.params import Parameters


def _spec(**changes) -> MeshSpec:
    """The tetrahedral mesh of the default blade (the hexahedral one: tests/test_hex.py)."""
    tets = Parameters().updated({"fe.cell": "tet", "fe.mesh_size": 0.0035})
    return dataclasses.replace(MeshSpec.from_params(tets), **changes)


@pytest.mark.parametrize("changes, key", [
    ({"shroud_width": 0.005}, "shroud.width"),                    # narrower than h = 7 mm
    ({"length": 0.02, "twist": math.radians(80.0)}, "blade.twist_deg"),   # edges wind at 54 deg
    ({"size": 0.004}, "fe.mesh_size"),                             # 1.75 elements through h
])
def test_bad_geometry_is_refused_before_gmsh(changes, key, tmp_path, monkeypatch):
    monkeypatch.setenv("SHROUD_CACHE", str(tmp_path))
    with pytest.raises(InputError) as err:
        mesh_file(_spec(**changes))
    assert err.value.key == key
    assert not list(tmp_path.rglob("*.msh"))


def test_bad_mesh_size_from_the_command_line_is_one_line_exit_2():
    run = subprocess.run([sys.executable, "-m", "workbench.cli", "modal", "--model", "fe",
                          "--set", "fe.cell=tet", "--set", "fe.mesh_size=0.01"], capture_output=True, text=True)
    assert run.returncode == 2
    assert run.stderr.strip().startswith("error: fe.mesh_size:")
    assert len(run.stderr.strip().splitlines()) == 1


@pytest.mark.fe
def test_mesh_volume_faces_and_tags_match_the_geometry(tmp_path, monkeypatch):
    meshio = pytest.importorskip("meshio")
    monkeypatch.setenv("SHROUD_CACHE", str(tmp_path))
    spec = _spec()
    check_geometry(spec)
    path = mesh_file(spec)
    mesh = meshio.read(path)
    pts = mesh.points

    def tet_volume(cells):
        a, b, c, d = (pts[cells[:, i]] for i in range(4))
        return np.abs(np.einsum("ij,ij->i", np.cross(b - a, c - a), d - a)).sum() / 6.0

    def tri_area(cells):
        a, b, c = (pts[cells[:, i]] for i in range(3))
        return 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1).sum()

    tags = {block: mesh.cell_data["gmsh:physical"][i] for i, block in enumerate(mesh.cells)}
    volume = sum(tet_volume(b.data) for b in mesh.cells if b.type == "tetra10")
    blade = spec.length * spec.width * spec.thickness      # a twisted prism keeps its volume
    shroud = spec.shroud_length * spec.shroud_width * spec.shroud_thickness
    assert volume == pytest.approx(blade + shroud, rel=1e-4)
    faces = {t: 0.0 for t in (ROOT, CONTACT_SIDE1, CONTACT_SIDE2)}
    e_vs, _ = shroud_frame(spec)
    for block, tag in tags.items():
        if block.type != "triangle6":
            continue
        for t in faces:
            chosen = block.data[tag == t]
            faces[t] += tri_area(chosen)
            if t in (CONTACT_SIDE1, CONTACT_SIDE2) and chosen.size:
                side = -1 if t == CONTACT_SIDE1 else 1
                assert np.allclose(pts[chosen.ravel()][:, 1:] @ e_vs[1:], side * spec.shroud_width / 2,
                                   atol=1e-9)
    assert faces[ROOT] == pytest.approx(spec.width * spec.thickness, rel=1e-9)
    assert faces[CONTACT_SIDE1] == pytest.approx(spec.shroud_length * spec.shroud_thickness, rel=1e-9)
    assert faces[CONTACT_SIDE2] == pytest.approx(spec.shroud_length * spec.shroud_thickness, rel=1e-9)
    for p in tip_points(spec):                                  # tip nodes are mesh nodes
        assert np.min(np.linalg.norm(pts - p, axis=1)) < 1e-12
    assert mesh_file(spec) == path                              # same inputs: reused, not rebuilt
