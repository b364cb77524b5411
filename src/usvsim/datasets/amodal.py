"""Amodal masks' pixel counts: each labelled object's pixels as if nothing else were in the scene.

An object's amodal mask is what the segmentation pass draws when only that object is in the scene (water,
other objects, own vessel hidden), clipped to the image like the amodal box. Rendering every object alone
costs one pass per object; objects whose amodal boxes do not overlap cannot cover one another's pixels (an
object's pixels lie inside its projected 3D box), so they are drawn together: one segmentation pass per group
of a greedy colouring of the box-overlap graph (typically 2-3 passes in `buoy_field`). Hidden geoms get alpha 0
(MuJoCo leaves them out of the scene); the model's colours are restored after the passes. The shader's water is
no geom: the passes leave it out explicitly (`water=False`); it hid the objects' parts below the waterline in their
"drawn alone" masks, so every visible fraction under `--renderer shader` was ~1.
"""

from __future__ import annotations

import numpy as np

from usvsim.sensors.camera.boxes2d import label_stats

PAD_PX = np.array([-1.0, -1.0, 1.0, 1.0])  # boxes grown by a pixel for grouping: rasterization at the rims


def groups_without_overlap(boxes: np.ndarray) -> list[list[int]]:
    """Greedy colouring: indices of boxes (n, 4: x0 y0 x1 y1, edge coordinates) in groups whose boxes are
    pairwise disjoint (boxes touching along an edge do not overlap)."""
    groups: list[list[int]] = []
    for i in np.argsort(-(boxes[:, 2] - boxes[:, 0]) * (boxes[:, 3] - boxes[:, 1]), kind="stable"):
        for g in groups:
            b = boxes[g]
            x0, y0, x1, y1 = boxes[i]
            if not np.any((b[:, 0] < x1) & (x0 < b[:, 2]) & (b[:, 1] < y1) & (y0 < b[:, 3])):
                g.append(int(i))
                break
        else:
            groups.append([int(i)])
    return groups


class AmodalCounter:
    """Pixel counts of objects' amodal masks from a camera (its renderer's segmentation pass)."""

    def __init__(self, model, objects, owner: np.ndarray):
        self.model, self.objects, self.owner = model, objects, owner

    def counts(self, cam, sim, pose, indices: list[int], boxes: np.ndarray) -> dict[int, int]:
        """{object index: amodal pixel count} for `indices` (object indices) with amodal `boxes` (same order)."""
        m, out = self.model, {}
        alpha = m.geom_rgba[:, 3].copy()
        try:
            for group in groups_without_overlap(boxes + PAD_PX):
                m.geom_rgba[:, 3] = 0.0
                for j in group:
                    geoms = self.objects[indices[j]].geoms
                    m.geom_rgba[geoms, 3] = alpha[geoms]
                seg = cam.render(sim, pose=pose, streams=("segmentation",), water=False)["segmentation"]
                pixels, _ = label_stats(seg, self.owner, len(self.objects))
                out.update({indices[j]: int(pixels[indices[j] + 1]) for j in group})
        finally:
            m.geom_rgba[:, 3] = alpha
        return out
