"""Scenario keys of world objects: buoys, docks, piers, walls, U-shaped berths, mesh obstacles.

Positions are world ENU metres; `yaw_deg` is CCW from east. Boxes are given by their centre and
full size (length along the object's x, width along y, height along z).
"""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import Field, model_validator

from usvsim.config.base import (
    MAX_SIZE_M,
    AngleDeg,
    GeoPose,
    LatLon,
    MassKg,
    Scale,
    Section,
    Size,
    Size3,
    Vec3,
)

MAX_PILES_PER_ROW = 500
Name = Annotated[str, Field(pattern=r"^[A-Za-z][A-Za-z0-9_]*$")]

COLORS = {
    "red": (0.85, 0.1, 0.1, 1.0),
    "green": (0.1, 0.7, 0.2, 1.0),
    "yellow": (0.95, 0.8, 0.1, 1.0),
    "orange": (1.0, 0.45, 0.0, 1.0),
    "white": (0.95, 0.95, 0.95, 1.0),
    "black": (0.1, 0.1, 0.1, 1.0),
    "grey": (0.55, 0.55, 0.55, 1.0),
    "wood": (0.55, 0.4, 0.25, 1.0),
    "concrete": (0.7, 0.7, 0.68, 1.0),
}
Color = Literal["red", "green", "yellow", "orange", "white", "black", "grey", "wood", "concrete"]


class Mooring(Section):
    """A slack mooring line from the buoy's bottom to an anchor on the seabed straight below."""

    water_depth_m: Size = Field(default=5.0, description="depth of the anchor below the still water")
    scope: float = Field(default=1.2, ge=1.0, description="line length / water depth")


class Buoy(LatLon):
    """A floating sphere buoy (marker); moored unless `mooring` is null (then it drifts freely)."""

    type: Literal["buoy"] = "buoy"
    name: Name
    position: Vec3 = Field(description="[x east, y north, z up] of the sphere's centre in the world frame (ENU), m")
    radius_m: Annotated[float, Field(ge=0.05, le=50.0)] = 0.3
    mass_kg: MassKg = 20.0
    color: Color = "red"
    mooring: Mooring | None = Mooring()


class Box(GeoPose):
    """A static box obstacle (dock, wall): centre position, size [length, width, height], yaw."""

    type: Literal["dock", "wall", "box"]
    name: Name
    position: Vec3 = Field(description="[x east, y north, z up] of the box's centre in the world frame (ENU), m")
    size: Size3 = Field(description="[length along its x, width along its y, height], full sides, m")
    yaw_deg: AngleDeg = Field(default=0.0, description="its x axis, counter-clockwise from east")
    color: Color = "concrete"


class Pier(GeoPose):
    """A pier: a deck on round piles. `position` is the deck's centre; piles reach down to the seabed."""

    type: Literal["pier"] = "pier"
    name: Name
    position: Vec3 = Field(description="[x east, y north, z up] of the deck's centre in the world frame (ENU), m")
    length_m: Size
    width_m: Size
    deck_thickness_m: Size = 0.3
    pile_radius_m: Size = 0.15
    pile_spacing_m: Size = 4.0
    water_depth_m: Size = 5.0
    yaw_deg: AngleDeg = 0.0
    color: Color = "wood"

    @model_validator(mode="after")
    def _piles(self):
        if 2 * self.pile_radius_m > min(self.width_m, self.pile_spacing_m):
            raise ValueError("pile_radius_m must be at most half of width_m and of pile_spacing_m")
        if self.length_m / self.pile_spacing_m > MAX_PILES_PER_ROW:
            raise ValueError(f"more than {MAX_PILES_PER_ROW} piles per row; increase pile_spacing_m")
        return self


class Berth(GeoPose):
    """A U-shaped berth: two side walls and a back wall around a slot open toward the berth's +x.

    `position` is the centre of the slot at the water line; the slot is `inner_length_m` long
    (along x) and `inner_width_m` wide; walls are `wall_thickness_m` thick and `height_m` tall,
    their top `freeboard_m` above the water.
    """

    type: Literal["berth"] = "berth"
    name: Name
    position: Vec3 = Field(description="[x east, y north, z] of the slot's centre in the world frame (ENU), m")
    inner_length_m: Size = 7.0
    inner_width_m: Size = 4.0
    wall_thickness_m: Size = 0.6
    height_m: Size = 2.0
    freeboard_m: Annotated[float, Field(ge=-MAX_SIZE_M, le=MAX_SIZE_M)] = 0.6
    yaw_deg: AngleDeg = 0.0
    color: Color = "concrete"


class MeshObstacle(GeoPose):
    """A static obstacle from a mesh file; non-convex meshes are decomposed into convex parts."""

    type: Literal["mesh"] = "mesh"
    name: Name
    file: str = Field(description="mesh file (OBJ, STL, PLY, glTF, DAE), m, z up, relative to the scenario file")
    position: Vec3 = Field(default=(0.0, 0.0, 0.0), description="where the mesh's origin goes in the world frame "
                           "(ENU), m")
    yaw_deg: AngleDeg = Field(default=0.0, description="about z, counter-clockwise from east")
    scale: Scale = Field(default=1.0, description="factor on the file's coordinates")
    color: Color = "grey"


WorldObject = Annotated[Buoy | Box | Pier | Berth | MeshObstacle, Field(discriminator="type")]
