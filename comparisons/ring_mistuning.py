"""Mistuning by Monte Carlo: the worst blade of mistuned rings against the tuned ring (issues 26, 33; docs/ring.md).

Each sample is the ring of ``ring.blades`` blades with E_j = E (1 + d_j),
d_j drawn with ``std`` and its own seed, run in time from rest at each of
``rpms`` (shroud.analysis.ring: the whole ring, every interface's contact
solved together). The unloaded ring does not settle (quasi-periodic at
10000 r/min, chaotic at 9500: docs/ring.md), so a blade's amplitude is its
cycle amplitude (:func:`cycle_amplitude`): the mean over the run's last
third of its half range (max - min) / 2 in each excitation period, the
amplitude itself where the ring settles on a period-1 response, and a
steady statistic where it does not. The third before it (the first third
is the transient from rest) gives the same statistic again: its change is
the statistic's drift, part of every margin.

The tuned reference is measured the same way on the tuned ring's response,
not on a state it holds only by symmetry: the tuned ring from rest, then
kicked (KICK of its largest coordinate, random over the blades) so that it
leaves a travelling wave that is unstable (24 blades at 10000 r/min sit on
their 11.0 um wave from rest for ~500 periods, then rattle at 12.0 um),
then TUNED_WINDOWS windows of a third of the run each: its level at a
speed is the windows' mean of the worst blade's cycle amplitude, its error
their 95 % interval. The tuned ring from rest is kept beside it against
the travelling wave by the tuned sector's harmonic balance
(shroud.analysis.ring_hb.sector_at, H = WAVE_HARMONICS): settled when its
last period repeats the one before to SETTLED of its amplitude, on the
wave when also within ON_WAVE of it.

A sample's amplification is its worst blade over the speeds against the
tuned peak (the largest level over the speeds; the classic peak over the
range). Reported: the median, 95th and 99th percentiles with bootstrap
confidence intervals, against Whitehead's (1 + sqrt N) / 2 (a bound for
one linear mode family; friction and neighbouring families are outside its
assumptions, so a sample past it is reported, not refused), and the worst
sample's amplitudes blade by blade (localisation). Samples are spread over
MPI ranks or local processes (shroud.base.parallel.map_parallel), each
written to ``samples.jsonl`` as it finishes (memory flat in the number of
samples), and a run that was killed resumes from the samples the file holds.

Amplification against the scatter's size: the same Monte Carlo at each of
``scatters`` (``scatter_samples`` samples, seeds shared across scatters, so
sample s is one pattern of E scaled), for two cases: the scene's ring
("unloaded", ``rpms``) and the ring with the shrouds preloaded by
``preload`` N ("preloaded", ``preload_rpms``: 24 blades at 20 N settle at
12000-13000 r/min on a travelling wave the sector HB calls stable).
Whether the amplification rises with the scatter is read on each sample's
own pattern: the paired difference between the smallest scatter and the
largest, its median with a bootstrap interval. The stream's lines are keyed
by (case, scatter, seed), so a killed sweep resumes scatter by scatter.

The study is compute (:func:`compute`, which streams the samples into the run's folder ->
:class:`MistuningStudy`: the main :class:`MistuningComparison` and a :class:`ScatterSweep` a case) -> plot ->
report.
"""

from __future__ import annotations

import json
import math
import os
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from comparisons._study import study
from shroud.analysis.ring import build_ring, run_ring
from shroud.analysis.ring_hb import sector_at
from shroud.base.errors import InputError
from shroud.base.markdown import markdown_table
from shroud.base.parallel import map_parallel, on_rank_zero
from shroud.core import signals
from shroud.core.plotting import figure, save
from shroud.core.verdict import Verdict

RING = True          # solves the ring of ring.blades (workbench.runner refuses a ring elsewhere)
OPTIONS = {"samples": 100, "std": 0.013, "rpms": [9500.0, 10000.0, 10500.0], "model": "reduced",
           "first_seed": 1, "bootstrap": 2000,
           "scatters": [0.0025, 0.005, 0.01, 0.013, 0.02, 0.04, 0.08], "scatter_samples": 24,
           "preload": 20.0, "preload_rpms": [12000.0, 12500.0, 13000.0]}
