"""Three-way comparisons with a dead band: how the studies turn two numbers into a word.

A conclusion drawn from two measured numbers (errors, run times) must not
flip when one of them moves by its own noise, so each comparison names a
factor inside which the two count as the same. Run times of one run on the
shared machine vary by up to 2x between runs (a millisecond run by more, when
the collector or a page fault lands in it), so cost bands use CHEAPER.
"""

from __future__ import annotations

CHEAPER = 3.0     # one run is cheaper than another when its time is below 1/CHEAPER of the other's


def versus(a: float, b: float, factor: float, words: tuple[str, str, str]) -> str:
    """words[0] if a > factor b, words[1] if a < b / factor, else words[2] (a, b > 0)."""
    if a > b * factor:
        return words[0]
    return words[1] if a < b / factor else words[2]


def cost_versus(a_s: float, b_s: float) -> str:
    """How run time ``a_s`` compares with ``b_s``: "costlier", "cheaper" or "comparable" (band CHEAPER)."""
    return versus(a_s, b_s, CHEAPER, ("costlier", "cheaper", "comparable"))
