"""A GeoScene as MuJoCo pieces: what is drawn (and seen by ray sensors) and what is solid.

Drawn (visual group, in this order): one mesh per land polygon, one mesh per structure, the coarse seabed.
Solid (collision group): the terrain height-field tiles and the structures' convex pieces.
"""

from __future__ import annotations

from dataclasses import dataclass

from usvsim.config.objects import COLORS
from usvsim.geo.scene import GeoScene
from usvsim.vessels.parts import Part

LAND_RGBA = (0.42, 0.47, 0.33, 1.0)
SEABED_RGBA = (0.62, 0.56, 0.40, 1.0)
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
    visual.append(_hfield(drawn, SEABED_RGBA))
    collision += [_hfield(tile, (0.5, 0.5, 0.5, 0.0)) for tile in scene.terrain.tiles()]
    return GeoParts(visual, collision)


def _hfield(tile, rgba) -> Part:
    return Part("hfield", size=tile.half_size, pos=(tile.center[0], tile.center[1], 0.0), rgba=rgba,
                name=tile.name, heights=tile.z)  # fmt: skip