MAIN_CASE = "unloaded"  # the scene's ring, whose Monte Carlo at ``std`` is the main one (``samples``)
SETTLED = 1e-3         # settled: the last period repeats the one before to this share of the amplitude
ON_WAVE = 5e-3         # on the wave: every blade within this share of the sector HB's wave (its 0.5 % test)
WAVE_HARMONICS = 20    # the beams' impacts need H = 20 for 0.1 % (docs/ring.md)
KICK = 1e-2            # the tuned ring's kick: this share of its largest coordinate, random over the blades
KICK_SEED = 0
TUNED_WINDOWS = 16     # the kicked tuned ring's windows (each a third of the run) its level is the mean of


def check(scene) -> None:
    o, N = scene.options, scene.params.ring.blades
    if N < 2:
        raise InputError("ring.blades", "mistuning is a ring's; allowed: ring.blades >= 2")
    if scene.params.time.periods < 3:
        raise InputError("time.periods", "the transient, the window and the window before it are a third each; "
                         "allowed: time.periods >= 3")
    if o["samples"] < 2 or not o["std"] > 0 or not o["rpms"] or min(o["rpms"]) <= 0:
        raise InputError("options.samples", "allowed: samples >= 2, std > 0 and speeds > 0 r/min")
    scatters = o["scatters"]
    if (len(scatters) < 2 or sorted(set(scatters)) != list(scatters) or min(scatters) <= 0
            or o["std"] not in scatters or o["scatter_samples"] < 2):
        raise InputError("options.scatters", "allowed: two or more increasing scatters > 0 holding options.std, "
                         "scatter_samples >= 2")
    if not o["preload"] > 0 or not o["preload_rpms"] or min(o["preload_rpms"]) <= 0:
        raise InputError("options.preload", "allowed: a preload > 0 N and speeds > 0 r/min")


def cycle_amplitude(x: np.ndarray, steps_per_period: int, periods: int) -> np.ndarray:
    """Each column's cycle amplitude over the last ``periods`` excitation periods (units of x): the mean over
    those periods of its half range (max - min) / 2 within each. A period-1 response's amplitude
    (signals.amplitude); a response that does not settle has a steady mean of its cycles where its maximum
    over a window keeps growing with the window (a chaotic ring's rare excursions)."""
    cycles = np.asarray(x)[len(x) - periods * steps_per_period:]
    cycles = cycles.reshape(periods, steps_per_period, *np.shape(x)[1:])
    return 0.5 * (cycles.max(axis=1) - cycles.min(axis=1)).mean(axis=0)


def window(params) -> int:
    """The periods of one window: a third of the run (the first third is the transient from rest)."""
    return params.time.periods // 3


def ring_in_time(params, model: str, rpms) -> tuple[list[list[float]], list[list[float]], list[float]]:
    """The ring in time from rest at each speed: each blade's v_L cycle amplitude (m) over the last third of
    the run and over the third before it, and the ring's change over its last period,
    max |v(t) - v(t - T)| over the blades against the largest amplitude (0 on a periodic state)."""
    late, early, change = [], [], []
    for rpm in rpms:
        p = params.updated({"speed.rpm": float(rpm)})
        tr = run_ring(build_ring(p, model), p)
        spp, w, v = p.time.steps_per_period, window(p), tr.tip[:, :, 0]
        late.append([float(a) for a in cycle_amplitude(v, spp, w)])
        early.append([float(a) for a in cycle_amplitude(v[:len(v) - w * spp], spp, w)])
        largest = max(signals.amplitude(v[:, j], spp) for j in range(v.shape[1]))
        change.append(float(np.abs(v[-spp:] - v[-2 * spp:-spp]).max() / largest))
    return late, early, change


def blade_amplitudes(params, model: str, rpms) -> list[list[float]]:
    """Each blade's v_L cycle amplitude (m) at each speed: the ring in time from rest."""
    return ring_in_time(params, model, rpms)[0]


def _sample(task) -> dict:
    """One mistuned ring (module level: it is sent to the workers); appended to the stream as it ends."""
    case, params, model, rpms, std, seed, stream = task
    p = params.updated({"ring.mistuning_std": std, "ring.seed": seed})
    late, early, change = ring_in_time(p, model, rpms)
    record = {"case": case, "std": std, "seed": seed, "deviations": list(p.ring.deviations),
              "amplitudes": late, "earlier": early, "change": change}
    with open(stream, "a") as fh:                    # one line a sample, appended whole
        fh.write(json.dumps(record) + "\n")
        fh.flush()
        os.fsync(fh.fileno())
    return record


def _key(record: dict) -> tuple[str, float, int]:
    return record["case"], record["std"], record["seed"]


