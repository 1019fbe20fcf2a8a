"""Verdicts flip where their number crosses the threshold and read "not decided" inside the margin."""

import json
from pathlib import Path

import pytest

from shroud.core.verdict import (BAND, DIFFERENCE, NOT_DECIDED, RATIO, BandVerdict, RatioVerdict, Verdict, answer_of,
                                 declared_rounding, is_verdict, kind_of, with_rounding)


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


def test_a_rounding_is_declared_only_for_the_record_s_own_numbers_and_keeps_a_verdict_a_verdict():
    """A declared spread names a key of the record and is >= 0; a verdict's record with its rounding
    declared is still read as a verdict (its answer, by gates and answer_of)."""
    record = Verdict.of(0.0067, threshold=0.015, margin=0.002, below="within", above="outside",
                        reason="mesh").to_json()
    declared = with_rounding(record, "MUMPS orderings", value=1e-4, margin=7e-5)
    assert is_verdict(declared) and answer_of(declared) == "within"
    assert declared_rounding(declared) == {"value": 1e-4, "margin": 7e-5}
    assert declared_rounding(record) == {}
    twice = with_rounding(with_rounding(record, "ordering", value=1e-4), "Newton", margin=1e-10)
    assert declared_rounding(twice) == {"value": 1e-4, "margin": 1e-10}
    assert twice["rounding"]["reason"] == "ordering; Newton"
    with pytest.raises(ValueError, match="lacks"):
        with_rounding(record, "", tip=1e-7)
    with pytest.raises(ValueError, match=">= 0"):
        with_rounding(record, "", value=-1e-4)


def test_each_verdict_says_how_its_threshold_and_margin_read_and_records_made_before_still_read():
    """A ratio's band is a factor (x3 +- a factor 1.5), a band's an interval +-0.5 around zero, a
    difference's a line: the record's kind says which. fig8's conclusions as its record held them before
    verdicts wrote their kind (tests/data/fig8_conclusions_before_kinds.json, kept from 37db1a7: the records
    have all been made again since) still read as verdicts, their ratios told by their unit."""
    ratio = RatioVerdict(5.0, 1.0, factor=3.0, noise=1.5, above="costlier", below="cheaper", between="comparable",
                         reason="").to_json()
    band = BandVerdict(0.8, band=0.5, margin=0.1, above="higher", below="lower", between="the same", reason="")
    line = Verdict.of(0.03, threshold=0.05, margin=0.01, below=True, above=False, reason="")
    assert [kind_of(v) for v in (ratio, band.to_json(), line.to_json())] == [RATIO, BAND, DIFFERENCE]
    assert all(is_verdict(v) for v in (ratio, band.to_json(), line.to_json()))
    old = json.loads((Path(__file__).parent / "data" / "fig8_conclusions_before_kinds.json").read_text())
    amplitudes = [v for model in old["amplitude_vs_reference"].values() for v in model.values()]
    assert amplitudes and all(is_verdict(v) and "kind" not in v and kind_of(v) == RATIO for v in amplitudes)
    slips = old["slip_vs_reference"].values()       # BandVerdicts: written as a difference was, no kind to tell
    assert slips and all(is_verdict(v) and kind_of(v) is None and answer_of(v) == v["answer"] for v in slips)
