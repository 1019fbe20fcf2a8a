"""Every study's quick version concludes what its full version concludes.

Each test runs a scene's ``--quick`` version as a user would (workbench.runner.run_scene) and
compares the conclusions its study returns as data (``results["conclusions"]``) with those of the
full scene, recorded in tests/data/records/<scene>.json by `shroud record` (workbench.records; the
full scenes take minutes to hours, too long for CI; tests/test_records.py holds each record
current). Resonant and crossing speeds must agree within the quick grid's speed step (for the resonance followed in the preload: optimal preloads within the
curves' brackets, the onset of full stick within the quick curve's step in N0), every yes/no and every
sign of a comparison exactly.

A verdict is held by its answer, "not decided" contradicting nothing (tests/quick_full.py); a test
that holds no verdict decided on both sides fails (the ``held`` fixture, tests/conftest.py) and each
says how many it held. Verdicts drawn from run times are never held: timing decides nothing a test may
assert.
"""

from pathlib import Path

import pytest

from shroud.core.verdict import NOT_DECIDED, answer_of, is_cost_record, is_verdict
from quick_full import quick_run
from workbench import records


def full_conclusions(scene: str) -> dict:
    """The conclusions the full version of scenes/<scene>.toml drew, as recorded."""
    return records.load(scene)["conclusions"]


def quick(study: str, tmp_path: Path) -> tuple[dict, dict]:
    """(conclusions, options) of the quick version of scenes/<study>.toml."""
    record, _ = quick_run(study, tmp_path)
    assert record["status"] == "complete" and record["quick"]
    return record["results"]["conclusions"], record["options"]


def step(options: dict) -> float:
    return (options["rpm_to"] - options["rpm_from"]) / (options["rpm_count"] - 1)


def model_error(verdicts: list[str]) -> bool:
    """Whether the curves differ anywhere by more than coexisting states explain."""
    return "different" in verdicts


@pytest.mark.slow
def test_fig4_quick_agrees_with_full(tmp_path, held):
    got, options = quick("fig4", tmp_path)
    full = full_conclusions("fig4")
    for case in got.keys() & full.keys():
        q, f = got[case], full[case]
        for model in ("reduced", "full"):
            assert abs(q[f"{model}_resonance_rpm"] - f[f"{model}_resonance_rpm"]) <= step(options), (case, model)
        assert held.agrees(q["same_resonant_speed"], f["same_resonant_speed"]), case
        assert model_error(q["differing_speed_verdicts"]) == model_error(f["differing_speed_verdicts"]), case
        assert "no steady state" not in q["differing_speed_verdicts"], case
    assert len(got.keys() & full.keys()) == 6


@pytest.mark.slow
@pytest.mark.parametrize("study", ["gap_preload", "friction", "stiffness_ratio"])
def test_family_quick_agrees_with_full(tmp_path, held, study):
    got, options = quick(study, tmp_path)
    full = full_conclusions(study)
    shared = got["resonances"].keys() & full["resonances"].keys()
    assert len(shared) >= 4
    for case in shared:
        q, f = got["resonances"][case], full["resonances"][case]
        assert q["beyond_range"] == f["beyond_range"], case
        assert abs(q["rpm"] - f["rpm"]) <= step(options), case
    for key in full.keys() - {"resonances"}:
        assert held.agrees(got[key], full[key]), (key, got[key], full[key])


@pytest.mark.fe
@pytest.mark.slow
def test_fig7_quick_agrees_with_full(tmp_path, held):
    got, options = quick("fig7", tmp_path)
    full = full_conclusions("fig7")
    shared = got.keys() & full.keys()
    assert {"gap 600 um", "gap 1 um", "N0 10 N"} <= shared
    for case in shared:
        q, f = got[case], full[case]
        assert held.agrees(q["peaked"], f["peaked"]), case
        if answer_of(q["peaked"]) is True and answer_of(f["peaked"]) is True:
            for model in ("beam", "solid"):
                assert abs(q[f"{model}_resonance_rpm"] - f[f"{model}_resonance_rpm"]) <= step(options), (case, model)
            assert held.agrees(q["same_resonant_speed"], f["same_resonant_speed"]), case
        assert held.agrees(q["curves_agree"], f["curves_agree"]), case
        assert model_error(q["differing_speed_verdicts"]) == model_error(f["differing_speed_verdicts"]), case
        assert "no steady state" not in q["differing_speed_verdicts"], case


