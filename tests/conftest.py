"""Shared test set-up: the models come from the registry, where the installed builders declare them."""

import pytest

from quick_full import Held


@pytest.fixture
def held(request):
    """The verdict pairs a quick-against-full test holds (tests/quick_full.py): after the test, it fails
    unless it held at least one decided on both sides, and says how many it held. A test marked
    ``holds_no_decided_verdict(reason)`` is a known finding (a study that draws no verdict objects yet, a
    full scene that decides none of the quick scene's cases): it fails once it holds one, so that the mark
    goes."""
    pairs = Held(request.node.name)
    yield pairs
    print(pairs.summary())
    known = request.node.get_closest_marker("holds_no_decided_verdict")
    if known is None:
        pairs.check()
    else:
        print(f"holds no decided verdict: {known.args[0]}")
        assert pairs.decided == 0, f"{pairs.summary()}: remove its holds_no_decided_verdict mark"


@pytest.fixture(scope="module")
def ccx():
    """The CalculiX executable (tests/test_calculix.py, test_disk_calculix.py: a second FE code on the same
    mesh); the test skipped, saying why, where it is not installed."""
    from reference_fe.calculix import ccx
    path = ccx()
    if path is None:
        pytest.skip("CalculiX (ccx) is not installed: bash scripts/install_calculix.sh, or see the README")
    return path
