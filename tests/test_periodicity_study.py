"""Which waveform the periodicity study shows is decided by what its runs found."""

from types import SimpleNamespace

from comparisons.periodicity import CaseRun, waveform_case


def _run(label, period, mu=0.1):
    return CaseRun(mu=mu, label=label, result=SimpleNamespace(period=period))


def test_the_longest_period_found_is_shown_whatever_the_paper_expects():
    # the paper expects P1 at mu = 0.1: a P3 found there is what a user must see
    assert waveform_case([_run("gap 1 um", 1), _run("N0 10 N", 3)]).label == "N0 10 N"
    # the paper expects P10 at mu = 0.5: without one, the longest period found is shown
    assert waveform_case([_run("a", 1, 0.5), _run("b", 5, 0.5), _run("c", 2, 0.5)]).label == "b"


def test_a_response_without_a_period_outranks_every_periodic_one():
    assert waveform_case([_run("a", 9), _run("b", None)]).label == "b"
    assert waveform_case([_run("a", 1), _run("b", 1)]).label == "a"         # ties: the first case
