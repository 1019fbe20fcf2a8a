"""Each study's verdicts flip where their number crosses the threshold and read "not decided" within the margin.

The studies' own verdict functions on synthetic inputs: a number well below the threshold, one well above
(the answer flips), and one inside the margin (``not decided``). The margins are the numbers' measured
uncertainties (speed grid, settling, timing noise); shroud.core.verdict holds the arithmetic, these tests
hold that each study hands it the right number, threshold and margin and reads the right side.
"""

import itertools
import json
import math
from types import SimpleNamespace

import numpy as np
import pytest

from comparisons import (_bands, _families, calculix, convergence, default, error_vs_time, fig3, fig7, fig8, friction,
                         gap_preload, stability, table1)
from shroud.analysis import coexistence
from shroud.analysis.agreement import agreement
from comparisons.paper import TABLE1_FE, TABLE1_LABELS, TABLE1_REDUCED
from shroud.core.results import SweepResult
from shroud.core.verdict import KEYS, NOT_DECIDED, TIME_RATIO, contradicts, is_verdict

STEP = 400.0      # r/min, a speed grid's step


# --- the speed grid: resonant speeds ---------------------------------------------

@pytest.mark.parametrize("difference, answer", [(0.0, True), (STEP, NOT_DECIDED), (2 * STEP, False)])
def test_same_resonant_speed_is_decided_outside_one_grid_step(difference, answer):
    """fig4, fig7: equal readings are one speed, two steps apart two speeds; one step apart may be either."""
    assert _families.same_speed(8000.0, 8000.0 + difference, STEP).answer == answer


@pytest.mark.parametrize("speeds, answer", [([8000, 8400, 13600], True), ([8000, 8000, 13600], NOT_DECIDED),
                                            ([8000, 7600, 13600], NOT_DECIDED), ([8000, 7200, 13600], False)])
def test_resonant_speed_rises_as_the_gap_closes(speeds, answer):
    """gap_preload: a rise of a step is a rise; equal readings or a step down are not decided; two down fall."""
    ordered = [{"resonance_rpm": float(s)} for s in speeds]
    assert gap_preload.rises(ordered, STEP).answer == answer


def test_grid_margin_is_the_change_on_every_other_speed():
    """A sharp peak that the odd speeds miss moves its amplitude by the difference; a flat curve by nothing."""
    rpm = np.arange(5.0) * STEP
    def sweep(a):
        return SweepResult("m", rpm, np.asarray(a, float), rpm, (1,) * 5, rpm, 1, 0.0, 0.0, (True,) * 5)
    case = _families.Case("gap 600 um", "gap", 600.0, None)
    amplitude = lambda rows: rows[0]["resonance_amplitude_m"]            # noqa: E731
    assert _families.grid_margin({"a": [(case, sweep([1, 2, 4, 2, 1]))]}, amplitude) == 2.0
    assert _families.grid_margin({"a": [(case, sweep([1, 1, 1, 1, 1]))]}, amplitude) == 0.0


# --- friction: "no effect at large gaps" and the small-gap trends ----------------

def family_rows(big_gap_amplitudes: tuple[float, float], small_gap: tuple[tuple[float, float], ...]) -> list[dict]:
    """Resonance rows of two variants: one gap of 100 um and the small gap (rpm, amplitude)."""
    rows = []
    for k, name in enumerate(("mu 0.1", "mu 0.5")):
        rows.append({"variant": name, "case": "gap 100 um", "kind": "gap", "value": 100.0, "resonance_rpm": 10000.0,
                     "beyond_range": False, "resonance_amplitude_m": big_gap_amplitudes[k]})
        rpm, amp = small_gap[k]
        rows.append({"variant": name, "case": "gap 1 um", "kind": "preload", "value": -10.0, "resonance_rpm": rpm,
                     "beyond_range": False, "resonance_amplitude_m": amp})
    return rows


MARGINS = friction.Margins(tolerance=2e-3, step_rpm=STEP, spread=0.006, change=0.01)   # spread margin 1 %


@pytest.mark.parametrize("spread, answer", [(0.03, True), (0.045, NOT_DECIDED), (0.055, NOT_DECIDED),
                                            (0.07, False)])
def test_large_gaps_no_effect_flips_at_five_percent_with_the_measured_margin(spread, answer):
    rows = family_rows((1e-4, 1e-4 * (1 - spread)), ((27000.0, 2e-5), (29000.0, 1e-5)))
    found = friction.conclusions(rows, 1.0, MARGINS)
    verdict = found["large_gaps_no_effect"]
    assert verdict.value == pytest.approx(spread)
    assert verdict.margin == pytest.approx(2 * 2e-3 + 0.006)
    assert verdict.answer == answer