def _done(stream: Path) -> dict[tuple[str, float, int], dict]:
    """The samples a stream holds by (case, scatter, seed) (a killed run's last line may be cut, and a line of
    an older study may lack the key or the earlier window: each is run again)."""
    found = {}
    if stream.exists():
        for line in stream.read_text().splitlines():
            try:
                record = json.loads(line)
                if "earlier" in record:
                    found[_key(record)] = record
            except (json.JSONDecodeError, KeyError):
                continue
    return found


def _opened(stream: Path) -> tuple[Path, dict[tuple[str, float, int], dict]]:
    """The stream and the samples it holds, a killed run's cut last line dropped from it (the whole ones stay)."""
    done = _done(stream)
    if stream.exists():
        stream.write_text("".join(json.dumps(r) + "\n" for r in done.values()))
    return stream.resolve(), done


def percentile_with_ci(values: np.ndarray, q: float, resamples: int, rng) -> tuple[float, float, float]:
    """The q-th percentile of ``values`` and its 95 % bootstrap interval (percentile method)."""
    boot = np.percentile(rng.choice(values, (resamples, values.size), replace=True), q, axis=1)
    return float(np.percentile(values, q)), float(np.percentile(boot, 2.5)), float(np.percentile(boot, 97.5))


def paired_rise(low: np.ndarray, high: np.ndarray, resamples: int, rng) -> tuple[float, float, float]:
    """The median of ``high - low`` sample by sample (each sample's own pattern of E at two scatters) and its
    95 % bootstrap interval: pairing takes the patterns' spread out of the difference."""
    return percentile_with_ci(np.asarray(high) - np.asarray(low), 50.0, resamples, rng)


PERCENTILES = (("median", 50.0), ("p95", 95.0), ("p99", 99.0))


def _answer(stable) -> str:
    return "not decided" if stable is None else ("yes" if stable else "no")


