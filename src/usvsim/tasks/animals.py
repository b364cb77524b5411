"""The wildlife task's moving animals, as in VRX's `practice_2023_wildlife0_task.sdf`.

VRX's animals (crocodile, platypus, turtle) are free floating models with buoyancy and drag
(PolyhedraBuoyancyDrag, linear drag 25) moved by gz-sim's TrajectoryFollower system: it turns the animal
with a constant yaw torque until the next waypoint lies within ±2° of its heading, then pushes it with a
constant force along its heading until the waypoint is within 0.5 m, and loops over the waypoints. Each
animal shuttles between two waypoints 3–4 m apart (force 18 N / torque 1.5 N m; the turtle 6 N / 1 N m). The
scoring plugin tracks the animals where they are: engagement distance and the 8 virtual gates follow them.

Here the animals are free (unmoored) buoys with the same linear drag, and `AnimalMotion` applies the same
rule through MuJoCo's `qfrc_applied` (world-frame force at the CoM, yaw torque), set after every physics
step for the next one. Positions are VRX's, moved into the task's frame: the WAM-V starts at the origin
heading east, where VRX spawns it at (-532, 162) with yaw 1 rad (vrx_gz/launch/competition.launch.py).
"""

from __future__ import annotations

import math

import numpy as np

VRX_START = (-532.0, 162.0, 1.0)  # WAM-V spawn in VRX's world: x, y (m), yaw (rad)
VRX_ANIMALS = {  # name: (goal, pose x y, TrajectoryFollower waypoints, force N, torque N m), VRX world frame
    "crocodile": ("avoid", (-520.0, 180.0), [(-523.0, 179.0), (-520.0, 180.0)], 18.0, 1.5),
    "platypus": ("circumnavigate_clockwise", (-500.0, 210.0), [(-496.0, 211.0), (-500.0, 210.0)], 18.0, 1.5),
    "turtle": ("circumnavigate_counterclockwise", (-550.0, 230.0), [(-551.0, 233.0), (-550.0, 230.0)], 6.0, 1.0),
}
RANGE_TOLERANCE_M, BEARING_TOLERANCE_RAD = 0.5, math.radians(2.0)  # gz-sim TrajectoryFollower defaults


def task_frame(x: float, y: float) -> tuple[float, float]:
    """A point of VRX's wildlife world in the task frame (WAM-V start at the origin, heading east)."""
    x0, y0, yaw = VRX_START
    dx, dy, c, s = x - x0, y - y0, math.cos(yaw), math.sin(yaw)
    return c * dx + s * dy, -s * dx + c * dy


ANIMALS = {name: (task_frame(*pose), goal) for name, (goal, pose, _, _, _) in VRX_ANIMALS.items()}


class AnimalMotion:
    """TrajectoryFollower for every animal body of a bound task (`apply(world)` after each physics step)."""

    def __init__(self, names: list[str]):
        self.names = names
        self.paths = {n: [task_frame(*w) for w in VRX_ANIMALS[n][2]] for n in names}
        self.reset()

    def reset(self) -> None:
        self.target = dict.fromkeys(self.names, 0)

    def apply(self, world) -> None:
        world = getattr(world, "world", world)  # a Simulation delegates to its World
        for name in self.names:
            i = world.bodies[name].index
            d = world.qvel_adr[i]
            world.data.qfrc_applied[d : d + 6] = self._wrench(name, world.state.pos[i], world.state.rot[i])

    def _wrench(self, name: str, pos: np.ndarray, rot: np.ndarray) -> np.ndarray:
        """Free-joint generalized force: world-frame force (N) at the CoM, torque (N m) in the body frame."""
        _, _, _, force_n, torque_nm = VRX_ANIMALS[name]
        path = self.paths[name]
        tx, ty = path[self.target[name]]
        if math.hypot(tx - pos[0], ty - pos[1]) <= RANGE_TOLERANCE_M:
            self.target[name] = (self.target[name] + 1) % len(path)
            tx, ty = path[self.target[name]]
        heading = math.atan2(rot[1, 0], rot[0, 0])
        bearing = math.remainder(math.atan2(ty - pos[1], tx - pos[0]) - heading, 2 * math.pi)
        out = np.zeros(6)
        if abs(bearing) > BEARING_TOLERANCE_RAD:
            out[3:] = rot[2, :] * math.copysign(torque_nm, bearing)  # world z torque in the body frame
        else:
            out[:2] = force_n * math.cos(heading), force_n * math.sin(heading)
        return out