@pytest.mark.parametrize("rpms, answer", [((27000.0, 28200.0), 1), ((27000.0, 27400.0), NOT_DECIDED),
                                          ((27000.0, 26200.0), -1)])
def test_small_gap_speed_trend_needs_more_than_one_grid_step(rpms, answer):
    rows = family_rows((1e-4, 1e-4), ((rpms[0], 2e-5), (rpms[1], 1e-5)))
    assert friction.conclusions(rows, 1.0, MARGINS)["gap 1 um"]["speed_trend"].answer == answer


@pytest.mark.parametrize("ratio, answer", [(0.5, -1), (0.99, NOT_DECIDED), (1.2, 1)])
def test_small_gap_amplitude_trend_is_not_decided_within_settling_and_grid(ratio, answer):
    rows = family_rows((1e-4, 1e-4), ((27000.0, 2e-5), (29000.0, 2e-5 * ratio)))
    assert friction.conclusions(rows, 1.0, MARGINS)["gap 1 um"]["amplitude_trend"].answer == answer


# --- fig7: peak and curve agreement ------------------------------------------------

def fig7_row(peak_ratio: float, curve_gap: float) -> dict:
    return {"case": "gap 600 um", "peak_ratio": peak_ratio, "curve_gap": curve_gap,
            "reduced_resonance_rpm": 8400.0, "fe_reduced_resonance_rpm": 8400.0}


@pytest.mark.parametrize("gap, answer", [(0.01, True), (0.0515, NOT_DECIDED), (0.09, False)])
def test_fig7_curves_agree_flips_at_the_coexistence_threshold(gap, answer):
    found = fig7.conclusions([fig7_row(3.0, gap)], [], STEP, 0.05, 2e-3)["gap 600 um"]
    assert found["curves_agree"].answer == answer
    assert found["same_resonant_speed"].answer is True


@pytest.mark.parametrize("ratio, answer", [(3.0, True), (1.501, NOT_DECIDED), (1.1, False)])
def test_fig7_a_curve_without_a_clear_peak_reads_no_resonant_speed(ratio, answer):
    found = fig7.conclusions([fig7_row(ratio, 0.01)], [], STEP, 0.05, 2e-3)["gap 600 um"]
    assert found["peaked"].answer == answer
    assert (found["beam_resonance_rpm"] is None) == (answer is not True)


# --- fig8: amplitudes, slip, NRMSE targets, cost -----------------------------------

def fig8_results(v_l: float = 1.0, slip: float = 0.3, nrmse: float = 0.005, change: float = 1e-3,
                 times: tuple[float, float] = (1.0, 1.0)) -> dict:
    """A results.json's numbers for two models and a reference, as fig8.run returns them."""
    states = lambda s: {side: {"separate": 0.5, "slip": s, "stick": 0.5 - s} for side in ("side1", "side2")}  # noqa: E731
    return {"reference": "fe-reduced", "periods": 100, "steps_per_period": 256,
            "amplitude": {"reduced": {"v_L": v_l * 40e-6, "w_L": 10e-6},
                          "full": {"v_L": 40e-6, "w_L": 10e-6}, "fe-reduced": {"v_L": 40e-6, "w_L": 10e-6}},
            "versus_reference": {"reduced": {"worst_nrmse": 0.1}, "full": {"worst_nrmse": 0.1}},
            "pairs": {"reduced vs full": {"worst_nrmse": nrmse, "target": 0.01}},
            "state_fraction": {"reduced": states(slip), "full": states(0.3), "fe-reduced": states(0.3)},
            "amplitude_change": {"reduced": change, "full": change, "fe-reduced": change},
            "table3": [{"model": "reduced", "total_s": times[0], "status": "complete"},
                       {"model": "full", "total_s": times[1], "status": "complete"}]}


@pytest.mark.parametrize("scale, answer", [(1.02, "larger"), (1.0055, NOT_DECIDED), (1.001, "the same"),
                                           (0.98, "smaller")])
def test_fig8_amplitude_against_the_reference_with_the_runs_settling_as_margin(scale, answer):
    """Band 0.5 %, margin the runs' settling change (0.1 %): 0.55 % is within it of the band's edge."""
    found = fig8.conclusions(fig8_results(v_l=scale))
    assert found["amplitude_vs_reference"]["reduced"]["v_L"].answer == answer


@pytest.mark.parametrize("slip, answer", [(0.35, "more"), (0.3201, NOT_DECIDED), (0.31, "the same"),
                                          (0.25, "less")])
