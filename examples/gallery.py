"""Render the look gallery of docs/rendering.md: python examples/gallery.py [OUT_DIR] [WIDTH HEIGHT]."""

import os
import sys

os.environ.setdefault("MUJOCO_GL", "egl")

from usvsim.rendering.gallery import render_gallery

out = sys.argv[1] if len(sys.argv) > 1 else "docs/gallery"
size = (int(sys.argv[2]), int(sys.argv[3])) if len(sys.argv) > 3 else (960, 540)
for path in render_gallery(out, *size):
    print(path)
