"""Hostile input a new user tried, each through the command: one line naming the key or file
and what is allowed, exit status 2, no output folder (and for a damaged cache: the run succeeds)."""

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
