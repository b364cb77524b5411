"""A GeoScene as MuJoCo pieces: what is drawn (and seen by ray sensors) and what is solid.

Drawn (visual group, in this order): one mesh per land polygon, one mesh per structure, the coarse seabed.
Solid (collision group): the terrain height-field tiles and the structures' convex pieces.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from usvsim.config.objects import COLORS
from usvsim.geo.scene import GeoScene
from usvsim.vessels.parts import Part

LAND_RGBA = (0.42, 0.47, 0.33, 1.0)
SEABED_RGBA = (0.62, 0.56, 0.40, 1.0)
DEEP_WATER_RGB = (0.06, 0.27, 0.40)  # the drawn sea's mean colour (world/water_visual.py)
SEABED_VISIBLE_DEPTH_M = 3.0
UNDER_LAND_M = -0.3  # the drawn seabed under land: hidden inside the land prisms
SEABED_DRAWN_VERTICES = 257  # per side of the drawn seabed (the solid one keeps every terrain vertex)


@dataclass(frozen=True)
class GeoParts:
    visual: list[Part]
    collision: list[Part]


def geo_parts(scene: GeoScene) -> GeoParts:
    visual, collision = [], []
    for i, mesh in enumerate(scene.land):
        visual.append(Part("mesh", mesh=mesh, rgba=LAND_RGBA, name=f"land_{i}"))
    for name, mesh, pieces, color in scene.structures:
        visual.append(Part("mesh", mesh=mesh, rgba=COLORS[color], name=name))
        collision += [Part("mesh", mesh=p, name=f"{name}_{j}") for j, p in enumerate(pieces)]
    drawn = scene.terrain.coarse(SEABED_DRAWN_VERTICES)
    seabed = np.where(drawn.z > 0.0, UNDER_LAND_M, drawn.z)  # land is drawn by its prisms
    visual.append(Part("hfield", size=drawn.half_size, pos=(*drawn.center, 0.0), rgba=(1.0, 1.0, 1.0, 1.0),
                       name="seabed", heights=seabed, texture=seabed_colours(seabed)[::-1]))
    collision += [_hfield(tile, (0.5, 0.5, 0.5, 0.0)) for tile in scene.terrain.tiles()]
    return GeoParts(visual, collision)


def set_clip_planes(model, extent_m: float, near_m: float = 0.2) -> None:
    """Cameras see from `near_m` to the far side of the place. MuJoCo scales its clip planes by the model's
    extent, which a place makes kilometres long (a default near plane of 1 % of it would hide the boat)."""
    model.vis.map.znear = near_m / model.stat.extent
    model.vis.map.zfar = 3.0 * extent_m / model.stat.extent


def seabed_colours(z: np.ndarray) -> np.ndarray:
    """Sand seen through clear water: the colour fades to the water's own with depth (e-folding 3 m), so
    shallows show and deep water does not. Rows along +y, as the heights."""
    fade = np.exp(-np.maximum(-z, 0.0) / SEABED_VISIBLE_DEPTH_M)[..., None]
    rgb = fade * np.asarray(SEABED_RGBA[:3]) + (1.0 - fade) * np.asarray(DEEP_WATER_RGB)
    return (255.0 * rgb).astype(np.uint8)


def _hfield(tile, rgba) -> Part:
    return Part("hfield", size=tile.half_size, pos=(tile.center[0], tile.center[1], 0.0), rgba=rgba,
                name=tile.name, heights=tile.z)  # fmt: skip
