"""Render the look gallery of docs/rendering.md: python examples/gallery.py [OUT_DIR] [WIDTH HEIGHT];
`python examples/gallery.py --readme [DOCS_DIR]` renders the README's docs/harbor.png and docs/viewer.png."""

import os
import sys

os.environ.setdefault("MUJOCO_GL", "egl")

from usvsim.rendering.gallery import render_gallery, render_readme

if sys.argv[1:2] == ["--readme"]:
    for path in render_readme(sys.argv[2] if len(sys.argv) > 2 else "docs"):
        print(path)
    sys.exit()
out = sys.argv[1] if len(sys.argv) > 1 else "docs/gallery"
size = (int(sys.argv[2]), int(sys.argv[3])) if len(sys.argv) > 3 else (960, 540)
for path in render_gallery(out, *size):
    print(path)
