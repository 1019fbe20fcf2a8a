"""The stability study says what it leaves out and refuses what it cannot study."""

import subprocess
import sys
from types import SimpleNamespace

import numpy as np

from comparisons import stability
from shroud.core import registry
from shroud.core.system import ContactElements, StructuralSystem
from shroud.params import Parameters

SCENE = """study = "stability"
title = "stability probe"
[speed]
rpm = 10000.0
[time]
periods = 4
[options]
kn_values = [1e7]
steps_per_period = [32]
refine = 2
"""


def _run(tmp_path, *sets):
    path = tmp_path / "s.toml"
    path.write_text(SCENE)
    cmd = [sys.executable, "-m", "workbench.cli", "run", str(path), "--out", str(tmp_path / "out")]
    for s in sets:
        cmd += ["--set", s]
    return subprocess.run(cmd, capture_output=True, text=True)


def test_a_blade_without_contact_is_bad_input_not_a_crash(tmp_path):
    proc = _run(tmp_path, "contact.enabled=false")
    assert proc.returncode == 2, proc.stderr
    assert proc.stderr.strip().splitlines() == [proc.stderr.strip()]          # one line
    assert proc.stderr.startswith("error: contact.enabled:")
    assert not (tmp_path / "out").exists()


def _chain(params):
    """201 masses in a chain, the last one carrying both shroud contacts (a dense model above 200 DOF)."""
    n = 201
    K = 2e6 * (2 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1))
    tip = np.zeros((2, n))
    tip[0, -1] = tip[1, -2] = 1.0
    contact = ContactElements(W=tip.copy(), normal_row=np.array([0, 0]), tangent_row=np.array([1, 1]),
                              side=np.array([1, 2]), weight=np.array([1.0, 1.0]))
    return StructuralSystem(model="chain", M=np.eye(n), C=1e-4 * K, K=K, f_const=np.zeros(n),
                            f_aero=np.ones(n), omega_e=params.load.ke * params.speed.omega, tip=tip,
                            contact=contact)


def test_the_lag_analysis_left_out_above_its_size_is_reported(monkeypatch):
    monkeypatch.setattr(registry, "_MODELS", dict(registry._MODELS))
    registry.register(registry.ModelEntry("chain", build_system=_chain))
    rows, why = stability.lag_analysis(Parameters(), [1e7], [32], "chain")
    assert rows == [] and "201" in why and "200" in why
    result = stability.StabilityResult(rows=[], linear_limits={}, explicit_lag=rows,
                                       left_out=[f"explicit lag analysis: {why}"])
    scene = SimpleNamespace(params=Parameters(), title="probe", options={"refine": 2})
    assert "Left out of this run" in stability.report(result, scene, [])
