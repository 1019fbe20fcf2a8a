"""shroud sweep --method hb as a user runs it: the JSON of interface.md, and one-line errors (exit 2)."""

import json
import subprocess
import sys

import numpy as np
import pytest

from workbench.cli import main
from shroud.analysis.hb import run_hb
from shroud.params import Parameters


def _cli(*args):
    return subprocess.run([sys.executable, "-m", "workbench.cli", *args], capture_output=True, text=True)


def test_hb_sweep_json_follows_the_branch():
    r = _cli("sweep", "--method", "hb", "--harmonics", "5", "--samples", "128", "--rpm-from", "9000",
             "--rpm-to", "16000", "--set", "contact.gap=1e-4", "--json")
    assert r.returncode == 0, r.stderr
    out = json.loads(r.stdout)
    assert out["method"] == "hb" and out["harmonics"] == 5 and out["model"] == "reduced"
    assert len(out["rpm"]) == len(out["amplitude_v_L"]) == len(out["stable"])
    rpm = np.array(out["rpm"])
    assert rpm[0] == 9000 and rpm[-1] == 16000 and np.any(np.diff(rpm) < 0)    # it goes back at a fold
    assert out["resonance"]["amplitude"] == max(out["amplitude_v_L"])
    assert not all(out["stable"]) and any(b["kind"] == "fold" for b in out["bifurcations"])


@pytest.mark.parametrize("args, key", [
    (["--harmonics", "0"], "--harmonics"),
    (["--harmonics", "10", "--samples", "20"], "--samples"),
    (["--method", "shooting"], "--method"),
    (["--rpm-from", "9000", "--rpm-to", "9000"], "--rpm-from"),
])
def test_bad_hb_input_is_one_line_and_exit_2(args, key, capsys):
    base = {"--rpm-from": "8000", "--rpm-to": "9000", "--method": "hb"}
    for flag, value in zip(args[::2], args[1::2]):
        base[flag] = value
    argv = ["sweep"] + [x for kv in base.items() for x in kv]
    assert main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith(f"error: {key}:")


def test_a_branch_that_stops_converging_is_kept_and_marked_incomplete():
    """A corrector held to at most one easy step cannot pass the first fold: the branch so far is returned,
    marked incomplete with where and why."""
    from shroud.core import continuation
    p = Parameters().updated({"contact.gap": 1e-4})
    full = run_hb(p, "reduced", 9000.0, 16000.0, harmonics=5, samples=128)
    original = continuation._corrector
    calls = {"n": 0}

    def failing(*a, **k):
        calls["n"] += 1
        u, it, ok, R, J, Rp = original(*a, **k)
        return u, it, ok and calls["n"] <= 10, R, J, Rp
    continuation._corrector = failing
    try:
        part = run_hb(p, "reduced", 9000.0, 16000.0, harmonics=5, samples=128)
    finally:
        continuation._corrector = original
    assert not part.complete and "did not converge beyond p =" in part.stopped
    assert 1 < len(part.rpm) < len(full.rpm)
    assert part.to_json()["complete"] is False and part.to_json()["stopped"] == part.stopped


def test_harmonics_chosen_to_a_tail_of_the_contact_forces():
    """H doubles until the contact forces' spectrum above H is within the tolerance; the peak amplitude then
    agrees with a branch of twice the harmonics to 0.5 %."""
    from shroud.analysis.hb import run_hb_to_tail
    p = Parameters().updated({"contact.gap": 1e-4})
    r = run_hb_to_tail(p, "reduced", 9000.0, 16000.0, tail=0.1)
    tails = [t["spectral_tail"] for t in r.harmonics_tried]
    assert tails[-1] <= 0.1 < min(tails[:-1]) and r.harmonics == r.harmonics_tried[-1]["harmonics"]
    finer = run_hb(p, "reduced", 9000.0, 16000.0, harmonics=2 * r.harmonics)
    assert r.resonance["amplitude"] == pytest.approx(finer.resonance["amplitude"], rel=5e-3)
