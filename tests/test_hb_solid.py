"""The full solid by harmonic balance, condensed exactly on its contact coordinates (reference_fe.harmonic).

* A gap never reached: the condensed full-solid harmonic balance gives the
  solid's own harmonic response, a direct complex sparse solve (SuperLU) of
  Z_1 q = F_1 with the very M, C, K, to 1e-8 (MUMPS on the real block form
  is the method under test).
* The Fig. 8 point: the full solid's harmonic balance against its own
  16-minute transient within 1 %. The transient cannot run in CI: its steady
  amplitudes are stored with their provenance in tests/data/fig8_fe_transient.json.
* The reduced solid's harmonic balance against the full solid's at
  checkpoints (contact in touch at the Fig. 8 point; impacts across a
  0.1 mm gap near resonance) within 0.5 %.
* Under mpirun -n 2 the condensation agrees with the serial one.
* ``shroud sweep --method hb --checkpoints``: a beam checkpoint is the
  continuation's state at that speed; bad input is one line, exit 2.
"""

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

DATA = Path(__file__).parent / "data"


def _params(**overrides):
    from shroud.params import Parameters
    return Parameters().updated(overrides)


@pytest.mark.fe
def test_a_gap_never_reached_gives_the_solids_own_harmonic_response():
    """Harmonic coefficients compared (a_k - i b_k of the tip and of the contact coordinates), not the sampled
    amplitude (512 samples of a sine miss its peak by up to 2e-5)."""
    import scipy.sparse as sp
    import scipy.sparse.linalg as spl
    from reference_fe.harmonic import condensed_at
    from shroud.analysis.hb import checkpoint
    from shroud.analysis.transient import contact_law_for
    from shroud.core import harmonic_balance as hb
    p = _params(**{"contact.gap": 1e-3})                  # 1 mm: the free blade moves by 0.1 mm at most
    cp = checkpoint(p, "fe", 10000.0, harmonics=2, samples=64)
    assert cp.converged and cp.condensed_on == 396 and cp.stable      # the free damped blade is stable
    system, lin = condensed_at(p, 10000.0, 2)
    sol = hb.solve(system, contact_law_for(system, p.contact), 2, 64, lin=lin)
    assert not sol.contact.N.any()                        # never touches
    w = system.omega_e
    Z = sp.csc_matrix(system.K - w**2 * system.M + 1j * w * system.C)
    q1 = spl.splu(Z).solve(-1j * system.f_aero.astype(complex))     # F_1 = -i f_aero (f_aero sin wt)
    tip = sol.tip[1] - 1j * sol.tip[2]                    # harmonic 1 of v_L, w_L
    y = sol.X.reshape(5, -1)[1] - 1j * sol.X.reshape(5, -1)[2]
    assert np.abs(tip - system.tip @ q1).max() <= 1e-8 * np.abs(system.tip @ q1).max()
    assert np.abs(y - system.contact.W @ q1).max() <= 1e-8 * np.abs(system.contact.W @ q1).max()
    assert np.abs(sol.tip[[0, 3, 4]]).max() <= 1e-8 * np.abs(tip).max()      # no static part, no harmonic 2


@pytest.mark.fe
@pytest.mark.slow
def test_full_solid_hb_matches_its_transient_at_the_fig8_point():
    from shroud.analysis.hb import checkpoint
    ref = json.loads((DATA / "fig8_fe_transient.json").read_text())
    cp = checkpoint(_params(), "fe", ref["rpm"], harmonics=7, samples=256)
    assert cp.converged and cp.start == "fe-reduced state"
    assert cp.amplitude_v_L == pytest.approx(ref["v_L_m"], rel=0.01)
    assert cp.amplitude_w_L == pytest.approx(ref["w_L_m"], rel=0.01)


@pytest.mark.fe
@pytest.mark.slow
@pytest.mark.parametrize("overrides", [{}, {"contact.gap": 1e-4, "speed.rpm": 9000.0}],
                         ids=["fig8-in-touch", "gap-0.1mm-9000rpm"])
def test_reduced_solid_hb_matches_the_full_solid_at_checkpoints(overrides):
    """The reduced solid on its basis built at the checkpoint's speed (its state starts the full solid's
    Newton, whose converged state is the full solid's own). The full solid's multipliers (its orbit, the
    perturbations on the reduced solid's basis and on one twice as large) agree with each other and with
    the reduced solid's on its own orbit: the projection has converged."""
    from shroud.analysis.hb import checkpoint
    p = _params(**overrides)
    rpm = p.speed.rpm
    cp = checkpoint(p, "fe", rpm, harmonics=7, samples=256)
    reduced = checkpoint(p, "fe-reduced", rpm, harmonics=7, samples=256)
    assert cp.converged and reduced.converged
    assert reduced.amplitude_v_L == pytest.approx(cp.amplitude_v_L, rel=0.005)
    assert reduced.amplitude_w_L == pytest.approx(cp.amplitude_w_L, rel=0.005)
    one, twice = cp.largest_multiplier.values()
    assert twice == pytest.approx(one, abs=0.01)
    assert twice == pytest.approx(reduced.largest_multiplier[reduced.dofs], abs=0.01)
    assert cp.stable == reduced.stable


