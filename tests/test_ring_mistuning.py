"""The mistuning Monte Carlo (comparisons/ring_mistuning.py): samples streamed to disk as they end, a
killed study resumed from them, the same answer either way; percentiles' bootstrap intervals."""

import json
from dataclasses import replace
from pathlib import Path

import numpy as np

from comparisons.ring_mistuning import percentile_with_ci
from workbench.runner import run_scene

SCENE = Path(__file__).resolve().parents[1] / "scenes" / "ring_mistuning.toml"
SMALL = ["ring.blades=4", "time.periods=20", "options.samples=3", "options.rpms=[10000.0]",
         "options.scatters=[0.005, 0.013]", "options.scatter_samples=2", "options.preload_rpms=[12000.0]"]


def _keys(lines: list[str]) -> list[tuple]:
    return [(r["case"], r["std"], r["seed"]) for r in map(json.loads, lines)]


def test_a_killed_study_resumes_from_its_streamed_samples_scatter_by_scatter(tmp_path):
    """Main Monte Carlo (3 samples at 1.3 %) and both cases' sweeps (2 samples at 0.5 and 1.3 %; the unloaded
    sweep's 1.3 % samples are the main ones): 9 rings, one line each. Killed in the middle of the fifth line,
    the run again computes only the missing (case, scatter, seed) and gives the same statistics."""
    out = tmp_path / "m"
    run_scene(SCENE, out, SMALL, quick=True)
    first = json.loads((out / "results.json").read_text())["results"]
    lines = (out / "samples.jsonl").read_text().splitlines()
    assert all(len(json.loads(line)["deviations"]) == 4 for line in lines)
    assert sorted(_keys(lines)) == sorted([("unloaded", 0.013, s) for s in (1, 2, 3)] +
                                          [("unloaded", 0.005, s) for s in (1, 2)] +
                                          [("preloaded", x, s) for x in (0.005, 0.013) for s in (1, 2)])
    (out / "samples.jsonl").write_text("\n".join(lines[:4]) + "\n" + lines[4][:25])
    run_scene(SCENE, out, SMALL, quick=True)
    again = json.loads((out / "results.json").read_text())["results"]
    assert again["amplification"] == first["amplification"] and again["scatter"] == first["scatter"]
    kept = _keys(lines[:4])
    now = _keys((out / "samples.jsonl").read_text().splitlines())
    assert now[:4] == kept and sorted(now[4:]) == sorted(set(_keys(lines)) - set(kept))   # only the missing ran


def test_bootstrap_interval_holds_the_normal_median():
    """400 normal draws: the 95 % interval of the median holds 0 and is about 2 x 1.96 x 1.2533 / sqrt(400)."""
    rng = np.random.default_rng(5)
    value, lo, hi = percentile_with_ci(rng.normal(size=400), 50.0, 4000, np.random.default_rng(0))
    assert lo < 0.0 < hi and abs(value) < 0.15
    assert 0.7 * 0.245 < hi - lo < 1.3 * 0.245


def _comparison(sample_change: float):
    """Two speeds: the tuned ring settles on its 11 um wave at the second, rattles 30 % above its wave at the
    first; every sample's worst blade is 9 % above the tuned peak at the second; its change a period given."""
    from comparisons.ring_mistuning import MistuningComparison
    N = 4
    tuned = np.array([[13.0e-6] * N, [11.0e-6] * N])
    records = [{"seed": s, "deviations": [0.0] * N, "change": [0.5, sample_change],
                "amplitudes": [[13.1e-6] * N, [11.99e-6 + 1e-9 * s] + [11.5e-6] * (N - 1)]} for s in range(20)]
    return MistuningComparison(N=N, model="reduced", std=0.013, rpms=[9500.0, 10000.0], tuned=tuned,
                               tuned_change=np.array([0.4, 1e-9]), wave=np.array([10.0e-6, 11.0e-6]),
                               records=records, stats={"median": (1.09, 1.089, 1.091)})


def test_amplification_is_not_decided_against_a_settled_tuned_ring_when_no_sample_settles():
    """A sample that never settles is read by its largest blade, which an unsettled ring overshoots its wave
    by (here the tuned ring's own 30 %): 9 % above a settled tuned peak decides nothing then; settled samples
    9 % above it do say mistuning amplifies (margin half the bootstrap interval plus the largest change a
    period, the settling error)."""
    unsettled = _comparison(sample_change=0.2)
    assert abs(unsettled.unsettled_overshoot - 0.3) < 1e-12
    amplifies, _ = unsettled.verdicts()
    assert amplifies.answer == "not decided" and abs(amplifies.margin - (0.001 + 0.3)) < 1e-12
    settled = _comparison(sample_change=1e-6)
    amplifies, _ = settled.verdicts()
    assert amplifies.answer is True and abs(amplifies.margin - (0.001 + 1e-6)) < 1e-12   # plus the settling error


def test_the_sweep_rises_only_where_its_samples_settle():
    """Two scatters whose samples' worst blades are 1 % and 9 % above the settled tuned peak, pattern by
    pattern: settled samples say the amplification rises with the scatter (a paired rise of 0.08 against a
    margin of 1e-6 settling), also with a third, larger scatter whose samples rattle (the rise is read up to
    the last scatter that settles); unsettled ones, read against a tuned ring that overshoots its wave by 30 %
    where it rattles, decide nothing; the largest sample is held to Whitehead's (1 + sqrt 4) / 2 = 1.5."""
    from comparisons.ring_mistuning import ScatterSweep

    def at(change: float, std: float, worst: float):
        c = replace(_comparison(change), std=std, case="preloaded")
        c = replace(c, records=[{**r, "amplitudes": [r["amplitudes"][0], [worst] * 4]} for r in c.records])
        return replace(c, stats={"median": (float(np.median(c.ratio)),) * 3})

    for changes, answer in (((1e-6, 1e-6), True), ((1e-6, 1e-6, 0.2), True), ((0.2, 0.2), "not decided")):
        scatters = tuple(at(c, x, w) for c, x, w in zip(changes, (0.005, 0.013, 0.02), (11.11e-6, 11.99e-6, 12.5e-6)))
        sweep = ScatterSweep(case="preloaded", preload=20.0, scatters=scatters, bootstrap=200)
        verdicts = sweep.verdicts(0.013)
        assert sweep.settled_range == (0, 1) and abs(sweep.rise[0] - 0.08) < 1e-9
        assert verdicts["preloaded_rises_with_scatter"].answer == answer
        assert verdicts["preloaded_within_whitehead"].answer is True


def test_a_sweep_that_misses_the_main_scatter_or_runs_backwards_is_refused(tmp_path, capsys):
    """Bad input, one line and exit 2, before any ring is run: scatters not holding options.std, scatters
    not increasing, a preload that is none."""
    from workbench.cli import main
    for bad in ("options.scatters=[0.005, 0.02]", "options.scatters=[0.02, 0.013]", "options.preload=0.0"):
        assert main(["run", str(SCENE), "--out", str(tmp_path / "bad"), "--set", bad]) == 2
        err = capsys.readouterr().err
        assert ("options.scatters" in err or "options.preload" in err) and len(err.strip().splitlines()) == 1
    assert not (tmp_path / "bad" / "samples.jsonl").exists()
