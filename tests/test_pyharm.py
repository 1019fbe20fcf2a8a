"""The workbench's harmonic balance against a second code, pyHarm, on Jenkins friction oscillators.

pyHarm (PyPI ``pyharm-os``, Safran's open harmonic-balance code: its own AFT, Jenkins element,
arc-length continuation and scipy solver) needs numpy < 2.5, so it runs in an environment of its
own, ``.venv-pyharm`` (scripts/install_pyharm.sh), through scripts/pyharm_frf.py, which answers
in JSON; where that environment is missing the tests skip and say why. Against pyHarm's curves: one
oscillator by the workbench's harmonic balance; a tuned cyclic chain by its harmonic balance of the
whole chain, by Newmark in time and by harmonic balance of one sector (shroud.core.cyclic,
shroud.analysis.ring_hb: the ring's travelling wave). docs/pyharm.md has the cases and the numbers
measured.

The Jenkins element is a spring kt in series with a Coulomb slider mu N0 (constant normal load).
The workbench expresses it with its one contact law: a contact element whose normal coordinate
never moves (a zero row of W, so N = N0) and whose tangential coordinate is x_i (to the ground)
or x_i - x_j (a W row with +1 and -1: an interface between two oscillators).
"""

from __future__ import annotations

import dataclasses
import json
import math
import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

from shroud import api
from shroud.analysis.ring_hb import Sector, sector_balance, sector_solve
from shroud.core import harmonic_balance as hb
from shroud.core import registry
from shroud.core.contact import contact_law
from shroud.core.cyclic import Faces
from shroud.core.newmark import NewmarkScheme, integrate
from shroud.core.ring import face_selectors, interface_elements
from shroud.core.signals import amplitude

ROOT = Path(__file__).resolve().parents[1]
# pyHarm's interpreter: SHROUD_PYHARM_PYTHON names another than the one install_pyharm.sh makes
PYHARM_PYTHON = Path(os.environ.get("SHROUD_PYHARM_PYTHON") or ROOT / ".venv-pyharm" / "bin" / "python")
DRIVER = ROOT / "scripts" / "pyharm_frf.py"

# m x'' + c x' + k x + F_J = P sin(omega t): natural frequency 100 rad/s with the slider free,
# sqrt((k + kt) / m) = 141 rad/s stuck; the slider slips once kt |x| passes mu N0 (0.1 mm), so the
# resonance, near 111 rad/s at 0.35 mm, lies in the stick-slip regime and both ends of the range stick
MASS, DAMPING, STIFF, KT, MU, N0, P = 1.0, 2.0, 1e4, 1e4, 0.2, 5.0, 1.0     # kg, N s/m, N/m, N/m, -, N, N
X_SLIP = MU * N0 / KT                                                       # m
OMEGA = (80.0, 180.0)                                                       # rad/s
KN = 1e6                   # N/m: acts on the normal coordinate, which never moves (W's zero row)


def jenkins_case(blades: int = 1, engine_order: int = 0, harmonics: int = 10, samples: int = 512,
                 ds_max: float = 2.0, omega: tuple[float, float] = OMEGA) -> dict:
    """The case in scripts/pyharm_frf.py's format: one oscillator with a Jenkins element to the ground
    (``blades`` 1), or a tuned cyclic chain of ``blades`` oscillators with one Jenkins element between
    each pair of neighbours, oscillator j forced by P sin(omega t - j phi), phi = 2 pi engine_order /
    blades (a travelling wave); pyHarm continues over ``omega`` (rad/s)."""
    phi = 2 * math.pi * engine_order / blades
    jenkins = ([{"dofs": [0], "kt": KT, "mu": MU, "N0": N0}] if blades == 1 else
               [{"dofs": [j, (j + 1) % blades], "kt": KT, "mu": MU, "N0": N0} for j in range(blades)])
    return {"mass": [MASS] * blades, "damping": [DAMPING] * blades, "stiffness": [STIFF] * blades,
            "jenkins": jenkins, "forcing": [{"dof": j, "amp": P, "phase": j * phi} for j in range(blades)],
            "harmonics": harmonics, "samples": samples, "omega": list(omega), "ds0": 0.5, "ds_max": ds_max}


