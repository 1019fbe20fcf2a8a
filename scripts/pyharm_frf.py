"""Frequency-response curve of a chain of oscillators with Jenkins friction elements, by pyHarm.

Run on pyHarm's own environment (scripts/install_pyharm.sh; it cannot share the project's numpy), as
the second harmonic-balance code of tests/test_pyharm.py (docs/pyharm.md):

    .venv-pyharm/bin/python scripts/pyharm_frf.py < case.json > curve.json

The case (JSON on stdin) is a set of DOFs x_i, each with a mass, a viscous damper and a spring to
the ground, Jenkins elements (a spring ``kt`` in series with a Coulomb slider ``mu N0``, constant
normal load) acting on x_i (to the ground) or on x_i - x_j (between two DOFs), and harmonic
forces ``amp sin(omega t - phase)`` on DOFs; SI units, omega in rad/s:

    {"mass": [m_i], "damping": [c_i], "stiffness": [k_i],
     "jenkins": [{"dofs": [i] or [i, j], "kt": .., "mu": .., "N0": ..}],
     "forcing": [{"dof": i, "amp": .., "phase": ..}],
     "harmonics": H, "samples": nti, "omega": [from, to], "ds0": .., "ds_max": ..}

pyHarm continues the curve from ``omega[0]`` to ``omega[1]`` (tangent predictor, arc-length
corrector, scipy's hybr solver with the elements' analytic Jacobians). The answer (JSON on stdout)
holds, per accepted point, omega and the harmonic coefficients (H + 1 + H, dofs) of x in the order
a_0, a_1, b_1, ..., a_H, b_H of x = a_0 + sum_k a_k cos(k omega t) + b_k sin(k omega t), and the
share of the period each Jenkins element sticks. This file imports nothing from the workbench.
"""

from __future__ import annotations

import json
import os
import sys
import time
from importlib.metadata import version

import numpy as np


def pyharm_input(case: dict) -> dict:
    """pyHarm's input dictionary for ``case``: one 'onlydofs' substructure with a node per DOF."""
    n = len(case["mass"])
    sub = "chain"
    connectors = {}
    for i in range(n):
        ground = {"connect": {sub: [i]}, "dirs": [0]}
        connectors[f"mass_{i}"] = {"type": "GOElement", "dto": 2, "xo": 1, "k": case["mass"][i], **ground}
        connectors[f"damper_{i}"] = {"type": "LinearDamper", "k": case["damping"][i], **ground}
        connectors[f"spring_{i}"] = {"type": "LinearSpring", "k": case["stiffness"][i], **ground}
    for e, jen in enumerate(case["jenkins"]):
        dofs = jen["dofs"]
        connect = {sub: [dofs[0]]} if len(dofs) == 1 else {sub: [dofs[0]], "INTERNAL": [dofs[1]]}
        connectors[f"jenkins_{e}"] = {"type": "Jenkins", "connect": connect, "dirs": [0],
                                      "k": jen["kt"], "mu": jen["mu"], "N0": jen["N0"]}
    for f, force in enumerate(case["forcing"]):
        # GOForcing loads amp (cos(phi) cos + sin(phi) sin) = amp cos(omega t - phi) on harmonic 1:
        # amp sin(omega t - phase) is phi = phase + pi / 2
        connectors[f"force_{f}"] = {"type": "GOForcing", "connect": {sub: [force["dof"]]}, "dirs": [0],
                                    "dto": 0, "ho": 1, "phi": force["phase"] + np.pi / 2, "amp": force["amp"]}
    return {
        "system": {"type": "Base", "nh": case["harmonics"], "nti": case["samples"]},
        "substructures": {sub: {"type": "onlydofs", "ndofs": 1, "nnodes": n, "matrix": {}}},
        "connectors": connectors,
        "analysis": {"frf": {"study": "frf", "puls_inf": case["omega"][0], "puls_sup": case["omega"][1],
                             "ds0": case.get("ds0", 0.1), "ds_min": 1e-6, "ds_max": case.get("ds_max", 1.0),
                             "verbose": False}},
    }


def run(case: dict) -> dict:
    # pyHarm keeps a record of its running kernels in ./.pyHarm unless told where: in its environment
    os.environ.setdefault("PYHARM_CONTEXT_FILE", os.path.join(sys.prefix, "pyharm-context.json"))
    from pyHarm.Maestro import Maestro

    t0 = time.perf_counter()
    maestro = Maestro(pyharm_input(case))
    maestro.operate()
    analysis = maestro.nls["frf"]
    n, H = len(case["mass"]), case["harmonics"]
    edf = maestro.system.expl_dofs            # what each entry of x is: harmonic, cos or sin, node
    row = np.where(edf["harm"] == 0, 0, 2 * edf["harm"] - (edf["cs"] == "c")).astype(int)
    node = edf["node_num"].to_numpy(int)
    jenkins = [e for e in maestro.system.LE if e.name.startswith("jenkins_")]
    points = {"omega": [], "coefficients": [], "stuck_share": []}
    for sol in analysis.SolList:
        if not sol.flag_accepted:
            continue
        x = sol.x                              # every DOF (no kinematic conditions), then omega
        c = np.zeros((2 * H + 1, n))
        c[row, node] = x[:-1]
        points["omega"].append(float(x[-1]))
        points["coefficients"].append(c.tolist())
        shares = []
        for e in jenkins:
            e.evalResidual(x, x[-1])
            shares.append(e.tau / 100.0)
        points["stuck_share"].append(shares)
    return {"code": "pyHarm", "version": version("pyharm-os"), "harmonics": H, "samples": case["samples"],
            "points": len(points["omega"]), "rejected": sum(not s.flag_accepted for s in analysis.SolList),
            "elapsed_s": time.perf_counter() - t0, **points}


if __name__ == "__main__":
    case = json.load(sys.stdin)
    out = sys.stdout
    sys.stdout = sys.stderr                    # pyHarm's banner and log go to stderr
    answer = run(case)
    json.dump(answer, out)
