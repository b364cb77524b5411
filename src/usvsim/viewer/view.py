"""What the viewer shows, independent of the window: camera pose, HUD rows, layers, the frame itself."""

from __future__ import annotations

import math
from collections.abc import Callable

import mujoco
import numpy as np

from usvsim.viewer.camera import CameraPose, FollowCamera, above_water, mujoco_ray
from usvsim.viewer.frame import FrameRenderer
from usvsim.viewer.hud import HELP, RateMeter, hud_lines

Layer = np.ndarray | Callable[[object], np.ndarray | None] | None


def resolve_layer(layer: Layer, sim) -> np.ndarray | None:
    """A layer is an array, a callable of the simulation returning one (or None), or None."""
    return layer(sim) if callable(layer) else layer


class View:
    """Follow camera on one vessel + optional points/inset layers; draws frames with a FrameRenderer."""

    def __init__(self, sim, vessel_name: str | None = None, camera: FollowCamera | None = None,
                 points: Layer = None, inset: Layer = None, show_hud: bool = True):  # fmt: skip
        self.sim = sim
        self.vessel_name = vessel_name or next(iter(sim.vessels))
        self.vessel = sim.vessels[self.vessel_name]
        self.camera = camera or FollowCamera()
        self.points, self.inset, self.show_hud = points, inset, show_hud
        self.rates = RateMeter()
        self._ray = mujoco_ray(sim.model, sim.data, exclude_body=self.vessel.index + 1)

    @property
    def heading_deg(self) -> float:
        return math.degrees(float(self.vessel.rpy[2]))

    def camera_pose(self, dt: float = 0.0) -> CameraPose:
        self.camera.update(self.heading_deg, dt)
        pose = self.camera.pose(self.vessel.position, self.heading_deg, self._ray)
        ocean, t = self.sim.ocean, self.sim.time
        return above_water(pose, lambda x, y: float(np.ravel(ocean.elevation(x, y, t))[0]))

    def hud_rows(self, paused: bool = False, axes=None) -> list[tuple[str, str]] | None:
        if not self.show_hud:
            return None
        return hud_lines(self.sim, self.vessel_name, self.rates, paused, self.camera.follow, axes)

    def draw(self, renderer: FrameRenderer, viewport: mujoco.MjrRect, dt: float = 0.0, paused: bool = False,
             axes=None) -> None:  # fmt: skip
        pose = self.camera_pose(dt)
        renderer.update_water(self.sim, self.vessel.position[:2])
        renderer.draw(self.sim, viewport, pose, self.hud_rows(paused, axes), resolve_layer(self.points, self.sim),
                      resolve_layer(self.inset, self.sim), help_text=HELP if self.show_hud else None)  # fmt: skip
