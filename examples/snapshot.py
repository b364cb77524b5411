"""Drive the WAM-V around the harbour for a few seconds and save a rendered picture.

    MUJOCO_GL=egl python examples/snapshot.py [SCENARIO] [OUT.png]

Renders with MuJoCo's offscreen renderer (EGL; works on a CPU-only machine through Mesa).
"""

from __future__ import annotations

import os
import sys

os.environ.setdefault("MUJOCO_GL", "egl")

import mujoco
from PIL import Image

from usvsim import Simulation


def main(scenario: str = "harbor", out: str = "harbor.png") -> None:
    sim = Simulation.from_scenario(scenario)
    boat = next(iter(sim.vessels.values()))
    for k in range(700):
        boat.command(0.8, 0.25 if k > 300 else 0.0)  # straight, then a turn to starboard
        sim.step()
    renderer = mujoco.Renderer(sim.model, 720, 1280)
    camera = mujoco.MjvCamera()
    camera.lookat[:], camera.distance, camera.azimuth, camera.elevation = [8, -4, 0], 30.0, 200.0, -16.0
    option = mujoco.MjvOption()
    option.geomgroup[:] = [0, 1, 1, 0, 0, 0]  # visuals and water, not the collision pieces
    option.flags[mujoco.mjtVisFlag.mjVIS_TENDON] = 1  # mooring lines
    renderer.update_scene(sim.data, camera, option)
    Image.fromarray(renderer.render()).save(out)
    print(f"wrote {out} at t = {sim.time:.1f} s")


if __name__ == "__main__":
    main(*sys.argv[1:3])
