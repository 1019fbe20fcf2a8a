"""Off-screen rendering with pyvista/VTK, set up once for every picture the workbench draws.

Without a display, VTK (9.4+) first tries an X window, prints a coloured
"bad X server connection. DISPLAY=" warning, and only then falls back to
EGL or OSMesa. Choosing the off-screen render window up front, through
VTK's own ``VTK_DEFAULT_OPENGL_WINDOW`` setting, skips the failed attempt:
EGL where libEGL is installed, else OSMesa where libOSMesa is. A user's
own choice of that variable, or a display, is left alone.
"""

from __future__ import annotations

import ctypes.util
import os


def offscreen_window() -> str | None:
    """The VTK render window class for this process, or None to let VTK choose (a display is there)."""
    if os.environ.get("VTK_DEFAULT_OPENGL_WINDOW"):
        return os.environ["VTK_DEFAULT_OPENGL_WINDOW"]
    if os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY"):
        return None
    for library, window in (("EGL", "vtkEGLRenderWindow"), ("OSMesa", "vtkOSOpenGLRenderWindow")):
        if ctypes.util.find_library(library):
            return window
    return None


def pyvista():
    """The pyvista module, set to render off screen with the window :func:`offscreen_window` picks."""
    window = offscreen_window()
    if window is not None:
        os.environ["VTK_DEFAULT_OPENGL_WINDOW"] = window
    import pyvista as pv
    pv.OFF_SCREEN = True
    return pv
