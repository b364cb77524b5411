"""Material classes for the geoms of the shader look: how shiny each surface is under the sun.

MuJoCo's renderer lights geoms with a Phong model (specular level, shininess = exponent / 128); this assigns
each visual geom one of a small set of classes, once per model, and writes them into the scene's geoms each
frame (the model and MuJoCo's plain look are untouched). The class comes from what the geom is: on a vessel,
dark parts are rubber (inflatable pontoons, fenders), light grey or white parts metal (frames, superstructure),
the rest painted hull; floating bodies that are not vessels are buoy plastic; static geoms by their paint
(the object library's `wood`, `concrete`, `grey`) are wood, concrete and metal; anything else is paint.
Values are Phong approximations of the materials' gloss, not a physically based BRDF.
"""

from __future__ import annotations

import mujoco
import numpy as np

CLASSES = {  # name: (specular, shininess)
    "paint": (0.35, 0.55),
    "metal": (0.7, 0.8),
    "rubber": (0.08, 0.15),
    "plastic": (0.45, 0.45),
    "wood": (0.06, 0.1),
    "concrete": (0.04, 0.05),
}


def _close(rgba, ref) -> bool:
    return bool(np.max(np.abs(np.asarray(rgba[:3]) - np.asarray(ref[:3]))) < 0.02)


def geom_classes(model: mujoco.MjModel, vessels, bodies) -> dict[int, str]:
    """Geom id → class name for the visual geoms (group 1) of `model`."""
    from usvsim.config.objects import COLORS

    vessel_ids = {model.body(n).id for n in vessels}
    floating_ids = {model.body(n).id for n in bodies}
    out = {}
    for g in np.flatnonzero(model.geom_group == 1):
        rgba, body = model.geom_rgba[g], int(model.geom_bodyid[g])
        grey = float(np.ptp(rgba[:3])) < 0.06
        if body in vessel_ids:
            cls = (
                "rubber"
                if grey and rgba[:3].max() < 0.3
                else "metal"
                if grey and rgba[:3].min() > 0.5
                else "paint"
            )
        elif body in floating_ids:
            cls = "plastic"
        elif _close(rgba, COLORS["wood"]):
            cls = "wood"
        elif _close(rgba, COLORS["concrete"]):
            cls = "concrete"
        elif _close(rgba, COLORS["grey"]):
            cls = "metal"
        else:
            cls = "paint"
        out[int(g)] = cls
    return out


class Materials:
    """Per-geom specular and shininess arrays of a model, applied to a scene's geoms."""

    def __init__(self, model: mujoco.MjModel, vessels, bodies):
        self.classes = geom_classes(model, vessels, bodies)
        self.specular = np.full(model.ngeom, -1.0)
        self.shininess = np.zeros(model.ngeom)
        for g, cls in self.classes.items():
            self.specular[g], self.shininess[g] = CLASSES[cls]

    def apply(self, scene: mujoco.MjvScene) -> None:
        geom_type = mujoco.mjtObj.mjOBJ_GEOM
        for i in range(scene.ngeom):
            geom = scene.geoms[i]
            if (
                geom.objtype == geom_type
                and 0 <= geom.objid < len(self.specular)
                and self.specular[geom.objid] >= 0
            ):
                geom.specular = self.specular[geom.objid]
                geom.shininess = self.shininess[geom.objid]
