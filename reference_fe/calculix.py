"""The same solid in CalculiX (``ccx``): input deck, run, and its frequencies read back.

A second FE code on the same mesh (the cached .msh of meshes.blade):
quadratic tetrahedra as C3D10 (the same 10-node element as DOLFINx's P2
tetrahedron), 27-node hexahedra as C3D20 (CalculiX has no 27-node brick: its
20 corner and edge nodes, the serendipity element, whose space lacks the 6
face and the centre bubble of Lagrange Q2). Node order: meshio's (VTK)
order of tetra10 and of the first 20 nodes of hexahedron27 is CalculiX's.

Steps, as the DOLFINx model (reference_fe.solid): root nodes clamped,
isotropic steel, the centrifugal load *DLOAD CENTRIF (rho Omega^2 r about
+Z through the origin); a perturbation *FREQUENCY step about the
prestressed state (stress stiffening and spin softening), then *COMPLEX
FREQUENCY, CORIOLIS for the gyroscopic frequencies (CalculiX projects them
onto the modes of the *FREQUENCY step: without the blade's axial modes in
that basis, the Coriolis coupling of flap and axial motion is lost;
DOLFINx's Ritz basis holds it through the static Coriolis responses
K^-1 G Phi, reference_fe.modal). The tip nodes
(meshes.blade.tip_points) are printed per mode so that modes are named by
the same tip kinematics (shroud.core.modes).

The prestressed state, two ways (``prestress``):

``"linear"`` (the documented model, docs/geometry.md: prestress from the
    centrifugal load, and spin softening; DOLFINx's K_e + K_sigma + K_spin)
    Two ccx runs. The first solves the linear centrifugal static step and
    prints its stresses at every integration point; the second starts from
    them (*INITIAL CONDITIONS, TYPE=STRESS) on the undeformed mesh, where
    the same centrifugal load leaves them in equilibrium (its static step
    moves the nodes by ~1e-9 m, 1e-4 of the first run's), and takes the
    perturbation steps there. CalculiX's perturbation stiffness about a
    displaced state also holds the initial-displacement matrix (the
    material stiffness with F = I + grad u0 in the strain variations,
    O(strain) ~ 5e-4 of K_e), which the documented model leaves out:
    starting from zero displacement removes it and keeps K_sigma.
``"nonlinear"``
    One run: an NLGEOM static step, then the perturbation steps about the
    deformed state (CalculiX's usual rotor path). It differs from the
    linear prestress by the initial-displacement matrix, measured at
    10000 r/min: torsion1 +0.019 % (short blade) to +0.06 % (default).
"""

from __future__ import annotations

import math
import re
import shutil
import subprocess
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from meshes.blade import ROOT, MeshSpec, mesh_file, section_frame, tip_points
from shroud.core.modes import label_modes
from shroud.params import Parameters

ELEMENTS = {"tetra10": ("C3D10", 10), "hexahedron27": ("C3D20", 20)}


@dataclass(frozen=True)
class CalculixModes:
    """Frequencies from one ccx run, in ascending order."""

    f_hz: np.ndarray                 # (k,) perturbation frequencies (no Coriolis)
    f_coriolis_hz: np.ndarray | None  # (k,) complex-frequency step, or None
    labels: tuple[str, ...]
    element: str
    dofs: int                        # 3 x nodes of the deck (clamped included)
    wall_s: float                    # the ccx process, s


def ccx() -> str | None:
    """Path of the ccx executable, or None."""
    return shutil.which("ccx") or shutil.which("ccx_2.20")


PRESTRESS = ("linear", "nonlinear")


def write_deck(params: Parameters, rpm: float, n_modes: int, path: Path, coriolis: bool, prestress: str,
               initial_stress: np.ndarray | None = None) -> dict:
    """Write ``path`` (.inp) for the solid of ``params`` at ``rpm``; return mesh facts.

    ``prestress = "nonlinear"``: the one-run deck (NLGEOM static step, then the
    perturbation steps). ``"linear"`` without ``initial_stress``: the first
    deck of the linear path (a linear static step printing the stresses at
    the integration points); with ``initial_stress`` (rows: element,
    integration point, sxx, syy, szz, sxy, sxz, syz in Pa, as
    :func:`read_stresses` returns them): the second (those stresses on the
    undeformed mesh, the centrifugal static step that keeps them, then the
    perturbation steps).
    """
    spec = MeshSpec.from_params(params)
    lines, facts = _model_lines(mesh_file(spec), spec, params.material)
    path.write_text("\n".join(lines + _step_lines(rpm, n_modes, coriolis, prestress, initial_stress)) + "\n")
    return facts


