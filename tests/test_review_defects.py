"""Defects found in review, each held by a test that failed before its fix."""

from __future__ import annotations

import numpy as np
import pytest

from shroud.analysis import coexistence
from shroud.analysis.sweep import States
from shroud.analysis.agreement import SIGNALS, agreement, nrmse
from shroud.core.modes import pair_by_mac


# --- shroud/analysis/coexistence: a model with no steady state shares nothing -------------
class _Sweep:
    def __init__(self, amplitudes):
        self.amplitude_v_L = np.asarray(amplitudes, dtype=float)
        self.settled = (True,) * len(amplitudes)


@pytest.mark.parametrize("found", [{"reduced": [], "full": []}, {"reduced": [], "full": [40e-6]},
                                   {"reduced": [40e-6, 120e-6], "full": []}])
def test_no_steady_state_is_never_called_the_same_or_shared(monkeypatch, found):
    monkeypatch.setattr(coexistence, "coexisting_states",
                        lambda params, model, rpm, starts, settling: States(found[model], unsettled=0))
    sweeps = {"reduced": [_Sweep([40e-6, 120e-6])], "full": [_Sweep([40e-6, 40e-6])]}
    opts = dict(coexistence.OPTIONS)
    rows = coexistence.coexistence([("50 um gap", None)], sweeps, np.array([12000.0, 13000.0]), opts,
                                    ("reduced", "full"))
    assert len(rows) == 1
    row = rows[0]
    assert not row["shared_states"] and not row["same_states"]
    assert row["largest_state_difference"] == np.inf
    table = "".join(coexistence.section(rows, opts, ("reduced", "full"), ("reduced beam", "full beam")))
    assert "| no steady state |" in table and "| same |" not in table and "| shared |" not in table
    assert "no settled steady state" in coexistence.summary(rows)
    assert "have the same coexisting" not in coexistence.summary(rows)


def test_matched_states_within_one_percent_are_the_same():
    assert coexistence.matched_difference([30.05e-6, 62.41e-6], [30.06e-6, 62.38e-6]) < coexistence.SAME


# --- shroud/analysis/agreement: a flat reference ---------------------------------------------
def _runs(delta: float):
    """Side 1 never touches (N1 = Ff1 = 0 in the reference); the candidate differs by ``delta``."""
    t = np.linspace(0.0, 0.02, 2001)
    wave = np.sin(2 * np.pi * 500 * t)
    ref = {"N1": 0 * t, "Ff1": 0 * t, "N2": 100 * np.maximum(wave, 0), "Ff2": 30 * wave,
           "v_L": 1e-4 * wave, "w_L": 2e-5 * wave}
    cand = {k: v + delta * (1e-6 if k in ("v_L", "w_L") else 1.0) * wave for k, v in ref.items()}
    return t, cand, ref


@pytest.mark.parametrize("delta", [1e-12, 1e-6, 1e-3])
def test_nrmse_against_a_flat_reference_shrinks_with_the_difference(delta):
    t, cand, ref = _runs(delta)
    a = agreement(t, cand, t, ref, period=1 / 500, periods=5)
    assert a.nrmse["N1"] < 10 * delta           # was 1.0 for any difference, however small
    assert a.nrmse["N1"] == pytest.approx(a.nrmse["Ff1"])
    for name in SIGNALS:
        assert a.nrmse[name] < 1e-1


def test_nrmse_of_a_moving_reference_is_rms_over_its_range():
    t = np.linspace(0.0, 2 * np.pi, 1001)
    assert nrmse(np.sin(t) + 0.01, np.sin(t), scale=0.02) == pytest.approx(0.005, rel=1e-9)
    assert nrmse(np.zeros(3), np.zeros(3)) == 0.0


# --- one-to-one pairing of modes by MAC (Campbell tracks and the solid's Coriolis modes) ---
def test_mac_pairing_is_one_to_one():
    macs = np.array([[0.90, 0.85, 0.0], [0.88, 0.20, 0.0], [0.0, 0.1, 0.95]])
    assert list(np.argmax(macs, axis=1)) == [0, 0, 2]      # per-row argmax: mode 0 taken twice
    assert list(pair_by_mac(macs)) == [1, 0, 2]
