"""Scenario keys of the `geo:` section: a real place from geospatial files around the geodetic origin.

Files are resolved relative to the scenario file. Vector files (GeoJSON, GeoPackage, shapefile, anything
pyogrio reads) hold polygons (land, structures) or points (marks); rasters are GeoTIFFs. Every file must
carry its CRS, or name one with `crs:` (any string pyproj accepts: "EPSG:25832", a PROJ string...).
Heights are metres above the still-water level (z up); depths are metres below it (positive down).
"""

from __future__ import annotations

import math
from pathlib import PurePath
from typing import Annotated, Literal

from pydantic import Field, model_validator

from usvsim.config.base import NonNegativeFloat, PositiveFloat, Section, TupleOf
from usvsim.config.objects import Color, Mooring

FileName = Annotated[str, Field(min_length=1)]
MAX_TERRAIN_CELLS = 4000  # cells per side of the terrain grid: 4001² vertices build in ~10 s and ~1.1 GB


class Source(Section):
    """A geospatial file: `file` (relative to the scenario), optional `layer`, optional `crs` override."""

    file: FileName = Field(description="relative to the scenario file's folder")
    layer: str | None = Field(default=None, description="layer of a multi-layer file (GeoPackage); default the first")
    crs: str | None = Field(default=None, description="CRS to assume when the file has none; an error if it has another")


class Dem(Source):
    """A raster of land heights (m above still water), sampled bilinearly."""

    band: int = Field(default=1, ge=1)


class Land(Source):
    """Land polygons (coastline): solid from the seabed up to a constant height or a DEM's heights."""

    height_m: PositiveFloat = Field(default=3.0, description="land height above still water when there is no DEM")
    dem: Dem | None = None
    top_resolution_m: PositiveFloat = Field(default=25.0, description="grid of the land's top surface under a DEM")


RASTER_SUFFIXES = (".tif", ".tiff", ".vrt", ".asc", ".img", ".nc")


def is_raster(file: str | PurePath) -> bool:
    """Whether a bathymetry or DEM file is read as a raster (by its suffix); else as a vector file."""
    return PurePath(file).suffix.lower() in RASTER_SUFFIXES


class Bathymetry(Source):
    """The seabed: a raster (GeoTIFF), or soundings / depth contours (points or lines of a vector file, value in
    `value_property`, interpolated linearly). `values: elevation` (z up, negative under water) or `depth`
    (positive down); by default `elevation` for a raster (GEBCO, NOAA DEMs) and `depth` for soundings and
    contours (charts), whose default `value_property` is `depth` too."""

    band: int = Field(default=1, ge=1, description="raster band")
    value_property: str = Field(default="depth", description="property holding a sounding's or contour's value")
    values: Literal["elevation", "depth"] | None = Field(
        default=None, description="null: elevation for a raster, depth for soundings and contours")

    @model_validator(mode="before")
    @classmethod
    def _default_values(cls, data):
        """Soundings with their default `depth` property were read as elevations under the old default
        `values: elevation` (the run stopped: 'are they depths? then set values: depth'; qa20)."""
        if isinstance(data, dict) and data.get("values") is None and isinstance(data.get("file"), str) and data["file"]:
            data = {**data, "values": "elevation" if is_raster(data["file"]) else "depth"}
        return data


class Structures(Source):
    """Footprints of quays, piers and buildings (polygons), extruded to a height. Class `structure`."""

    height_m: PositiveFloat = Field(default=2.0, description="height above still water when the feature has none")
    height_property: str | None = Field(default="height", description="feature property holding the height (m)")
    base_m: float = Field(default=-3.0, le=0.0, description="z of the bottom (m); quays reach below the water")
    color: Color = "concrete"


class Marks(Source):
    """Buoys at the points of a vector file (e.g. a fairway's marks); colour from a property or one colour."""

    color: Color = "green"
    color_property: str | None = "color"
    radius_m: PositiveFloat = 0.3
    mooring: Mooring | None = Mooring()


class Geo(Section):
    """A real place around the geodetic origin (world.origin): land, seabed, structures and marks."""

    extent_m: PositiveFloat = Field(default=2000.0, le=20000.0, description="half side of the square kept around the origin")
    land: Land | None = None
    bathymetry: Bathymetry | None = None
    default_depth_m: PositiveFloat = Field(default=20.0, description="seabed depth where no bathymetry covers the water")
    min_depth_m: NonNegativeFloat = Field(default=0.0, description="the seabed is kept at least this deep under water")
    structures: TupleOf[Structures] = ()
    marks: TupleOf[Marks] = ()
    terrain_cell_m: PositiveFloat = Field(default=2.0, ge=0.25, description="cell of the seabed/land collision grid")

    @model_validator(mode="after")
    def _grid_size(self):
        """A fine cell over a wide extent asked for 160001² vertices and died with a MemoryError (QA)."""
        cells = math.ceil(2.0 * self.extent_m / self.terrain_cell_m - 1e-9)  # as terrain.vertex_grid
        if cells > MAX_TERRAIN_CELLS:
            raise ValueError(f"the terrain grid would be {cells + 1} vertices a side (2·extent_m/terrain_cell_m, "
                             f"at most {MAX_TERRAIN_CELLS + 1}); raise terrain_cell_m to at least "
                             f"{2.0 * self.extent_m / MAX_TERRAIN_CELLS:g} or lower extent_m")
        return self
