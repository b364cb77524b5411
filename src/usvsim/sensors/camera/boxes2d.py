"""Ground-truth 2D boxes of one camera frame (vision_msgs/Detection2D), from the frame's own segmentation.

Visibility (occlusion): an object is reported when at least `min_visible_pixels` pixels of the frame's
segmentation belong to its visual geoms, so objects hidden behind others, below the water surface or outside
the image are left out, and the box never describes an object the image does not show.

Box (`box` in the config), in published-image pixels (pixel centres at integers, u right, v down):
- `projected` (default): the 3D box (sensors/objects.py) projected with the camera's CameraInfo model,
  distortion included: its faces clipped against the view frustum, projected and clipped to the image
  [-0.5, W-0.5] x [-0.5, H-0.5] (camera/clip.py), so objects cut by the image edge or reaching behind the
  camera get the box of their part in view (the amodal box).
- `visible`: the tight box around the object's visible pixels (modal box: occluded parts are not included).
The hypothesis pose is the object's box pose in the camera's optical frame.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from usvsim.sensors.camera.clip import camera_planes, image_box
from usvsim.sensors.camera.intrinsics import Intrinsics
from usvsim.sensors.detections import quat_of
from usvsim.sensors.messages import detection2d_msg
from usvsim.sensors.objects import TrackedObject, geom_owner


@njit(cache=True, nogil=True)
def label_stats(seg, owner, n_objects):
    """Pixel count and pixel bounds (u_min, v_min, u_max, v_max) per object (row k + 1 for object k)."""
    counts = np.zeros(n_objects + 1, np.int64)
    bounds = np.empty((n_objects + 1, 4), np.int64)
    bounds[:, 0] = bounds[:, 1] = 1 << 30
    bounds[:, 2] = bounds[:, 3] = -1
    for v in range(seg.shape[0]):
        for u in range(seg.shape[1]):
            k = owner[min(np.int64(seg[v, u]), owner.shape[0] - 1)]
            if k > 0:
                counts[k] += 1
                bounds[k, 0], bounds[k, 1] = min(bounds[k, 0], u), min(bounds[k, 1], v)
                bounds[k, 2], bounds[k, 3] = max(bounds[k, 2], u), max(bounds[k, 3], v)
    return counts, bounds


class BoxMaker:
    """Makes a camera's Detection2D messages for the selected objects from (segmentation, camera pose)."""

    def __init__(self, rule, objects: list[TrackedObject], model, cam: Intrinsics, near_m: float):
        self.rule, self.objects, self.cam, self.near_m = rule, objects, cam, near_m
        self.owner = geom_owner(model, objects)
        self.planes = camera_planes(cam, near_m)

    def project(self, corners_optical: np.ndarray) -> np.ndarray | None:
        """Pixel box (u_min, v_min, u_max, v_max) of a 3D box (8 corners, optical frame) clipped to the view
        frustum and the image (camera/clip.py); None if no part of it is in view."""
        return image_box(corners_optical, self.cam, self.planes)

    def visible(self, seg: np.ndarray) -> list[tuple[int, np.ndarray]]:
        """(object index, pixel box of its visible pixels) of every object with enough visible pixels."""
        counts, bounds = label_stats(seg, self.owner, len(self.objects))
        keep = np.flatnonzero(counts[1:] >= self.rule.min_visible_pixels)
        return [(int(k), bounds[k + 1] + np.array([-0.5, -0.5, 0.5, 0.5])) for k in keep]

    def detections(self, sim, seg: np.ndarray, pos_world, rot_optical, stamp_ns: int, frame_id: str) -> list:
        """Detection2D messages of the frame; `rot_optical`: optical frame → world rotation, camera at `pos_world`."""
        out = []
        for k, pixel_box in self.visible(seg):
            obj = self.objects[k]
            corners = (obj.corners_world(sim) - pos_world) @ rot_optical
            box = pixel_box if self.rule.box == "visible" else self.project(corners)
            if box is None:
                continue
            center, axes = obj.pose_world(sim)
            center_opt, axes_opt = (center - pos_world) @ rot_optical, rot_optical.T @ axes
            out.append(detection2d_msg(stamp_ns, frame_id, obj.name, obj.label, box, center_opt, quat_of(axes_opt)))
        return out
