"""Forced-response curves by pyHarm (PyPI pyharm-os), run in its own environment by tests/test_pyharm.py.

Prints one JSON object: for each case the accepted continuation points [omega (rad/s), amplitude of
each mass ((max - min) / 2 over the period, m)]. Cases (SI units): a mass on a spring and damper with a
Jenkins element to the ground (spring kt, slip force mu N0), forced by F cos(omega t); a tuned cyclic
chain of N such masses joined by Jenkins elements, forced by the travelling wave F cos(omega t + j phi),
phi = 2 pi ke / N (a cosine and a sine forcing per mass: pyHarm's forcings carry no phase).
"""

import json
import math
import sys

import numpy as np
from pyHarm.Maestro import Maestro

CASE = {"m": 1.0, "k": 1.0e4, "zeta": 0.02, "kt": 5.0e3, "mu": 2.0, "N0": 1.0, "F": 10.0, "H": 10, "nti": 512,
        "N": 5, "ke": 2, "omega": [60.0, 200.0]}


def curve(substructures, connectors, blades):
    c = CASE
    data = {"export": {"status": False}, "system": {"type": "Base", "nh": c["H"], "nti": c["nti"]},
            "substructures": substructures, "connectors": connectors,
            "analysis": {"frf": {"study": "frf", "puls_inf": c["omega"][0], "puls_sup": c["omega"][1],
                                 "ds0": 1.0, "ds_max": 2.0, "verbose": False}}}
    maestro = Maestro(data)
    maestro.operate()
    ft = maestro.system.dynop["ft"]
    return [[float(s.x[-1])] + [0.5 * float(np.ptp(s.x[:-1][j::blades] @ ft)) for j in range(blades)]
            for s in maestro.nls["frf"].SolList if s.flag_accepted]


def mass(c):
    return {"matrix": {"M": np.array([[c["m"]]]), "K": np.array([[c["k"]]]),
                       "C": np.array([[2 * c["zeta"] * math.sqrt(c["k"] * c["m"])]])}, "ndofs": 1}


def main():
    c = CASE
    jenkins = {"type": "Jenkins", "dirs": [0], "mu": c["mu"], "N0": c["N0"], "k": c["kt"]}
    one = curve({"m0": mass(c)},
                {"load": {"type": "CosinusForcing", "connect": {"m0": [0]}, "dirs": [0], "amp": c["F"]},
                 "jenkins": {**jenkins, "connect": {"m0": [0]}}}, 1)
    N, phi = c["N"], 2 * math.pi * c["ke"] / c["N"]
    connectors = {}
    for j in range(N):
        connectors[f"cos{j}"] = {"type": "CosinusForcing", "connect": {f"m{j}": [0]}, "dirs": [0],
                                 "amp": c["F"] * math.cos(j * phi)}
        connectors[f"sin{j}"] = {"type": "SinusForcing", "connect": {f"m{j}": [0]}, "dirs": [0],
                                 "amp": -c["F"] * math.sin(j * phi)}
        connectors[f"jenkins{j}"] = {**jenkins, "connect": {f"m{j}": [0], f"m{(j + 1) % N}": [0]}}
    chain = curve({f"m{j}": mass(c) for j in range(N)}, connectors, N)
    json.dump({"case": c, "oscillator": one, "chain": chain}, sys.stdout)


if __name__ == "__main__":
    main()
