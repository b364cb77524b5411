"""Ground-truth detections: 3D boxes of the scene's objects (vision_msgs/Detection3DArray).

The objects and their boxes are defined in sensors/objects.py; 2D boxes per camera are made by the camera
itself (camera/boxes2d.py) from the same objects, so both agree. Boxes are exact: no noise, score 1.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import mujoco
import numpy as np

from usvsim.messages.envelope import Envelope
from usvsim.sensors.base import Sensor
from usvsim.sensors.messages import detection3d_msg, detection_array_msg
from usvsim.sensors.objects import TrackedObject, catalogue

if TYPE_CHECKING:
    from usvsim.config.sensors import Detections as DetectionsConfig
    from usvsim.config.sensors import ObjectFilter
    from usvsim.world.world import World

OBJECTS_KEY = "objects"  # the suite's one object catalogue in `shared`
WORLD_FRAME = "world"


def shared_objects(sim: World, shared: dict) -> list[TrackedObject]:
    """The scene's objects, built once per suite."""
    if OBJECTS_KEY not in shared:
        shared[OBJECTS_KEY] = catalogue(sim)
    return shared[OBJECTS_KEY]


def selected(objects: list[TrackedObject], rule: ObjectFilter, vessel: str) -> list[TrackedObject]:
    """The objects a sensor on `vessel` reports under `rule` (categories, own vessel)."""
    return [o for o in objects if o.category in rule.categories and (rule.include_own_vessel or
            not (o.category == "vessel" and o.name == vessel))]  # fmt: skip


def quat_of(rot: np.ndarray) -> np.ndarray:
    """Quaternion (w, x, y, z) of a rotation matrix."""
    quat = np.zeros(4)
    mujoco.mju_mat2Quat(quat, np.ascontiguousarray(rot, dtype=float).reshape(9))
    return quat


class Detections3D(Sensor):
    """Oriented 3D boxes of the selected objects in `world` or in the sensor frame, on `/<vessel>/<name>`."""

    cfg: DetectionsConfig

    def __init__(self, cfg: DetectionsConfig, vessel: str, sim: World, shared: dict):
        super().__init__(cfg, vessel, sim)
        self.objects = selected(shared_objects(sim, shared), cfg, vessel)

    def boxes(self, sim: World) -> list[tuple[TrackedObject, np.ndarray, np.ndarray]]:
        """(object, box centre, box axes → output frame rotation) in the output frame, range-filtered."""
        pos, rot = self.pose_world(sim)
        out = []
        for obj in self.objects:
            center, axes = obj.pose_world(sim)
            if self.cfg.range_max_m is not None and np.linalg.norm(center - pos) > self.cfg.range_max_m:
                continue
            if self.cfg.frame == "sensor":
                center, axes = rot.T @ (center - pos), rot.T @ axes
            out.append((obj, center, axes))
        return out

    def sample(self, sim: World, stamp_ns: int) -> list[Envelope]:
        frame = WORLD_FRAME if self.cfg.frame == "world" else self.frame_id
        detections = [detection3d_msg(stamp_ns, frame, obj.name, obj.label, center, quat_of(axes), obj.size_m)
                      for obj, center, axes in self.boxes(sim)]  # fmt: skip
        return [Envelope(self.topic, stamp_ns, detection_array_msg(stamp_ns, frame, detections, 3))]
