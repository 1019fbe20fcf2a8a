"""Three-way comparisons with a dead band and a margin: how the studies turn two numbers into a word.

A conclusion drawn from two measured numbers (errors, run times) must not
flip when one of them moves by its own noise, so each comparison names a
factor inside which the two count as the same (the band) and the numbers'
own uncertainty around its edges (the margin), inside which the answer is
"not decided" (shroud.core.verdict.RatioVerdict).

Run times: TIMING_NOISE is measured, not chosen. Three identical
``shroud run scenes/fig8.toml --quick`` runs (OMP_NUM_THREADS=1, the 2-core
machine shared with other jobs) gave the totals (build + run, warm) reduced
5.6 / 3.6 / 4.1 ms, full 7.2 / 6.9 / 9.9 ms, fe-reduced 244 / 252 ms (and
3187 ms in the first run, whose reduction basis was built rather than read:
cold and warm must never be mixed, comparisons.error_vs_time); the ratio
reduced/full moved between 0.41 and 0.78, a factor 1.9 between identical
runs. Two identical ``table1 --quick`` runs moved millisecond solves by 25 %.
A cost verdict is therefore not decided within a factor 2 of its band's edge.
"""

from __future__ import annotations

from shroud.core.verdict import TIME_RATIO, RatioVerdict

CHEAPER = 3.0        # one run is cheaper than another when its time is below 1/CHEAPER of the other's
TIMING_NOISE = 2.0   # run times of identical runs differ by up to this factor (measured: module docstring)
COST_REASON = (f"run times of identical runs differ by up to x{TIMING_NOISE:g} on this machine "
               "(comparisons._bands: three identical fig8 --quick runs)")


def versus(a: float, b: float, factor: float, noise: float, words: tuple[str, str, str], reason: str,
           unit: str = "ratio") -> RatioVerdict:
    """words[0] if a > factor b, words[1] if a < b / factor, else words[2] (a, b > 0); not decided
    within a factor ``noise`` of either edge."""
    return RatioVerdict(a, b, factor=factor, noise=noise, above=words[0], below=words[1], between=words[2],
                        reason=reason, unit=unit)


def cost_versus(a_s: float, b_s: float) -> RatioVerdict:
    """How run time ``a_s`` compares with ``b_s``: "costlier", "cheaper" or "comparable" (band CHEAPER),
    not decided within the timing noise (a verdict of unit TIME_RATIO: shroud compare skips it)."""
    return versus(a_s, b_s, CHEAPER, TIMING_NOISE, ("costlier", "cheaper", "comparable"), COST_REASON,
                  TIME_RATIO)
