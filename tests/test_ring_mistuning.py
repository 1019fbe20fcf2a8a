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