def test_fig8_slip_share_against_the_reference_with_one_time_step_as_margin(slip, answer):
    """Band 0.02 of the window, margin one step of 10 periods x 256 steps (0.0004)."""
    assert fig8.conclusions(fig8_results(slip=slip))["slip_vs_reference"]["reduced"].answer == answer


@pytest.mark.parametrize("nrmse, answer", [(0.005, True), (0.010005, NOT_DECIDED), (0.02, False)])
def test_fig8_pair_target_flips_at_its_nrmse_target(nrmse, answer):
    assert fig8.conclusions(fig8_results(nrmse=nrmse))["pairs_met"]["reduced vs full"].answer == answer


@pytest.mark.parametrize("times, answer", [((1.0, 1.0), "comparable"), ((1.0, 3.0), NOT_DECIDED),
                                           ((1.0, 5.0), NOT_DECIDED), ((1.0, 7.0), "cheaper"),
                                           ((7.0, 1.0), "costlier")])
def test_fig8_cost_is_never_decided_by_timing_noise(times, answer):
    """Band x3, margin the measured timing noise x2: a 5x ratio is within noise of the band's edge."""
    cost = fig8.conclusions(fig8_results(times=times))["cost"]["reduced vs full"]
    assert cost.answer == answer
    assert cost.to_json()["unit"] == TIME_RATIO and cost.noise == _bands.TIMING_NOISE


def test_fig8_verdicts_serialize_as_answer_value_threshold_margin_unit_reason():
    found = json.loads(json.dumps(fig8.conclusions(fig8_results()), default=lambda v: v.to_json()))
    for group in ("pairs_met", "settled", "slip_vs_reference", "cost"):
        for record in found[group].values():
            assert is_verdict(record) and tuple(record) == KEYS, (group, record)


# --- default: frequencies against the solid ----------------------------------------

@pytest.mark.parametrize("percent, answer", [(0.5, "higher"), (0.1, "the same"), (-0.5, "lower"),
                                             (float("nan"), NOT_DECIDED)])
def test_default_frequency_against_the_solid(percent, answer):
    results = {"modal": {"rows": [{"label": "flap1", "reduced_vs_fe_percent": percent}]}}
    assert default.conclusions(results)["frequency_vs_solid"]["flap1"]["reduced"].answer == answer


# --- error_vs_time: errors and costs -------------------------------------------------

STEP_ERROR = error_vs_time.StepError("fe-reduced", 256, (64, 128, 256), (0.004, 0.001))   # q 1/4: e = 0.001
LADDER = STEP_ERROR.resolution(128, 256)        # a step ladder: each error within e = 0.001 of its true one


@pytest.mark.parametrize("changes, error", [((0.02, 0.002), 0.002),        # q 0.1: at least the last change
                                            ((0.004, 0.003), 0.009),       # q 3/4: 0.003 x 3/4 / (1 - 3/4)
                                            ((0.001, 0.002), math.inf),    # growing: not converging
                                            ((0.001,), math.inf)])         # two rungs: no rate
def test_reference_step_error_sums_the_changes_still_to_come(changes, error):
    assert error_vs_time.StepError("fe-reduced", 256, (), changes).error == pytest.approx(error)


def test_runs_at_the_references_step_are_compared_exactly():
    """Runs that all share the reference's step are judged against the solid at that step: margin 0; a run at
    another step brings the reference's own step error in."""
    assert STEP_ERROR.resolution(256, 256)[0] == 0.0
    assert STEP_ERROR.resolution(256, 128) == (0.001, STEP_ERROR.reason)
    assert error_vs_time.ordering(0.12, 0.1199, STEP_ERROR.resolution(256, 256)).answer == "the same"
    assert error_vs_time.ordering(0.12, 0.0799, STEP_ERROR.resolution(256, 256)).answer == "smaller"


@pytest.mark.parametrize("a, b, spread, answer", [
    (0.12, 0.1199, 0.001, "the same"),      # a converged ladder: the runs differ by far less than their error
    (0.12, 0.1199, math.inf, "the same"),   # ... and, e = 0.001 on an error of 0.12, by the errors alone
    (0.1, 0.05, math.inf, "smaller"),
    (0.1, 0.2, math.inf, "larger"),
    (0.01, 0.0069, math.inf, NOT_DECIDED),  # true ratio in [0.54, 0.88]: either side of 1 / 1.5
    (0.01, 0.001, math.inf, "smaller"),     # true b may vanish: [0, 0.22], below 1 / 1.5 all the same
    (0.001, 0.0009, 1e-5, NOT_DECIDED)])    # an error no larger than the reference's own: unbounded