@dataclass(frozen=True)
class MistuningComparison:
    """One case at one scatter: the tuned ring (from rest and kicked) and every sample's cycle amplitudes, with
    the amplification's statistics."""

    N: int                        # blades
    model: str
    std: float                    # the scatter of E (relative)
    rpms: list[float]             # the speeds, r/min
    tuned: np.ndarray             # (speeds, N) the tuned ring from rest: blade amplitudes, last 10 periods (m)
    tuned_change: np.ndarray      # (speeds,) its change over the last period against its amplitude
    wave: np.ndarray              # (speeds,) the tuned travelling wave by the sector's HB (m)
    kicked: np.ndarray            # (speeds, TUNED_WINDOWS) the kicked tuned ring's worst cycle amplitude a window (m)
    records: list[dict]           # per sample: seed, deviations, amplitudes and earlier (speeds x N, m), change
    stats: dict[str, tuple[float, float, float]]   # median, p95, p99: (value, 95 % interval low, high)
    case: str = MAIN_CASE
    stable: tuple = ()            # (speeds,) the wave's stability by the sector HB (True, False, None: not decided)

    @property
    def settled(self) -> np.ndarray:
        """(speeds,) whether the tuned ring from rest settled (its last period repeats the one before)."""
        return self.tuned_change <= SETTLED

    @property
    def on_wave(self) -> np.ndarray:
        """(speeds,) settled with every blade within ON_WAVE of the travelling wave."""
        return self.settled & (np.abs(self.tuned / self.wave[:, None] - 1.0).max(axis=1) <= ON_WAVE)

    @property
    def tuned_level(self) -> np.ndarray:
        """(speeds,) the tuned ring's worst cycle amplitude, the kicked ring's windows' mean (m)."""
        return self.kicked.mean(axis=1)

    @property
    def tuned_error(self) -> np.ndarray:
        """(speeds,) the level's 95 % interval's half over the windows, against the level (0 on a settled ring)."""
        k = self.kicked.shape[1]
        return 1.96 * self.kicked.std(axis=1, ddof=1) / math.sqrt(k) / self.tuned_level

    @property
    def peak_speed(self) -> int:
        return int(np.argmax(self.tuned_level))

    @property
    def tuned_peak(self) -> float:
        """The tuned ring's largest level over the speeds (m)."""
        return float(self.tuned_level[self.peak_speed])

    def amplification(self, window: str = "amplitudes") -> np.ndarray:
        """Each sample's worst blade over the speeds against the tuned peak, over the run's last third
        (``amplitudes``) or the third before it (``earlier``)."""
        return np.array([np.max(r[window]) for r in self.records]) / self.tuned_peak

    @property
    def ratio(self) -> np.ndarray:
        return self.amplification()

    def drift(self, statistic) -> float:
        """How much ``statistic`` of the samples' amplifications changes from the earlier window to the last,
        plus the tuned peak's own error (relative, on a statistic near 1): the statistic's convergence."""
        value = statistic(self.ratio)
        return abs(value - statistic(self.amplification("earlier"))) + abs(value) * self.tuned_error[self.peak_speed]

    @property
    def per_speed(self) -> np.ndarray:
        """(speeds,) the samples' median worst blade at each speed against the tuned level there."""
        worst = np.array([np.max(r["amplitudes"], axis=1) for r in self.records])
        return np.median(worst, axis=0) / self.tuned_level

    @property
    def samples_settled(self) -> np.ndarray:
        """(speeds,) how many samples settled at each speed."""
        return np.sum([np.array(r["change"]) <= SETTLED for r in self.records], axis=0)

    @property
    def bound(self) -> float:
        """Whitehead's (1 + sqrt N) / 2."""
        return (1 + math.sqrt(self.N)) / 2

    @property
    def worst(self) -> tuple[int, int]:
        """(sample, speed index) of the largest amplification."""
        i = int(np.argmax(self.ratio))
        return i, int(np.argmax(np.max(np.array(self.records[i]["amplitudes"]), axis=1)))

    def verdicts(self) -> tuple[Verdict, Verdict]:
        """(mistuning amplifies, within Whitehead's bound)."""
        median = self.stats["median"]
        amplifies = Verdict.of(median[0], threshold=1.0, margin=0.5 * (median[2] - median[1]) + self.drift(np.median),
                               below=False, above=True,
                               reason="median worst-blade amplification (cycle amplitudes, the kicked tuned ring's "
                                      "peak) against 1, margin half its 95 % bootstrap interval plus its change from "
                                      "the window before and the tuned peak's error")
        within = Verdict.of(float(self.ratio.max()), threshold=self.bound, margin=self.drift(np.max), below=True,
                            above=False,
                            reason=f"largest sample against Whitehead's (1 + sqrt {self.N}) / 2 = {self.bound:.3f} "
                                   "(one linear family; friction is outside its assumptions), margin its change from "
                                   "the window before and the tuned peak's error")
        return amplifies, within

    def tuned_json(self) -> list[dict]:
        """The tuned ring per speed: from rest (blades, change, settled, wave, on the wave, the wave's stability)
        and kicked (its level and error)."""
        return [{"rpm": r, "blades_m": [float(self.tuned[i].min()), float(self.tuned[i].max())],
                 "change_a_period": float(self.tuned_change[i]), "settled": bool(self.settled[i]),
                 "wave_m": float(self.wave[i]), "on_wave": bool(self.on_wave[i]),
                 "wave_stable": _answer(self.stable[i]) if self.stable else "not asked",
                 "kicked_level_m": float(self.tuned_level[i]), "kicked_error": float(self.tuned_error[i])}
                for i, r in enumerate(self.rpms)]

    def statistics_json(self) -> dict:
        return {name: {"value": v, "ci95": [lo, hi]} for name, (v, lo, hi) in self.stats.items()}

    def to_json(self) -> dict:
        amplifies, within = self.verdicts()
        return {"conclusions": {"mistuning_amplifies": amplifies.to_json(), "within_whitehead": within.to_json()},
                "amplification": self.statistics_json(),
                "largest": float(self.ratio.max()), "whitehead": self.bound, "tuned_peak_m": self.tuned_peak,
                "tuned": self.tuned_json(), "samples_settled": [int(n) for n in self.samples_settled],
                "per_speed": [float(x) for x in self.per_speed], "samples": len(self.records)}


def rises_verdict(rise: tuple[float, float, float], error: float, low: float, high: float) -> Verdict:
    """Whether the amplification rises from scatter ``low`` to ``high``: the samples' paired median rise
    (value, 95 % interval) against 0, margin half the interval plus ``error`` (the rise's drift)."""
    value, lo, hi = rise
    return Verdict.of(value, threshold=0.0, margin=0.5 * (hi - lo) + error, below=False, above=True,
                      reason=f"median over the samples of the amplification at {100 * high:g} % less that at "
                             f"{100 * low:g} % (each sample's own pattern of E), margin half its 95 % bootstrap "
                             "interval plus its change from the window before and the tuned peak's error")


