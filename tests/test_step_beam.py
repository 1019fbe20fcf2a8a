"""The beams on the user's STEP file (blade.step): the solid sliced into sections (reduced_model.step_slices).

Truth: the spec's NACA blade (shared/spec/geometry.md, "Airfoil blades": m
0.04, p 0.4, chord 40 -> 30 mm, thickness 7 -> 4.2 mm, the paper's stagger,
twist and shroud, alpha 15 deg) lofted here with gmsh from this file's own
NACA points (its own formula, splines, sections and one fused solid, in
millimetres: none of the project's loft code), read back as a STEP file; the
beams built from the keys' profiles are the second path. Every file the
beams cannot honour: one line, exit 2, nothing written.
"""

import json
import math

import numpy as np
import pytest

from workbench.cli import main

pytestmark = pytest.mark.fe          # gmsh writes and reads the files

NACA = ["blade.section=naca4", "blade.chord_taper=0.75", "blade.thickness_taper=0.6", "contact.alpha_deg=15"]
R_D, L, STAGGER, TWIST = 0.150, 0.150, 30.0, 10.0           # the paper's blade (m, deg)
SHROUD = (0.040, 0.020, 0.007)                               # l_s (along e_ws), b_s (along e_vs), t_s, m


def _naca(m, p, t, c, n=61):
    """The closed NACA four-digit outline (y, s) in metres, chord c along s, thickness t, its area centroid
    at the origin: upper surface trailing edge -> leading edge, lower back (Abbott & von Doenhoff, Sect. 6.4)."""
    s = 0.5 * (1 - np.cos(np.linspace(0, np.pi, n)))
    tau = t / c
    yt = 5 * tau * (0.2969 * np.sqrt(s) - 0.1260 * s - 0.3516 * s**2 + 0.2843 * s**3 - 0.1036 * s**4)
    yc = np.where(s < p, m / p**2 * (2 * p * s - s**2), m / (1 - p) ** 2 * (1 - 2 * p + 2 * p * s - s**2))
    th = np.arctan(np.where(s < p, 2 * m / p**2 * (p - s), 2 * m / (1 - p) ** 2 * (p - s)))
    upper = np.column_stack([yc + yt * np.cos(th), s - yt * np.sin(th)])
    lower = np.column_stack([yc - yt * np.cos(th), s + yt * np.sin(th)])
    loop = c * np.concatenate([upper[::-1], lower[1:-1]])
    a, b = loop, np.roll(loop, -1, axis=0)
    cross = a[:, 0] * b[:, 1] - b[:, 0] * a[:, 1]
    return loop - np.sum((a + b) * cross[:, None], axis=0) / (3 * np.sum(cross))