@pytest.mark.fe
@pytest.mark.slow
def test_campbell_quick_agrees_with_full(tmp_path, held):
    got, options = quick("campbell", tmp_path)
    full = full_conclusions("campbell")
    grid = (options["rpm_to"] - options["rpm_from"]) / (options["speeds"] - 1)
    assert got["ke"] == full["ke"]
    for kind, tol in (("beam_crossings_rpm", grid), ("solid_crossings_rpm", grid)):
        assert got[kind].keys() == full[kind].keys(), kind
        for mode, rpm in full[kind].items():
            assert (got[kind][mode] is None) == (rpm is None), (kind, mode)
            if rpm is not None:
                assert abs(got[kind][mode] - rpm) <= tol, (kind, mode)
    every = full["beam_crossings_every_order_rpm"]
    assert got["beam_crossings_every_order_rpm"].keys() == every.keys()
    for crossing, rpm in every.items():
        assert abs(got["beam_crossings_every_order_rpm"][crossing] - rpm) <= grid, crossing
    verdicts = [key for key in full if is_verdict(full[key])]
    assert set(verdicts) == {key for key in got if is_verdict(got[key])}
    assert all(held.agrees(got[key], full[key]) for key in verdicts)
    assert held.decided >= 2


@pytest.mark.fe
@pytest.mark.slow
def test_error_vs_time_quick_agrees_with_full(tmp_path, held):
    got, _ = quick("error_vs_time", tmp_path)
    full = full_conclusions("error_vs_time")
    # Costs of harmonic balance against the time domain are verdicts drawn from run times (TIME_RATIO):
    # never held; their order is benchmarks/bench_hb.py's to measure.
    shared = {key for key in got.keys() & full.keys() if not is_cost_record(got[key])}
    assert len(shared) >= 3
    for key in shared:
        assert held.agrees(got[key], full[key]), (key, got[key], full[key])


@pytest.mark.parametrize("study", ["stability", pytest.param("stability_fe", marks=[pytest.mark.fe, pytest.mark.slow])])
def test_stability_quick_agrees_with_full(tmp_path, held, study):
    got, _ = quick(study, tmp_path)
    full = full_conclusions(study)
    for key in ("implicit_bounded", "implicit_energy_closed", "explicit_diverges_somewhere"):
        assert held.agrees(got[key], full[key]), (key, got[key], full[key])
    shared = got["explicit_bounded"].keys() & full["explicit_bounded"].keys()
    assert len(shared) >= 8
    for case in shared:
        assert got["explicit_bounded"][case] == full["explicit_bounded"][case], case
    assert got["linear_limit_met"].keys() == full["linear_limit_met"].keys()
    assert held.agrees(got["linear_limit_met"], full["linear_limit_met"])


def test_periodicity_quick_agrees_with_full(tmp_path, held):
    got, _ = quick("periodicity", tmp_path)
    full = full_conclusions("periodicity")
    shared = got["periods"].keys() & full["periods"].keys()
    assert len(shared) >= 4
    for case in shared:
        assert got["periods"][case] == full["periods"][case], case
    for key in ("p10_at_scene_speed", "p10_in_band"):
        assert got[key] == full[key], key
    # the harmonic-balance prediction: where and how P1 loses stability, and how it reads against the time domain
    q, f = got["hb"], full["hb"]
    for key in ("period_doubling_in_band", "instability_kinds_in_band"):
        assert q[key] == f[key], key
    assert held.agrees(q["td_p1_on_stable_p1_at_least_95pct"], f["td_p1_on_stable_p1_at_least_95pct"])
    assert held.decided == 1
    # "every" over the quick map's fewer points: a quick counterexample must be one of the full map too
    # (the full map has points without a P1 state within its 15 % reach that the quick one does not run)
    if not q["every_td_non_p1_on_unstable_p1"]:
        assert not f["every_td_non_p1_on_unstable_p1"]
    cases = q["p1_unstable_in_band"].keys() & f["p1_unstable_in_band"].keys()
    assert len(cases) >= 3
    for case in cases:
        assert q["p1_unstable_in_band"][case] == f["p1_unstable_in_band"][case], case


