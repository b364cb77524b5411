"""Ground-truth outputs of the simulation: /clock, /tf_static, /tf, per-vessel odometry, the episode marker.

Episodes: `Simulation.reset` starts a new episode at t = 0. Its first messages are `/usvsim/episode`
(std_msgs/String, JSON `{"episode": k, "seed": s}`, stamp 0, latched like /tf_static), then /tf_static and
the t = 0 messages. `/clock` and every stamp restart at 0 in each episode (simulation time is per
episode); the MCAP recorder keeps its log times increasing across episodes (see io/mcap_recorder.py).

Frames (REP 105): `world` is ENU at the geodetic origin; `<vessel>/odom` is fixed in the world at the
vessel's initial pose (static TF `world → <vessel>/odom`); `<vessel>/base_link` is the body frame
(FLU). `outputs.tf` turns either transform off for nodes that publish their own (SLAM, robot_localization). Odometry `/<vessel>/ground_truth/odometry` gives base_link in `<vessel>/odom`, twist in base_link.
"""

from __future__ import annotations

import json
from typing import TYPE_CHECKING

from usvsim.core.clock import steps_per_period
from usvsim.core.transforms import matrix_from_quat, quat_conjugate, quat_multiply
from usvsim.messages import ros
from usvsim.messages.envelope import EPISODE_TOPIC, Envelope

if TYPE_CHECKING:
    from usvsim.world.world import World


class GroundTruth:
    def __init__(self, world: World, clock_rate_hz: float, odometry_rate_hz: float):
        self.world = world
        self.clock_every = steps_per_period(clock_rate_hz, world.clock.step_ns)
        self.odom_every = steps_per_period(odometry_rate_hz, world.clock.step_ns)
        self.vessels = list(world.vessels.values())
        self.odom_origin = world.odom_origin
        self.tf = world.scenario.outputs.tf

    def static_transforms(self, extra=()) -> list[Envelope]:
        """The one `/tf_static` message: `world → <vessel>/odom` plus `extra` transforms (sensor mounts)."""
        transforms = [ros.transform_stamped(0, "world", f"{name}/odom", pos, quat)
                      for name, (pos, quat) in self.odom_origin.items() if self.tf.world_to_odom]  # fmt: skip
        transforms += list(extra)
        return [Envelope("/tf_static", 0, ros.tf_message(transforms))] if transforms else []

    @staticmethod
    def episode(index: int, seed: int) -> Envelope:
        """The episode marker (stamp 0: the episode's start)."""
        text = json.dumps({"episode": index, "seed": seed})
        return Envelope(EPISODE_TOPIC, 0, ros.msg_class("std_msgs/msg/String")(data=text))

    def due(self, steps: int, stamp_ns: int) -> list[Envelope]:
        """Messages due at physics step count `steps` (time `stamp_ns`)."""
        out = []
        if steps % self.clock_every == 0:
            out.append(Envelope("/clock", stamp_ns, ros.clock_msg(stamp_ns)))
        if steps % self.odom_every == 0 and self.vessels:
            out += self._odometry(stamp_ns)
        return out

    def _odometry(self, stamp_ns: int) -> list[Envelope]:
        out, transforms = [], []
        for v in self.vessels:
            origin_pos, origin_quat = self.odom_origin[v.name]
            inv = quat_conjugate(origin_quat)
            pos = matrix_from_quat(inv) @ (v.position - origin_pos)
            quat = quat_multiply(inv, v.quat)
            odom, base = f"{v.name}/odom", f"{v.name}/base_link"
            msg = ros.odometry_msg(stamp_ns, odom, base, pos, quat, v.velocity_body, v.angular_velocity_body)
            out.append(Envelope(f"/{v.name}/ground_truth/odometry", stamp_ns, msg))
            transforms.append(ros.transform_stamped(stamp_ns, odom, base, pos, quat))
        if self.tf.odom_to_base_link:
            out.append(Envelope("/tf", stamp_ns, ros.tf_message(transforms)))
        return out

