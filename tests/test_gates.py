"""Verification gates: the reduced beam model held to the solid FE reference.

The gates are the ``[gates]`` table of scenes/ci_gates.toml (thresholds,
the errors measured when they were set and why they sit where they do live
there, and in the README's "Verification gates"): the default study on the
default, coarse solid mesh; frequencies at the paper's Table 1 speed and the
Fig. 8 transient of the reduced beam against the reduced solid. This test
runs that scene as CI and a user would, through the command: exit status 0
and a junit.xml holding every gate of the scene, none failed. A change that
loosens agreement past a threshold fails here.
"""

import subprocess
import sys
import tomllib
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

SCENE = Path(__file__).resolve().parents[1] / "scenes" / "ci_gates.toml"


@pytest.mark.fe
@pytest.mark.slow
def test_the_gate_scene_holds_through_the_command(tmp_path):
    out = tmp_path / "out"
    proc = subprocess.run([sys.executable, "-m", "workbench.cli", "run", str(SCENE), "--out", str(out)],
                          capture_output=True, text=True)
    assert proc.returncode == 0, proc.stdout + proc.stderr[-3000:]
    root = ET.parse(out / "junit.xml").getroot()
    cases = root.findall("testsuite/testcase")
    gates = tomllib.loads(SCENE.read_text())["gates"]
    assert sorted(c.get("name") for c in cases) == sorted(gates)
    failed = [f"{c.get('name')}: {c.find('failure').get('message')}"
              for c in cases if c.find("failure") is not None]
    assert not failed and root.get("failures") == "0"