def test_error_ordering_reads_the_true_errors_ratio(a, b, spread, answer):
    """Within x1.5 the same, decided where the ratio of the true errors (each within e = 0.001 of the measured
    one, the two within the runs' own difference) lies on one side of an edge. The old margin x1.5 around a
    band of width 1 left the first two not decided."""
    verdict = error_vs_time.ordering(a, b, LADDER, spread)
    assert verdict.answer == answer
    assert ("to decide:" in verdict.reason) == (answer == NOT_DECIDED)


def test_error_margin_bounds_the_true_ratio():
    """Every pair of true errors the bounds allow (each within e of its measured one, the two within the runs'
    difference of each other) has its ratio inside the margin around the measured ratio."""
    a, b, e, d = 0.05, 0.04, 0.005, 0.02
    noise = error_vs_time.error_margin(a, b, e, 1.5, d)
    grid = np.linspace(-e, e, 41)
    ratios = [(b + y) / (a + x) for x in grid for y in grid if abs((b + y) - (a + x)) <= d]
    assert min(ratios) >= b / a / noise * (1 - 1e-12) and max(ratios) <= b / a * noise * (1 + 1e-12)
    assert min(ratios) == pytest.approx(b / a / noise) or max(ratios) == pytest.approx(b / a * noise)
    # two runs 0.001 apart with errors 0.05 and 0.049: the true ratio in [0.978, 1.022] instead of [0.8, 1.2]
    assert error_vs_time.error_margin(0.05, 0.049, 0.005, 1.5) == pytest.approx(0.98 / (0.044 / 0.055))
    assert error_vs_time.error_margin(0.05, 0.049, 0.005, 1.5, 0.001) == pytest.approx((1 + 0.001 / 0.045) / 0.98)


def test_distance_is_agreements_worst_nrmse_and_a_norm():
    """The verdicts' norm on the reference's window is shroud.analysis.agreement's worst NRMSE (a second
    implementation) for runs on other time grids, and obeys the triangle inequality the margins rest on."""
    period, t_ref = 0.01, np.linspace(0.0, 0.3, 3001)
    t_run = np.linspace(0.0, 0.3, 1201)

    def wave(t, k, phase):
        return {name: (1 + j) * np.sin(2 * np.pi * t / period + phase + j) + 0.1 * k * np.cos(6 * np.pi * t / period)
                for j, name in enumerate(error_vs_time.SIGNALS)}
    ref, a, b = wave(t_ref, 0, 0.0), wave(t_run, 1, 0.05), wave(t_run, 2, -0.1)
    window = error_vs_time.on_window(t_ref, ref, t_ref, period, 10)
    ranges = error_vs_time.spans(window)
    on = {k: error_vs_time.on_window(t_run, s, t_ref, period, 10) for k, s in (("a", a), ("b", b))}
    for k, s in (("a", a), ("b", b)):
        assert error_vs_time.distance(on[k], window, ranges) == pytest.approx(
            agreement(t_run, s, t_ref, ref, period, 10).worst_nrmse, rel=1e-12)
    d_a, d_b = (error_vs_time.distance(on[k], window, ranges) for k in "ab")
    assert abs(d_a - d_b) <= error_vs_time.distance(on["a"], on["b"], ranges)


@pytest.mark.parametrize("error, best, answer", [(0.13, 0.12, False), (0.006, 0.12, True), (0.1205, 0.12, NOT_DECIDED)])
def test_beats_every_beam(error, best, answer):
    """The P1 solid's 0.13 against the best beam's 0.12 (ratio 1.08: not decided under the old x1.5) is
    decided when the reference's own error is 0.001."""
    assert error_vs_time.beats(error, best, LADDER).answer == answer


@pytest.mark.parametrize("hb, spreads, answer", [(3.28, (1.02, 1.03), "costlier"),     # x2 left it undecided
                                                 (3.28, (1.1, 1.1), NOT_DECIDED),
                                                 (0.1, (1.2, 1.2), "cheaper"), (1.3, (1.2, 1.2), "comparable")])
def test_cost_verdict_margin_is_the_repeats_spread(hb, spreads, answer):
    verdict = error_vs_time.cost_verdict(hb, spreads[0], 1.0, spreads[1])
    assert verdict.answer == answer and verdict.unit == TIME_RATIO


def test_spread_of_repeats():
    assert error_vs_time.spread([1.0, 1.1, 1.3]) == pytest.approx(1.3 / 1.1)


@pytest.mark.parametrize("a, answer", [(1.0, "comparable"), (0.1, "cheaper"), (0.25, NOT_DECIDED)])
def test_cost_versus_has_the_timing_noise_as_its_margin(a, answer):
    assert _bands.cost_versus(a, 1.0).answer == answer


# --- table1 and fig3 -------------------------------------------------------------------

