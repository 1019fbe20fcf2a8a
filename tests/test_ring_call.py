"""ring.blades = N as a user gives it: every command answers for the ring or refuses it (exit 2), the
checkpoints solve the ring (one dispatch: shroud.analysis.systems), and a checkpoint Newton did not converge
on exits 1 with no amplitude (issue 32). The truths: the ring in time (shroud transient), the single blade in
time."""

import json

import numpy as np
import pytest

from shroud import api
from shroud.base.errors import InputError
from workbench.cli import main

PRELOAD = ["contact.N0=20", "contact.kn=1e7", "contact.kt=5e6", "contact.mu=0.3", "contact.alpha_deg=30"]


def _sets(values):
    return [a for v in values for a in ("--set", v)]


def _run(capsys, *args):
    code = main(list(args))
    out, err = capsys.readouterr()
    return code, out, err


def test_a_ring_checkpoint_is_the_ring_in_time(capsys, tmp_path):
    """6 tuned blades, preload 20 N, 10000 r/min: every blade of `sweep --method hb --checkpoints` within 1 %
    of the ring from rest in time (300 periods, settled on P1; measured 0.39138 um HB, 0.39136-0.39138 um in
    time), where the single blade between fixed neighbours has 0.5845 um (what the checkpoint answered
    before the dispatch)."""
    ring = _sets(["ring.blades=6", *PRELOAD])
    code, out, err = _run(capsys, "sweep", "--method", "hb", "--checkpoints", "10000", *ring, "--json")
    assert code == 0, err
    hb = json.loads(out)
    assert hb["blades"] == 6 and hb["converged"] == [True] and len(hb["blades_amplitude_v_L"][0]) == 6
    code, out, err = _run(capsys, "transient", "--rpm", "10000", *ring, "--set", "time.periods=300", "--json",
                          "--out", str(tmp_path))
    assert code == 0, err
    timed = json.loads(out)
    assert timed["period"] == 1
    in_time = np.array([b["amplitude"]["v_L"] for b in timed["blades"]])
    assert np.abs(np.array(hb["blades_amplitude_v_L"][0]) / in_time - 1).max() < 0.01


def test_a_checkpoint_newton_did_not_converge_on_exits_1_with_null_amplitudes(capsys):
    """A nearly tuned 12-blade ring (d_0 = 1e-9), 1 um gap (Fig. 11b contact), 8000 r/min, H = 12, solved as a
    whole: no linear start and no stiffness continuation reaches a state (the tuned sector's wave there is
    reached only from other numbers of harmonics, docs/ring-tuned.md): exit 1, one line on stderr naming the
    speed, the amplitudes null. (At H = 10, the case before, the stiffness continuation passes a fold at a
    corner since the continuation takes a corner that lies within its step, and reaches a state, unstable:
    largest |multiplier| 1.737 +- 0.058, refused with exit 2.)"""
    code, out, err = _run(capsys, "sweep", "--method", "hb", "--checkpoints", "8000", "--harmonics", "12",
                          "--samples", "256", "--json",
                          *_sets(["ring.blades=12", "ring.mistuning=[1e-9,0,0,0,0,0,0,0,0,0,0,0]",
                                  "contact.alpha_deg=30", "contact.kt=5e6", "contact.mu=0.3", "contact.gap=1e-6"]))
    assert code == 1
    assert len(err.strip().splitlines()) == 1 and "8000 r/min" in err and "did not converge" in err
    payload = json.loads(out)
    assert payload["converged"] == [False] and payload["amplitude_v_L"] == [None]
    assert payload["blades_amplitude_v_L"] == [None] and payload["checkpoints"][0]["amplitude_v_L"] is None


def test_a_checkpoint_on_an_unstable_travelling_wave_exits_2_and_names_the_ring_in_time(capsys, tmp_path):
    """6 tuned blades (the default contact), 6000 and 7200 r/min: the wave at 7200 r/min is unstable against
    another nodal diameter (|mu| 1.68; tests/test_ring_hb.py holds its growth in time), and the ring from rest
    in time does not settle on it (measured at 100 periods: no period, blades 1.44 and 1.52 um in turn
    against the wave's 1.05 um). The checkpoints refuse it: exit 2, nothing on stdout, one line naming
    7200 r/min (not 6000, whose wave the ring settles on) with its multiplier and the transient it points to;
    before, exit 0 with the wave's 1.05 um as the ring's answer."""
    ring = _sets(["ring.blades=6"])
    code, out, err = _run(capsys, "sweep", "--method", "hb", "--checkpoints", "6000", "7200", *ring, "--json")
    assert code == 2 and out == "" and len(err.strip().splitlines()) == 1
    assert err.startswith("error: --checkpoints:") and "unstable at 7200 r/min (largest |multiplier| 1.6" in err
    assert "6000 r/min" not in err and "shroud transient --set ring.blades=6 --rpm 7200" in err
    wave = api.harmonic_balance(api.parameters({"ring.blades": 6}), "reduced", 7200.0, multipliers=False)
    code, out, err = _run(capsys, "transient", "--rpm", "7200", *ring, "--set", "time.periods=100", "--json",
                          "--out", str(tmp_path))
    assert code == 0, err
    timed = np.array([b["amplitude"]["v_L"] for b in json.loads(out)["blades"]])
    assert np.abs(timed / wave.amplitude_v_L - 1).min() > 0.2


