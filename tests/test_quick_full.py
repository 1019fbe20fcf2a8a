"""A quick-against-full comparison that compares nothing fails (tests/quick_full.py): all its verdicts
undecided, or its tables sharing no keys, it held no verdict decided on both sides."""

import pytest

from quick_full import Held
from shroud.core.verdict import NOT_DECIDED, BandVerdict, Verdict
from workbench import records


def _verdict(value: float) -> dict:
    """"within" below 0.15 %, "outside" above, not decided within 0.02 % of it (convergence's tolerance)."""
    return Verdict.of(value, 0.15, 0.02, below="within", above="outside", reason="mesh", unit="%").to_json()


def test_a_comparison_of_undecided_verdicts_only_fails():
    pairs = Held("undecided")
    assert pairs.agrees({"flap1": _verdict(0.14)}, {"flap1": _verdict(0.10)})      # not decided in the quick run
    assert pairs.same(_verdict(0.16), _verdict(0.14))                               # nor in either
    assert (pairs.decided, pairs.undecided) == (0, 2)
    with pytest.raises(AssertionError, match="compared no decided verdict"):
        pairs.check()


def test_a_comparison_of_tables_sharing_no_key_fails():
    pairs = Held("no shared keys")
    assert pairs.agrees({"gap 1 um": _verdict(0.10)}, {"gap 2 um": _verdict(0.10)})     # all([]) held nothing
    with pytest.raises(AssertionError, match="compared no decided verdict"):
        pairs.check()


def test_a_comparison_counts_what_it_held_and_still_sees_a_contradiction():
    pairs = Held("decided")
    band = BandVerdict(0.8, band=0.5, margin=0.1, above="higher", below="lower", between="the same", reason="")
    assert pairs.agrees({"a": _verdict(0.10), "b": band.to_json()}, {"a": _verdict(0.05), "b": band.to_json()})
    assert not pairs.agrees(_verdict(0.10), _verdict(0.20))        # within against outside: a contradiction
    assert (pairs.decided, pairs.undecided) == (3, 0)
    pairs.check()
    assert "held 3" in pairs.summary()


def test_a_full_record_held_against_itself_made_undecided_compares_nothing():
    """hb_fig4's record (made before verdicts wrote their kind) against a quick run that decided nothing."""
    full = records.load("hb_fig4")["conclusions"]
    quick = {case: {**c, "same_resonance": {**c["same_resonance"], "answer": NOT_DECIDED}} for case, c in full.items()}
    pairs = Held("hb_fig4 undecided")
    assert all(pairs.same(full[c]["same_resonance"], full[c]["same_resonance"]) for c in full)
    assert pairs.decided == sum(full[c]["same_resonance"]["answer"] != NOT_DECIDED for c in full) > 0
    pairs = Held("hb_fig4 undecided")
    assert pairs.agrees(quick, full)
    with pytest.raises(AssertionError, match="compared no decided verdict"):
        pairs.check()
