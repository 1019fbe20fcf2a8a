"""fe-reduced by harmonic balance on its one speed-range basis against its own time domain (per-speed basis)."""

import pytest

pytestmark = pytest.mark.fe


def test_fe_reduced_hb_point_matches_a_p1_time_domain_run():
    from shroud.analysis.api import transient
    from shroud.analysis.hb import checkpoint
    from shroud.params import Parameters
    p = Parameters().updated({"contact.gap": 1e-4, "speed.rpm": 9000.0, "time.periods": 150})
    td = transient(p, "fe-reduced")
    assert td.period == 1
    sol = checkpoint(p, "fe-reduced", 9000.0, harmonics=7, samples=256)
    assert sol.converged and sol.stable
    assert sol.amplitude_v_L == pytest.approx(td.amplitude["v_L"], rel=0.01)
