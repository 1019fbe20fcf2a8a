"""Bad input to the beam model through the ``shroud`` command: one line on stderr, exit 2."""

import json
import subprocess
import sys
from pathlib import Path

import pytest

SHROUD = str(Path(sys.executable).with_name("shroud"))


def shroud(*args):
    return subprocess.run([SHROUD, *args], capture_output=True, text=True, timeout=120)


@pytest.mark.parametrize("setting, key", [
    ("blade.thickness=-0.007", "blade.thickness"),
    ("material.nu=0.5", "material.nu"),
    ("reduced.N=0", "reduced.N"),
    ("blade.thicknes=0.007", "blade.thicknes"),
])
def test_bad_beam_input_gives_one_line_and_exit_2(setting, key):
    r = shroud("modal", "--model", "reduced", "--set", setting, "--json")
    assert r.returncode == 2
    assert r.stdout == ""
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"error: {key}:")
    assert "allowed" in lines[0]


def test_too_many_kept_modes_names_reduced_nr(tmp_path):
    r = shroud("transient", "--model", "reduced", "--set", "reduced.nr=31", "--out", str(tmp_path), "--json")
    assert r.returncode == 2
    assert r.stderr.strip().splitlines() == [r.stderr.strip()] and "reduced.nr" in r.stderr


def test_modal_json_gives_the_labelled_table1_modes():
    r = shroud("modal", "--model", "reduced", "--rpm", "8500", "--modes", "4", "--json")
    assert r.returncode == 0, r.stderr
    out = json.loads(r.stdout)
    assert out["dofs"] == 30 and out["rpm"] == 8500.0
    assert [m["label"] for m in out["modes"]] == ["flap1", "chord1", "flap2", "flap3"]
    assert out["modes"][0]["f_hz"] == pytest.approx(282.4, rel=0.005)      # paper's ANSYS value
