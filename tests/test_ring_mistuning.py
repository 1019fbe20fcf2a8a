"""The mistuning Monte Carlo (comparisons/ring_mistuning.py): samples streamed to disk as they end, a
killed study resumed from them, the same answer either way; percentiles' bootstrap intervals."""

import json
from pathlib import Path

import numpy as np

from comparisons.ring_mistuning import percentile_with_ci
from workbench.runner import run_scene

SCENE = Path(__file__).resolve().parents[1] / "scenes" / "ring_mistuning.toml"
SMALL = ["ring.blades=4", "time.periods=20", "options.samples=3", "options.rpms=[10000.0]"]


def test_a_killed_study_resumes_from_its_streamed_samples(tmp_path):
    out = tmp_path / "m"
    run_scene(SCENE, out, SMALL, quick=True)
    first = json.loads((out / "results.json").read_text())["results"]
    lines = (out / "samples.jsonl").read_text().splitlines()
    assert len(lines) == 3 and all(len(json.loads(line)["deviations"]) == 4 for line in lines)
    # killed after one sample, in the middle of writing the second
    (out / "samples.jsonl").write_text(lines[0] + "\n" + lines[1][:25])
    run_scene(SCENE, out, SMALL, quick=True)
    again = json.loads((out / "results.json").read_text())["results"]
    assert again["amplification"] == first["amplification"]
    kept = json.loads(lines[0])["seed"]
    seeds = [json.loads(line)["seed"] for line in (out / "samples.jsonl").read_text().splitlines()]
    assert seeds[0] == kept and sorted(seeds[1:]) == sorted({1, 2, 3} - {kept})   # only the missing ones ran


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
    9 % above it do say mistuning amplifies (margin half the bootstrap interval)."""
    unsettled = _comparison(sample_change=0.2)
    assert abs(unsettled.unsettled_overshoot - 0.3) < 1e-12
    amplifies, _ = unsettled.verdicts()
    assert amplifies.answer == "not decided" and amplifies.margin == unsettled.unsettled_overshoot
    settled = _comparison(sample_change=1e-6)
    amplifies, _ = settled.verdicts()
    assert amplifies.answer is True and abs(amplifies.margin - 0.001) < 1e-12