def write_naca_step(path, twist=TWIST, shift=0.0, shroud=True, sections=11, unit_off=False):
    """The spec's NACA blade and shroud as one fused solid, drawn in millimetres, to the STEP file ``path``;
    ``shift`` (m) moves the blade off the X axis along Y; ``unit_off``: the millimetres said to be metres."""
    import gmsh
    mm = 1e3
    gmsh.initialize(interruptible=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.option.setString("Geometry.OCCTargetUnit", "M" if unit_off else "MM")    # options outlive finalize
        occ = gmsh.model.occ
        wires = []
        for x in np.linspace(0, L, sections):
            loop = _naca(0.04, 0.4, 0.007 * (1 - 0.4 * x / L), 0.040 * (1 - 0.25 * x / L))
            beta = math.radians(STAGGER + twist * x / L)
            y = loop[:, 0] * math.cos(beta) - loop[:, 1] * math.sin(beta) + shift
            z = loop[:, 0] * math.sin(beta) + loop[:, 1] * math.cos(beta)
            points = [occ.addPoint(mm * (R_D + x), mm * yi, mm * zi) for yi, zi in zip(y, z)]
            points.append(points[0])
            wires.append(occ.addWire([occ.addSpline(points)]))
        blade = occ.addThruSections(wires, makeSolid=True)
        solid = blade
        if shroud:
            l_s, b_s, t_s = SHROUD
            box = occ.addBox(mm * (R_D + L), -mm * b_s / 2, -mm * l_s / 2, mm * t_s, mm * b_s, mm * l_s)
            occ.rotate([(3, box)], 0, 0, 0, 1, 0, 0, math.radians(STAGGER + TWIST + 15.0))
            solid, _ = occ.fuse(blade, [(3, box)])
        occ.synchronize()
        assert len(gmsh.model.getEntities(3)) == 1
        gmsh.write(str(path))            # the model's millimetres, the file's unit millimetres
    finally:
        gmsh.finalize()
    return path


@pytest.fixture(scope="module")
def naca_step(tmp_path_factory):
    return write_naca_step(tmp_path_factory.mktemp("step") / "naca.step")


def _frequencies(capsys, model, rpm, *sets):
    argv = ["modal", "--json", "--model", model, "--rpm", str(rpm), "--modes", "5"]
    assert main(argv + [a for s in sets for a in ("--set", s)]) == 0
    return np.array([m["f_hz"] for m in json.loads(capsys.readouterr().out)["modes"]])


@pytest.mark.parametrize("model", ["reduced", "extended"])
def test_the_beam_from_the_files_slices_has_the_profiles_frequencies(naca_step, capsys, monkeypatch, tmp_path,
                                                                     model):
    """The issue's must-show: the first five frequencies at 0 and 10000 r/min within 0.5 %."""
    monkeypatch.setenv("SHROUD_CACHE", str(tmp_path / "cache"))
    for rpm in (0, 10000):
        profile = _frequencies(capsys, model, rpm, *NACA)
        sliced = _frequencies(capsys, model, rpm, *NACA, f"blade.step={naca_step}")
        assert np.abs(sliced / profile - 1).max() < 5e-3, (rpm, profile, sliced)


def test_the_slices_are_the_profiles_sections(naca_step):
    """Each slice against the keys' profile at its station (reduced_model.airfoil.blade_section, 240 points a
    surface): area and second moments within 1e-3 (the file's splines through 61 points), J within 1 %,
    the shear centre within 2 % of its offset; the principal axes turned as the keys' twist."""
    from reduced_model.airfoil import blade_section
    from reduced_model.step_slices import sliced_blade
    from shroud.params import Parameters
    params = Parameters().with_overrides(NACA + [f"blade.step={naca_step}"])
    sliced = sliced_blade(params.blade, params.shroud)
    profile_blade = params.updated({"blade.step": ""}).blade
    for x, section in zip(sliced.stations, sliced.sections):
        ref = blade_section(profile_blade, float(x))
        for key in ("area", "I_v", "I_w", "I_rr"):
            assert getattr(section, key) == pytest.approx(getattr(ref, key), rel=1e-3), (x, key)
        assert section.J == pytest.approx(ref.J, rel=1e-2), x
        offset = np.subtract(section.shear_centre, section.centroid)
        ref_offset = np.subtract(ref.shear_centre, ref.centroid)
        assert np.linalg.norm(offset - ref_offset) < 2e-2 * np.linalg.norm(ref_offset), x
    # the cambered profile's principal axes sit 0.17 deg from its chord, nearly the same at every t/c
    assert np.ptp(np.degrees(sliced.principal)) < 0.1


def _refused(capsys, path, *sets, model="reduced"):
    code = main(["modal", "--model", model, "--set", f"blade.step={path}", *[a for s in sets for a in ("--set", s)]])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2, err
    assert "Traceback" not in "\n".join(err)
    return err[-1]


@pytest.mark.parametrize("case", ["empty", "not STEP", "units", "off the axis", "other twist", "no shroud",
                                  "root off the disk"])
def test_a_file_the_beam_cannot_honour_is_one_line_exit_2_and_nothing_written(tmp_path, capsys, monkeypatch, case):
    cache = tmp_path / "cache"
    monkeypatch.setenv("SHROUD_CACHE", str(cache))
    path = tmp_path / "blade.step"
    sets = NACA
    if case == "empty":
        path.write_text("")
        words = "blade.step: " + repr(str(path)) + " is not a STEP file"
    elif case == "not STEP":
        path.write_text("ISO-10303-21? no: a shopping list\n")
        words = "is not a STEP file"
    elif case == "units":
        write_naca_step(path, unit_off=True)
        words = "units are off by 1000"
    elif case == "off the axis":
        write_naca_step(path, shift=0.5e-3)
        words = "off the X axis"
    elif case == "other twist":
        write_naca_step(path, twist=20.0)
        words = "blade.twist_deg: 10.0: the sections of"
    elif case == "no shroud":
        write_naca_step(path, shroud=False)
        words = "shroud.thickness"
    else:
        write_naca_step(path)
        sets = NACA + ["blade.disk_radius=0.16"]
        words = "spans X = 0.15 .. 0.307"
    assert words in _refused(capsys, path, *sets)
    assert not list(cache.glob("step_slices/*.npz")), "slices were written for a file the beam refuses"


@pytest.mark.parametrize("command", [["modal", "--model", "shell"], ["transient", "--model", "fe"]])
def test_the_models_that_do_not_read_a_step_file_refuse_it(naca_step, capsys, command):
    code = main(command + ["--set", f"blade.step={naca_step}"])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and err[-1].startswith("error: blade.step:") and "only the beams" in err[-1], err


def test_the_papers_rectangle_from_its_step_file_has_the_grid_beams_frequencies(tmp_path, capsys, monkeypatch):
    """The paper's blade (meshes.blade.write_step) cut into slices solved on triangles, against the beam on
    the grid method's rectangle (Timoshenko & Goodier's J, Cowper's kappa): 2.4e-5 measured, held to 1e-3."""
    from meshes.blade import write_step
    from meshes.spec import MeshSpec
    from shroud.params import Parameters
    monkeypatch.setenv("SHROUD_CACHE", str(tmp_path / "cache"))
    path = tmp_path / "paper.step"
    write_step(MeshSpec.from_params(Parameters()), path)
    keys = _frequencies(capsys, "extended", 10000)
    sliced = _frequencies(capsys, "extended", 10000, f"blade.step={path}")
    assert np.abs(sliced / keys - 1).max() < 1e-3, (keys, sliced)
