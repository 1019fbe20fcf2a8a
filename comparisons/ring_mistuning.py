"""Mistuning by Monte Carlo: the worst blade of mistuned rings against the tuned ring (issue 26; docs/ring.md).

Each sample is the ring of ``ring.blades`` blades with E_j = E (1 + d_j),
d_j drawn with ``std`` and its own seed, run in time from rest at each of
``rpms`` (shroud.analysis.ring: the whole ring, every interface's contact
solved together); its amplification is the largest blade amplitude over
those speeds against the tuned ring's largest. Reported: the median, 95th
and 99th percentiles with bootstrap confidence intervals, against
Whitehead's (1 + sqrt N) / 2 (a bound for one linear mode family; friction
and neighbouring families are outside its assumptions, so a sample past
it is reported, not refused), and the worst sample's amplitudes blade by
blade (localisation). Samples are spread over MPI ranks or local processes
(shroud.base.parallel.map_parallel), each written to ``samples.jsonl`` as
it finishes (memory flat in the number of samples), and a run that was
killed resumes from the samples the file holds.
"""

from __future__ import annotations

import json
import math
import os
from pathlib import Path

import numpy as np

from shroud.analysis.ring import build_ring, run_ring
from shroud.base.errors import InputError
from shroud.base.markdown import markdown_table
from shroud.base.parallel import map_parallel
from shroud.core import signals
from shroud.core.plotting import figure, save
from shroud.core.verdict import Verdict

OPTIONS = {"samples": 100, "std": 0.013, "rpms": [9500.0, 10000.0, 10500.0], "model": "reduced",
           "first_seed": 1, "bootstrap": 2000}


def check(scene) -> None:
    o, N = scene.options, scene.params.ring.blades
    if N < 2:
        raise InputError("ring.blades", "mistuning is a ring's; allowed: ring.blades >= 2")
    if o["samples"] < 2 or not o["std"] > 0 or not o["rpms"] or min(o["rpms"]) <= 0:
        raise InputError("options.samples", "allowed: samples >= 2, std > 0 and speeds > 0 r/min")


def blade_amplitudes(params, model: str, rpms) -> list[list[float]]:
    """Each blade's v_L amplitude (m) at each speed: the ring in time from rest."""
    out = []
    for rpm in rpms:
        p = params.updated({"speed.rpm": float(rpm)})
        tr = run_ring(build_ring(p, model), p)
        spp = p.time.steps_per_period
        out.append([signals.amplitude(tr.tip[:, j, 0], spp) for j in range(tr.tip.shape[1])])
    return out


def _sample(task) -> dict:
    """One mistuned ring (module level: it is sent to the workers); appended to the stream as it ends."""
    params, model, rpms, std, seed, stream = task
    p = params.updated({"ring.mistuning_std": std, "ring.seed": seed})
    record = {"seed": seed, "deviations": list(p.ring.deviations), "amplitudes": blade_amplitudes(p, model, rpms)}
    with open(stream, "a") as fh:                    # one line a sample, appended whole
        fh.write(json.dumps(record) + "\n")
        fh.flush()
        os.fsync(fh.fileno())
    return record


def _done(stream: Path) -> dict[int, dict]:
    """The samples a stream holds (a killed run's last line may be cut: it is run again)."""
    found = {}
    if stream.exists():
        for line in stream.read_text().splitlines():
            try:
                record = json.loads(line)
            except json.JSONDecodeError:
                continue
            found[record["seed"]] = record
    return found


def percentile_with_ci(values: np.ndarray, q: float, resamples: int, rng) -> tuple[float, float, float]:
    """The q-th percentile of ``values`` and its 95 % bootstrap interval (percentile method)."""
    boot = np.percentile(rng.choice(values, (resamples, values.size), replace=True), q, axis=1)
    return float(np.percentile(values, q)), float(np.percentile(boot, 2.5)), float(np.percentile(boot, 97.5))