def test_fig3_quick_agrees_with_full(tmp_path, held):
    got, _ = quick("fig3", tmp_path)
    full = full_conclusions("fig3")
    assert got.keys() == full.keys()
    assert held.agrees(got, full)


@pytest.mark.fe
def test_table1_quick_agrees_with_full(tmp_path, held):
    got, _ = quick("table1", tmp_path)
    full = full_conclusions("table1")
    shared = got["within_2pct_of_paper"].keys() & full["within_2pct_of_paper"].keys()
    assert len(shared) >= 8
    for case in shared:
        assert held.agrees(got["within_2pct_of_paper"][case], full["within_2pct_of_paper"][case]), case
    for key in ("falls_with_N", "converged_within_0.1pct_of_paper_fe"):
        assert got[key].keys() == full[key].keys(), key
        assert held.agrees(got[key], full[key]), key


# Not "cost": the models' cost verdicts are drawn from run times (TIME_RATIO), which decide nothing a test
# may assert; benchmarks/ measure costs.
FIG8_VERDICTS = ("pairs_met", "settled", "closer_to_reference", "amplitude_vs_reference", "slip_vs_reference",
                 "state_order")


@pytest.mark.fe
@pytest.mark.slow
def test_fig8_quick_agrees_with_full(tmp_path, held):
    """The quick version's reference is the reduced solid, the full scene's the full solid (which the
    reduced solid follows to 0.08 % NRMSE there): each beam compares with either the same way."""
    got, _ = quick("fig8", tmp_path)
    full = full_conclusions("fig8")
    held.same_where_shared(got, full, FIG8_VERDICTS)
    assert got["settled"] and all(answer_of(v) is True for v in got["settled"].values())
    assert {"reduced", "full", "extended"} <= got["amplitude_vs_reference"].keys()     # the extended beam held too


@pytest.mark.fe
@pytest.mark.slow
def test_airfoil_quick_agrees_with_full(tmp_path, held):
    """The same modes (the quick version keeps the solid, the beams and the shell) and the transients over 30
    periods instead of 100: every frequency verdict and every transient comparison the same."""
    got, _ = quick("airfoil", tmp_path)
    full = full_conclusions("airfoil")
    assert got["solid_vs_converged"] and held.agrees(got["solid_vs_converged"], full["solid_vs_converged"])
    assert got["within_limit"].keys() == full["within_limit"].keys()
    assert held.agrees(got["within_limit"], full["within_limit"])
    held.same_where_shared(got["fig8"], full["fig8"], FIG8_VERDICTS)


@pytest.mark.fe
def test_default_quick_agrees_with_full(tmp_path, held):
    got, _ = quick("default", tmp_path)
    full = full_conclusions("default")
    assert held.agrees(got["frequency_vs_solid"], full["frequency_vs_solid"])
    held.same_where_shared(got["fig8"], full["fig8"], FIG8_VERDICTS)
    assert got["fig8"]["amplitude_vs_reference"].keys() == full["fig8"]["amplitude_vs_reference"].keys()


@pytest.mark.fe
@pytest.mark.slow
def test_convergence_quick_agrees_with_full(tmp_path, held):
    got, _ = quick("convergence", tmp_path)
    full = full_conclusions("convergence")
    assert held.agrees(got["default_mesh_meets_tolerance"], full["default_mesh_meets_tolerance"])
    if None not in (got["cheaper_at_equal_error"], full["cheaper_at_equal_error"]):   # None: the meshes run cannot tell
        assert got["cheaper_at_equal_error"] == full["cheaper_at_equal_error"]
    # the mesh chosen is the cheapest decided within the tolerance: where the full scene cannot decide the
    # default mesh (its error within the converged values' own uncertainty) it goes finer, so the two
    # scenes' choices are held against each other only where both decided the default
    if NOT_DECIDED not in (answer_of(full["default_mesh_meets_tolerance"]), answer_of(got["default_mesh_meets_tolerance"])):
        assert got["chosen"] == full["chosen"], (got["chosen"], full["chosen"])
    held.same_where_shared(got, full, ("meets_tolerance", "asymptotic"))
    for kind in got["observed_order"].keys() & full["observed_order"].keys():
        q, f = got["observed_order"][kind], full["observed_order"][kind]
        assert q.keys() & f.keys(), kind
        for mode in q.keys() & f.keys():
            assert (q[mode] is None) == (f[mode] is None), (kind, mode)
            if q[mode] is not None:
                assert abs(q[mode] - f[mode]) <= 0.2, (kind, mode)


