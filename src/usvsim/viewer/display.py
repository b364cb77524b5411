"""Whether a window can open here, known before any window system is loaded."""

from __future__ import annotations

import os
import sys

NO_DISPLAY = "GLFW could not initialise: no display? (set DISPLAY, or run under Xvfb)"


def display_missing() -> bool:
    """True on Linux with neither DISPLAY nor WAYLAND_DISPLAY set: GLFW cannot open a window there."""
    return sys.platform.startswith("linux") and not (os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY"))
