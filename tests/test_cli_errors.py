"""Bad input, end to end: every mistake a user can make in a scene, a campaign
or on the command line ends with one line ``error: <key>: ...`` on stderr,
exit status 2, no traceback, and no output folder."""

import subprocess
import sys
from pathlib import Path

import pytest

from workbench.cli import main
from shroud.params import SECTIONS

GOOD = 'study = "default"\ntitle = "t"\n'


def _scene(tmp_path: Path, text: str, name: str = "scene.toml") -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


def _refused(capsys, argv: list[str], key: str, out: Path) -> str:
    """Run the CLI; assert exit 2, one line naming ``key``, and nothing written to ``out``."""
    code = main(argv)
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2, err
    last = err[-1]
    assert last.startswith(f"error: {key}:"), last
    assert "Traceback" not in "\n".join(err)
    assert not out.exists(), f"{out} was created for bad input"
    return last


# --- mistakes inside a scene file --------------------------------------------
SCENE_CASES = {
    "unknown top-level key": (GOOD + 'colour = "red"\n', "colour"),
    "unknown option": (GOOD + "[options]\nn_moodes = 4\n", "options.n_moodes"),
    "option of the wrong type": (GOOD + '[options]\nn_modes = "four"\n', "options.n_modes"),
    "unknown quick option": (GOOD + "[quick.options]\nperiod = 3\n", "quick.options.period"),
    "unknown quick table": (GOOD + "[quick.colour]\nred = 1\n", "quick.colour"),
    "unknown key in a quick section": (GOOD + "[quick.time]\nperiod = 3\n", "quick.time.period"),
    "out-of-range quick value": (GOOD + "[quick.time]\nperiods = 0\n", "quick.time.periods"),
    "string for a length": (GOOD + '[blade]\nlength = "long"\n', "blade.length"),
    "Poisson ratio out of range": (GOOD + "[material]\nnu = 0.7\n", "material.nu"),
    "too few steps per period": (GOOD + "[time]\nsteps_per_period = 8\n", "time.steps_per_period"),
    "non-integer N": (GOOD + "[reduced]\nN = 2.5\n", "reduced.N"),
    "boolean as a word": (GOOD + '[contact]\nenabled = "maybe"\n', "contact.enabled"),
    "gap and preload both": (GOOD + "[contact]\ngap = 1e-4\nN0 = 10.0\n", "contact.gap"),
    "shroud narrower than the blade": (GOOD + "[shroud]\nwidth = 0.005\n", "shroud.width"),
    "section as a value": (GOOD + "blade = 3\n", "blade"),
    "unknown study": ('study = "fig99"\n', "study"),
    "no study": ('title = "nothing to run"\n', "study"),
}


@pytest.mark.parametrize("case", sorted(SCENE_CASES))
def test_bad_scene_content(tmp_path, capsys, case):
    text, key = SCENE_CASES[case]
    path = _scene(tmp_path, text)
    _refused(capsys, ["run", str(path), "--out", str(tmp_path / "out")], key, tmp_path / "out")


@pytest.mark.parametrize("section", sorted(SECTIONS))
def test_unknown_key_in_each_section(tmp_path, capsys, section):
    path = _scene(tmp_path, GOOD + f"[{section}]\nno_such_key = 1\n")
    line = _refused(capsys, ["run", str(path), "--out", str(tmp_path / "out")],
                    f"{section}.no_such_key", tmp_path / "out")
    assert "allowed keys" in line


def test_bad_toml_and_missing_file(tmp_path, capsys):
    path = _scene(tmp_path, 'study = "default\n[blade\n')
    line = _refused(capsys, ["run", str(path), "--out", str(tmp_path / "out")], str(path), tmp_path / "out")
    assert "TOML" in line
    missing = tmp_path / "nowhere.toml"
    _refused(capsys, ["run", str(missing), "--out", str(tmp_path / "out")], str(missing), tmp_path / "out")


# --- mistakes on the command line --------------------------------------------
CLI_CASES = {
    "--set without =": (["--set", "speed.rpm"], "--set"),
    "--set unknown key": (["--set", "speed.rmp=9000"], "speed.rmp"),
    "--set word for a number": (["--set", "speed.rpm=fast"], "speed.rpm"),
    "--set negative speed": (["--set", "speed.rpm=-10"], "speed.rpm"),
    "--set unknown option": (["--set", "options.nope=1"], "options.nope"),
    "--set option of the wrong type": (["--set", "options.transient_models=3"], "options.transient_models"),
    "--set gap over a scene preload": (["--set", "contact.gap=1e-4", "--set", "contact.N0=5"], "contact.gap"),
    "unknown flag": (["--fast"], "command line"),
}


@pytest.mark.parametrize("case", sorted(CLI_CASES))
def test_bad_run_arguments(tmp_path, capsys, case):
    extra, key = CLI_CASES[case]
    path = _scene(tmp_path, GOOD)
    _refused(capsys, ["run", str(path), "--out", str(tmp_path / "out"), *extra], key, tmp_path / "out")


