"""One antenna turn: the spokes of the current revolution with the antenna pose and time of each, and what is
published when a turn completes: the radar image (sensor_msgs/Image mono8 on `<topic>/image`, frame = the
sensor frame, head-up) and the ARPA target list (`<topic>/tracks`, frame `world`).

`polar` images are spokes × range bins (row k = spoke k, column = bin); `cartesian` images are a plan
position indicator of `image_size_px`² pixels, the antenna in the centre, the bow up, range_max_m to the edge.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from usvsim.messages import ros
from usvsim.messages.envelope import Envelope
from usvsim.sensors.radar.arpa import Tracker, plots

if TYPE_CHECKING:
    from usvsim.world.world import World


def cartesian_lookup(size: int, spokes: int, bins: int) -> np.ndarray:
    """Flat index spoke * bins + bin for every pixel of a head-up PPI (-1 outside the range circle)."""
    c = (np.arange(size) + 0.5) / size * 2.0 - 1.0  # -1..1 across the image
    up, right = -c[:, None], c[None, :]  # row 0 is the top (ahead)
    radius = np.hypot(up, right)
    angle = np.arctan2(-right, up)  # sensor frame, CCW from the bow (left of the bow is +)
    spoke = np.round(-angle / (2 * np.pi) * spokes).astype(int) % spokes  # spokes turn clockwise
    b = np.minimum((radius * bins).astype(int), bins - 1)
    return np.where(radius < 1.0, spoke * bins + b, -1)


class Revolution:
    def __init__(self, cfg, topic: str, frame_id: str, body: int):
        self.cfg, self.topic, self.frame_id = cfg, topic, frame_id
        n, bins = cfg.spokes, cfg.range_bins
        self.echoes = np.zeros((n, bins), np.float32)
        self.power = np.ones((n, bins))
        self.pose = np.zeros((n, 3))  # antenna x, y (world ENU, m), yaw (ENU rad) at each spoke
        self.time_s = np.zeros(n)
        self.lookup = cartesian_lookup(cfg.image_size_px, n, bins) if cfg.image == "cartesian" else None
        self.tracker = Tracker(cfg.arpa) if cfg.arpa is not None else None
        self.body = body  # the own vessel's index, for its velocity

    def reset(self) -> None:
        self.echoes[:] = 0.0
        self.power[:] = 1.0
        if self.tracker is not None:
            self.tracker.reset()

    def add(self, world: World, stamp_ns: int, k0: int, power, echoes, pos, yaw) -> list[Envelope]:
        n = self.cfg.spokes
        rows = (k0 + np.arange(len(power))) % n
        self.power[rows], self.echoes[rows] = power, echoes
        self.pose[rows] = (pos[0], pos[1], yaw)
        self.time_s[rows] = stamp_ns / 1e9
        if (k0 + len(power)) // n == k0 // n:
            return []  # the turn goes on
        out = []
        if self.cfg.image != "none":
            out.append(Envelope(f"{self.topic}/image", stamp_ns, self._image(stamp_ns)))
        if self.tracker is not None:
            found = plots(self.power, self.pose, self.time_s, self.cfg)
            self.tracker.update(found, stamp_ns / 1e9)
            out.append(Envelope(f"{self.topic}/tracks", stamp_ns, self.tracker.message(stamp_ns, pos, world.origin_velocity(self.body)[:2])))
        return out

    def _image(self, stamp_ns: int):
        pixels = np.round(self.echoes * 255.0).astype(np.uint8)
        if self.lookup is not None:
            flat = np.append(pixels.reshape(-1), np.uint8(0))
            pixels = flat[self.lookup]  # -1 → the appended black pixel
        return ros.image_msg(stamp_ns, self.frame_id, np.ascontiguousarray(pixels), "mono8")


def spoke_angle(k: np.ndarray, spokes: int) -> np.ndarray:
    """Sensor-frame angle (rad, CCW from the bow) of spoke k."""
    return -(np.asarray(k) % spokes) * 2.0 * math.pi / spokes