def table1_rows(scale: float) -> tuple[list[dict], dict, dict]:
    """Rows at N = 6 and 7 at ``scale`` times the paper's beam column, and a converged reference at the
    paper's ANSYS column (N = 14, N = 13 the same)."""
    rows = [{"N": N, "f": {lab: scale * TABLE1_REDUCED[N][k] for k, lab in enumerate(TABLE1_LABELS)}}
            for N in (6, 7)]
    ref = {"N": 14, "f": dict(zip(TABLE1_LABELS, TABLE1_FE))}
    return rows, ref, {**ref, "N": 13}


@pytest.mark.parametrize("scale, answer", [(1.01, True), (1.02, NOT_DECIDED), (1.03, False)])
def test_table1_within_two_percent_of_the_paper(scale, answer):
    rows, ref, before = table1_rows(scale)
    assert table1.conclusions(rows, ref, before)["within_2pct_of_paper"]["N 6, flap3"].answer == answer


def test_table1_converged_reference_margin_holds_its_own_convergence():
    """The reference's change from one N less is part of the margin: a reference still moving by 0.2 %
    cannot decide "within 0.1 %"."""
    rows, ref, before = table1_rows(1.0)
    assert table1.conclusions(rows, ref, before)["converged_within_0.1pct_of_paper_fe"]["flap1"].answer is True
    moving = {**before, "f": {lab: 1.002 * f for lab, f in before["f"].items()}}
    assert table1.conclusions(rows, ref, moving)["converged_within_0.1pct_of_paper_fe"]["flap1"].answer == NOT_DECIDED


def test_table1_shell_margin_is_the_measured_move_of_its_difference_from_the_solid():
    """The shell 0.6 % below the solid against flap1's 1 % limit: the meshes' tolerances (0.65 %) cannot
    decide it; halved meshes that move the difference by 0.03 % leave about 0.1 % (order 1/2): within; by
    0.2 % they leave about 0.7 %: not decided."""
    def column(shell_hz: float, solid_hz: float) -> tuple[dict, dict]:
        return ({"f": {lab: shell_hz if lab == "flap1" else None for lab in TABLE1_LABELS}},
                {"f": {lab: solid_hz if lab == "flap1" else None for lab in TABLE1_LABELS}})

    shell, solid = column(0.994 * 282.0, 282.0)
    assert table1.shell_conclusions(shell, solid)["flap1"].answer == NOT_DECIDED
    for move, answer in ((0.0003, True), (0.002, NOT_DECIDED)):
        shell_halved, solid_halved = column((0.994 + move) * 282.0, 282.0)
        halved = {"shell": shell_halved, "fe": solid_halved}
        assert table1.shell_conclusions(shell, solid, halved)["flap1"].answer == answer, move


def test_table1_falls_with_N():
    rows, ref, before = table1_rows(1.0)
    assert table1.conclusions(rows, ref, before)["falls_with_N"]["flap1"].answer is True    # 7 below 6
    rows.reverse()
    assert table1.conclusions(rows, ref, before)["falls_with_N"]["flap1"].answer is False


@pytest.mark.parametrize("error, answer", [(0.08, True), (1.5, False)])
def test_fig3_reduction_error_below_one_percent(error, answer):
    assert fig3.reduction_verdict(error, 30).answer == answer


# --- the quick-against-full rule --------------------------------------------------------

def test_a_quick_not_decided_contradicts_no_full_side():
    decided = {"answer": True, "value": 0.02, "threshold": 0.05, "margin": 0.01, "unit": "", "reason": ""}
    open_ = {**decided, "answer": NOT_DECIDED}
    assert not contradicts(open_, decided) and not contradicts(open_, False)
    assert contradicts({**decided, "answer": False}, decided) and contradicts(decided, False)
    assert not math.isnan(decided["value"])


# --- convergence and stability -----------------------------------------------------------

@pytest.mark.parametrize("worst, answer", [(0.10, True), (0.14, NOT_DECIDED), (0.20, False)])
@pytest.mark.parametrize("reference", ["p3", "hex"])
def test_convergence_mesh_within_tolerance_is_not_decided_within_how_well_the_values_are_known(worst, answer,
                                                                                             reference):
    """Tolerance 0.15 %; the converged values known to 0.02 % (the cubic series' finest step, or the other
    series' estimates), the reason saying which."""
    verdict = convergence.within(worst, 0.15, 0.02, reference)
    assert verdict.answer == answer
    assert ("cubic" in verdict.reason) == (reference == "p3")
    assert convergence.within(worst, 0.15, None, reference).margin == 0.0