def test_out_is_an_existing_file(tmp_path, capsys):
    path = _scene(tmp_path, GOOD)
    target = tmp_path / "taken"
    target.write_text("mine")
    assert main(["run", str(path), "--out", str(target)]) == 2
    assert capsys.readouterr().err.strip().startswith("error: --out:")
    assert target.read_text() == "mine"


@pytest.mark.parametrize("argv, key", [
    (["sweep", "--rpm-from", "8000", "--rpm-to", "9000", "--rpm-count", "-3"], "--rpm-count"),
    (["sweep", "--rpm-from", "9000", "--rpm-to", "8000", "--rpm-count", "3"], "--rpm-from"),
    (["sweep", "--rpm-from", "8000", "--rpm-to", "9000"], "command line"),
    (["modal", "--modes", "0"], "--modes"),
    (["modal", "--modes", "four"], "command line"),
    (["modal", "--model", "banana"], "command line"),
    (["modal", "--rpm", "-1"], "speed.rpm"),
    (["frequencies"], "command line"),
])
def test_bad_analysis_commands(tmp_path, capsys, argv, key):
    _refused(capsys, argv, key, tmp_path / "out")


UNBUILT = [("blade.section=naca4", "blade.section"), ("blade.chord_taper=0.75", "blade.chord_taper"),
           ("blade.thickness_taper=0.6", "blade.thickness_taper"), ("blade.step=blade.step", "blade.step")]
COMMANDS = [["modal"], ["static", "--tip-force", "0", "100", "0"], ["transient", "--out", "{out}"],
            ["sweep", "--rpm-from", "8000", "--rpm-to", "9000", "--rpm-count", "2"],
            ["sweep", "--method", "hb", "--checkpoints", "9000"], ["run", "{scene}", "--out", "{out}"]]


# Every model takes the airfoil and the tapers (the beams, the solid, the shell): the studies do not yet; a
# STEP file the beams and the solid's modes read, not the shell.
REFUSED = [(argv, assignment, key) for argv in COMMANDS for assignment, key in UNBUILT
           if key == "blade.step" or argv[0] == "run"]


@pytest.mark.parametrize("argv, assignment, key", REFUSED)
def test_blade_keys_no_model_takes_yet_are_refused_not_dropped(tmp_path, capsys, argv, assignment, key):
    """The airfoil and its tapers in studies, a STEP file on the shell models and in studies: refused,
    naming the key, before anything is written (a rectangle run in their place would answer another
    question). The beams (tests/test_reduced_airfoil.py, tests/test_step_beam.py), the solid
    (tests/test_airfoil_solid.py) and the shell (tests/test_shell.py) take the airfoil and the tapers,
    the beams and the solid's modes a STEP file."""
    out = tmp_path / "out"
    argv = [a.format(scene=_scene(tmp_path, GOOD), out=out) for a in argv]
    if argv[0] != "run":                                # the shell (the beams and the solid read the file)
        argv += ["--model", "shell-reduced" if "--rpm-count" in argv else "shell"]
    line = _refused(capsys, argv + ["--set", assignment], key, out)
    assert "only the beams" in line if key == "blade.step" else "only the beam models" in line


@pytest.mark.parametrize("argv, key", [
    # the NACA shell reads its tip outputs on the shroud plate
    (["modal", "--model", "shell", "--set", "blade.section=naca4", "--set", "shroud.thickness=0"], "shroud.thickness"),
    (["sweep", "--model", "fe-reduced", "--rpm-from", "8000", "--rpm-to", "9000", "--rpm-count", "2",
      "--set", "blade.step=b.step"], "blade.step"),
    (["static", "--model", "fe", "--tip-force", "0", "100", "0", "--set", "blade.step=b.step"], "blade.step"),
    (["transient", "--model", "fe", "--out", "{out}", "--set", "blade.step=b.step"], "blade.step"),
    (["modal", "--model", "fe", "--set", "blade.chord_taper=0.75", "--set", "fe.cell=hex"], "fe.cell"),
    (["modal", "--model", "fe", "--set", "blade.section=naca4", "--set", "fe.cell=tet"], "fe.mesh_size"),
])
def test_solid_paths_refuse_the_blade_they_cannot_build(tmp_path, capsys, argv, key):
    """The solid takes the airfoil (on hexahedra, or tetrahedra fine enough for its thin tip), a taper
    of the rectangle on tetrahedra only, and the STEP file only
    for its modes (F_e per unit span and the shroud's tip load need sections the file does not name);
    the shell takes the airfoil with its shroud only."""
    out = tmp_path / "out"
    _refused(capsys, [a.format(out=out) for a in argv], key, out)


DISK = ["--set", "ring.blades=24", "--set", "disk.thickness=0.04", "--set", "fe.cell=tet"]


