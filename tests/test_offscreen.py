"""Pictures drawn without a display say nothing on stderr (no failed X connection first)."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DRAW = """
import sys
from shroud.base.offscreen import pyvista
pv = pyvista()
plotter = pv.Plotter(window_size=(200, 150))
plotter.add_mesh(pv.Sphere())
plotter.screenshot(sys.argv[1])
plotter.close()
"""


@pytest.mark.fe
def test_an_offscreen_picture_without_a_display_is_quiet(tmp_path):
    env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY", "VTK_DEFAULT_OPENGL_WINDOW")}
    env["PYTHONPATH"] = str(ROOT)
    png = tmp_path / "sphere.png"
    run = subprocess.run([sys.executable, "-c", DRAW, str(png)], capture_output=True, text=True, env=env, timeout=300)
    assert run.returncode == 0, run.stderr
    assert png.stat().st_size > 1000
    assert run.stderr == "", run.stderr