def _step_lines(rpm: float, n_modes: int, coriolis: bool, prestress: str, initial_stress: np.ndarray | None,
                frequency: tuple[str, ...] = ()) -> list[str]:
    """The steps of :func:`write_deck` (``prestress`` and ``initial_stress`` as there); ``frequency``: more
    lines of the *FREQUENCY step (the nodal diameters of a cyclic sector)."""
    if prestress not in PRESTRESS:
        raise ValueError(f"prestress {prestress!r}; allowed: {PRESTRESS}")
    omega = 2.0 * math.pi * rpm / 60.0
    centrif = f"EALL, CENTRIF, {omega**2:.12e}, 0., 0., 0., 0., 0., 1."   # ccx reads <= 20 characters a number
    perturbation = ["*FREQUENCY, STORAGE=YES", f"{n_modes}", *frequency, "*NODE PRINT, NSET=NTIP", "U", "*END STEP"]
    if coriolis and omega > 0:
        perturbation += ["*STEP, PERTURBATION", "*COMPLEX FREQUENCY, CORIOLIS", f"{n_modes}",
                         "*DLOAD", centrif, "*END STEP"]
    if omega == 0:
        return ["*STEP"] + perturbation
    if prestress == "nonlinear":
        return ["*STEP, NLGEOM", "*STATIC", "1., 1.", "*DLOAD", centrif, "*END STEP",
                "*STEP, PERTURBATION"] + perturbation
    if initial_stress is None:
        return ["*STEP", "*STATIC", "*DLOAD", centrif, "*EL PRINT, ELSET=EALL", "S", "*END STEP"]
    return (["*INITIAL CONDITIONS, TYPE=STRESS"]
            + [f"{int(e)}, {int(g)}, " + ", ".join(f"{v:.7e}" for v in row) for e, g, *row in initial_stress.tolist()]
            + ["*STEP", "*STATIC", "*DLOAD", centrif, "*END STEP", "*STEP, PERTURBATION"] + perturbation)


def _node_lines(name: str, nodes: np.ndarray) -> list[str]:
    """*NSET ``name`` of the (0-based) ``nodes``, 12 a line."""
    return [f"*NSET, NSET={name}"] + [", ".join(str(v + 1) for v in nodes[i:i + 12]) for i in range(0, len(nodes), 12)]


def _model_lines(path: Path, spec, material, sides: tuple[int, int] | None = None) -> tuple[list[str], dict]:
    """Deck lines of the mesh ``path``, its ROOT facets clamped, tip set and ``material``; the mesh facts.
    ``sides`` (low, high facet tags of a cyclic sector): their unclamped nodes as the sets NLOW, NHIGH."""
    import meshio
    mesh = meshio.read(path)
    blocks = [(b, ELEMENTS[b.type]) for b in mesh.cells if b.type in ELEMENTS]
    facets = [(b, mesh.cell_data["gmsh:physical"][i]) for i, b in enumerate(mesh.cells)
              if b.type in ("triangle6", "quad9")]
    on = lambda t: np.unique(np.concatenate([b.data[tag == t].ravel() for b, tag in facets]))
    root = on(ROOT)
    used = np.unique(np.concatenate([b.data[:, :n].ravel() for b, (_, n) in blocks]))
    tip = [int(np.argmin(np.linalg.norm(mesh.points - p, axis=1))) for p in tip_points(spec)]
    lines = ["*HEADING", "shrouded blade (shroud workbench, reference_fe.calculix)", "*NODE, NSET=NALL"]
    lines += [f"{i + 1}, {x:.12e}, {y:.12e}, {z:.12e}" for i, (x, y, z) in zip(used.tolist(), mesh.points[used].tolist())]
    first = 1
    for b, (name, n) in blocks:
        lines.append(f"*ELEMENT, TYPE={name}, ELSET=EALL")
        for e, cell in enumerate(b.data[:, :n]):
            nodes = [str(first + e)] + [str(v + 1) for v in cell]
            # at most 16 entries per line: continue on the next
            lines.append(", ".join(nodes[:16]) + ("," if len(nodes) > 16 else ""))
            if len(nodes) > 16:
                lines.append(", ".join(nodes[16:]))
        first += len(b.data)
    lines += _node_lines("NROOT", root)
    if sides is not None:     # the bore's nodes are clamped: out of the tie (a node both fixed and tied)
        for name, tag in zip(("NLOW", "NHIGH"), sides):
            lines += _node_lines(name, np.setdiff1d(on(tag), root))
    lines += ["*NSET, NSET=NTIP", ", ".join(str(v + 1) for v in tip),
              "*BOUNDARY", "NROOT, 1, 3, 0.",
              "*MATERIAL, NAME=STEEL", "*ELASTIC", f"{material.E!r}, {material.nu!r}", "*DENSITY", f"{material.rho!r}",
              "*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL"]
    return lines, {"element": blocks[0][1][0], "nodes": int(used.size), "tip_nodes": tip}