def pyharm(case: dict) -> dict:
    """pyHarm's curve of ``case`` (scripts/pyharm_frf.py on pyHarm's environment), or a skip saying why."""
    if not PYHARM_PYTHON.exists():
        pytest.skip(f"pyHarm's interpreter {PYHARM_PYTHON} is missing: scripts/install_pyharm.sh makes "
                    ".venv-pyharm where pip can fetch pyharm-os (it could not here)")
    run = subprocess.run([str(PYHARM_PYTHON), str(DRIVER)], input=json.dumps(case), capture_output=True,
                         text=True, timeout=1800)
    if "No module named 'pyHarm'" in run.stderr:
        pytest.skip(f"{PYHARM_PYTHON} cannot import pyHarm (scripts/install_pyharm.sh installs pyharm-os)")
    assert run.returncode == 0, run.stderr[-3000:]
    answer = json.loads(run.stdout)
    answer["coefficients"] = np.array(answer["coefficients"])      # (points, 2 H + 1, dofs)
    return answer


def half_range(coefficients: np.ndarray) -> np.ndarray:
    """(max - min) / 2 over one period of each column of coefficients (2 H + 1, c) in pyHarm's order
    a_0, a_1, b_1, ..., sampled at 4096 instants."""
    tau = np.linspace(0.0, 2 * np.pi, 4096, endpoint=False)
    k = np.arange(1, (coefficients.shape[0] - 1) // 2 + 1)
    phase = np.outer(tau, k)
    x = coefficients[0] + np.cos(phase) @ coefficients[1::2] + np.sin(phase) @ coefficients[2::2]
    return 0.5 * (x.max(axis=0) - x.min(axis=0))


def chain_system(case: dict, omega: float, tip: tuple[int, int] = (0, 0)) -> api.StructuralSystem:
    """``case`` as the workbench's system at the forcing frequency ``omega`` (rad/s), reporting x of the
    oscillators ``tip`` as (v_L, w_L).

    The workbench loads f_aero sin(omega t), one phase for every DOF; a force P sin(omega t - phi) also
    has a part in cos(omega t). Where the phases differ, a last DOF u, a critically damped oscillator of
    natural frequency 2 omega driven by sin(omega t), u'' / (4 omega^2) + u' / omega + u = sin(omega t),
    so u = Im(z e^(i omega t)) with z = 1 / (3/4 + i), carries it: the oscillators see
    f_j sin(omega t) + b_j u, with b_j Im(z) = Im(P e^(-i phi_j)) and f_j = Re(P e^(-i phi_j)) - b_j Re(z),
    through K[j, u] = -b_j (u's row has no other term, so the chain does not act back on u; its
    start-up transient decays by e^(-2 omega t)).
    """
    n = len(case["mass"])
    load = np.zeros(n, complex)
    for f in case["forcing"]:
        load[f["dof"]] += f["amp"] * np.exp(-1j * f["phase"])
    lagged = bool(np.any(np.abs(load.imag) > 1e-12 * np.abs(load).max()))
    d = n + lagged
    M, C, K, f_aero = np.zeros((d, d)), np.zeros((d, d)), np.zeros((d, d)), np.zeros(d)
    M[:n, :n], C[:n, :n], K[:n, :n] = np.diag(case["mass"]), np.diag(case["damping"]), np.diag(case["stiffness"])
    f_aero[:n] = load.real
    if lagged:
        z = 1.0 / (0.75 + 1.0j)
        b = load.imag / z.imag
        M[n, n], C[n, n], K[n, n], f_aero[n] = 0.25 / omega ** 2, 1.0 / omega, 1.0, 1.0
        K[:n, n], f_aero[:n] = -b, load.real - b * z.real
    count = len(case["jenkins"])
    W = np.zeros((1 + count, d))               # row 0: every element's normal coordinate, which never moves
    for e, element in enumerate(case["jenkins"]):
        W[1 + e, element["dofs"][0]] = 1.0
        if len(element["dofs"]) == 2:
            W[1 + e, element["dofs"][1]] = -1.0
    contact = api.ContactElements(W=W, normal_row=np.zeros(count, int), tangent_row=1 + np.arange(count),
                                  side=np.ones(count, int), weight=np.ones(count))
    tip_rows = np.zeros((2, d))
    tip_rows[0, tip[0]] = tip_rows[1, tip[1]] = 1.0
    return api.StructuralSystem(model="jenkins-chain", M=M, C=C, K=K, f_const=np.zeros(d), f_aero=f_aero,
                                omega_e=omega, tip=tip_rows, contact=contact)


def register(name: str, case: dict, tip: tuple[int, int] = (0, 0)) -> api.Parameters:
    """Register ``case`` as a workbench model; its parameters (excitation order 1: the rotation speed
    Omega, rad/s, is the forcing frequency; the Jenkins elements' kt, mu, N0 as the contact's)."""
    for element in case["jenkins"]:
        assert (element["kt"], element["mu"], element["N0"]) == (KT, MU, N0)     # one law for every element
    def build(params: api.Parameters) -> api.StructuralSystem:
        return chain_system(case, params.load.ke * params.speed.omega, tip)

    api.register_model(api.ModelEntry(name, build_system=build, description="oscillators with Jenkins elements"))
    return api.parameters({"contact.kt": KT, "contact.mu": MU, "contact.N0": N0, "contact.kn": KN, "load.ke": 1})


def rpm(omega: float) -> float:
    return omega * 60.0 / (2 * math.pi)


def start_on(branch, omega: float) -> np.ndarray:
    """The branch's harmonics interpolated at ``omega`` (a Newton start at that frequency)."""
    w = np.asarray(branch.rpm) * 2 * math.pi / 60.0
    i = int(np.clip(np.searchsorted(w, omega), 1, len(w) - 1))
    t = (omega - w[i - 1]) / (w[i] - w[i - 1])
    return (1 - t) * branch.X[i - 1] + t * branch.X[i]


def one_oscillator_comparison(theirs: dict, name: str) -> dict:
    """pyHarm's curve ``theirs`` of the one oscillator against the workbench's: its branch by continuation
    (complete), then at each of pyHarm's frequencies within OMEGA Newton from that branch, at pyHarm's H
    and at 2 H. Amplitudes (max - min) / 2, m; pyHarm's stuck share of the period."""
    H, samples = theirs["harmonics"], theirs["samples"]
    p = register(name, jenkins_case(harmonics=H, samples=samples))
    branch = api.continuation(p, name, rpm(OMEGA[0]), rpm(OMEGA[1]), harmonics=H, min_points=60)
    omega = np.array(theirs["omega"])
    inside = omega <= OMEGA[1]

    def ours(w, harmonics, start):
        return api.harmonic_balance(p, name, rpm(w), harmonics=harmonics, samples=samples, start=start).amplitude_v_L

    return {"complete": branch.complete, "omega": omega[inside], "branch_points": len(branch.rpm),
            "branch_omega": np.asarray(branch.rpm) * 2 * math.pi / 60.0, "branch_amplitude": branch.amplitude_v_L,
            "pyharm": np.array([half_range(c)[0] for c in theirs["coefficients"][inside]]),
            "workbench": np.array([ours(w, H, start_on(branch, w)) for w in omega[inside]]),
            "workbench_2H": np.array([ours(w, 2 * H, None) for w in omega[inside]]),
            "stuck": np.array(theirs["stuck_share"])[inside, 0], "last_omega": float(omega[-1]),
            "pyharm_s": theirs["elapsed_s"]}


@pytest.fixture(scope="module", autouse=True)
def _models_leave_with_the_module():
    """The models these tests register (:func:`register`) are gone after them."""
    saved = dict(registry._MODELS)
    yield
    registry._MODELS.clear()
    registry._MODELS.update(saved)


@pytest.fixture(scope="module")
def one_oscillator() -> dict:
    return {H: pyharm(jenkins_case(harmonics=H)) for H in (10, 20)}


@pytest.mark.parametrize("H", [10, 20])
def test_one_jenkins_oscillator_by_pyharm_and_by_the_workbench(one_oscillator, H):
    """The frequency-response curve from 80 to 180 rad/s, through the resonance, by both codes with
    continuation in the forcing frequency, H harmonics each: at each of pyHarm's points the workbench
    (Newton at that frequency from its own branch) gives the same amplitude within 0.5 % (measured:
    1.8e-5, pyHarm's solver tolerance); the curve runs from stuck through stick-slip (the resonance
    at 3.6 x_slip) back to stuck, and it is converged in H: the workbench's amplitudes at H and 2 H
    differ by less than 0.05 % (measured 6e-5 at H = 10), so pyHarm's at H = 10 and 20 are both the
    converged curve."""
    r = one_oscillator_comparison(one_oscillator[H], f"jenkins-one-{H}")
    assert r["complete"] and r["omega"][0] == pytest.approx(OMEGA[0]) and r["last_omega"] >= OMEGA[1]
    assert np.all(np.diff(r["omega"]) > 0)
    assert np.abs(r["workbench"] / r["pyharm"] - 1).max() < 5e-3
    slipping = (r["stuck"] > 0.05) & (r["stuck"] < 0.95)
    assert slipping.sum() >= 10 and r["stuck"][0] == r["stuck"][-1] == 1.0      # stick-slip between stuck ends
    assert slipping[np.argmax(r["pyharm"])] and r["pyharm"].max() > 3 * X_SLIP  # the resonance slips
    assert np.all(r["pyharm"][~slipping] * KT <= MU * N0 * 1.001)               # stuck: kt x within mu N0
    assert np.abs(r["workbench_2H"] / r["workbench"] - 1).max() < 5e-4


# --- a tuned cyclic chain under a travelling wave ---------------------------------------------------

BLADES = 6
CHAIN_H, CHAIN_SAMPLES = 5, 256              # converged: the workbench's whole chain at 5 and 20 within 0.1 %
# Engine order -> forcing frequencies through its resonance, rad/s. An interface slides by 2 sin(phi / 2)
# times a blade's motion: 1 at engine order 1 (phi 60 deg), 1.73 at 2 (phi 120 deg; stuck, the nodal
# diameter rings at sqrt((k + 3 kt) / m) = 200 rad/s)
CHAINS = {1: (80.0, 180.0), 2: (120.0, 230.0)}


def chain_case(engine_order: int) -> dict:
    return jenkins_case(BLADES, engine_order, harmonics=CHAIN_H, samples=CHAIN_SAMPLES, ds_max=3.0,
                        omega=CHAINS[engine_order])


@pytest.fixture(scope="module", params=sorted(CHAINS))
def chain(request) -> tuple[int, dict]:
    return request.param, pyharm(chain_case(request.param))


def travelling_wave_defect(coefficients: np.ndarray, engine_order: int) -> float:
    """Largest departure of blade j's harmonic h from blade 0's turned by -h j phi (a travelling wave,
    x_j(t) = x_0(t - j phi / omega)), relative to the largest first harmonic."""
    c = coefficients[1::2] - 1j * coefficients[2::2]                   # (H, blades): a_h - i b_h
    h, j = np.arange(1, c.shape[0] + 1)[:, None], np.arange(c.shape[1])[None, :]
    wave = c[:, :1] * np.exp(-1j * h * j * 2 * np.pi * engine_order / c.shape[1])
    return float(np.abs(c - wave).max() / np.abs(c[0]).max())


def sector_amplitude(engine_order: int, omega: float) -> float:
    """Blade 0's amplitude (m) on the chain's travelling wave at ``omega`` (rad/s) by the harmonic balance of
    one sector (shroud.analysis.ring_hb.sector_solve), H and samples as pyHarm's.

    The sector is one oscillator forced by P sin(omega t) (blade 0's load) whose Jenkins element is
    interface 0, x_0 - x_1, seen as the ring sees it: side 2 its own x, side 1 the neighbour's, which is
    its own shifted in time (shroud.core.cyclic.sector_projection). The projection takes blade 1 as blade
    0 advanced by its angle; here blade 1 lags by phi, so the angle is 2 pi - phi (engine order
    BLADES - engine_order, the same wave seen from the other way round the ring).
    """
    alone = chain_system(jenkins_case(), omega)                        # W rows: [normal (zero), x]
    faces = api.ContactElements(W=alone.contact.W, normal_row=np.array([0, 0]), tangent_row=np.array([1, 1]),
                                side=np.array([1, 2]), weight=np.array([1.0, 1.0]))
    S1, S2, weight = face_selectors(faces)
    law = contact_law(interface_elements(weight, np.eye(S1.shape[0])), kn=KN, kt=KT, mu=MU, N0=N0)
    ke = BLADES - engine_order
    sector = Sector(N=BLADES, ke=ke, faces=Faces(S1, S2, 2 * math.pi * ke / BLADES), law=law)
    lin = hb.linear_harmonics(dataclasses.replace(alone, contact=faces), CHAIN_H)
    basis = hb.fourier(CHAIN_H, CHAIN_SAMPLES)
    X = sector_solve(lin, sector, basis)
    forces = sector_balance(X, lin, law, basis, sector.faces, jacobian=False).Lam_y
    return float(hb.amplitude_over_period(lin.tip(X.reshape(basis.nh, lin.nx), forces), 4096)[0])


def chain_comparison(engine_order: int, theirs: dict) -> dict:
    """pyHarm's chain against the workbench's harmonic balance of the whole chain (H as pyHarm's, Newton
    at each of pyHarm's frequencies; blades 0 and 3), against H = 20, and against the harmonic balance
    of one sector (blade 0)."""
    case, name = chain_case(engine_order), f"jenkins-chain-{engine_order}"
    p = register(name, case, tip=(0, BLADES // 2))
    omega = np.array(theirs["omega"])
    inside = omega <= case["omega"][1]

    def ours(w, H):
        point = api.harmonic_balance(p, name, rpm(w), harmonics=H, samples=CHAIN_SAMPLES)
        return point.amplitude_v_L, point.amplitude_w_L

    return {"omega": omega[inside], "first_omega": case["omega"][0], "last_omega": float(omega[-1]),
            "pyharm": np.array([half_range(c) for c in theirs["coefficients"][inside]]),     # (points, blades)
            "workbench": np.array([ours(w, CHAIN_H) for w in omega[inside]]),               # (points, 2)
            "workbench_20": np.array([ours(w, 20) for w in omega[inside]]),
            "sector": np.array([sector_amplitude(engine_order, w) for w in omega[inside]]),
            "defect": np.array([travelling_wave_defect(c, engine_order) for c in theirs["coefficients"][inside]]),
            "stuck": np.array(theirs["stuck_share"])[inside], "pyharm_s": theirs["elapsed_s"]}


@pytest.fixture(scope="module")
def compared(chain) -> dict:
    return chain_comparison(*chain)


def test_a_tuned_chain_by_pyharm_and_by_the_workbenchs_whole_chain(compared):
    """Six oscillators, a Jenkins element between neighbours, engine orders 1 and 2: pyHarm's curve is a
    travelling wave (blade j's harmonic h is blade 0's turned by h j phi, within 1e-3 of the first
    harmonic; measured 2e-4), with stick-slip at every interface around the resonance, and the
    workbench's harmonic balance of the whole chain gives blades 0 and 3 pyHarm's amplitude within
    0.5 % at each of pyHarm's frequencies (measured 1.8e-5), converged in H (5 against 20 within 0.2 %;
    measured 7.5e-4 and 1.25e-3)."""
    r = compared
    assert r["omega"][0] == pytest.approx(r["first_omega"]) and r["last_omega"] >= r["omega"][-1]
    assert r["defect"].max() < 1e-3
    slipping = np.all((r["stuck"] > 0.05) & (r["stuck"] < 0.95), axis=1)
    assert slipping.sum() >= 8 and slipping[np.argmax(r["pyharm"][:, 0])] and r["stuck"][0].min() == 1.0
    theirs = r["pyharm"][:, [0, BLADES // 2]]
    assert np.abs(r["workbench"] / theirs - 1).max() < 5e-3
    assert np.abs(r["workbench_20"] / r["workbench"] - 1).max() < 2e-3


def test_a_tuned_chain_by_pyharm_and_by_one_sector(compared):
    """The same chains by the harmonic balance of one sector (one oscillator, its neighbour its own motion
    shifted by the travelling wave's phase): blade 0 within 0.5 % of pyHarm's whole chain at each of
    pyHarm's frequencies, through the stick-slip resonance (measured 3.1e-4 and 2.5e-4, as far from the
    whole-chain HB: 256 instants, not a multiple of 6, sample the whole chain's interfaces at other
    points of the wave than the sector's; at 258 the two HBs agree within 3e-6)."""
    r = compared
    assert np.abs(r["sector"] / r["pyharm"][:, 0] - 1).max() < 5e-3
    slipping = np.all((r["stuck"] > 0.05) & (r["stuck"] < 0.95), axis=1)
    assert slipping[np.argmax(r["sector"])] and r["sector"].max() > 1.5 * r["sector"][0]    # a slipping resonance


def newmark_comparison(engine_order: int, theirs: dict, periods: int = 200, steps_per_period: int = 512) -> dict:
    """The whole chain in time from rest (Newmark, the workbench's implicit contact solve around the
    chain) at three of pyHarm's frequencies, in stick-slip: the resonance's and, on either side, where the
    amplitude is nearest 60 % of the resonance's. Every blade's settled amplitude (a run reports two:
    blades j and j + BLADES / 2), against pyHarm's."""
    case = chain_case(engine_order)
    omega = np.array(theirs["omega"])
    omega = omega[omega <= case["omega"][1]]
    blade0 = np.array([half_range(c)[0] for c in theirs["coefficients"][:omega.size]])
    peak = int(np.argmax(blade0))
    below = int(np.argmin(np.abs(blade0[:peak] - 0.6 * blade0[peak])))
    above = peak + int(np.argmin(np.abs(blade0[peak:] - 0.6 * blade0[peak])))
    rows = []
    for i in (below, peak, above):
        late, settled, unconverged = np.zeros(BLADES), 0.0, 0
        for j in range(BLADES // 2):
            system = chain_system(case, omega[i], tip=(j, j + BLADES // 2))
            law = contact_law(system.contact, kn=KN, kt=KT, mu=MU, N0=N0)
            run = integrate(system, law, NewmarkScheme(2 * math.pi / omega[i] / steps_per_period),
                            periods * steps_per_period)
            late[[j, j + BLADES // 2]] = [amplitude(run.tip[:, k], steps_per_period) for k in (0, 1)]
            earlier = amplitude(run.tip[:-20 * steps_per_period, 0], steps_per_period)
            settled, unconverged = max(settled, abs(earlier / late[j] - 1)), unconverged + run.contact_unconverged
        rows.append({"omega": float(omega[i]), "newmark": late, "settled": settled,
                     "pyharm": half_range(theirs["coefficients"][i]), "unconverged_steps": unconverged,
                     "stuck": np.array(theirs["stuck_share"][i])})
    return {"points": rows}


def test_a_tuned_chain_by_pyharm_against_the_whole_chain_in_time(chain):
    """The chain integrated in time from rest settles on pyHarm's travelling wave: at three of pyHarm's
    frequencies (stick-slip below, at and above the resonance) every blade within 0.5 % of pyHarm's
    amplitude after 200 periods (measured -7.8e-4 to +6.2e-4: the truncation at H = 5)."""
    for row in newmark_comparison(*chain)["points"]:
        assert np.all((row["stuck"] > 0.05) & (row["stuck"] < 0.95))
        assert row["unconverged_steps"] == 0 and row["settled"] < 1e-4
        assert np.abs(row["newmark"] / row["pyharm"] - 1).max() < 5e-3, row


def draw(one: dict, chains: dict, path: Path) -> Path:
    """The one oscillator's curves (H = 10) and the chains': pyHarm's points, the workbench's branch or
    its whole-chain HB and its one-sector HB at pyHarm's frequencies, the chain in time."""
    from shroud.core.plotting import figure, save
    fig, ax = figure(1, 2, width=7.5, height=3.0)
    a, b = ax[0]
    a.plot(one["branch_omega"], one["branch_amplitude"] * 1e3, "-", color="tab:red", label="workbench, continuation")
    a.plot(one["omega"], one["pyharm"] * 1e3, "o", ms=3, mfc="none", color="black", label="pyHarm, continuation")
    a.axhline(X_SLIP * 1e3, color="tab:gray", ls=":", label="slip onset mu N0 / kt")
    a.set(title="one oscillator, Jenkins element to the ground (H = 10)", xlabel="forcing frequency (rad/s)",
          ylabel="amplitude (mm)")
    for engine_order, (r, in_time) in chains.items():
        first = engine_order == min(chains)
        b.plot(r["omega"], r["workbench"][:, 0] * 1e3, "-", color="tab:red",
               label="workbench, whole-chain HB" if first else None)
        b.plot(r["omega"], r["pyharm"][:, 0] * 1e3, "o", ms=3, mfc="none", color="black",
               label="pyHarm" if first else None)
        b.plot(r["omega"][::3], r["sector"][::3] * 1e3, "x", ms=4, color="tab:green",
               label="workbench, one-sector HB (every 3rd)" if first else None)
        b.plot([p["omega"] for p in in_time["points"]], [p["newmark"][0] * 1e3 for p in in_time["points"]], "s",
               ms=6, mfc="none", color="tab:blue", label="Newmark, whole chain" if first else None)
        top = int(np.argmax(r["pyharm"][:, 0]))
        b.annotate(f"engine order {engine_order}", (r["omega"][top], r["pyharm"][top, 0] * 1e3),
                   xytext=(6, 4), textcoords="offset points", fontsize=8)
    b.set(title=f"tuned chain of {BLADES}, blade 0 (H = {CHAIN_H})", xlabel="forcing frequency (rad/s)",
          ylabel="amplitude (mm)")
    for panel in (a, b):
        panel.set_ylim(0.0, 0.56)                  # the legends above the resonances
        panel.legend(loc="upper left")
    return save(fig, path)


if __name__ == "__main__":          # the numbers of docs/pyharm.md; with a path, its figure
    import sys
    ones = {}
    for H in (10, 20):
        r = ones[H] = one_oscillator_comparison(pyharm(jenkins_case(harmonics=H)), f"jenkins-one-{H}")
        slipping = (r["stuck"] > 0.05) & (r["stuck"] < 0.95)
        print(f"one oscillator, H = {H}: {len(r['omega'])} pyHarm points in {r['pyharm_s']:.1f} s "
              f"({slipping.sum()} in stick-slip), "
              f"workbench branch {r['branch_points']} points; largest |workbench / pyHarm - 1| "
              f"{np.abs(r['workbench'] / r['pyharm'] - 1).max():.2e}; workbench 2H / H - 1 "
              f"{np.abs(r['workbench_2H'] / r['workbench'] - 1).max():.2e}; resonance "
              f"{r['pyharm'].max() * 1e3:.4f} mm at {r['omega'][np.argmax(r['pyharm'])]:.2f} rad/s, stuck share "
              f"{r['stuck'][np.argmax(r['pyharm'])]:.2f}")
    chains = {}
    for engine_order in sorted(CHAINS):
        theirs = pyharm(chain_case(engine_order))
        r = chain_comparison(engine_order, theirs)
        top = int(np.argmax(r["pyharm"][:, 0]))
        print(f"chain, engine order {engine_order}: {len(r['omega'])} pyHarm points in {r['pyharm_s']:.1f} s; "
              f"travelling-wave defect {r['defect'].max():.1e}; largest |whole-chain HB / pyHarm - 1| "
              f"{np.abs(r['workbench'] / r['pyharm'][:, [0, BLADES // 2]] - 1).max():.2e}; one sector / pyHarm "
              f"{np.abs(r['sector'] / r['pyharm'][:, 0] - 1).max():.2e} (/ whole-chain HB "
              f"{np.abs(r['sector'] / r['workbench'][:, 0] - 1).max():.1e}); H 20 / H {CHAIN_H} - 1 "
              f"{np.abs(r['workbench_20'] / r['workbench'] - 1).max():.2e}; resonance "
              f"{r['pyharm'][top, 0] * 1e3:.4f} mm at {r['omega'][top]:.2f} rad/s, stuck share "
              f"{r['stuck'][top].min():.2f}-{r['stuck'][top].max():.2f}")
        in_time = newmark_comparison(engine_order, theirs)
        for row in in_time["points"]:
            error = row["newmark"] / row["pyharm"] - 1
            print(f"  in time at {row['omega']:.3f} rad/s: blades {row['newmark'].min() * 1e3:.5f} to "
                  f"{row['newmark'].max() * 1e3:.5f} mm against pyHarm {row['pyharm'].min() * 1e3:.5f} to "
                  f"{row['pyharm'].max() * 1e3:.5f} mm ({error.min():+.1e} to {error.max():+.1e}); "
                  f"settled to {row['settled']:.1e}; stuck share {row['stuck'].min():.2f}-{row['stuck'].max():.2f}")
        chains[engine_order] = (r, in_time)
    if len(sys.argv) > 1:
        print(f"wrote {draw(ones[10], chains, Path(sys.argv[1]))}")
