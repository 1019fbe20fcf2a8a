"""A second harmonic-balance code on the same problems: pyHarm (PyPI pyharm-os, SAFRAN), in its own
environment (scripts/install_pyharm.sh: .venv-pyharm, or the interpreter named by SHROUD_PYHARM_PYTHON),
run in a subprocess by tests/pyharm_curves.py.

A mass with a Jenkins element to the ground, and a tuned cyclic chain of five such masses joined by
Jenkins elements under a travelling wave (engine order 2): pyHarm's whole-chain curves against this
code's harmonic balance (shroud.core.harmonic_balance) and its one-sector travelling wave
(shroud.core.cyclic), at pyHarm's own frequencies, within 0.5 %. The contact law's Jenkins element with
a normal coordinate that never moves is pyHarm's: N = N0, slip force mu N0, spring kt.
"""

import json
import math
import os
import subprocess
import tempfile
from pathlib import Path

import numpy as np
import pytest

from shroud.analysis.ring_hb import Sector, sector_balance, sector_solve
from shroud.core import harmonic_balance as hb
from shroud.core.contact import contact_law
from shroud.core.cyclic import sector_projection
from shroud.core.ring import face_selectors, interface_elements
from shroud.core.system import ContactElements, StructuralSystem

ROOT = Path(__file__).resolve().parents[1]


def _pyharm_python() -> str:
    python = os.environ.get("SHROUD_PYHARM_PYTHON") or str(ROOT / ".venv-pyharm" / "bin" / "python")
    if not Path(python).exists():
        pytest.skip(f"pyHarm's environment {python} is missing (scripts/install_pyharm.sh installs pyharm-os)")
    if subprocess.run([python, "-c", "import pyHarm"], capture_output=True, cwd=tempfile.gettempdir()).returncode:
        pytest.skip(f"{python} cannot import pyHarm (scripts/install_pyharm.sh installs pyharm-os)")
    return python


@pytest.fixture(scope="module")
def pyharm(tmp_path_factory):
    # run in a scratch folder: pyHarm writes its .pyHarm/ context where it runs
    run = subprocess.run([_pyharm_python(), str(ROOT / "tests" / "pyharm_curves.py")], capture_output=True,
                         text=True, timeout=1200, env={**os.environ, "PYTHONWARNINGS": "ignore"},
                         cwd=tmp_path_factory.mktemp("pyharm"))
    assert run.returncode == 0, run.stderr[-2000:]
    return json.loads(run.stdout)


def _mass(c, omega, contact):
    """The mass as a StructuralSystem: its x on the tangent row, a normal row that never moves (N = N0)."""
    damping = 2 * c["zeta"] * math.sqrt(c["k"] * c["m"])
    return StructuralSystem(model="mass", M=np.array([[c["m"]]]), C=np.array([[damping]]), K=np.array([[c["k"]]]),
                            f_const=np.zeros(1), f_aero=np.array([c["F"]]), omega_e=omega,
                            tip=np.array([[1.0], [0.0]]), contact=contact)


def test_jenkins_oscillator_against_pyharm(pyharm):
    c, points = pyharm["case"], pyharm["oscillator"]
    assert len(points) > 20
    element = ContactElements(W=np.array([[0.0], [1.0]]), normal_row=np.array([0]), tangent_row=np.array([1]),
                              side=np.array([2]), weight=np.array([1.0]))
    law = contact_law(element, kn=1.0, kt=c["kt"], mu=c["mu"], N0=c["N0"])
    ours = np.array([hb.solve(_mass(c, om, element), law, c["H"], c["nti"]).amplitude_v_L for om, _ in points])
    theirs = np.array([a for _, a in points])
    assert np.abs(ours / theirs - 1).max() < 0.005
    assert theirs.max() > 3 * theirs.min()               # the curve passes its resonance


def test_tuned_jenkins_chain_by_one_sector_against_pyharms_whole_chain(pyharm):
    c, points = pyharm["case"], pyharm["chain"]
    assert len(points) > 20
    element = ContactElements(W=np.array([[0.0], [1.0]]), normal_row=np.array([0, 0]), tangent_row=np.array([1, 1]),
                              side=np.array([1, 2]), weight=np.array([1.0, 1.0]))
    S1, S2, weight = face_selectors(element)
    law = contact_law(interface_elements(weight, np.eye(2)), kn=1.0, kt=c["kt"], mu=c["mu"], N0=c["N0"])
    basis = hb.fourier(c["H"], c["nti"])
    sector = Sector(N=c["N"], ke=c["ke"], P=sector_projection(S1, S2, c["H"], 2 * math.pi * c["ke"] / c["N"]), law=law)
    for om, *theirs in points[::3]:
        lin = hb.linear_harmonics(_mass(c, om, element), c["H"])
        X = sector_solve(lin, sector, basis)
        b = sector_balance(X, lin, law, basis, sector.P, jacobian=False)
        ours = hb.amplitude_over_period(lin.tip(X.reshape(basis.nh, lin.nx), b.Lam_y))[0]
        assert np.ptp(theirs) < 1e-3 * np.mean(theirs)       # pyHarm's chain is on the travelling wave
        assert ours == pytest.approx(theirs[0], rel=0.005)
