"""Hostile input a new user tried, each through the command: one line naming the key or file
and what is allowed, exit status 2, no output folder (and for a damaged cache: the run succeeds);
a run that diverged or failed: one line, exit status 1, whatever the command."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from workbench.cli import main

ROOT = Path(__file__).resolve().parents[1]


def _refused(capsys, argv: list[str], key: str, out: Path) -> str:
    code = main(argv)
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2, err
    assert err[-1].startswith(f"error: {key}:"), err[-1]
    assert "allowed:" in err[-1]
    assert "Traceback" not in "\n".join(err)
    assert not out.exists(), f"{out} was created for bad input"
    return err[-1]


def test_a_speed_of_zero_is_refused_not_divided_by(tmp_path, capsys):
    out = tmp_path / "out"
    _refused(capsys, ["run", str(ROOT / "scenes/fig3.toml"), "--quick", "--set", "speed.rpm=0",
                      "--out", str(out)], "speed.rpm", out)


def test_a_speed_of_zero_in_a_sweep_is_refused_before_any_point_runs(tmp_path, capsys):
    out = tmp_path / "out"
    _refused(capsys, ["run", str(ROOT / "scenes/gap_preload.toml"), "--quick", "--set", "options.rpm_from=0",
                      "--out", str(out)], "speed.rpm", out)


def test_a_scene_that_is_not_utf8_text(tmp_path, capsys):
    scene = tmp_path / "scene.toml"
    scene.write_bytes(b'study = "fig3"\ntitle = "\xff\xfe caf\xe9"\n')
    line = _refused(capsys, ["run", str(scene), "--out", str(tmp_path / "out")], str(scene), tmp_path / "out")
    assert "UTF-8" in line


def test_a_folder_given_as_the_scene(tmp_path, capsys):
    line = _refused(capsys, ["run", str(ROOT / "scenes"), "--out", str(tmp_path / "out")],
                    str(ROOT / "scenes"), tmp_path / "out")
    assert "folder" in line


@pytest.mark.parametrize("where", ["file", "missing root"])
def test_an_output_folder_that_cannot_be_written(tmp_path, capsys, where):
    if where == "file":
        blocker = tmp_path / "a_file"
        blocker.write_text("x")
        out = blocker / "out"
    else:
        out = Path("/proc/no_such_folder/out")        # /proc takes no new folders, even from root
    _refused(capsys, ["run", str(ROOT / "scenes/table1.toml"), "--quick", "--out", str(out)], "--out", out)


def test_a_run_whose_records_the_machine_cannot_hold(tmp_path, capsys):
    out = tmp_path / "out"
    line = _refused(capsys, ["run", str(ROOT / "scenes/fig3.toml"), "--quick", "--set", "time.periods=100000000",
                             "--out", str(out)], "time.periods", out)
    assert "TiB" in line and "at most" in line


def test_a_contact_stiffness_beyond_double_precision(tmp_path, capsys):
    out = tmp_path / "out"
    line = _refused(capsys, ["run", str(ROOT / "scenes/fig8.toml"), "--quick", "--set", "contact.kn=1e30",
                             "--set", 'options.models=["reduced", "full"]', "--set", "options.reference=full", "--out", str(out)], "contact.kn", out)
    assert "at most" in line


def test_the_stiffness_bound_lies_beyond_stiffnesses_that_run_well(tmp_path):
    """kn = 1e18 N/m (1e11 times the paper's) still closes the reduced beam's energy balance: the bound
    refuses only what double precision cannot resolve (at kn = 1e30 the run diverged at step 3)."""
    from shroud.analysis.api import build_system
    from shroud.analysis.checks import contact_stiffness_bounds
    from shroud.analysis.transient import run
    from shroud.params import Parameters
    p = Parameters().updated({"time.periods": 20, "contact.kn": 1e18})
    system = build_system(p, "reduced")
    bounds = contact_stiffness_bounds(system)
    assert 1e20 < bounds["contact.kn"] < 1e26 and 1e20 < bounds["contact.kt"] < 1e26
    tr = run(system, p)
    assert tr.diverged is None and tr.energy.relative_error < 1e-6


@pytest.mark.fe
def test_a_mesh_too_fine_for_the_machine_is_refused_before_gmsh(tmp_path, capsys, monkeypatch):
    monkeypatch.setenv("SHROUD_CACHE", str(tmp_path / "cache"))
    out = tmp_path / "out"
    line = _refused(capsys, ["run", str(ROOT / "scenes/table1.toml"), "--quick", "--set", "fe.mesh_size=1e-6",
                             "--set", "options.with_fe=true", "--out", str(out)], "fe.mesh_size", out)
    assert "DOF" in line and "a size >=" in line
    assert not list((tmp_path / "cache").rglob("*.msh"))


@pytest.mark.fe
@pytest.mark.slow
def test_a_truncated_cache_entry_is_rebuilt_and_the_run_succeeds(tmp_path):
    """A mesh and a reduction basis cut short (a run killed while writing, a full disk) are rebuilt."""
    env = {**os.environ, "SHROUD_CACHE": str(tmp_path / "cache"), "OMP_NUM_THREADS": "1"}
    argv = [sys.executable, "-m", "workbench.cli", "transient", "--model", "fe-reduced",
            "--set", "time.periods=2", "--json"]
    first = subprocess.run(argv + ["--out", str(tmp_path / "a")], capture_output=True, text=True, env=env)
    assert first.returncode == 0, first.stderr
    entries = [p for p in (tmp_path / "cache").rglob("*") if p.suffix in (".msh", ".npz")]
    assert {p.suffix for p in entries} == {".msh", ".npz"}
    for path in entries:
        path.write_bytes(path.read_bytes()[: path.stat().st_size // 2])
    second = subprocess.run(argv + ["--out", str(tmp_path / "b")], capture_output=True, text=True, env=env)
    assert second.returncode == 0, second.stderr
    assert second.stderr.count("cannot be read") == 2, second.stderr
    a, b = (json.loads(run.stdout) for run in (first, second))
    assert b["amplitude"]["v_L"] == pytest.approx(a["amplitude"]["v_L"], rel=1e-9)


# --- the environment, the output, the speed, the section: one line, exit 2, before the work -----------
def _shell(argv: list[str], env: dict | None = None, timeout: float = 300) -> subprocess.CompletedProcess:
    env = {**os.environ, "OMP_NUM_THREADS": "1", "PYTHONPATH": str(ROOT), **(env or {})}
    return subprocess.run([sys.executable, "-m", "workbench.cli", *argv], capture_output=True, text=True,
                          env=env, timeout=timeout)


def _one_line(proc: subprocess.CompletedProcess, status: int, key: str) -> str:
    lines = [l for l in proc.stderr.splitlines() if not l.startswith("[shroud]")]
    assert proc.returncode == status, proc.stderr
    assert len(lines) == 1 and lines[0].startswith(f"error: {key}:"), proc.stderr
    return lines[0]


@pytest.mark.parametrize("command", [["modal"], ["run", str(ROOT / "scenes/fig3.toml"), "--quick"]])
def test_a_cache_folder_below_a_file(tmp_path, command):
    blocker = tmp_path / "a_file"
    blocker.write_text("x")
    out = tmp_path / "out"
    proc = _shell(command + (["--out", str(out)] if command[0] == "run" else []),
                  env={"SHROUD_CACHE": str(blocker / "cache")})
    line = _one_line(proc, 2, "SHROUD_CACHE")
    assert "is a file" in line and "allowed:" in line
    assert not out.exists() and blocker.read_text() == "x"


def test_transient_into_an_existing_file(tmp_path, capsys):
    target = tmp_path / "taken"
    target.write_text("mine")
    assert main(["transient", "--out", str(target)]) == 2
    assert capsys.readouterr().err.strip().startswith("error: --out:")
    assert target.read_text() == "mine"


@pytest.mark.parametrize("argv", [
    ["modal", "--rpm", "1e9"],                                   # the beam: tens of MHz, said nothing
    ["modal", "--rpm", "1e9", "--model", "fe"],                  # the solid: SLEPc failed
    ["transient", "--rpm", "2e5"],
    ["sweep", "--rpm-from", "8000", "--rpm-to", "1e6", "--rpm-count", "3"],
    ["sweep", "--method", "hb", "--rpm-from", "8000", "--rpm-to", "1e6"],
    ["sweep", "--method", "hb", "--checkpoints", "9000", "1e6"],
])
def test_a_speed_beyond_where_the_models_mean_anything(tmp_path, capsys, argv):
    """Past 10 % centrifugal strain at the root (76 696 r/min for this blade) the linear, small-strain
    beam and solid describe nothing: refused with the strain, the reason and the bound."""
    out = tmp_path / "out"
    line = _refused(capsys, argv + (["--out", str(out)] if argv[0] == "transient" else []), "speed.rpm", out)
    assert "strains the blade root" in line and "small-strain" in line and "76696 r/min" in line


def test_the_speed_bound_is_the_root_strain_of_a_uniform_bar_with_a_tip_mass():
    """sigma(R) = rho Omega^2 (R L + L^2/2) + m_s Omega^2 (R + L) / A, by hand at 30000 r/min."""
    from shroud.params import MAX_ROOT_STRAIN, Parameters
    p = Parameters()
    omega = 30000 * 2 * 3.141592653589793 / 60
    bar = 7800 * (0.15 * 0.15 + 0.15**2 / 2) * omega**2
    tip = 7800 * 0.04 * 0.02 * 0.007 * omega**2 * 0.30 / (0.04 * 0.007)
    assert p.root_strain(30000) == pytest.approx((bar + tip) / 200e9, rel=1e-12)
    assert p.root_strain(p.max_rpm) == pytest.approx(MAX_ROOT_STRAIN, rel=1e-12)
    p.updated({"speed.rpm": 70000})                     # the HB studies' highest speed: inside


@pytest.mark.parametrize("model, key, words", [
    ("reduced", "blade.thickness", "torsion grid"),        # the beam's section solve: 105 GiB, was a MemoryError
    ("fe", "blade.thickness", "times longer than thick"),  # the solid's cells: MUMPS FACTOR_OUTMEMORY
])
def test_a_blade_one_micrometre_thick_is_refused_before_it_is_built(tmp_path, capsys, monkeypatch, model, key, words):
    monkeypatch.setenv("SHROUD_CACHE", str(tmp_path / "cache"))
    line = _refused(capsys, ["modal", "--model", model, "--rpm", "1000", "--set", "blade.thickness=1e-6"],
                    key, tmp_path / "out")
    assert words in line
    assert not list((tmp_path / "cache").rglob("*.msh"))


def test_a_blade_one_micrometre_thick_at_speed_is_torn_by_its_shroud(tmp_path, capsys):
    line = _refused(capsys, ["modal", "--set", "blade.thickness=1e-6"], "speed.rpm", tmp_path / "out")
    assert "180 %" in line


@pytest.mark.fe
@pytest.mark.parametrize("setting, key, words", [
    ("fe.cms_modes=100000", "fe.cms_modes", "DOF"),               # was a ValueError of the eigensolver
    ("fe.interface_modes=5000", "fe.interface_modes", "contact-face patterns"),   # was silently "all"
])
def test_kept_counts_the_solid_does_not_have(tmp_path, setting, key, words):
    out = tmp_path / "out"
    proc = _shell(["transient", "--model", "fe-reduced", "--set", "time.periods=2", "--set", setting,
                   "--out", str(out)])
    assert words in _one_line(proc, 2, key)
    assert not out.exists()


# --- a run that diverged: exit 1, whatever the command -------------------------------------------------
def test_a_scene_whose_only_model_diverges_exits_1(tmp_path):
    out = tmp_path / "out"
    proc = _shell(["run", str(ROOT / "scenes/fig8.toml"), "--quick", "--set", 'options.models=["reduced"]',
                   "--set", "options.reference=reduced", "--set", "time.contact=explicit",
                   "--set", "contact.kn=1e9", "--out", str(out)])
    assert "report.md" in _one_line(proc, 1, "run diverged (reduced)")
    record = json.loads((out / "results.json").read_text())
    assert record["status"] == "diverged (reduced)" and "reduced" in record["results"]["diverged"]
    assert (out / "transient_reduced.csv").read_text().startswith("# status: incomplete")


def test_a_sweep_whose_points_diverge_exits_1(tmp_path):
    proc = _shell(["sweep", "--rpm-from", "9000", "--rpm-to", "10000", "--rpm-count", "2", "--json",
                   "--set", "time.contact=explicit", "--set", "contact.kn=1e9", "--set", "time.periods=20"])
    assert "amplitudes are null" in _one_line(proc, 1, "run diverged at 2 of 2 speeds (9000, 10000 r/min)")
    assert json.loads(proc.stdout)["amplitude_v_L"] == [None, None]


def test_an_incomplete_harmonic_balance_branch_exits_1(capsys, monkeypatch):
    from shroud.core import continuation
    original = continuation._corrector
    calls = {"n": 0}

    def failing(*a, **k):
        calls["n"] += 1
        u, it, ok, R, J, Rp = original(*a, **k)
        return u, it, ok and calls["n"] <= 10, R, J, Rp
    monkeypatch.setattr(continuation, "_corrector", failing)
    code = main(["sweep", "--method", "hb", "--rpm-from", "9000", "--rpm-to", "16000", "--harmonics", "5",
                 "--samples", "128", "--set", "contact.gap=1e-4", "--json"])
    captured = capsys.readouterr()
    assert code == 1
    assert json.loads(captured.out)["complete"] is False
    assert [l for l in captured.err.splitlines() if l.startswith("error:")] == \
        [l for l in captured.err.splitlines() if l.startswith("error: the branch is incomplete:")]


@pytest.mark.parametrize("argv, key, words", [
    (["sweep", "--method", "hb", "--rpm-from", "8000", "--rpm-to", "9000", "--harmonics", "100000"],
     "--harmonics", "Fourier basis"),                       # was a numpy MemoryError (1.53 TiB), exit 1
    (["sweep", "--method", "hb", "--rpm-from", "8000", "--rpm-to", "9000", "--harmonics", "5",
      "--samples", "100000000000"], "--samples", "Fourier basis"),
    (["transient", "--set", "time.steps_per_period=100000000"], "time.steps_per_period",
     "steps per period"),                                   # was "at most 0 periods" on time.periods
    # --rpm-count 100000000 hung while its speeds were checked one by one (refused here: 55.9 GiB
    # against 23.5 GiB); 10**10 speeds (5.5 TiB) exceed any machine's memory
    (["sweep", "--rpm-from", "8000", "--rpm-to", "9000", "--rpm-count", "10000000000"], "--rpm-count",
     "speeds would hold"),
    (["sweep", "--method", "hb", "--rpm-from", "8000", "--rpm-to", "9000", "--rpm-count", "10000000000"],
     "--rpm-count", "speeds would hold"),
])
def test_more_resolution_than_the_machine_holds(tmp_path, capsys, argv, key, words):
    out = tmp_path / "out"
    line = _refused(capsys, argv + (["--out", str(out)] if argv[0] == "transient" else []), key, out)
    assert words in line


@pytest.mark.parametrize("table, key", [('[blade]\nstep = "/etc/passwd"\n', "blade.step"),
                                        ('[blade]\nsection = "naca4"\n', "blade.section"),
                                        ('[quick.blade]\nchord_taper = 0.5\n', "blade.chord_taper")])
def test_a_scene_asking_for_a_blade_no_model_builds_yet(tmp_path, capsys, table, key):
    """A STEP file (any file: it is not read), the airfoil or a taper in a scene: one line, exit 2,
    nothing written, never the rectangle run in its place."""
    scene = tmp_path / "scene.toml"
    scene.write_text(f'study = "fig3"\ntitle = "t"\n{table}')
    _refused(capsys, ["run", str(scene), "--quick", "--out", str(tmp_path / "out")], key, tmp_path / "out")