def run(scene, out: Path) -> dict:
    params, o = scene.params.updated({"ring.mistuning": (), "ring.mistuning_std": 0.0}), scene.options
    N, model, rpms = params.ring.blades, o["model"], [float(r) for r in o["rpms"]]
    tuned = np.array(blade_amplitudes(params, model, rpms))
    tuned_peak = float(tuned.max())
    stream = out / "samples.jsonl"
    seeds = [o["first_seed"] + s for s in range(o["samples"])]
    done = _done(stream)
    if stream.exists():                              # a killed run's cut last line goes; the whole ones stay
        stream.write_text("".join(json.dumps(r) + "\n" for r in done.values()))
    todo = [(params, model, rpms, o["std"], s, stream) for s in seeds if s not in done]
    for record in map_parallel(_sample, todo):
        done[record["seed"]] = record
    records = [done[s] for s in seeds]
    worst = np.array([np.max(r["amplitudes"]) for r in records])
    ratio = worst / tuned_peak
    rng = np.random.default_rng(0)
    stats = {name: percentile_with_ci(ratio, q, o["bootstrap"], rng) for name, q in
             (("median", 50.0), ("p95", 95.0), ("p99", 99.0))}
    bound = (1 + math.sqrt(N)) / 2
    spread = 0.5 * (stats["median"][2] - stats["median"][1])
    amplifies = Verdict.of(stats["median"][0], threshold=1.0, margin=spread, below=False, above=True,
                           reason="median worst-blade amplification against 1, margin half its 95 % bootstrap "
                                  "interval")
    within = Verdict.of(float(ratio.max()), threshold=bound, margin=0.0, below=True, above=False,
                        reason=f"largest sample against Whitehead's (1 + sqrt {N}) / 2 = {bound:.3f} (one linear "
                               "family; friction is outside its assumptions)")
    i = int(np.argmax(ratio))
    at = int(np.argmax(np.max(records[i]["amplitudes"], axis=1)))

    fig, axes = figure(1, 2, width=9.0, height=3.4)
    ax = axes[0][0]
    ax.plot(np.sort(ratio), np.arange(1, ratio.size + 1) / ratio.size, "o-", ms=2)
    ax.axvline(bound, color="k", ls="--", lw=0.8, label=f"Whitehead {bound:.2f}")
    ax.axvline(1.0, color="gray", lw=0.8)
    ax.set_xlabel("worst blade / tuned peak")
    ax.set_ylabel("share of samples")
    ax.set_title(f"(a) {ratio.size} samples, std {100 * o['std']:g} % of E")
    ax.legend()
    ax = axes[0][1]
    ax.plot(range(N), 1e6 * np.array(records[i]["amplitudes"][at]), "o-", label=f"worst sample (seed {records[i]['seed']})")
    ax.plot(range(N), 1e6 * tuned[at], "s--", label="tuned")
    ax.set_xlabel("blade")
    ax.set_ylabel(f"amplitude of v_L (um) at {rpms[at]:g} r/min")
    ax.set_title("(b) localisation")
    ax.legend()
    save(fig, out / "ring_mistuning.png")

    rows = [(name, f"{v:.4f}", f"{lo:.4f} .. {hi:.4f}") for name, (v, lo, hi) in stats.items()]
    lines = [f"# {scene.title}\n",
             f"{N} blades, {model}, E scattered by {100 * o['std']:g} %, {ratio.size} samples, speeds "
             f"{', '.join(f'{r:g}' for r in rpms)} r/min; tuned peak {1e6 * tuned_peak:.3f} um.\n",
             markdown_table(["amplification", "value", "95 % interval (bootstrap)"], rows), "",
             f"Largest {ratio.max():.4f} against Whitehead's {bound:.3f}: {within.answer}. Mistuning amplifies "
             f"(median against 1): {amplifies.answer}.\n", "![ring_mistuning.png](ring_mistuning.png)"]
    (out / "report.md").write_text("\n".join(lines) + "\n")
    return {"conclusions": {"mistuning_amplifies": amplifies.answer, "within_whitehead": within.answer},
            "amplification": {name: {"value": v, "ci95": [lo, hi]} for name, (v, lo, hi) in stats.items()},
            "largest": float(ratio.max()), "whitehead": bound, "tuned_peak_m": tuned_peak,
            "samples": len(records)}