@pytest.mark.parametrize("argv, key", [
    (["modal", "--interface", "free", "--model", "fe", "--set", "disk.thickness=0.04"], "disk.thickness"),
    (["modal", "--interface", "free", "--model", "fe", *DISK, "--set", "disk.bore_radius=0.15"], "disk.bore_radius"),
    (["modal", "--interface", "free", "--model", "fe", *DISK, "--set", "disk.thickness=0.02"], "disk.thickness"),
    (["modal", "--interface", "free", "--model", "fe", *DISK, "--set", "ring.blades=40"], "ring.blades"),
    (["modal", "--interface", "free", "--model", "fe", *DISK[:-2], "--set", "fe.cell=hex"], "fe.cell"),
    (["modal", "--interface", "free", "--model", "reduced", *DISK], "disk.thickness"),
    (["static", "--tip-force", "0", "100", "0", "--model", "fe", *DISK], "disk.thickness"),
    (["modal", *DISK], "disk.thickness"),
    (["transient", "--out", "{out}", *DISK], "disk.thickness"),
    (["modal", "--interface", "free", "--model", "fe", *DISK, "--set", "disk.E_factor=0"], "disk.E_factor"),
    (["modal", "--interface", "free", "--model", "fe", *DISK, "--set", "ring.mistuning_std=0.01"], "ring.mistuning"),
])
def test_disk_sector_bad_input(tmp_path, capsys, argv, key):
    """A disk the sector cannot be built of (no ring, a bore outside the rim, a rim thinner or a sector
    narrower than the blade's root, hexahedra) and the paths without a flexible disk: one line, exit 2."""
    out = tmp_path / "out"
    _refused(capsys, [a.format(out=out) for a in argv], key, out)


@pytest.mark.parametrize("argv, key", [(["section", "--at", "0.16"], "--at"), (["section", "--at", "-0.01"], "--at"),
                                       (["section", "--set", "blade.step=blade.step"], "blade.step"),
                                       (["section", "--set", "blade.section=naca6"], "blade.section")])
def test_bad_section_commands(tmp_path, capsys, argv, key):
    _refused(capsys, argv, key, tmp_path / "out")


def test_transient_at_standstill_writes_nothing(tmp_path, capsys):
    out = tmp_path / "tr"
    _refused(capsys, ["transient", "--rpm", "0", "--out", str(out)], "speed.rpm", out)


# --- mistakes in a campaign --------------------------------------------------
def _campaign(tmp_path: Path, body: str) -> Path:
    _scene(tmp_path, GOOD, "a.toml")
    _scene(tmp_path, GOOD, "b.toml")
    return _scene(tmp_path, 'title = "c"\n' + body, "camp.toml")


@pytest.mark.parametrize("body, key", [
    ('campaign = ["a", "nope"]\n', "campaign"),
    ("campaign = []\n", "campaign"),
    ('campaign = ["a", "a.toml"]\n', "campaign"),
    ('campaign = ["a", "b"]\n[overrides]\nb = ["speed.rpm=-5"]\n', "b: speed.rpm"),
    ('campaign = ["a", "b"]\n[overrides]\nc = ["speed.rpm=5"]\n', "overrides.c"),
    ('campaign = ["a", "b"]\nquick = "yes"\n', "quick"),
    ('campaign = ["a", "b"]\nrepeat = 2\n', "repeat"),
])
def test_bad_campaign_runs_nothing(tmp_path, capsys, body, key):
    path = _campaign(tmp_path, body)
    _refused(capsys, ["run", str(path), "--out", str(tmp_path / "out")], key, tmp_path / "out")


def test_campaign_checks_later_scenes_before_running_the_first(tmp_path, capsys):
    """The second scene's bad value stops the campaign before the first scene runs."""
    _scene(tmp_path, GOOD, "a.toml")
    _scene(tmp_path, GOOD + "[load]\nke = 0\n", "b.toml")
    path = _scene(tmp_path, 'campaign = ["a", "b"]\n', "camp.toml")
    _refused(capsys, ["run", str(path), "--out", str(tmp_path / "out")], "b: load.ke", tmp_path / "out")


# --- the installed command, as a user's shell sees it ------------------------
@pytest.mark.parametrize("argv, key", [
    (["run", "{bad}", "--out", "{out}"], "{bad}"),
    (["sweep", "--rpm-from", "8000", "--rpm-to", "9000", "--rpm-count", "-1"], "--rpm-count"),
    (["run", "{scene}", "--out", "{out}", "--set", "contact.gap=1e-4", "--set", "contact.N0=1"], "contact.gap"),
])
def test_shell_sees_one_line_and_status_2(tmp_path, argv, key):
    bad = _scene(tmp_path, "study = = 1\n", "bad.toml")
    scene = _scene(tmp_path, GOOD)
    out = tmp_path / "out"
    fill = {"bad": str(bad), "scene": str(scene), "out": str(out)}
    argv = [a.format(**fill) for a in argv]
    proc = subprocess.run([sys.executable, "-m", "workbench.cli", *argv], capture_output=True, text=True)
    assert proc.returncode == 2
    assert proc.stdout == ""
    assert proc.stderr.count("\n") == 1 and proc.stderr.startswith(f"error: {key.format(**fill)}:")
    assert not out.exists()