@dataclass(frozen=True)
class ScatterSweep:
    """One case's Monte Carlo at each scatter (ascending; the same seeds, so the same patterns, at each)."""

    case: str                                       # "unloaded" (the scene's ring) or "preloaded"
    preload: float                                  # contact.N0, N per side
    scatters: tuple[MistuningComparison, ...]
    bootstrap: int                                  # resamples for the paired rise's interval

    @property
    def stds(self) -> np.ndarray:
        return np.array([c.std for c in self.scatters])

    def at(self, std: float) -> MistuningComparison:
        return self.scatters[int(np.flatnonzero(self.stds == std)[0])]

    @property
    def rise(self) -> tuple[float, float, float]:
        """The paired median rise from the smallest scatter to the largest, with its 95 % bootstrap interval."""
        return paired_rise(self.scatters[0].ratio, self.scatters[-1].ratio, self.bootstrap, np.random.default_rng(0))

    @property
    def rise_drift(self) -> float:
        """The paired median rise's change from the earlier window, plus the rise times the tuned peak's error."""
        low, high = self.scatters[0], self.scatters[-1]
        earlier = np.median(high.amplification("earlier") - low.amplification("earlier"))
        return abs(self.rise[0] - earlier) + abs(self.rise[0]) * low.tuned_error[low.peak_speed]

    def verdicts(self, std: float) -> dict[str, Verdict]:
        """Whether the amplification rises with the scatter, whether every sample stays within Whitehead's
        bound, and (not for the main case, whose 100 samples say it) whether mistuning amplifies at ``std``."""
        low, high = self.scatters[0], self.scatters[-1]
        largest = max(self.scatters, key=lambda c: c.ratio.max())
        out = {f"{self.case}_rises_with_scatter": rises_verdict(self.rise, self.rise_drift, low.std, high.std),
               f"{self.case}_within_whitehead": Verdict.of(
                   float(largest.ratio.max()), threshold=low.bound, margin=largest.drift(np.max), below=True,
                   above=False,
                   reason=f"largest sample over the scatters against Whitehead's (1 + sqrt {low.N}) / 2 = "
                          f"{low.bound:.3f}, margin its change from the window before and the tuned peak's error")}
        if self.case != MAIN_CASE:
            out[f"{self.case}_mistuning_amplifies"] = self.at(std).verdicts()[0]
        return out

    def to_json(self) -> dict:
        return {"preload_N": self.preload, "rpms": self.scatters[0].rpms, "tuned": self.scatters[0].tuned_json(),
                "rise": {"from": self.scatters[0].std, "to": self.scatters[-1].std, "value": self.rise[0],
                         "ci95": list(self.rise[1:]), "drift": self.rise_drift},
                "scatters": [{"std": c.std, "samples": len(c.records), "amplification": c.statistics_json(),
                              "largest": float(c.ratio.max()), "median_drift": c.drift(np.median),
                              "samples_settled": [int(n) for n in c.samples_settled]} for c in self.scatters]}


@dataclass(frozen=True)
class MistuningStudy:
    """The main Monte Carlo (the scene's ring at ``std``) and each case's sweep over the scatter."""

    main: MistuningComparison
    sweeps: tuple[ScatterSweep, ...]

    def verdicts(self) -> dict[str, Verdict]:
        amplifies, within = self.main.verdicts()
        out = {"mistuning_amplifies": amplifies, "within_whitehead": within}
        for sweep in self.sweeps:
            out.update(sweep.verdicts(self.main.std))
        return out

    def conclusions(self) -> dict:
        return {name: v.to_json() for name, v in self.verdicts().items()}

    def to_json(self) -> dict:
        return {**self.main.to_json(), "conclusions": self.conclusions(),
                "scatter": {sweep.case: sweep.to_json() for sweep in self.sweeps}}


def kicked_windows(params, model: str, q0, v0, a0) -> np.ndarray:
    """The tuned ring kicked from the state (q0, v0, a0) at a whole period (the load's phase 0): after a third
    of the run of transient, the worst blade's cycle amplitude in each of TUNED_WINDOWS windows of a third of
    the run (m)."""
    w = window(params)
    kick = KICK * np.abs(q0).max() * np.random.default_rng(KICK_SEED).normal(size=np.shape(q0))
    p = params.updated({"time.periods": w * (1 + TUNED_WINDOWS)})
    tr = run_ring(build_ring(p, model), p, q0=q0 + kick, v0=v0, a0=a0)
    spp, v = p.time.steps_per_period, tr.tip[:, :, 0]
    return np.array([cycle_amplitude(v[:len(v) - k * w * spp], spp, w).max() for k in range(TUNED_WINDOWS)])


