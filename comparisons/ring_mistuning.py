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

The study is compute (:func:`compute`, which streams the samples into the run's folder ->
:class:`MistuningComparison`) -> plot -> report.
"""

from __future__ import annotations

import json
import math
import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from comparisons._study import study
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


@dataclass(frozen=True)
class MistuningComparison:
    """The tuned ring's amplitudes and every sample's, with the amplification's statistics."""

    N: int                        # blades
    model: str
    std: float                    # the scatter of E (relative)
    rpms: list[float]             # the speeds, r/min
    tuned: np.ndarray             # (speeds, N) the tuned ring's blade amplitudes (m)
    records: list[dict]           # per sample: seed, deviations, amplitudes (speeds x N, m)
    stats: dict[str, tuple[float, float, float]]   # median, p95, p99: (value, 95 % interval low, high)

    @property
    def tuned_peak(self) -> float:
        return float(self.tuned.max())

    @property
    def ratio(self) -> np.ndarray:
        """Each sample's worst blade over the speeds against the tuned ring's largest."""
        return np.array([np.max(r["amplitudes"]) for r in self.records]) / self.tuned_peak

    @property
    def bound(self) -> float:
        """Whitehead's (1 + sqrt N) / 2."""
        return (1 + math.sqrt(self.N)) / 2

    @property
    def worst(self) -> tuple[int, int]:
        """(sample, speed index) of the largest amplification."""
        i = int(np.argmax(self.ratio))
        return i, int(np.argmax(np.max(self.records[i]["amplitudes"], axis=1)))

    def verdicts(self) -> tuple[Verdict, Verdict]:
        """(mistuning amplifies, within Whitehead's bound)."""
        median = self.stats["median"]
        amplifies = Verdict.of(median[0], threshold=1.0, margin=0.5 * (median[2] - median[1]), below=False,
                               above=True, reason="median worst-blade amplification against 1, margin half its "
                                                  "95 % bootstrap interval")
        within = Verdict.of(float(self.ratio.max()), threshold=self.bound, margin=0.0, below=True, above=False,
                            reason=f"largest sample against Whitehead's (1 + sqrt {self.N}) / 2 = {self.bound:.3f} "
                                   "(one linear family; friction is outside its assumptions)")
        return amplifies, within

    def conclusions(self) -> dict:
        amplifies, within = self.verdicts()
        return {"mistuning_amplifies": amplifies.answer, "within_whitehead": within.answer}

    def to_json(self) -> dict:
        return {"conclusions": self.conclusions(),
                "amplification": {name: {"value": v, "ci95": [lo, hi]} for name, (v, lo, hi) in self.stats.items()},
                "largest": float(self.ratio.max()), "whitehead": self.bound, "tuned_peak_m": self.tuned_peak,
                "samples": len(self.records)}


def compute(scene, out: Path) -> MistuningComparison:
    """The tuned ring, then the samples (those ``out/samples.jsonl`` holds from a killed run are kept, the
    rest spread over ranks or processes and streamed there), and the percentiles' bootstrap intervals."""
    params, o = scene.params.updated({"ring.mistuning": (), "ring.mistuning_std": 0.0}), scene.options
    model, rpms = o["model"], [float(r) for r in o["rpms"]]
    tuned = np.array(blade_amplitudes(params, model, rpms))
    stream = out / "samples.jsonl"
    seeds = [o["first_seed"] + s for s in range(o["samples"])]
    done = _done(stream)
    if stream.exists():                              # a killed run's cut last line goes; the whole ones stay
        stream.write_text("".join(json.dumps(r) + "\n" for r in done.values()))
    todo = [(params, model, rpms, o["std"], s, stream) for s in seeds if s not in done]
    for record in map_parallel(_sample, todo):
        done[record["seed"]] = record
    records = [done[s] for s in seeds]
    ratio = np.array([np.max(r["amplitudes"]) for r in records]) / float(tuned.max())
    rng = np.random.default_rng(0)
    stats = {name: percentile_with_ci(ratio, q, o["bootstrap"], rng) for name, q in
             (("median", 50.0), ("p95", 95.0), ("p99", 99.0))}
    return MistuningComparison(N=params.ring.blades, model=model, std=o["std"], rpms=rpms, tuned=tuned,
                               records=records, stats=stats)


def plot(result: MistuningComparison, scene, out: Path) -> list[str]:
    """(a) the samples' amplification against Whitehead's bound, (b) the worst sample blade by blade."""
    N, ratio, bound, rpms = result.N, result.ratio, result.bound, result.rpms
    i, at = result.worst
    worst = result.records[i]
    fig, axes = figure(1, 2, width=9.0, height=3.4)
    ax = axes[0][0]
    ax.plot(np.sort(ratio), np.arange(1, ratio.size + 1) / ratio.size, "o-", ms=2)
    ax.axvline(bound, color="k", ls="--", lw=0.8, label=f"Whitehead {bound:.2f}")
    ax.axvline(1.0, color="gray", lw=0.8)
    ax.set_xlabel("worst blade / tuned peak")
    ax.set_ylabel("share of samples")
    ax.set_title(f"(a) {ratio.size} samples, std {100 * result.std:g} % of E")
    ax.legend()
    ax = axes[0][1]
    ax.plot(range(N), 1e6 * np.array(worst["amplitudes"][at]), "o-", label=f"worst sample (seed {worst['seed']})")
    ax.plot(range(N), 1e6 * result.tuned[at], "s--", label="tuned")
    ax.set_xlabel("blade")
    ax.set_ylabel(f"amplitude of v_L (um) at {rpms[at]:g} r/min")
    ax.set_title("(b) localisation")
    ax.legend()
    save(fig, out / "ring_mistuning.png")
    return ["ring_mistuning.png"]


def report(result: MistuningComparison, scene, files: list[str]) -> str:
    amplifies, within = result.verdicts()
    ratio = result.ratio
    rows = [(name, f"{v:.4f}", f"{lo:.4f} .. {hi:.4f}") for name, (v, lo, hi) in result.stats.items()]
    lines = [f"# {scene.title}\n",
             f"{result.N} blades, {result.model}, E scattered by {100 * result.std:g} %, {ratio.size} samples, "
             f"speeds {', '.join(f'{r:g}' for r in result.rpms)} r/min; tuned peak "
             f"{1e6 * result.tuned_peak:.3f} um.\n",
             markdown_table(["amplification", "value", "95 % interval (bootstrap)"], rows), "",
             f"Largest {ratio.max():.4f} against Whitehead's {result.bound:.3f}: {within.answer}. Mistuning "
             f"amplifies (median against 1): {amplifies.answer}.\n"]
    lines += [f"![{f}]({f})" for f in files]
    return "\n".join(lines) + "\n"


run = study(compute, plot, report, writes=True)
