"""Per-frame labels from a camera's segmentation: instance and semantic masks, visible and amodal boxes.

Classes (fixed ids, the same in every scenario, so data sets can be merged): 0 sky, 1 water, 2 other (the
camera's own vessel and unlabelled world geometry), then the detectable classes of sensors/objects.py. Each
class belongs to one of the MaSTr1325/LaRS groups: sky, water, static obstacle, dynamic obstacle.

Boxes are in pixel-edge coordinates (COCO: the pixel at column u covers [u, u + 1)):
- visible box: the tight box of the object's visible pixels (modal; occluders and the image edge cut it);
- amodal box: the object's 3D box projected, clipped against the view frustum and the image
  (sensors/camera/clip.py): where the whole object would be if nothing hid it;
- visible_fraction: visible pixels / pixels of the amodal mask (the object drawn alone, clipped to the
  image; datasets/amodal.py), in 0–1 (1: unoccluded); truncated: the amodal box reaches the image edge.

In fog, a pixel is visible only where the fog's transmittance along its ray reaches Koschmieder's 2 %
(datasets/fog_sight.py): pixels the fog hides count nowhere (pixel counts, visible box, fraction, instance
mask), and fog_transmittance is the mean transmittance over the visible pixels (1.0 without fog).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from usvsim.config.objects import COLORS
from usvsim.datasets.fog_sight import FogFrame
from usvsim.sensors.camera.boxes2d import label_stats
from usvsim.sensors.camera.clip import image_box
from usvsim.sensors.objects import TrackedObject, geom_owner
from usvsim.world.builder import WATER_GROUP

STATIC = ("dock", "wall", "box", "pier", "berth", "mesh", "land", "structure")
CLASSES = ("sky", "water", "other", "vessel", *(f"buoy_{c}" for c in COLORS), *STATIC)
GROUPS = {"sky": "sky", "water": "water", "other": "static_obstacle", "vessel": "dynamic_obstacle",
          **{f"buoy_{c}": "dynamic_obstacle" for c in COLORS}, **dict.fromkeys(STATIC, "static_obstacle")}  # fmt: skip
FIRST_OBJECT_CLASS = CLASSES.index("vessel")
DETECTABLE = CLASSES[FIRST_OBJECT_CLASS:]


@dataclass(frozen=True)
class ObjectLabel:
    """One object visible in a frame; boxes (x_min, y_min, x_max, y_max) in pixel-edge coordinates."""

    instance: int  # value in the instance mask (object index + 1)
    name: str
    category: str
    visible_box: tuple[float, float, float, float]
    amodal_box: tuple[float, float, float, float]
    visible_pixels: int
    visible_fraction: float
    truncated: bool
    fog_transmittance: float = 1.0  # mean over the visible pixels of exp(-fog optical depth) along the ray


class Labeller:
    """Masks and object labels of one camera's frames for the scenario's `objects` (own vessel left out)."""

    def __init__(self, model, objects: list[TrackedObject], cam, near_m: float, planes):
        self.objects, self.cam, self.planes = objects, cam, planes
        self.owner = geom_owner(model, objects)  # geom id + 1 → object index + 1
        sem = np.full(model.ngeom + 1, CLASSES.index("other"), np.uint8)
        sem[0] = CLASSES.index("sky")
        sem[1:][model.geom_group == WATER_GROUP] = CLASSES.index("water")
        for obj in objects:
            sem[obj.geoms + 1] = CLASSES.index(obj.label)
        self.semantic_lut = sem
        self.instance_lut = self.owner.astype(np.uint16)

    def masks(self, seg: np.ndarray, labels: list[ObjectLabel], hidden: np.ndarray | None = None):
        """(instance mask uint16: object index + 1 of the `labels`' objects, 0 elsewhere; semantic mask uint8:
        class id) of a segmentation. Objects left out of the labels (fewer visible pixels or a smaller fraction
        than asked, or hidden by fog) are 0 in the instance mask, which holds only ids that have an annotation;
        they keep their class in the semantic mask. `hidden` (FogFrame.hidden): pixels the fog hides, 0 in the
        instance mask too."""
        keep = np.zeros(len(self.objects) + 1, bool)
        keep[[label.instance for label in labels]] = True
        instance = np.where(keep[self.instance_lut], self.instance_lut, 0).astype(np.uint16)[seg]
        if hidden is not None:
            instance[hidden] = 0
        return instance, self.semantic_lut[seg]

    def objects_in(self, sim, seg: np.ndarray, pos_world, rot_optical, min_pixels: int, min_fraction: float,
                   amodal_pixels=None, fog: FogFrame | None = None):  # fmt: skip
        """ObjectLabel of every object with at least `min_pixels` visible pixels and `min_fraction`.
        `amodal_pixels(indices, boxes)` → {object index: amodal mask pixels} (datasets/amodal.py); None: the
        fraction falls back to the boxes' area ratio. `fog` (FogSight.frame): only pixels the fog leaves
        visible count; it marks the others in `fog.hidden`."""
        if fog is None:
            counts, bounds = label_stats(seg, self.owner, len(self.objects))
            keep_sum = counts.astype(np.float64)
        else:
            counts, bounds, keep_sum = fog.stats(seg, self.owner, len(self.objects))
        found = [int(k) for k in np.flatnonzero(counts[1:] >= max(min_pixels, 1))]
        boxes = {k: self._boxes(sim, k, bounds[k + 1], pos_world, rot_optical) for k in found}
        amodal_n = None
        if amodal_pixels is not None and found:
            amodal_n = amodal_pixels(found, np.array([boxes[k][1] for k in found]))
        w, h = self.cam.width, self.cam.height
        out = []
        for k in found:
            visible, amodal = boxes[k]
            if amodal_n is not None:
                fraction = counts[k + 1] / max(amodal_n[k], counts[k + 1])
            else:
                area = (amodal[2] - amodal[0]) * (amodal[3] - amodal[1])
                fraction = float((visible[2] - visible[0]) * (visible[3] - visible[1]) / area)
            if fraction < min_fraction:
                continue
            truncated = bool(amodal[0] <= 0 or amodal[1] <= 0 or amodal[2] >= w or amodal[3] >= h)
            out.append(ObjectLabel(int(k + 1), self.objects[k].name, self.objects[k].label, tuple(visible.tolist()),
                                   tuple(amodal.tolist()), int(counts[k + 1]), min(float(fraction), 1.0), truncated,
                                   float(keep_sum[k + 1] / counts[k + 1])))  # fmt: skip
        return out

    def _boxes(self, sim, k: int, pixel_bounds, pos_world, rot_optical):
        """(visible box, amodal box) of object k in pixel-edge coordinates; the amodal box contains the visible."""
        w, h = self.cam.width, self.cam.height
        obj = self.objects[k]
        amodal = image_box((obj.corners_world(sim) - pos_world) @ rot_optical, self.cam, self.planes)
        visible = pixel_bounds.astype(float) + np.array([0.0, 0.0, 1.0, 1.0])  # pixel edges
        if amodal is None:  # rendered pixels of a box the projection misses: only at the rim, by rounding
            amodal = visible - 0.5
        amodal = np.minimum(np.maximum(amodal + 0.5, 0.0), [w, h, w, h])  # pixel-centre → edge coordinates
        return visible, np.concatenate([np.minimum(amodal[:2], visible[:2]), np.maximum(amodal[2:], visible[2:])])