_NUMBER = r"[-+]?\d*\.?\d+(?:[EeDd][-+]?\d+)?"


def read_frequencies(dat: str) -> tuple[np.ndarray, np.ndarray | None]:
    """(undamped Hz, Coriolis Hz or None) from the text of a ccx .dat file."""
    blocks = dat.split("E I G E N V A L U E   O U T P U T")[1:]
    out = []
    for block in blocks:
        rows = []
        for line in block.splitlines():
            parts = line.split()
            if len(parts) >= 4 and parts[0].isdigit() and all(re.fullmatch(_NUMBER, p) for p in parts[1:]):
                rows.append([float(p.replace("D", "E")) for p in parts])
            elif rows:
                break
        out.append(np.array(rows))
    # *FREQUENCY: MODE, EIGENVALUE, omega (rad/time), f (cycles/time), imag omega.
    f0 = out[0][:, 3]
    # *COMPLEX FREQUENCY: MODE, omega (rad/time), f (cycles/time), ...
    fc = np.sort(np.abs(out[1][:, 2])) if len(out) > 1 else None
    return f0, fc


def read_cyclic_frequencies(dat: str, n_modes: int) -> dict[int, np.ndarray]:
    """{nodal diameter: its ``n_modes`` lowest frequencies, Hz} from the .dat of a cyclic *FREQUENCY step.
    CalculiX solves every nodal diameter (0 and N/2 too) on the sector doubled, cosine and sine parts:
    each frequency comes twice, and the deck asks for 2 ``n_modes``."""
    found: dict[int, list[float]] = {}
    for block in dat.split("E I G E N V A L U E   O U T P U T")[1:]:
        for line in block.split("P A R T I C I P A T I O N")[0].splitlines():
            parts = line.split()    # ND, MODE, EIGENVALUE, omega (rad/time), f (cycles/time), imaginary omega
            if len(parts) == 6 and parts[0].isdigit() and parts[1].isdigit():
                found.setdefault(int(parts[0]), []).append(float(parts[4].replace("D", "E")))
    out = {}
    for nd, f in found.items():
        f = np.sort(f)
        if f.size < 2 * n_modes or not np.allclose(f[0::2], f[1::2], rtol=1e-6):
            raise RuntimeError(f"ccx: nodal diameter {nd} has {f.size} frequencies, not {n_modes} pairs")
        out[nd] = f[0::2][:n_modes]
    return out


def read_tip_shapes(dat: str, n_modes: int) -> np.ndarray:
    """(n_modes, 3, 3) displacements of the three tip nodes per mode of the *FREQUENCY step."""
    parts = dat.split("displacements (vx,vy,vz) for set NTIP")[1:n_modes + 1]
    shapes = []
    for part in parts:
        rows = [line.split() for line in part.splitlines()[1:] if line.split()]
        rows = [r for r in rows[:3]]
        shapes.append(np.array([[float(v) for v in r[1:4]] for r in rows]))
    return np.array(shapes)


def tip_kinematics(spec: MeshSpec, shapes: np.ndarray) -> np.ndarray:
    """(k, 4) [flap, chord, torsion * c(L)/2, axial] of tip-node shapes (as reference_fe.modal)."""
    e_v, e_w = section_frame(spec.beta_tip)
    centre, minus, plus = shapes[:, 0], shapes[:, 1], shapes[:, 2]
    theta = -((plus - minus) @ e_v) / (0.5 * spec.tip_chord)
    return np.column_stack([centre @ e_v, centre @ e_w, theta * 0.5 * spec.tip_chord, centre[:, 0]])


def read_stresses(dat: str) -> np.ndarray:
    """(n, 8) rows [element, integration point, sxx, syy, szz, sxy, sxz, syz] (Pa) of a ccx .dat."""
    block = dat.split("stresses (elem, integ.pnt.,sxx,syy,szz,sxy,sxz,syz)")[1]
    rows = [line.split() for line in block.splitlines()[1:]]
    return np.array([[float(v) for v in r] for r in rows if len(r) == 8])


def run_calculix(params: Parameters, rpm: float, n_modes: int, workdir: Path,
                 coriolis: bool = True, prestress: str = "linear") -> CalculixModes:
    """Write the deck(s) in ``workdir``, run ccx (one thread), read its frequencies and name the modes.

    ``prestress``: "linear" (the documented model, two runs) or "nonlinear"
    (NLGEOM, one run); see the module docstring. ``wall_s`` sums the runs.
    """
    dat, facts, wall = _run_prestressed(
        lambda path, stress: write_deck(params, rpm, n_modes, path, coriolis, prestress, stress),
        workdir, "blade", linear=prestress == "linear" and rpm > 0)
    f0, fc = read_frequencies(dat)
    labels, _ = label_modes(tip_kinematics(MeshSpec.from_params(params), read_tip_shapes(dat, len(f0))))
    return CalculixModes(f_hz=f0, f_coriolis_hz=fc, labels=tuple(labels), element=facts["element"],
                         dofs=3 * facts["nodes"], wall_s=wall)