def test_an_undecided_rings_checkpoint_is_answered_with_a_warning(capsys):
    """24 blades, preload 20 N, 13000 r/min: largest |multiplier| 0.981 +- 0.02, undecided, where the ring in
    time settles on the wave (9.2408-9.2465 um against 9.2682, docs/ring.md): answered (exit 0, `stable`
    null) with one warning line on stderr naming the speed and the transient that decides."""
    code, out, err = _run(capsys, "sweep", "--method", "hb", "--checkpoints", "13000", "--json",
                          *_sets(["ring.blades=24", *PRELOAD]))
    assert code == 0, err
    hb = json.loads(out)
    assert hb["stable"] == [None] and abs(hb["amplitude_v_L"][0] / 9.2682e-6 - 1) < 1e-3
    warnings = [line for line in err.splitlines() if "warning" in line]
    assert len(warnings) == 1 and "13000 r/min" in warnings[0] and "neither stable nor unstable" in warnings[0]
    assert "shroud transient --set ring.blades=24 --rpm 13000" in warnings[0]


def test_the_single_blades_checkpoint_finds_the_state_of_its_time_run(capsys, tmp_path):
    """Preload 20 N, 9000 r/min: Newton from the free blade's linear solution fails at once (|R| 244 N) and so
    does the load homotopy (the preload is not scaled); the checkpoint reaches the state from the linear blade
    with contact springs: within 1e-4 of the blade from rest in time (measured 0.576109 against 0.576114 um),
    stable (the continuation passes it at 0.576 um, stable)."""
    sets = _sets(PRELOAD)
    code, out, err = _run(capsys, "sweep", "--method", "hb", "--checkpoints", "9000", *sets, "--json")
    assert code == 0, err
    hb = json.loads(out)
    assert hb["converged"] == [True] and hb["stable"] == [True] and "blades" not in hb
    code, out, err = _run(capsys, "transient", "--rpm", "9000", *sets, "--set", "time.periods=200", "--json",
                          "--out", str(tmp_path))
    timed = json.loads(out)
    assert timed["period"] == 1
    assert abs(hb["amplitude_v_L"][0] / timed["amplitude"]["v_L"] - 1) < 1e-4


@pytest.mark.parametrize("args", [
    ["modal"],
    ["static", "--tip-force", "0", "100", "0"],
    ["sweep", "--method", "hb", "--rpm-from", "9000", "--rpm-to", "9500", "--tail", "0.01"],
])
def test_a_command_that_cannot_solve_a_ring_refuses_it(args, capsys):
    code, out, err = _run(capsys, *args, "--set", "ring.blades=4")
    assert code == 2 and out == ""
    assert err.startswith("error: ring.blades:") and "allowed:" in err and len(err.strip().splitlines()) == 1


def test_a_study_that_solves_the_blade_refuses_a_ring_before_writing(capsys, tmp_path):
    """`shroud run` of a blade's study (fig4) with ring.blades = 4: exit 2 on ring.blades, no folder made."""
    code, out, err = _run(capsys, "run", "scenes/fig4.toml", "--quick", "--set", "ring.blades=4",
                          "--out", str(tmp_path / "fig4"))
    assert code == 2 and err.startswith("error: ring.blades:") and not (tmp_path / "fig4").exists()


def test_the_commands_that_answer_answer_for_the_ring(capsys, tmp_path):
    """transient, the time-domain sweep, modal --interface: every blade's answer (4 tuned blades, preload
    20 N, 9000 r/min): the sweep's every blade is the ring transient's (the same run from rest, extended
    until settled), not the single blade's (0.5761 um)."""
    ring = ["--set", "ring.blades=4", *_sets(PRELOAD)]
    code, out, err = _run(capsys, "modal", "--interface", "stuck", "--modes", "2", *ring, "--json")
    assert code == 0, err
    assert [d["nd"] for d in json.loads(out)["nodal_diameters"]] == [0, 1, 2]
    code, out, err = _run(capsys, "transient", "--rpm", "9000", *ring, "--set", "time.periods=400", "--json",
                          "--out", str(tmp_path))
    assert code == 0, err
    timed = np.array([b["amplitude"]["v_L"] for b in json.loads(out)["blades"]])
    code, out, err = _run(capsys, "sweep", "--rpm-from", "9000", "--rpm-to", "9000", "--rpm-count", "1", *ring,
                          "--set", "time.periods=40", "--json")
    assert code == 0, err
    swept = json.loads(out)
    assert swept["blades"] == 4 and swept["settled"] == [True]
    assert np.allclose(swept["blades_amplitude_v_L"][0], timed, rtol=2e-3)
    assert abs(swept["amplitude_v_L"][0] / 0.5761e-6 - 1) > 0.1


def test_the_api_refuses_as_the_commands():
    ring = api.parameters({"ring.blades": 4})
    for call in (lambda: api.modal(ring, "reduced"), lambda: api.static(ring, "reduced", (0.0, 100.0, 0.0)),
                 lambda: api.build_system(ring, "reduced")):
        with pytest.raises(InputError, match="ring.blades"):
            call()