def tuned_in_time(params, model: str) -> tuple[list[float], float, np.ndarray]:
    """The tuned ring from rest at params' speed (blade amplitudes over the last 10 periods, m; its change a
    period), then kicked from where that run ends (:func:`kicked_windows`)."""
    tr = run_ring(build_ring(params, model), params)
    spp, v = params.time.steps_per_period, tr.tip[:, :, 0]
    amplitudes = [signals.amplitude(v[:, j], spp) for j in range(v.shape[1])]
    change = float(np.abs(v[-spp:] - v[-2 * spp:-spp]).max() / max(amplitudes))
    return amplitudes, change, kicked_windows(params, model, tr.q, tr.v, tr.a)


def tuned_ring(params, model: str, rpms) -> tuple[np.ndarray, np.ndarray, np.ndarray, tuple, np.ndarray]:
    """At each speed: the tuned ring from rest and kicked (:func:`tuned_in_time`), and its travelling wave by
    the sector's HB (amplitude, stability against every nodal diameter)."""
    runs = [tuned_in_time(params.updated({"speed.rpm": float(rpm)}), model) for rpm in rpms]
    waves = [sector_at(params.updated({"speed.rpm": float(rpm)}), model, float(rpm), harmonics=WAVE_HARMONICS)
             for rpm in rpms]
    return (np.array([r[0] for r in runs]), np.array([r[1] for r in runs]),
            np.array([float(w["amplitude_v_L"]) for w in waves]), tuple(w["stable"] for w in waves),
            np.array([r[2] for r in runs]))


def compute(scene, out: Path) -> MistuningStudy:
    """The tuned rings (from rest and kicked), then the samples (those ``out/samples.jsonl`` holds from a killed run are kept, the
    rest spread over ranks or processes and streamed there), and the percentiles' bootstrap intervals."""
    o = scene.options
    model, std = o["model"], float(o["std"])
    base = scene.params.updated({"ring.mistuning": (), "ring.mistuning_std": 0.0})
    cases = {MAIN_CASE: (base, [float(r) for r in o["rpms"]]),
             "preloaded": (base.updated({"contact.N0": float(o["preload"])}), [float(r) for r in o["preload_rpms"]])}
    tuned = {case: tuned_ring(params, model, rpms) for case, (params, rpms) in cases.items()}
    main_seeds = [o["first_seed"] + s for s in range(o["samples"])]
    sweep_seeds = main_seeds[:o["scatter_samples"]] if o["scatter_samples"] <= o["samples"] else \
        [o["first_seed"] + s for s in range(o["scatter_samples"])]
    scatters = [float(s) for s in o["scatters"]]
    wanted = list(dict.fromkeys([(MAIN_CASE, std, s) for s in main_seeds] +
                                [(case, x, s) for case in cases for x in scatters for s in sweep_seeds]))
    # Rank 0 reads the stream and every rank gets its path and samples: under mpirun the other ranks run in
    # scratch folders, and a stream of their own would leave their samples out of a resumed run.
    stream, done = on_rank_zero(lambda: _opened(out / "samples.jsonl"))
    todo = [(case, cases[case][0], model, cases[case][1], x, s, stream) for case, x, s in wanted
            if (case, x, s) not in done]
    for record in map_parallel(_sample, todo):
        done[_key(record)] = record
    rng = np.random.default_rng(0)

    def comparison(case: str, x: float, seeds: list[int]) -> MistuningComparison:
        amplitudes, change, wave, stable, kicked = tuned[case]
        result = MistuningComparison(N=base.ring.blades, model=model, std=x, rpms=cases[case][1], tuned=amplitudes,
                                     tuned_change=change, wave=wave, kicked=kicked,
                                     records=[done[case, x, s] for s in seeds], stats={}, case=case, stable=stable)
        return replace(result, stats={name: percentile_with_ci(result.ratio, q, o["bootstrap"], rng)
                                      for name, q in PERCENTILES})

    main = comparison(MAIN_CASE, std, main_seeds)
    sweeps = []
    for case, (params, _) in cases.items():
        sweeps.append(ScatterSweep(case=case, preload=float(params.contact.N0), bootstrap=o["bootstrap"],
                                   scatters=tuple(comparison(case, x, sweep_seeds) for x in scatters)))
    return MistuningStudy(main=main, sweeps=tuple(sweeps))


