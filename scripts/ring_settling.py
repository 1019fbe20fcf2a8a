"""Why the unloaded 24-blade ring of ring_mistuning does not settle, and which statistic converges on it
(issue 33; docs/ring.md, "A ring that does not settle").

For each case (the tuned ring and the sample of seed 1 at 1.3 %, 9500 / 10000 / 10500 r/min, reduced beams,
no preload, from rest):

- separation: after 300 periods the run is continued twice, once from its end state and once from it moved by
  1e-8 of its largest coordinate (random over the blades); the two runs' largest difference a period
  against the amplitude, and its growth a period over the first 40 (a chaotic ring: > 1, up to saturation;
  a quasi-periodic or periodic one: none);
- windows: over ``--periods`` periods from rest, in windows of 100 periods, the worst blade's envelope
  (its largest half range in any one period) and its cycle amplitude
  (comparisons.ring_mistuning.cycle_amplitude: the mean of its half ranges), so that their convergence with
  the window can be compared;
- lines: the share of the largest spectral line in the worst blade's amplitude period by period, after the
  first 100 periods (a torus: a few lines hold most of it; chaos: broadband).

    OMP_NUM_THREADS=1 python scripts/ring_settling.py --periods 600
"""

from __future__ import annotations

import argparse

import numpy as np

from comparisons.ring_mistuning import cycle_amplitude
from shroud.analysis.ring import build_ring, run_ring
from shroud.params import Parameters

WINDOW = 100     # periods


def case(std: float, rpm: float, periods: int) -> str:
    p = Parameters().with_overrides(["ring.blades=24", f"time.periods={periods}", f"speed.rpm={rpm}"])
    if std:
        p = p.updated({"ring.mistuning_std": std, "ring.seed": 1})
    ring, spp = build_ring(p, "reduced"), p.time.steps_per_period
    v = run_ring(ring, p).tip[:, :, 0]
    cycles = v[1:].reshape(periods, spp, -1)
    worst_a_period = (0.5 * (cycles.max(axis=1) - cycles.min(axis=1))).max(axis=1)
    windows = range(WINDOW, periods - WINDOW + 1, WINDOW)
    envelope = [worst_a_period[k:k + WINDOW].max() for k in windows]
    cycle = [cycle_amplitude(v[:1 + (k + WINDOW) * spp], spp, WINDOW).max() for k in windows]
    x = worst_a_period[WINDOW:] - worst_a_period[WINDOW:].mean()
    spectrum = np.abs(np.fft.rfft(x))[1:]
    line = int(np.argmax(spectrum))

    first = p.updated({"time.periods": 300})
    tr = run_ring(ring, first)
    more = p.updated({"time.periods": 200})
    a = run_ring(ring, more, q0=tr.q, v0=tr.v, a0=tr.a).tip[:, :, 0]
    kick = 1e-8 * np.abs(tr.q).max() * np.random.default_rng(3).normal(size=tr.q.shape)
    b = run_ring(ring, more, q0=tr.q + kick, v0=tr.v, a0=tr.a).tip[:, :, 0]
    apart = np.array([np.abs(a[k * spp:(k + 1) * spp] - b[k * spp:(k + 1) * spp]).max() for k in range(200)])
    apart /= np.abs(a).max()
    return "\n".join([
        f"{'tuned' if not std else f'{100 * std:g} % seed 1'} at {rpm:g} r/min:",
        "  separation a period / amplitude at periods 1, 10, 40, 80, 199: "
        + ", ".join(f"{apart[k]:.1e}" for k in (1, 10, 40, 80, 199))
        + f"; growth a period over 1-40: {(apart[40] / apart[1]) ** (1 / 39):.3f}",
        "  windows of 100 periods from " + ", ".join(str(k) for k in windows) + ":",
        "    envelope (um):        " + " ".join(f"{1e6 * e:.3f}" for e in envelope),
        "    cycle amplitude (um): " + " ".join(f"{1e6 * c:.3f}" for c in cycle),
        f"  largest spectral line: {(line + 1) / x.size:.4f} cycles a period, "
        f"{spectrum[line] / spectrum.sum():.3f} of the sum of the lines"])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--periods", type=int, default=600)
    args = parser.parse_args()
    for std in (0.0, 0.013):
        for rpm in (9500.0, 10000.0, 10500.0):
            print(case(std, rpm, args.periods), flush=True)


if __name__ == "__main__":
    main()