def tracked_step(options: dict) -> float:
    """The quick tracked curve's largest step in N0 (N): what its optimum and stuck onset can resolve."""
    return (options["n0_to"] - options.get("n0_from", 0.0)) / (options["track_points"] - 1)


def same_optimum(q: float, f: float, q_bracket: list[float], f_bracket: list[float]) -> bool:
    """Whether two optimal preloads agree within the wider of the two curves' brackets around them."""
    return abs(q - f) <= max(q_bracket[1] - q_bracket[0], f_bracket[1] - f_bracket[0])


@pytest.mark.slow
def test_hb_optimal_preload_quick_agrees_with_full(tmp_path, held):
    got, options = quick("hb_optimal_preload", tmp_path)
    full = full_conclusions("hb_optimal_preload")
    for key in ("optimum_inside", "resonant_speed_rises_with_preload", "brute_force_agrees", "complete"):
        assert got[key] == full[key], key
    assert held.agrees(got["brute_force_agrees_verdict"], full["brute_force_agrees_verdict"])
    assert same_optimum(got["optimal_preload_N"], full["optimal_preload_N"], got["optimal_bracket_N"],
                        full["optimal_bracket_N"])
    assert got["optimal_amplitude_m"] == pytest.approx(full["optimal_amplitude_m"], rel=0.01)
    assert (got["stuck_from_N0"] is None) == (full["stuck_from_N0"] is None)
    if full["stuck_from_N0"] is not None:
        assert abs(got["stuck_from_N0"] - full["stuck_from_N0"]) <= tracked_step(options)


@pytest.mark.slow
@pytest.mark.parametrize("study", ["hb_friction", "hb_stiffness_ratio"])
def test_hb_family_quick_agrees_with_full(tmp_path, held, study):
    got, options = quick(study, tmp_path)
    full = full_conclusions(study)
    for key in ("optimal_preload_trend", "minimum_amplitude_nearly_same", "optimal_preload_unaffected",
                "stuck_resonance_same", "peak_tracking_complete"):
        assert held.agrees(got[key], full[key]), (key, got[key], full[key])      # "not decided" contradicts nothing
    assert held.agrees(got["large_gaps"]["no_effect"], full["large_gaps"]["no_effect"])
    # the verdicts these words are drawn from, held themselves (the words alone are no verdict objects)
    for key in ("minimum_amplitude_nearly_same_verdict", "optimal_preload_unaffected_verdict",
                "resonant_speed_rises_as_gap_closes_verdict"):
        assert held.agrees(got[key], full[key]), (key, got[key], full[key])
    for key in ("speed_spread_verdict", "amplitude_spread_verdict"):
        assert held.agrees(got["large_gaps"][key], full["large_gaps"][key]), (key, got["large_gaps"][key])
    cases = got["preload_cases"].keys() & full["preload_cases"].keys()
    assert len(cases) >= 2
    for case in cases:
        assert got["preload_cases"][case] == full["preload_cases"][case], case
    variants = got["optimal_preload_N"].keys() & full["optimal_preload_N"].keys()
    assert len(variants) >= 2
    for v in variants:
        assert got["resonant_speed_rises_as_gap_closes"][v] == full["resonant_speed_rises_as_gap_closes"][v], v
        assert got["optimum_inside"][v] == full["optimum_inside"][v], v
        assert same_optimum(got["optimal_preload_N"][v], full["optimal_preload_N"][v],
                            got["optimal_bracket_N"][v], full["optimal_bracket_N"][v]), v
        q, f = got["stuck_from_N0"][v], full["stuck_from_N0"][v]
        assert (q is None) == (f is None), v
        if f is not None:
            assert abs(q - f) <= tracked_step(options), v


@pytest.mark.fe
@pytest.mark.slow
def test_fig10_quick_agrees_with_full(tmp_path, held):
    """Fig. 10 (the fig8 study with the shell): the quick run's beam and reduced shell against the
    reduced solid, as the full scene's."""
    got, _ = quick("fig10", tmp_path)
    full = full_conclusions("fig10")
    # the quick version runs no full model, so no reduction meets its full model there (pairs_met)
    held.same_where_shared(got, full, tuple(k for k in FIG8_VERDICTS if k != "pairs_met"))
    assert {"reduced", "shell-reduced"} <= got["amplitude_vs_reference"].keys()


