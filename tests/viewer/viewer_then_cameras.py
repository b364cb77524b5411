"""Run under Xvfb by test_viewer_with_cameras.py: the viewer on `harbor_sensors`, then the simulation goes on.
Prints JSON: whether the viewer's window was visible, and the camera image's sky after the viewer closed."""

import json
import os

# the camera sensors' contexts: hidden GLFW windows, as `usvsim run --view` makes them
os.environ["MUJOCO_GL"] = "glfw"

import glfw

from usvsim.simulation import Simulation
from usvsim.viewer import app

visible = []
frame = app.ViewerWindow.frame


def first_frame(self, dt):
    if not visible:
        visible.append(int(glfw.get_window_attrib(self.window, glfw.VISIBLE)))
    return frame(self, dt)


app.ViewerWindow.frame = first_frame
sim = Simulation.from_scenario("harbor_sensors")
app.run_viewer(sim, max_seconds=0.2)
sim.run(0.3)
rgb = sim.sensors["wamv/camera"].latest["rgb"]
print(json.dumps({"visible": visible[0], "sky": rgb[:40].reshape(-1, 3).mean(axis=0).tolist()}))
sim.close()
