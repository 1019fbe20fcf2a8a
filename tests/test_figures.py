"""No legend entry is drawn invisibly under another curve (shroud.core.plotting.hidden_entries).

Fig. 8 once drew the full beam over the reduced beam (they agree to 0.1 %): the reduced beam's legend
entry had no visible curve. Reductions are now dashed above their full models, and every saved figure is
checked: a wholly covered entry is a warning naming the figure and the curve.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from shroud.core.plotting import figure, hidden_entries, save

ROOT = Path(__file__).resolve().parents[1]


def _drawn(*curves):
    fig, axes = figure(1, 1)
    ax = axes[0][0]
    x = np.linspace(0.0, 1.0, 200)
    for label, y, style in curves:
        ax.plot(x, y(x), label=label, **style)
    ax.set_title("panel")
    fig.canvas.draw()
    return fig


SINE = lambda x: np.sin(6 * x)          # noqa: E731


@pytest.mark.parametrize("below, above, hidden", [
    (dict(ls="-"), dict(ls="-"), True),                      # the same curve twice, solid over solid
    (dict(ls="--"), dict(ls="-"), True),                     # dashed under solid
    (dict(ls="-"), dict(ls=(0, (5, 3)), zorder=3), False),   # dashed above: the solid shows in its gaps
    (dict(ls="-", zorder=3), dict(ls="-", zorder=2), False), # drawn later but lower: the first is on top
    (dict(ls="-", lw=2.5), dict(ls="-", lw=1.0), False),     # a wider curve shows around a thinner one
])
def test_a_curve_wholly_under_a_solid_one_is_found(below, above, hidden):
    fig = _drawn(("below", SINE, below), ("above", SINE, above))
    found = hidden_entries(fig)
    assert (found == ["panel: 'below' is hidden under another curve"]) == hidden, found


def test_an_offset_or_a_partly_different_curve_is_visible():
    shifted = lambda x: np.sin(6 * x) + 0.05                          # noqa: E731
    apart = lambda x: np.where(x < 0.5, np.sin(6 * x), 0.3)           # noqa: E731
    assert hidden_entries(_drawn(("below", SINE, {}), ("above", shifted, {}))) == []
    assert hidden_entries(_drawn(("below", SINE, {}), ("above", apart, {}))) == []


def test_a_curve_covered_piecewise_by_two_segments_is_found():
    """An HB branch is drawn in stretches (stable solid, unstable dashed): their union can cover a curve."""
    fig, axes = figure(1, 1)
    ax = axes[0][0]
    x = np.linspace(0.0, 1.0, 200)
    ax.plot(x, SINE(x), label="below")
    ax.plot(x[:101], SINE(x[:101]), "-", label="first half")
    ax.plot(x[100:], SINE(x[100:]), "-")
    fig.canvas.draw()
    assert hidden_entries(fig) == ["a panel: 'below' is hidden under another curve"]


def test_save_warns_of_a_hidden_entry(tmp_path, capsys):
    fig = _drawn(("below", SINE, {}), ("above", SINE, {}))
    save(fig, tmp_path / "f.png")
    assert "f.png: panel: 'below' is hidden under another curve" in capsys.readouterr().err


def test_fig8_shows_every_model_it_names(tmp_path):
    """The beams of Fig. 8 (reduced, full, extended) at the quick scene: no entry hidden in any panel."""
    env = {**os.environ, "OMP_NUM_THREADS": "1", "PYTHONPATH": str(ROOT)}
    proc = subprocess.run([sys.executable, "-m", "workbench.cli", "run", str(ROOT / "scenes/fig8.toml"), "--quick",
                           "--set", 'options.models=["reduced", "full", "extended"]', "--set", "options.reference=full",
                           "--out", str(tmp_path / "f8")], capture_output=True, text=True, env=env, timeout=600)
    assert proc.returncode == 0, proc.stderr
    assert (tmp_path / "f8" / "fig8.png").exists()
    assert "is hidden under another curve" not in proc.stderr, proc.stderr
