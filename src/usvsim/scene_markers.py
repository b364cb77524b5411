"""The scene as `visualization_msgs/MarkerArray`s, so RViz and Foxglove draw the boats, buoys and obstacles from
ROS 2 topics and from recordings (messages/markers.py says how a part becomes a marker).

- `/usvsim/markers` (latched: transient_local, depth 1, like /tf_static; stamp 0, once per episode and to a
  subscriber or recording that joins later): each vessel's drawn parts (its visuals, or its physics hull) in
  `<v>/base_link`, frame-locked, so `/tf` moves them (namespace `vessel/<v>`), and the static obstacles (docks,
  piers, berths, walls, mesh obstacles, anchors) in `world` (namespace `obstacles`).
- `/usvsim/markers/bodies` every `outputs.markers.bodies_rate_hz` of simulation time: the floating bodies that
  are not vessels (buoys: they have no TF frame) at their current poses in `world` (namespace `body/<b>`), and
  the kinematic traffic ships (`traffic.ships` without `vessel`: hull and superstructure, namespace `ship/<s>`).

Set in `outputs.markers` (`scene: false` or `bodies_rate_hz: 0` turns either off; `bodies_rate_hz: null`: 10 Hz, or
the nearest rate below that fits the physics step).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np
from numba import njit

from usvsim.core.clock import steps_per_period
from usvsim.messages.envelope import MARKERS_TOPIC, Envelope
from usvsim.messages.markers import MovingMarkers, marker_array, part_marker
from usvsim.world.shapes import drawn_parts, kinematic_parts, static_parts

if TYPE_CHECKING:
    from usvsim.world.world import World

BODIES_TOPIC = MARKERS_TOPIC + "/bodies"
MARKER_ARRAY = "visualization_msgs/msg/MarkerArray"
WORLD_FRAME = "world"


class SceneMarkers:
    """Builds the scene's marker arrays from a world (call from the simulation thread)."""

    def __init__(self, world: World, scene: bool, bodies_rate_hz: float):
        """`bodies_rate_hz`: the rate of `/usvsim/markers/bodies` (Hz of simulation time, a whole number of physics
        steps; 0: off)."""
        self.world = world
        self.scene = scene
        self.bodies = [b for name, b in world.bodies.items() if name not in world.vessels]
        self.ships = kinematic_parts(world.model)  # (geom id, ship, part): traffic ships moved by the kernel
        moving = self.bodies or self.ships
        self.every = steps_per_period(bodies_rate_hz, world.clock.step_ns) if bodies_rate_hz and moving else 0
        self._ship_geoms = np.zeros(0, np.intp)  # the ship markers' geom ids (they follow the bodies' markers)
        self._static: tuple[Any, bytes] | None = None  # the /usvsim/markers message and its CDR (never change)
        self._moving: MovingMarkers | None = None  # the bodies' array, made on first use
        # the bodies' markers: their body index, pose in the body frame (position m; quaternion w, x, y, z)
        self._parts: tuple[np.ndarray, np.ndarray, np.ndarray] = (np.zeros(0, np.intp), np.zeros((0, 3)),
                                                                   np.zeros((0, 4)))  # fmt: skip
        self._poses = np.zeros((0, 7))  # per marker: x, y, z, qx, qy, qz, qw in world

    def static(self) -> list[Envelope]:
        """The latched `/usvsim/markers` message (stamp 0), or nothing when turned off."""
        if not self.scene:
            return []
        if self._static is None:
            markers = []
            for name, vessel in self.world.vessels.items():
                parts = drawn_parts(vessel.model)
                markers += [part_marker(p, 0, f"{name}/base_link", f"vessel/{name}", k, frame_locked=True)
                            for k, p in enumerate(parts)]  # fmt: skip
            markers += [part_marker(p, 0, WORLD_FRAME, "obstacles", k)
                        for k, p in enumerate(static_parts(self.world.model))]  # fmt: skip
            msg = marker_array([m for m in markers if m is not None])
            self._static = (msg, Envelope(MARKERS_TOPIC, 0, msg).cdr)  # ~150 kB for the harbour: serialized once
        return [Envelope(MARKERS_TOPIC, 0, self._static[0], cdr=self._static[1])]

    def due(self, steps: int, stamp_ns: int) -> list[Envelope]:
        """`/usvsim/markers/bodies` when its period divides the physics step count `steps` (its CDR bytes made by
        patching the stamps and poses into the array serialized once: messages/markers.py `MovingMarkers`)."""
        if not self.every or steps % self.every:
            return []
        moving = self._moving if self._moving is not None else self._build_moving()
        world = self.world
        _place_parts(world.state.pos, world.state.rot, world.data.qpos, world.qpos_adr, *self._parts, self._poses)
        if len(self._ship_geoms):  # world-body geoms: their model pose is their world pose (w, x, y, z)
            n, geoms = len(self._parts[0]), self._ship_geoms
            self._poses[n:, :3] = world.model.geom_pos[geoms]
            self._poses[n:, 3:6], self._poses[n:, 6] = world.model.geom_quat[geoms, 1:], world.model.geom_quat[geoms, 0]
        return [Envelope(BODIES_TOPIC, stamp_ns, msgtype=MARKER_ARRAY, cdr=moving.cdr(stamp_ns, self._poses))]

    def _build_moving(self) -> MovingMarkers:
        markers, index, pos, quat = [], [], [], []
        for body in self.bodies:
            for k, part in enumerate(drawn_parts(body.model)):
                marker = part_marker(part, 0, WORLD_FRAME, f"body/{body.name}", k)
                if marker is not None:
                    markers.append(marker)
                    index.append(body.index)
                    pos.append(part.pos)
                    quat.append(part.quat)
        self._parts = (np.array(index, dtype=np.intp), np.array(pos, float).reshape(-1, 3),
                       np.array(quat, float).reshape(-1, 4))  # fmt: skip
        ship_ids: dict[str, int] = {}
        geoms = []
        for g, ship, part in self.ships:
            marker = part_marker(part, 0, WORLD_FRAME, f"ship/{ship}", ship_ids.setdefault(ship, 0))
            if marker is not None:
                markers.append(marker)
                geoms.append(g)
                ship_ids[ship] += 1
        self._ship_geoms = np.array(geoms, dtype=np.intp)
        self._poses = np.zeros((len(markers), 7))
        self._moving = MovingMarkers(markers)
        return self._moving


