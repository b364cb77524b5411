"""Drive the WAM-V around the harbour for a few seconds and save a rendered picture.

    MUJOCO_GL=egl python examples/snapshot.py [SCENARIO] [OUT.png]

Renders offscreen through the viewer's renderer (EGL; works on a CPU-only machine through Mesa), with the
scenario's `rendering:` look (docs/rendering.md), from a fixed camera above the harbour.
"""

from __future__ import annotations

import os
import sys

os.environ.setdefault("MUJOCO_GL", "egl")

import numpy as np

from usvsim import Simulation
from usvsim.viewer.camera import CameraPose
from usvsim.viewer.offscreen import OffscreenViewer, save_png


def main(scenario: str = "harbor", out: str = "harbor.png") -> None:
    sim = Simulation.from_scenario(scenario)
    boat = next(iter(sim.vessels.values()))
    for k in range(700):
        boat.command(0.8, 0.25 if k > 300 else 0.0)  # straight, then a turn to starboard
        sim.step()
    viewer = OffscreenViewer(sim, 1280, 720)
    viewer.view.show_hud = False
    pose = CameraPose(np.array([8.0, -4.0, 0.0]), 30.0, 200.0, -16.0)
    viewer.view.camera_pose = lambda dt=0.0: pose  # a fixed view instead of the follow camera
    save_png(viewer.render(), out)
    viewer.close()
    print(f"wrote {out} at t = {sim.time:.1f} s")


if __name__ == "__main__":
    main(*sys.argv[1:3])