def _run_prestressed(write, workdir: Path, job: str, linear: bool) -> tuple[str, dict, float]:
    """(text of ``job``.dat, mesh facts, wall s of the ccx runs) of the deck ``write(path, stress)`` writes;
    ``linear``: the linear prestress's two runs (the first one's stresses given to the second)."""
    exe = ccx()
    if exe is None:
        raise FileNotFoundError("ccx (CalculiX) is not installed")
    workdir.mkdir(parents=True, exist_ok=True)
    wall = 0.0
    stress = None
    if linear:
        write(workdir / "prestress.inp", None)
        wall += _run(exe, workdir, "prestress")
        stress = read_stresses((workdir / "prestress.dat").read_text())
    facts = write(workdir / f"{job}.inp", stress)
    wall += _run(exe, workdir, job)
    return (workdir / f"{job}.dat").read_text(), facts, wall


def write_sector_deck(params: Parameters, rpm: float, n_modes: int, path: Path, prestress: str,
                      initial_stress: np.ndarray | None = None, diameters: tuple[int, int] = (0, 0)) -> dict:
    """Write ``path`` (.inp): the disk sector of ``params`` (meshes.disk, docs/disk.md) as a CalculiX cyclic
    symmetry model of ``ring.blades`` sectors about +Z, the side theta = +pi/N tied to the side -pi/N
    (*TIE, CYCLIC SYMMETRY; bore nodes clamped, out of the tie), its ``n_modes`` lowest modes of every
    nodal diameter diameters[0] .. diameters[1] (*SELECT CYCLIC SYMMETRY MODES); the steps and
    ``prestress`` as :func:`write_deck`, without Coriolis (the *COMPLEX FREQUENCY step is not written:
    not tried on a cyclic model). One material: refuses disk.E_factor != 1."""
    from meshes.disk import CYCLIC_HIGH, CYCLIC_LOW, DiskSpec, sector_mesh_file
    if params.disk.E_factor != 1.0:
        raise ValueError("the CalculiX sector has one material: disk.E_factor must be 1")
    spec = DiskSpec.from_params(params)
    lines, facts = _model_lines(sector_mesh_file(spec), spec, params.material, (CYCLIC_LOW, CYCLIC_HIGH))
    lines += ["*SURFACE, NAME=SLOW, TYPE=NODE", "NLOW", "*SURFACE, NAME=SHIGH, TYPE=NODE", "NHIGH",
              "*TIE, NAME=CYCLIC, CYCLIC SYMMETRY", "SHIGH, SLOW",
              f"*CYCLIC SYMMETRY MODEL, N={spec.blades}, TIE=CYCLIC", "0., 0., 0., 0., 0., 1."]
    select = (f"*SELECT CYCLIC SYMMETRY MODES, NMIN={diameters[0]}, NMAX={diameters[1]}",)
    steps = _step_lines(rpm, 2 * n_modes, False, prestress, initial_stress, select)    # each frequency twice
    path.write_text("\n".join(lines + steps) + "\n")
    return facts


def run_calculix_sector(params: Parameters, rpm: float, n_modes: int, workdir: Path, diameters: tuple[int, int],
                        prestress: str = "linear") -> tuple[dict[int, np.ndarray], float]:
    """({nd: the ``n_modes`` lowest frequencies, Hz} for nd = diameters[0] .. diameters[1], wall s of ccx)
    of the disk sector (:func:`write_sector_deck`), at ``rpm`` without Coriolis."""
    dat, _, wall = _run_prestressed(
        lambda path, stress: write_sector_deck(params, rpm, n_modes, path, prestress, stress, diameters),
        workdir, "sector", linear=prestress == "linear" and rpm > 0)
    return read_cyclic_frequencies(dat, n_modes), wall


def _run(exe: str, workdir: Path, job: str) -> float:
    """Run ``ccx -i job`` in ``workdir`` on one thread; its wall time, s."""
    env = {"OMP_NUM_THREADS": "1", "CCX_NPROC_EQUATION_SOLVER": "1", "PATH": "/usr/bin:/bin"}
    t0 = time.perf_counter()
    done = subprocess.run([exe, "-i", job], cwd=workdir, capture_output=True, text=True, env=env)
    wall = time.perf_counter() - t0
    (workdir / f"{job}.log").write_text(done.stdout + done.stderr)
    if done.returncode != 0 or not (workdir / f"{job}.dat").exists():
        raise RuntimeError(f"ccx failed (exit {done.returncode}); see {workdir / (job + '.log')}")
    return wall