@pytest.mark.fe
def test_shell_benchmarks_quick_agree_with_full(tmp_path, held):
    """Every published benchmark the full scene finds within its tolerance the quick one does not find
    outside it (and the other way round)."""
    got, _ = quick("shell_benchmarks", tmp_path)
    full = full_conclusions("shell_benchmarks")
    for group in ("macneal_harder", "fv16"):
        assert got[group].keys() == full[group].keys(), group
        assert held.agrees(got[group], full[group]), group


@pytest.mark.fe
def test_calculix_quick_agrees_with_full(tmp_path, held):
    """The quick scene runs one of the full scene's meshes (the 5 mm bricks): the two codes' agreement there
    is the full scene's answer."""
    from reference_fe.calculix import ccx
    if ccx() is None:
        pytest.skip("CalculiX (ccx) is not installed: bash scripts/install_calculix.sh")
    got, _ = quick("calculix", tmp_path)
    full = full_conclusions("calculix")
    assert got.keys() <= full.keys() and got
    assert all(held.agrees(got[mesh], full[mesh]) for mesh in got)


def test_interference_quick_agrees_with_full(tmp_path, held):
    """The ring's stuck flap family at the engine order's nodal diameter against fixed neighbours: the
    eigenvalues at the scene's speed do not depend on the Campbell grid the quick version thins. The FE
    sector of blade and disk (its rigid-disk verdicts) is the full scene's only: the quick one keeps the
    rigid disk."""
    got, _ = quick("interference", tmp_path)
    full = full_conclusions("interference")
    assert full.keys() - got.keys() == {"rigid_disk_holds_free", "rigid_disk_holds_stuck"}
    assert all(held.agrees(got[k], full[k]) for k in got)
    assert held.decided >= 3


@pytest.mark.slow
def test_ring_mistuning_quick_agrees_with_full(tmp_path, held):
    """8 samples against 100: whether mistuning amplifies (the quick median's wider interval may leave it
    undecided, never the other side) and whether every sample stays within Whitehead's bound."""
    got, _ = quick("ring_mistuning", tmp_path)
    full = full_conclusions("ring_mistuning")
    assert got.keys() == full.keys()
    for key in got:
        assert held.agrees(got[key], full[key]), (key, got[key], full[key])
    assert held.decided >= 1


VERDICTS_OVER_POINTS = ("hb_agrees_where_on_wave", "hb_stable_where_on_wave", "stability_threshold_bracketed",
                        "departures_explained", "branch_agrees_with_points", "fixed_neighbours_stand_in_for_ring")


@pytest.mark.slow
def test_ring_tuned_quick_agrees_with_full(tmp_path, held):
    """Every time point the quick scene runs is one the full scene runs (the same case, ring size, speed
    and settings): named alike (on or off the wave, and what explains a departure), its HB agreement
    and the sector branch's stability there alike; and what the quick scene finds wrong on its points (the
    HB differing where the ring is on a wave, a departure the HB does not explain, the branch's stability
    against the wave's own verdict) the full scene, which runs them all, finds too."""
    got, _ = quick("ring_tuned", tmp_path)
    full = full_conclusions("ring_tuned")
    shared = got["points"].keys() & full["points"].keys()
    assert shared == got["points"].keys()
    for point in shared:
        assert got["points"][point] == full["points"][point], point
    # Each verdict is read over the time points: the quick scene's are some of the full scene's, so a quick
    # "no" (a point the HB does not match, explain or call stable) is one the full scene has too and cannot
    # answer "yes"; a quick "yes" over fewer points denies nothing. A verdict with nothing to judge (None: no
    # such point, no undecided wave to bracket) is no verdict and is not held.
    pairs = [(got[key], full[key]) for key in VERDICTS_OVER_POINTS if got[key] is not None]
    pairs += [(got["hb_agrees_on_wave_by_speed"][r], full["hb_agrees_on_wave_by_speed"][r])
              for r in got["hb_agrees_on_wave_by_speed"] if got["hb_agrees_on_wave_by_speed"][r] is not None]
    for q, f in pairs:
        held.count(q, f)
        if answer_of(q) is False:
            assert answer_of(f) is not True, (q, f)
    assert held.decided >= 1
