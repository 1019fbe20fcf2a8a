"""Anything over a few seconds says where it is on stderr, and a log line says which variant it shows."""

from __future__ import annotations

import functools
import json
import re

import pytest

from workbench.cli import main
from shroud.base.log import Progress


def test_a_harmonic_balance_branch_reports_points_speed_and_amplitude(capsys, monkeypatch):
    import shroud.analysis.hb as hb_analysis
    monkeypatch.setattr(hb_analysis, "Progress", functools.partial(Progress, every_s=0.0, after_s=0.0))
    assert main(["sweep", "--method", "hb", "--rpm-from", "8000", "--rpm-to", "9000", "--harmonics", "5",
                 "--samples", "128", "--json"]) == 0
    captured = capsys.readouterr()
    branch = json.loads(captured.out)
    lines = [l for l in captured.err.splitlines() if "HB branch reduced 8000-9000 r/min:" in l]
    assert len(lines) >= len(branch["rpm"]) - 1            # one a point (and the last: done)
    seen = [re.search(r"(\d+) points, at (\d+) r/min, amplitude (\S+) m \((\d+) %\)", l) for l in lines[:-1]]
    assert all(seen)
    counts = [int(m.group(1)) for m in seen]
    assert counts == sorted(counts) and counts[-1] == len(branch["rpm"])
    assert int(seen[-1].group(2)) == round(branch["rpm"][-1]) and seen[-1].group(4) == "100"
    assert float(seen[-1].group(3)) == pytest.approx(branch["amplitude_v_L"][-1], rel=1e-2)
    assert lines[-1].endswith("s") and "done in" in lines[-1]


@pytest.mark.fe
def test_the_solid_modal_log_line_shows_the_frequencies_of_its_result(capsys):
    """The log once showed the frequencies without Coriolis (282.3 Hz) beside a result with it (282.15 Hz)."""
    for coriolis, variant in (("--coriolis", "with Coriolis"), ("--no-coriolis", "without Coriolis")):
        assert main(["modal", "--model", "fe", "--rpm", "8500", "--modes", "3", coriolis, "--json"]) == 0
        captured = capsys.readouterr()
        result = json.loads(captured.out)
        line = next(l for l in captured.err.splitlines() if "FE modes at 8500 r/min," in l)
        assert variant in line
        logged = dict(re.findall(r"(\w+\d) ([\d.]+) Hz", line))
        for mode in result["modes"]:
            assert float(logged[mode["label"]]) == pytest.approx(mode["f_hz"], abs=0.005)