def plot(result: MistuningStudy, scene, out: Path) -> list[str]:
    """(a) the samples' amplification against Whitehead's bound, (b) the worst sample blade by blade, (c) the
    same for each other case at its largest scatter; then the amplification against
    the scatter, one panel a case."""
    main = result.main
    N, ratio, bound = main.N, main.ratio, main.bound
    others = [(s.case, s.scatters[-1]) for s in result.sweeps if s.case != MAIN_CASE]
    fig, axes = figure(1, 2 + len(others), width=4.5 * (2 + len(others)), height=3.6)
    ax = axes[0][0]
    ax.plot(np.sort(ratio), np.arange(1, ratio.size + 1) / ratio.size, "o-", ms=2)
    ax.axvline(bound, color="k", ls="--", lw=0.8, label=f"Whitehead {bound:.2f}")
    ax.axvline(1.0, color="gray", lw=0.8)
    ax.set_xlabel("worst blade / tuned peak (cycle amplitudes)")
    ax.set_ylabel("share of samples")
    ax.set_title(f"(a) {MAIN_CASE}: {ratio.size} samples, std {100 * main.std:g} % of E")
    ax.legend()
    for ax, (case, c), letter in zip(axes[0][1:], [(MAIN_CASE, main)] + others, "bcd"):
        i, at = c.worst
        worst = c.records[i]
        ax.plot(range(N), 1e6 * np.array(worst["amplitudes"][at]), "o-", label=f"worst sample (seed {worst['seed']})")
        ax.plot(range(N), 1e6 * c.tuned[at], "s--", label="tuned from rest")
        ax.axhline(1e6 * c.tuned_level[at], color="k", lw=0.8, label="tuned kicked, worst blade")
        ax.axhline(1e6 * c.wave[at], color="gray", lw=0.8, label="tuned wave (sector HB)")
        ax.set_xlabel("blade")
        ax.set_ylabel(f"amplitude of v_L (um) at {c.rpms[at]:g} r/min")
        ax.set_title(f"({letter}) localisation, {case}, std {100 * c.std:g} %")
        ax.legend(fontsize=8)
    save(fig, out / "ring_mistuning.png")

    fig, axes = figure(1, len(result.sweeps), width=4.6 * len(result.sweeps), height=3.8)
    for ax, sweep in zip(axes[0], result.sweeps):
        x, lowest = 100 * sweep.stds, 0.0
        for (name, _), marker in zip(PERCENTILES, "os^"):
            value, lo, hi = (np.array([c.stats[name][k] for c in sweep.scatters]) - 1.0 for k in range(3))
            ax.errorbar(x, value, yerr=[value - lo, hi - value], marker=marker, ms=4, capsize=3, label=name)
            lowest = min(lowest, lo.min())
        ax.axhline(bound - 1.0, color="k", ls="--", lw=0.8, label=f"Whitehead {bound:.2f}")
        ax.set_xscale("log")
        ax.set_xticks(x, [f"{v:g}" for v in x], minor=False)    # the scatters measured, in plain numbers
        ax.set_xticks([], minor=True)
        ax.set_yscale("symlog", linthresh=1e-3)      # linear through 0 (a sample below its tuned peak), log above
        ax.set_ylim(1.2 * lowest, 1.5 * (bound - 1.0))
        ax.set_xlabel("scatter of E (std, %)")
        ax.set_ylabel("worst blade / tuned peak - 1")
        first = sweep.scatters[0]
        settled = sum(int(c.samples_settled.min()) for c in sweep.scatters)
        said = f"{settled} of {sum(len(c.records) for c in sweep.scatters)} samples settled at every speed"
        ax.set_title(f"{sweep.case}: N0 {sweep.preload:g} N, {', '.join(f'{r:g}' for r in first.rpms)} r/min\n"
                     f"{len(first.records)} samples a scatter, {said}", fontsize=9)
        ax.legend(fontsize=8)
    save(fig, out / "ring_mistuning_scatter.png")
    return ["ring_mistuning.png", "ring_mistuning_scatter.png"]


