"""The resonance peak followed in the preload against the peaks of speed branches solved at each preload."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from shroud.analysis.hb import run_hb
from shroud.analysis.peak import track_peak
from workbench.cli import main
from shroud.base.errors import InputError
from shroud.params import Parameters

FIG11 = {"contact.alpha_deg": 30.0, "contact.kt": 5e6, "contact.mu": 0.3}     # the paper's Fig. 11 contact
RPM_FROM, RPM_TO, BRUTE_POINTS = 4000.0, 60000.0, 300
ROOT = Path(__file__).resolve().parents[1]


def brute_force_peak(params: Parameters, n0: float) -> tuple[float, float]:
    """(rpm, amplitude) of the largest amplitude of the speed branch at ``n0``, points every ~190 r/min."""
    br = run_hb(params.updated({"contact.N0": n0}), "reduced", RPM_FROM, RPM_TO, min_points=BRUTE_POINTS)
    assert br.complete
    return br.resonance["rpm"], br.resonance["amplitude"]


def test_tracked_peak_is_the_speed_branches_peak():
    """At a slipping (5 N), an optimal (20 N) and a partly stuck (100 N) preload the tracked resonance is the
    brute-force one: amplitude within 1 %, speed within two of the brute-force branch's steps; the optimal
    preload lies inside the curve, where the resonant amplitude is smallest; the resonant speed rises with
    the preload (the shroud constrains the blade more)."""
    params = Parameters().updated(FIG11)
    checks = (5.0, 20.0, 100.0)
    curve = track_peak(params, "reduced", 0.0, 120.0, RPM_FROM, RPM_TO, at=checks, min_points=25)
    assert curve.complete, curve.stopped
    step = (RPM_TO - RPM_FROM) / (BRUTE_POINTS - 1)
    for n0 in checks:
        rpm, amplitude = brute_force_peak(params, n0)
        point = curve.at(n0)
        assert point["amplitude"] == pytest.approx(amplitude, rel=0.01), n0
        assert abs(point["rpm"] - rpm) <= 2 * step, n0
    best = curve.optimum
    assert not best["at_end"]
    assert best["amplitude"] < 0.5 * curve.amplitude_v_L[0] and best["amplitude"] < 0.5 * curve.amplitude_v_L[-1]
    assert np.all(np.diff(curve.rpm) > -1.0)


def test_a_start_whose_peak_is_outside_the_speed_range_is_refused():
    params = Parameters().updated(FIG11)
    with pytest.raises(InputError, match="rpm_to"):
        track_peak(params, "reduced", 0.0, 50.0, 4000.0, 20000.0)
    with pytest.raises(InputError, match="n0_to"):
        track_peak(params, "reduced", 50.0, 10.0, 4000.0, 60000.0)


@pytest.mark.parametrize("scene, setting, key", [
    ("hb_optimal_preload", "options.n0_to=-5", "options.n0_to"),
    ("hb_optimal_preload", "options.preloads_N=[500.0]", "options.preloads_N"),
    ("hb_friction", "options.n0_to=50", "options.n0_to"),
    ("hb_stiffness_ratio", "options.rpm_to=3000", "options.rpm_to"),
    ("hb_friction", "options.values=[0.3]", "options.values"),
])
def test_bad_options_of_the_preload_studies_are_one_line_and_exit_2(tmp_path, capsys, scene, setting, key):
    out = tmp_path / "out"
    code = main(["run", str(ROOT / "scenes" / f"{scene}.toml"), "--quick", "--set", setting, "--out", str(out)])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and err[-1].startswith(f"error: {key}:") and "allowed:" in err[-1], err
    assert not out.exists()
