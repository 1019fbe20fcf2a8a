"""Shared test set-up: the models come from the registry, where the installed builders declare them."""

import pytest

from quick_full import Held


@pytest.fixture
def held(request):
    """The verdict pairs a quick-against-full test holds (tests/quick_full.py): after the test, it fails
    unless it held at least one decided on both sides, and says how many it held. A test marked
    ``compares_no_verdict(reason)`` (a study that draws no verdict objects yet) must hold none: the mark
    goes when its study draws them."""
    pairs = Held(request.node.name)
    yield pairs
    print(pairs.summary())
    none_yet = request.node.get_closest_marker("compares_no_verdict")
    if none_yet is None:
        pairs.check()
    else:
        assert pairs.decided + pairs.undecided == 0, f"{pairs.summary()}: remove its compares_no_verdict mark"