def _tuned_rows(c: MistuningComparison, samples: bool) -> list[tuple]:
    return [(f"{r:g}", f"{1e6 * c.tuned[i].min():.3f} .. {1e6 * c.tuned[i].max():.3f}",
             f"{c.tuned_change[i]:.1e}", "yes" if c.settled[i] else "no", f"{1e6 * c.wave[i]:.3f}",
             "yes" if c.on_wave[i] else "no", _answer(c.stable[i]) if c.stable else "not asked",
             f"{1e6 * c.tuned_level[i]:.3f} +- {100 * c.tuned_error[i]:.2g} %")
            + ((f"{c.samples_settled[i]} / {len(c.records)}", f"{c.per_speed[i]:.4f}") if samples else ())
            for i, r in enumerate(c.rpms)]


TUNED_HEADER = ["r/min", "from rest: blades (um)", "change a period", "settled", "wave (um)", "on the wave",
                "wave stable (HB)", "kicked: worst cycle amplitude (um, 95 %)"]


def report(result: MistuningStudy, scene, files: list[str]) -> str:
    main = result.main
    verdicts = result.verdicts()
    amplifies, within = verdicts["mistuning_amplifies"], verdicts["within_whitehead"]
    ratio = main.ratio
    rows = [(name, f"{v:.4f}", f"{lo:.4f} .. {hi:.4f}") for name, (v, lo, hi) in main.stats.items()]
    w = window(scene.params)
    lines = [f"# {scene.title}\n",
             f"## Case `{MAIN_CASE}` at {100 * main.std:g} %\n",
             f"{main.N} blades, {main.model}, E scattered by {100 * main.std:g} %, {ratio.size} samples, "
             f"speeds {', '.join(f'{r:g}' for r in main.rpms)} r/min, contact.N0 "
             f"{result.sweeps[0].preload:g} N.\n",
             f"A blade's amplitude is its cycle amplitude: the mean over the run's last {w} periods of its half range "
             f"in each period (its amplitude where it settles on a period-1 response); the {w} periods before give "
             "it again, and the change is the statistic's drift. The tuned ring from rest, against its travelling "
             f"wave by the sector's harmonic balance (H = {WAVE_HARMONICS}), and kicked ({KICK:g} of its largest "
             f"coordinate at the end of the run from rest) so that it leaves a wave it holds only by symmetry: "
             f"its worst blade's cycle amplitude, the mean of {TUNED_WINDOWS} windows of {w} periods after {w} "
             "periods of transient, with its 95 % interval:\n",
             markdown_table(TUNED_HEADER + ["samples settled", "samples' median worst / tuned there"],
                            _tuned_rows(main, samples=True)), "",
             f"Tuned peak {1e6 * main.tuned_peak:.3f} um (kicked, at {main.rpms[main.peak_speed]:g} r/min); a "
             "sample's amplification is its worst blade over the speeds against it.\n",
             markdown_table(["amplification", "value", "95 % interval (bootstrap)"], rows), "",
             f"`within_whitehead`: {within.sentence()}. `mistuning_amplifies`: {amplifies.sentence()}.\n",
             "## Amplification against the scatter's size\n",
             "Each case's Monte Carlo at each scatter, the same seeds (so the same pattern of E, scaled) at each; "
             "amplification as above (worst blade over the case's speeds against its kicked tuned peak).\n"]
    for sweep in result.sweeps:
        first = sweep.scatters[0]
        table = [(f"{100 * c.std:g}", str(len(c.records)))
                 + tuple(f"{c.stats[n][0]:.4f} ({c.stats[n][1]:.4f} .. {c.stats[n][2]:.4f})" for n, _ in PERCENTILES)
                 + (f"{c.ratio.max():.4f}", f"{c.drift(np.median):.2g}",
                    f"{int(c.samples_settled.min())} / {len(c.records)}") for c in sweep.scatters]
        lines += [f"### Case `{sweep.case}`: contact.N0 {sweep.preload:g} N, "
                  f"{', '.join(f'{r:g}' for r in first.rpms)} r/min\n",
                  markdown_table(TUNED_HEADER, _tuned_rows(first, samples=False)), "",
                  markdown_table(["scatter (%)", "samples", "median (95 %)", "p95 (95 %)", "p99 (95 %)", "largest",
                                  "median's drift", "samples settled (fewest over the speeds)"], table), "",
                  f"Against Whitehead's {first.bound:.3f}. Verdicts of this case:\n"]
        lines += [f"- `{name}`: {v.sentence()}" for name, v in verdicts.items() if name.startswith(sweep.case + "_")]
        lines.append("")
    lines += [f"![{f}]({f})" for f in files]
    return "\n".join(lines) + "\n"


run = study(compute, plot, report, writes=True)
