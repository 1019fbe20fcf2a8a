"""The periodicity study: which waveform it shows, how it names a lost P1 and reads a time-domain point."""

from types import SimpleNamespace

import numpy as np

from comparisons.periodicity import OPTIONS, CaseRun, HBState, reading, waveform_case
from shroud.core.floquet import crossing


def _run(label, period, mu=0.1):
    return CaseRun(mu=mu, label=label, result=SimpleNamespace(period=period))


def test_the_longest_period_found_is_shown_whatever_the_paper_expects():
    # the paper expects P1 at mu = 0.1: a P3 found there is what a user must see
    assert waveform_case([_run("gap 1 um", 1), _run("N0 10 N", 3)]).label == "N0 10 N"
    # the paper expects P10 at mu = 0.5: without one, the longest period found is shown
    assert waveform_case([_run("a", 1, 0.5), _run("b", 5, 0.5), _run("c", 2, 0.5)]).label == "b"


def test_a_response_without_a_period_outranks_every_periodic_one():
    assert waveform_case([_run("a", 9), _run("b", None)]).label == "b"
    assert waveform_case([_run("a", 1), _run("b", 1)]).label == "a"         # ties: the first case


def test_the_largest_multiplier_names_what_replaces_p1():
    # a complex pair at angle 2 pi / 5: Neimark-Sacker, a P5 if it locks
    pair = 1.05 * np.exp(2j * np.pi / 5)
    kind, n = crossing(np.array([pair, np.conj(pair), 0.3]))
    assert kind == "Neimark-Sacker" and abs(n - 5.0) < 1e-9
    assert crossing(np.array([-1.2, 0.5]))[0] == "period-doubling"
    assert crossing(np.array([0.2, 1.3]))[0] == "fold"


def _state(a, stable, largest=0.9):
    return HBState(amplitude=a, stable=stable, largest=largest, kind="Neimark-Sacker", n=5.0, source="branch")


def test_a_point_is_read_against_the_nearest_state():
    # a run without P1 beside an unstable state agrees; beside a stable one (far from |mu| = 1) it does not
    assert reading(None, 6e-6, [_state(5.6e-6, False, 1.08)], 0.01, 0.10)["verdict"] == "agree"
    assert reading(5, 6e-6, [_state(5.9e-6, True, 0.8)], 0.01, 0.10)["verdict"] == "disagree"
    # beside a state of undecided stability: marginal, not a side
    assert reading(5, 6e-6, [_state(5.9e-6, None, 1.005)], 0.01, 0.10)["verdict"] == "marginal"
    # a P1 run agrees only with a stable state within the match, whichever coexisting state it is
    assert reading(1, 25e-6, [_state(6e-6, True), _state(25.1e-6, True)], 0.01, 0.10)["verdict"] == "agree"
    assert reading(1, 25e-6, [_state(6e-6, True), _state(25.1e-6, None, 1.005)], 0.01, 0.10)["verdict"] == "marginal"
    assert reading(1, 25e-6, [_state(6e-6, True), _state(25.1e-6, False, 1.3)], 0.01, 0.10)["verdict"] == "disagree"


def test_a_point_without_p1_agrees_with_an_unstable_state_only_within_the_stated_tolerance():
    """An unstable P1 state explains a run without P1 only nearby: at 14 % of the amplitude it does (the
    study's tolerance, 15 %), at 16 % and at a factor 3 it does not: 'no P1 state nearby', whatever its
    stability."""
    near = OPTIONS["near"]
    assert reading(3, 6e-6, [_state(6e-6 * 0.86, False, 1.2)], 0.01, near)["verdict"] == "agree"
    far = reading(3, 6e-6, [_state(6e-6 * 1.16, False, 1.2)], 0.01, near)
    assert far["verdict"] == "no P1 state nearby" and "15 %" in far["why"]
    assert reading(None, 6e-6, [_state(2e-6, False, 1.2)], 0.01, near)["verdict"] == "no P1 state nearby"


def test_hb_predicts_where_the_time_domain_loses_p1():
    """Gap 1 um, mu 0.5 (the scene's contact): HB's P1 branch loses stability through a complex pair inside
    the band, and a run from rest (an independent method) finds no P1 there; where HB's P1 is stable the
    run settles on it within 1 %."""
    from comparisons.periodicity import map_cases, hb_case, OPTIONS
    from shroud.analysis.sweep import Settling, run_sweeps
    from workbench.scene import load_scene
    from pathlib import Path
    scene = load_scene(Path(__file__).resolve().parents[1] / "scenes" / "periodicity.toml")
    opts = {**OPTIONS, **scene.options, "search_gaps_um": [1.0], "search_preloads_N": []}
    (label, params), = map_cases(scene.params, opts)
    sw, = run_sweeps([params], "reduced", np.array([23500.0, 25500.0]), settling=Settling(max_periods=400))
    case = hb_case(label, params, 20000.0, 26000.0, sw, opts)
    inside, outside = case.states
    assert sw.period[0] != 1 and sw.period[1] == 1
    assert inside and not any(st.stable for st in inside) and inside[0].kind == "Neimark-Sacker"
    assert any(st.stable and abs(st.amplitude / sw.amplitude_v_L[1] - 1) <= 0.01 for st in outside)
