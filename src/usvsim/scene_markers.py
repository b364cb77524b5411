"""The scene as `visualization_msgs/MarkerArray`s, so RViz and Foxglove draw the boats, buoys and obstacles from
ROS 2 topics and from recordings (messages/markers.py says how a part becomes a marker).

- `/usvsim/markers` (latched: transient_local, depth 1, like /tf_static; stamp 0, once per episode and to a
  subscriber or recording that joins later): each vessel's drawn parts (its visuals, or its physics hull) in
  `<v>/base_link`, frame-locked, so `/tf` moves them (namespace `vessel/<v>`), and the static obstacles (docks,
  piers, berths, walls, mesh obstacles, anchors) in `world` (namespace `obstacles`).
- `/usvsim/markers/bodies` every `outputs.markers.bodies_rate_hz` of simulation time: the floating bodies that
  are not vessels (buoys: they have no TF frame) at their current poses in `world` (namespace `body/<b>`).

Set in `outputs.markers` (`scene: false` or `bodies_rate_hz: null` turns either off).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from usvsim.core.clock import steps_per_period
from usvsim.core.transforms import quat_multiply
from usvsim.messages.envelope import MARKERS_TOPIC, Envelope
from usvsim.messages.markers import MovingMarkers, marker_array, part_marker
from usvsim.world.shapes import drawn_parts, static_parts

if TYPE_CHECKING:
    from usvsim.world.world import World

BODIES_TOPIC = MARKERS_TOPIC + "/bodies"
MARKER_ARRAY = "visualization_msgs/msg/MarkerArray"
WORLD_FRAME = "world"


class SceneMarkers:
    """Builds the scene's marker arrays from a world (call from the simulation thread)."""

    def __init__(self, world: World, scene: bool, bodies_rate_hz: float | None):
        self.world = world
        self.scene = scene
        self.bodies = [b for name, b in world.bodies.items() if name not in world.vessels]
        self.every = steps_per_period(bodies_rate_hz, world.clock.step_ns) if bodies_rate_hz and self.bodies else 0
        self._static: Any = None  # the /usvsim/markers message (the geometry never changes)
        self._moving: MovingMarkers | None = None  # the bodies' array, made on first use
        self._parts: tuple[np.ndarray, np.ndarray, np.ndarray] = (np.zeros(0, np.intp), np.zeros((0, 3)), np.zeros((0, 4)))

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
            self._static = marker_array([m for m in markers if m is not None])
        return [Envelope(MARKERS_TOPIC, 0, self._static)]

    def due(self, steps: int, stamp_ns: int) -> list[Envelope]:
        """`/usvsim/markers/bodies` when its period divides the physics step count `steps` (its CDR bytes made by
        patching the stamps and poses into the array serialized once: messages/markers.py `MovingMarkers`)."""
        if not self.every or steps % self.every:
            return []
        moving = self._moving if self._moving is not None else self._build_moving()
        index, part_pos, part_quat = self._parts
        state = self.world.state
        rot, body_pos = state.rot[index], state.pos[index]
        positions = body_pos + np.einsum("nij,nj->ni", rot, part_pos)
        body_quat = self.world.data.qpos[self.world.qpos_adr[index][:, None] + np.arange(3, 7)]  # (w, x, y, z)
        body_quat = body_quat / np.linalg.norm(body_quat, axis=1, keepdims=True)  # as World.body_quat
        quats = quat_multiply(body_quat.T, part_quat.T).T
        return [Envelope(BODIES_TOPIC, stamp_ns, msgtype=MARKER_ARRAY, cdr=moving.cdr(stamp_ns, positions, quats))]

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
        self._moving = MovingMarkers(markers)
        return self._moving
