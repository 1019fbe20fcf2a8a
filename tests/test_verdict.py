"""Verdicts flip where their number crosses the threshold and read "not decided" inside the margin."""

import pytest

from shroud.core.verdict import NOT_DECIDED, RatioVerdict, Verdict


@pytest.mark.parametrize("value, answer", [(0.030, "no effect"), (0.049, NOT_DECIDED), (0.051, NOT_DECIDED),
                                           (0.070, "effect"), (float("nan"), NOT_DECIDED)])
def test_threshold_verdict_flips_across_its_threshold(value, answer):
    v = Verdict.of(value, threshold=0.05, margin=0.01, below="no effect", above="effect", reason="grid step")
    assert v.answer == answer
    assert v.to_json()["answer"] == answer


def test_negative_margin_is_refused():
    with pytest.raises(ValueError):
        Verdict.of(1.0, 0.0, -1.0, True, False, "")


@pytest.mark.parametrize("a, answer", [(1.0, "comparable"), (2.5, NOT_DECIDED), (3.5, NOT_DECIDED),
                                       (5.0, "costlier"), (0.2, "cheaper"), (0.3, NOT_DECIDED)])
def test_ratio_verdict_has_a_dead_band_and_a_margin_at_its_edges(a, answer):
    v = RatioVerdict(a, 1.0, factor=3.0, noise=1.5, above="costlier", below="cheaper", between="comparable",
                     reason="run times vary 1.5x between identical runs")
    assert v.answer == answer
