"""The sensor framework: a config becomes a sampler scheduled on the simulation clock.

A sensor is mounted on a vessel's body at a fixed pose in `base_link` (FLU). Its frame is
`<vessel>/<name>` (FLU); cameras add `<vessel>/<name>_optical` (z forward, x right, y down). It samples
every `every` physics steps (period = 1 / rate_hz, an exact multiple of the step) and its messages
reach subscribers `latency_steps` steps later, stamped with the sample time and with `publish_ns` = the
release time (what the MCAP recorder logs). Each sensor draws noise
from its own named stream `sensor/<vessel>/<name>`, so adding a sensor never changes another's noise.
"""

from __future__ import annotations

import math
from collections import deque
from typing import TYPE_CHECKING, Any

import numpy as np

from usvsim.core.clock import latency_steps, steps_per_period
from usvsim.core.transforms import matrix_from_quat, quat_from_rpy, quat_multiply
from usvsim.messages import ros
from usvsim.messages.envelope import Envelope
from usvsim.sensors.readings import Reading, reading

if TYPE_CHECKING:
    from usvsim.config.sensors import SensorBase
    from usvsim.world.world import World

# optical frame (z fwd, x right, y down) expressed in the FLU sensor frame: columns are optical axes
OPTICAL_ROT = np.array([[0.0, 0.0, 1.0], [-1.0, 0.0, 0.0], [0.0, -1.0, 0.0]])
OPTICAL_QUAT = np.array([0.5, -0.5, 0.5, -0.5])  # (w, x, y, z) of OPTICAL_ROT


class Sensor:
    """Base of every sensor. Subclasses implement `sample(sim, stamp_ns) -> list[Envelope]` and may set
    `observes_every_step` to get `observe(sim)` after every physics step (e.g. the IMU's finite difference)."""

    observes_every_step = False
    optical = False

    def __init__(self, cfg: SensorBase, vessel: str, sim: World):
        self.cfg, self.vessel = cfg, vessel
        self.body = sim.vessels[vessel].index
        self.name = f"{vessel}/{cfg.name}"
        self.frame_id = cfg.frame_id or self.name
        self.optical_frame_id = f"{self.frame_id}_optical"
        self.topic = cfg.topic or f"/{vessel}/{cfg.name}"
        self.every = steps_per_period(cfg.rate_hz, sim.clock.step_ns)
        self.latency_steps = latency_steps(cfg.latency_s, sim.clock.step_ns)
        m = cfg.mount
        self.mount_pos = np.array(m.position, dtype=float)
        self.mount_quat = quat_from_rpy(*(math.radians(a) for a in (m.roll_deg, m.pitch_deg, m.yaw_deg)))
        self.mount_rot = matrix_from_quat(self.mount_quat)
        self.rng = sim.rng.get(f"sensor/{self.name}")
        self.released: list[Envelope] = []  # the messages of the last sample released to subscribers
        self._reading: tuple[list[Envelope] | None, Reading | None] = (None, None)  # (of which sample, reading)
        self._read_of: list[Envelope] | None = None
        self._pending: deque[tuple[int, list[Envelope]]] = deque()

    # -- scheduling -------------------------------------------------------------------------------
    def tick(self, sim: World) -> list[Envelope]:
        """Called after every physics step: observe, sample when due, release what its latency allows."""
        steps, now_ns = sim.clock.steps, sim.clock.now_ns
        if self.observes_every_step:
            self.observe(sim)
        if steps > 0 and steps % self.every == 0:
            envs = self.sample(sim, now_ns)
            for env in envs:
                env.publish_ns = now_ns  # a LiDAR sweep stamped at its start is published at its end
            if self.latency_steps == 0:
                self.released = envs
                return envs
            self._pending.append((steps + self.latency_steps, envs))
        out: list[Envelope] = []
        while self._pending and self._pending[0][0] <= steps:
            self.released = self._pending.popleft()[1]
            for env in self.released:
                env.publish_ns = now_ns
            out += self.released
        return out

    def reset(self, sim: World) -> None:
        """Back to the state at construction (the world has been reset, random streams included).
        Subclasses with state of their own extend this."""
        self._pending.clear()
        self.released = []
        self._reading, self._read_of = (None, None), None

    # -- data as arrays (sensors/readings.py) ---------------------------------------------------
    @property
    def latest(self) -> Reading | None:
        """The last released sample as arrays (None before the first); converted once, on first access."""
        of, value = self._reading
        if of is not self.released:
            value = reading(self.released)
            self._reading = (self.released, value)
        return value

    def read(self) -> Reading | None:
        """The sample released since the previous `read()`, or None: poll it after every step."""
        if self._read_of is self.released:
            return None
        self._read_of = self.released
        return self.latest

    def observe(self, sim: World) -> None:  # pragma: no cover - overridden where used
        pass

    def sample(self, sim: World, stamp_ns: int) -> list[Envelope]:
        raise NotImplementedError

    # -- frames -----------------------------------------------------------------------------------
    def pose_world(self, sim: World) -> tuple[np.ndarray, np.ndarray]:
        """Sensor frame origin (ENU, m) and rotation matrix sensor (FLU) → world (ENU)."""
        rot_body = sim.state.rot[self.body]
        return sim.state.pos[self.body] + rot_body @ self.mount_pos, rot_body @ self.mount_rot

    def quat_world(self, sim: World) -> np.ndarray:
        """Orientation (w, x, y, z) of the sensor frame w.r.t. world ENU."""
        return quat_multiply(sim.body_quat(self.body), self.mount_quat)

    def static_transforms(self) -> list[Any]:
        """`<vessel>/base_link → frame_id` (and `frame_id → frame_id_optical` for cameras), stamp 0."""
        out = [ros.transform_stamped(0, f"{self.vessel}/base_link", self.frame_id, self.mount_pos, self.mount_quat)]
        if self.optical:
            out.append(ros.transform_stamped(0, self.frame_id, self.optical_frame_id, np.zeros(3), OPTICAL_QUAT))
        return out


def gaussian(rng: np.random.Generator, stddev: float, shape=3) -> np.ndarray:
    """Zero-mean Gaussian noise, or exact zeros (no draw) when stddev is 0."""
    return rng.normal(0.0, stddev, shape) if stddev > 0 else np.zeros(shape)


def diagonal_covariance(variances) -> np.ndarray:
    """3x3 row-major covariance (9,) with the given diagonal."""
    out = np.zeros(9)
    out[::4] = variances  # a number or three (per axis)
    return out