@njit(cache=True)
def _place_parts(pos, rot, qpos, qpos_adr, index, part_pos, part_quat, out):
    """out[k] = the world pose of part k (x, y, z m; quaternion x, y, z, w) of body index[k]: its body-frame pose
    `part_pos`, `part_quat` (w, x, y, z) placed by the body's base_link pose (pos, rot: World's state; the
    orientation from the free joint's quaternion in qpos, normalized as World.body_quat)."""
    for k in range(len(index)):
        b = index[k]
        for i in range(3):
            out[k, i] = pos[b, i] + rot[b, i, 0] * part_pos[k, 0] + rot[b, i, 1] * part_pos[k, 1] \
                + rot[b, i, 2] * part_pos[k, 2]
        a = qpos_adr[b] + 3
        n = np.sqrt(qpos[a] ** 2 + qpos[a + 1] ** 2 + qpos[a + 2] ** 2 + qpos[a + 3] ** 2)
        aw, ax, ay, az = qpos[a] / n, qpos[a + 1] / n, qpos[a + 2] / n, qpos[a + 3] / n
        bw, bx, by, bz = part_quat[k, 0], part_quat[k, 1], part_quat[k, 2], part_quat[k, 3]
        out[k, 3] = aw * bx + ax * bw + ay * bz - az * by
        out[k, 4] = aw * by - ax * bz + ay * bw + az * bx
        out[k, 5] = aw * bz + ax * by - ay * bx + az * bw
        out[k, 6] = aw * bw - ax * bx - ay * by - az * bz