@pytest.mark.parametrize("order, holds", [(1.0, True), (1.09, True), (2.0, True), (4.0, True), (0.5, False)])
def test_cubic_reference_uncertainty_holds_the_limit_of_sequences_converging_at_the_floor_order_or_faster(order,
                                                                                                        holds):
    """f_k = 300 Hz + 2 h_k^q + 0.5 h_k^6 (a slow singular term and the smooth P3 one) on three meshes
    (h = 1, 0.8, 0.62): from q = ORDER_FLOOR (1) up the exact limit 300 Hz lies within reference_uncertainty
    of the Richardson estimate (whose observed order lies between q and 6) and of the finest value (fewer than
    three meshes); below the floor (q = 0.5) not of the finest value: the floor is what carries the bound."""
    h = np.array([1.0, 0.8, 0.62])
    f = 300.0 + 2.0 * h ** order + 0.5 * h ** 6
    value, found = convergence.richardson(h, f)
    finest = f[-1]
    assert (abs(finest / 300.0 - 1.0) <= convergence.reference_uncertainty(h[1:], f[1:], np.array(finest))) == holds
    if holds:
        assert min(order, 6.0) <= found <= 6.0
        assert abs(value / 300.0 - 1.0) <= convergence.reference_uncertainty(h[1:], f[1:], np.array(value))


@pytest.mark.parametrize("order, amplified", [(4.0, False), (0.6, True)])
def test_richardson_round_off_is_the_worst_move_of_its_inputs_and_grows_as_the_order_falls(order, amplified):
    """f_k = 300 Hz + 2 h_k^p on three meshes: the declared round-off of the extrapolated value (each input
    moved by eps of itself, moves summed) is the worst of the 2^3 sign combinations, found by brute force
    (to first order: within 1 %); and a low observed order amplifies the inputs' round-off tenfold or more
    ((h2 / h3)^p - 1 small), a high one does not."""
    h = np.array([1.0, 0.8, 0.6])
    f = 300.0 + 2.0 * h ** order
    eps = 1e-9
    value, found = convergence.richardson(h, f)
    assert found == pytest.approx(order, rel=1e-6)
    spread, order_spread = convergence.richardson_rounding(h, f, eps=eps)
    worst = max(abs(convergence.richardson(h, f * (1.0 + eps * np.array(signs)))[0] - value) / value
                for signs in itertools.product((-1.0, 1.0), repeat=3))
    assert spread == pytest.approx(worst, rel=0.01)
    assert order_spread > 0.0
    assert (spread > 10 * eps) == amplified


@pytest.mark.parametrize("difference, step_error, answer", [(0.005, 1e-4, True), (0.0095, 1e-3, NOT_DECIDED),
                                                             (0.02, 1e-3, False)])
def test_linear_limit_holds_the_transients_step_error_as_margin(difference, step_error, answer):
    assert stability.linear_limit(difference, step_error).answer == answer


@pytest.mark.parametrize("difference, answer", [(0.002, True), (0.011, NOT_DECIDED), (0.02, False),
                                                (math.inf, NOT_DECIDED)])
def test_coexisting_states_match_within_one_percent_and_twice_the_settling_tolerance(difference, answer):
    assert coexistence.state_match(difference, 2e-3).answer == answer


def test_fig8_a_run_too_short_to_measure_its_settling_decides_nothing_from_its_window():
    """Fewer periods than two windows: the settling is unknown (None), so amplitudes, slip and the NRMSE
    target read "not decided" however far apart the numbers are; its cost (run times) is still decided."""
    results = fig8_results(v_l=2.0, slip=0.1, nrmse=0.001, times=(1.0, 100.0))
    results["amplitude_change"] = {m: None for m in results["amplitude_change"]}
    found = fig8.conclusions(results)
    assert found["amplitude_vs_reference"]["reduced"]["v_L"].answer == NOT_DECIDED
    assert found["slip_vs_reference"]["reduced"].answer == NOT_DECIDED
    assert found["pairs_met"]["reduced vs full"].answer == NOT_DECIDED
    assert found["settled"]["reduced"].answer == NOT_DECIDED
    assert found["cost"]["reduced vs full"].answer == "cheaper"


# --- ring_tuned: on the travelling wave, the HB's agreement, what explains a departure ----------------

