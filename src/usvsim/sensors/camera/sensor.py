"""Camera sensor: RGB (rgb8), depth (32FC1, REP 118) and segmentation (16UC1) images + CameraInfo.

Frames: mounted at `<vessel>/<name>` (FLU, looking along +x); images and CameraInfo are in
`<vessel>/<name>_optical` (z forward, x right, y down). Topics under `/<vessel>/<name>/`:
`image_raw` + `camera_info`, `depth/image_raw` + `depth/camera_info`, `segmentation/image_raw`; all
share one stamp. Depth is metres along the optical z axis; NaN = no surface within `far_m` (sky, REP 117),
and depth noise is added per pixel as N(0, depth_noise_stddev_m²). RGB noise is multiplicative:
out = clip(in·(1 + σ n)), n ~ N(0, 1) per pixel and channel. Segmentation holds MuJoCo geom id + 1 (0 =
background); no noise, no blending. The water surface is the ocean's own height field (world/water_visual),
refreshed around the camera before each frame.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from usvsim.messages.envelope import Envelope
from usvsim.messages.ros import image_msg
from usvsim.sensors.base import OPTICAL_ROT, Sensor
from usvsim.sensors.camera.intrinsics import Intrinsics, Remap
from usvsim.sensors.camera.render import PinholeRenderer
from usvsim.sensors.messages import camera_info_msg

if TYPE_CHECKING:
    from usvsim.simulation import Simulation

try:  # the drawn ocean surface (another module); without it the flat still-water plane is drawn
    from usvsim.world.water_visual import update_water_visual
except ImportError:  # pragma: no cover
    update_water_visual = None


class Camera(Sensor):
    optical = True

    def __init__(self, cfg, vessel: str, sim: Simulation, shared: dict):
        super().__init__(cfg, vessel, sim)
        d = cfg.distortion
        self.intrinsics = Intrinsics.from_fov(cfg.width, cfg.height, cfg.horizontal_fov_deg, (d.k1, d.k2, d.p1, d.p2, d.k3))
        self.remap = Remap(self.intrinsics) if self.intrinsics.distorted else None
        render_cam = self.remap.render if self.remap else self.intrinsics
        self.renderer = PinholeRenderer(sim.model, render_cam, cfg.near_m, cfg.far_m, cfg.shadows, cfg.fog)
        shared[f"camera/{self.name}"] = self.renderer  # closed by SensorSuite.close()
        self.streams = set(cfg.streams)

    def render(self, sim: Simulation) -> dict[str, np.ndarray]:
        """Images of the current state: 'rgb' (H, W, 3) uint8, 'depth' (H, W) float32 m, 'segmentation' uint16."""
        pos, rot = self.pose_world(sim)
        r = self.renderer
        if self.cfg.water_surface and update_water_visual is not None:
            r.gl.make_current()
            update_water_visual(sim, r.ctx, pos[:2])
        r.update(sim.data.qpos, pos, rot @ OPTICAL_ROT)
        out: dict[str, np.ndarray] = {}
        if self.streams & {"rgb", "depth"}:
            out["rgb"], depth = r.rgb_depth(want_depth="depth" in self.streams)
            if depth is not None:
                out["depth"] = depth
        if "segmentation" in self.streams:
            out["segmentation"] = r.segmentation()
        if self.remap is not None:
            out = {k: (self.remap.linear(v) if k == "rgb" else self.remap.closest(v)) for k, v in out.items()}
        return out

    def _noisy(self, images: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
        c = self.cfg
        if "rgb" in images and c.rgb_noise_stddev > 0:
            gain = 1.0 + c.rgb_noise_stddev * self.rng.standard_normal(images["rgb"].shape, np.float32)
            images["rgb"] = np.clip(images["rgb"] * gain, 0, 255).round().astype(np.uint8)
        if "depth" in images and c.depth_noise_stddev_m > 0:
            images["depth"] = images["depth"] + c.depth_noise_stddev_m * self.rng.standard_normal(
                images["depth"].shape, np.float32)  # fmt: skip
        return images

    def sample(self, sim: Simulation, stamp_ns: int) -> list[Envelope]:
        images = self._noisy(self.render(sim))
        frame, base, cam = self.optical_frame_id, self.topic, self.intrinsics
        info = camera_info_msg(stamp_ns, frame, cam.width, cam.height, cam.K, cam.D)
        out = []
        if "rgb" in self.streams:
            out += [Envelope(f"{base}/image_raw", stamp_ns, image_msg(stamp_ns, frame, images["rgb"], "rgb8")),
                    Envelope(f"{base}/camera_info", stamp_ns, info)]  # fmt: skip
        if "depth" in images:
            out += [Envelope(f"{base}/depth/image_raw", stamp_ns, image_msg(stamp_ns, frame, images["depth"], "32FC1")),
                    Envelope(f"{base}/depth/camera_info", stamp_ns, info)]  # fmt: skip
        if "segmentation" in images:
            seg = image_msg(stamp_ns, frame, images["segmentation"], "16UC1")
            out.append(Envelope(f"{base}/segmentation/image_raw", stamp_ns, seg))
        return out