@pytest.mark.fe
@pytest.mark.slow
def test_the_full_solids_three_states_at_12000_rpm_carry_the_reduced_solids_stability():
    """Gap 0.1 mm, 12000 r/min: the reduced solid's branch (9000-16000 r/min) folds back at ~14400 and
    ~9900 r/min, so three P1 states coexist there. The full solid's Newton from each lands on a state
    within 0.5 %, and its multipliers (its own orbit, perturbations on 33- and 57-DOF bases) give the
    branch's verdicts: stable, unstable (|multiplier| ~1.9), stable."""
    from comparisons._hb import starts_at
    from shroud.analysis.hb import checkpoint, run_hb
    p = _params(**{"contact.gap": 1e-4})
    branch = run_hb(p, "fe-reduced", 9000.0, 16000.0, harmonics=5, samples=256)
    starts = starts_at(branch, 12000.0)
    assert [stable for _, stable in starts] == [True, False, True]
    for X, stable in starts:
        cp = checkpoint(p, "fe", 12000.0, harmonics=5, samples=256, start=X)
        assert cp.converged and cp.amplitude_v_L == pytest.approx(cp.start_amplitude_v_L, rel=0.005)
        one, twice = cp.largest_multiplier.values()
        assert twice == pytest.approx(one, abs=0.01)
        assert cp.stable == stable and (twice > 1.5 if not stable else twice < 0.95)


@pytest.mark.fe
@pytest.mark.slow
@pytest.mark.mpi
def test_two_ranks_condense_as_one(tmp_path):
    mpirun = Path(sys.executable).parent / "mpirun"
    shroud = Path(sys.executable).parent / "shroud"
    if not mpirun.exists() or not shroud.exists():
        pytest.skip("mpirun or the shroud command is not installed in this environment")
    args = ["sweep", "--method", "hb", "--model", "fe", "--checkpoints", "10000", "--harmonics", "2",
            "--samples", "64", "--json", "--set", "blade.length=0.1"]
    env = dict(os.environ, SHROUD_CACHE=str(tmp_path), OMP_NUM_THREADS="1")
    # the ranks first, on an empty cache: rank 0 alone builds the mesh and the reduced solid's basis
    parallel = subprocess.run([str(mpirun), "-n", "2", str(shroud), *args], capture_output=True,
                              text=True, env=env, check=True, timeout=900)
    serial = subprocess.run([str(shroud), *args], capture_output=True, text=True, env=env, check=True)
    one, two = json.loads(serial.stdout), json.loads(parallel.stdout)
    assert one["converged"] == two["converged"] == [True]
    assert np.allclose(one["amplitude_v_L"] + one["amplitude_w_L"], two["amplitude_v_L"] + two["amplitude_w_L"],
                       rtol=1e-7)


def test_a_checkpoint_is_the_continuations_state_at_that_speed():
    """The beam at 12000 r/min, 0.1 mm gap: the branch followed from 11000 r/min ends where a checkpoint
    solved there alone (linear start, load homotopy) lands."""
    from shroud.analysis.hb import run_hb
    from shroud.params import Parameters
    r = subprocess.run([sys.executable, "-m", "workbench.cli", "sweep", "--method", "hb", "--checkpoints",
                        "12000", "--harmonics", "5", "--samples", "128", "--set", "contact.gap=1e-4", "--json"],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    out = json.loads(r.stdout)
    assert out["method"] == "hb" and out["model"] == "reduced" and out["rpm"] == [12000.0]
    assert out["stable"] == [True] and out["checkpoints"][0]["stability"] == "Floquet multipliers"
    branch = run_hb(Parameters().updated({"contact.gap": 1e-4}), "reduced", 11000.0, 12000.0, harmonics=5,
                    samples=128)
    assert branch.rpm[-1] == 12000.0
    assert out["amplitude_v_L"][0] == pytest.approx(branch.amplitude_v_L[-1], rel=1e-6)


@pytest.mark.parametrize("args, key", [
    (["--checkpoints", "9000"], "--checkpoints"),                                  # needs --method hb
    (["--method", "hb", "--checkpoints", "0"], "--checkpoints"),
    (["--method", "hb", "--checkpoints", "9000", "--rpm-count", "3"], "--rpm-count"),
    (["--method", "hb", "--checkpoints", "9000", "--harmonics", "0"], "--harmonics"),
    (["--method", "hb", "--model", "fe", "--rpm-from", "8000", "--rpm-to", "9000"], "--model"),
    (["--model", "fe", "--rpm-from", "8000", "--rpm-to", "9000", "--rpm-count", "3"], "--model"),
])
def test_bad_checkpoint_input_is_one_line_and_exit_2(args, key, capsys):
    from workbench.cli import main
    assert main(["sweep", *args]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith(f"error: {key}:")