def ring_point(spread=0.0, period=1, drift=0.0, wave=1e-5, coexisting=(), stable=None, tried=True, beside=None):
    """A 12-blade time point at 10000 r/min whose blades spread by ``spread`` around 1e-5 m, its wave and
    stability (largest |multiplier|, margin 0.02), ``beside`` {rpm: largest |multiplier| or None} there."""
    from comparisons.ring_tuned import RingPoint
    from shroud.core.verdict import Verdict

    def verdict(mu):
        return None if mu is None else Verdict.of(mu, threshold=1.0, margin=0.02, below=True, above=False, reason="")
    a = 1e-5 * (1 + spread * (np.arange(12) / 11 - 0.5))
    return RingPoint(blades=12, rpm=10000.0, amplitudes=list(a), period=period, drift=drift, wave=wave,
                     coexisting=list(coexisting), stability=verdict(stable), wave_spread=0.005, stability_tried=tried,
                     beside={r: verdict(mu) for r, mu in (beside or {}).items()})


@pytest.mark.parametrize("spread, answer", [(0.002, True), (0.0045, NOT_DECIDED), (0.0055, NOT_DECIDED),
                                            (0.008, False)])
def test_ring_on_the_wave_flips_at_half_a_percent_of_spread_with_the_steps_margin(spread, answer):
    assert ring_point(spread).on == answer


def test_a_ring_not_p1_or_still_drifting_is_off_the_wave_whatever_its_spread():
    assert ring_point(0.0, period=None).on is False
    assert ring_point(0.0, period=3).on is False
    assert ring_point(0.0, drift=2e-3).on is False


@pytest.mark.parametrize("wave, answer", [(1.002e-5, True), (1.005e-5, NOT_DECIDED), (1.01e-5, False)])
def test_ring_hb_agrees_within_half_a_percent_of_the_nearest_wave(wave, answer):
    assert ring_point(0.0, wave=wave).agreement(0.005).answer == answer
    assert ring_point(0.0, wave=3e-5, coexisting=[wave]).agreement(0.005).answer == answer   # the nearest wave


@pytest.mark.parametrize("kwargs, named", [
    ({"stable": 1.5}, "wave unstable"),
    ({"stable": 0.9, "coexisting": [1e-5, 2e-5, 3e-5]}, "coexisting branch"),
    ({"stable": 0.9, "coexisting": [1e-5]}, "unexplained"),
    ({"stable": 1.01}, "stability not decided"),
    ({"wave": None}, "no wave reached"),
    ({"tried": False}, "stability not computed"),
    ({}, "stability not reached at 2 H")])
def test_a_departure_from_the_wave_is_named_by_what_the_hb_shows(kwargs, named):
    assert ring_point(0.02, period=2, **kwargs).explanation() == named


def ring_comparison(*points):
    from comparisons.ring_tuned import RingCase, RingTunedComparison
    return RingTunedComparison(cases=[RingCase(label="gap 1 um", gap_um=1.0, fixed=None, sectors={}, failures={},
                                               points=list(points))], agree=0.005)


# A settled wave at |mu| 1.0001 +- 0.02 (not decided) beside one decided stable (0.9): the stability 200 r/min
# either side decides whether it is at a bracketed threshold, (|mu| - 1) / 0.02 the smaller side's distance.
@pytest.mark.parametrize("beside, named, bracketed, first", [
    ({9800.0: 0.91, 10200.0: 1.17}, "at the stability threshold", True, True),       # +4.5 margins
    ({9800.0: 1.17, 10200.0: 0.91}, "at the stability threshold", True, True),       # losing it downwards
    ({9800.0: 0.91, 10200.0: 0.95}, "stability not decided", False, NOT_DECIDED),    # stable on both: -2.5
    ({9800.0: 1.10, 10200.0: 1.17}, "stability not decided", False, NOT_DECIDED),    # unstable on both: -5
    ({9800.0: 1.01, 10200.0: 1.17}, "stability not decided", NOT_DECIDED, NOT_DECIDED),  # one side undecided
    ({9800.0: 0.91, 10200.0: 1.019}, "stability not decided", NOT_DECIDED, NOT_DECIDED),  # +0.95: within one
    ({9800.0: None, 10200.0: 1.17}, "stability not decided", NOT_DECIDED, NOT_DECIDED),  # no wave on one side
    ({9800.0: 0.91, 10200.0: None}, "stability not decided", NOT_DECIDED, NOT_DECIDED),
    ({}, "stability not decided", NOT_DECIDED, NOT_DECIDED)])                        # sides not computed
def test_a_settled_wave_at_a_bracketed_threshold_is_judged_apart_and_any_other_stays(beside, named, bracketed,
                                                                                     first):
    """A wave the ring settled on whose |multiplier| is within its margin of 1 is at its stability threshold
    where the same verdict THRESHOLD_STEP either side is decided stable on one side and unstable on the
    other: stability_threshold_bracketed says yes and hb_stable_where_on_wave, judged on the other waves,
    decides (stable, 0.9) and names the one left out. Stable or unstable on both sides the threshold is not
    bracketed (no), a side undecided or not reached decides nothing; either way the wave stays in
    hb_stable_where_on_wave, which stays not decided."""
    at, other = ring_point(0.0, stable=1.0001, beside=beside), ring_point(0.0, stable=0.9)
    assert at.explanation() == named
    result = ring_comparison(at, other)
    b, v = result.threshold_bracketed(), result.stable_where_on_wave()
    assert b.answer == bracketed and b.threshold == 0.0 and b.margin == 1.0
    assert v.answer == first
    assert v.value == (0.9 if first is True else 1.0001)
    assert ("1 left to `stability_threshold_bracketed`" in v.reason) == (bracketed is True)
    assert ("of the 1 waves" if bracketed is True else "of the 2 waves") in v.reason
    assert "gap 1 um, 12 blades, 10000 r/min" in b.reason


def test_the_bracket_reads_the_smaller_sides_distance_in_margins():
    """(|mu| - 1) / margin on each side, the smaller of the two: 0.91 and 1.17 at +-0.02 are 4.5 and 8.5."""
    b = ring_comparison(ring_point(0.0, stable=1.0001, beside={9800.0: 0.91, 10200.0: 1.17})).threshold_bracketed()
    assert b.value == pytest.approx(4.5)
    b = ring_comparison(ring_point(0.0, stable=1.0001, beside={9800.0: 0.91, 10200.0: 0.95})).threshold_bracketed()
    assert b.value == pytest.approx(-2.5)


def test_one_wave_not_bracketed_among_bracketed_ones_keeps_both_verdicts_open_to_it():
    """Two undecided settled waves, one bracketed and one stable on both sides: the bracket verdict reads at
    the one not bracketed (no), and hb_stable_where_on_wave keeps that one (not decided), leaving out only the
    bracketed one."""
    good = ring_point(0.0, stable=1.0001, beside={9800.0: 0.91, 10200.0: 1.17})
    bad = ring_point(0.0, stable=0.999, beside={9800.0: 0.91, 10200.0: 0.95})
    result = ring_comparison(good, bad, ring_point(0.0, stable=0.9))
    assert result.threshold_bracketed().answer is False
    v = result.stable_where_on_wave()
    assert v.answer == NOT_DECIDED and v.value == 0.999
    assert "of the 2 waves" in v.reason and "1 left to" in v.reason


def test_no_undecided_settled_wave_leaves_nothing_to_bracket():
    """Every settled wave decided: the bracket verdict is None (nothing to judge; not a decided verdict, so a
    quick-against-full test skips it: tests/test_quick_conclusions.py) and hb_stable_where_on_wave reads every
    wave."""
    result = ring_comparison(ring_point(0.0, stable=0.9), ring_point(0.0, stable=0.95))
    assert result.threshold_bracketed() is None
    v = result.stable_where_on_wave()
    assert v.answer is True and v.value == 0.95 and "left to" not in v.reason


@pytest.mark.parametrize("gaps, preloads, refused", [([], [10.0], False), ([1.0], [-5.0], True), ([], [], True),
                                                     ([1.0], [0.0], True)])
def test_ring_tuned_takes_positive_preloads_and_at_least_one_case(gaps, preloads, refused):
    from comparisons.ring_tuned import OPTIONS, check
    from shroud.base.errors import InputError
    scene = SimpleNamespace(options={**OPTIONS, "gaps_um": gaps, "preloads_N": preloads})
    if refused:
        with pytest.raises(InputError):
            check(scene)
    else:
        check(scene)


def test_a_ring_on_its_wave_is_named_by_the_waves_stability():
    assert ring_point(0.0, stable=0.9).explanation() == "stable wave"
    assert ring_point(0.0, stable=1.5).explanation() == "on an unstable wave"
    assert ring_point(0.0, stable=1.01).explanation() == "stability not decided"


# --- calculix: two codes on one mesh ---------------------------------------------------

@pytest.mark.parametrize("cell, worst, answer", [("tet", 1e-4, "agree"), ("tet", 0.01 + 2e-5, NOT_DECIDED),
                                                 ("tet", 0.02, "differ"), ("hex", 0.046, "agree"),
                                                 ("hex", 0.22, "differ")])
def test_two_codes_agree_within_what_they_solve_on_one_mesh(cell, worst, answer):
    """The same element (tetrahedra) is held to 0.01 %, two element spaces (bricks) to the mesh tolerance
    (0.15 %); within ccx's printed digits of a threshold, not decided. 0.046 % and 0.22 %: C3D20 against Q2
    measured on the 5 mm and 10 mm bricks."""
    assert calculix.agreement(cell, worst).answer == answer
