"""Rebuild the shipped sample place `usvsim/scenarios/geo/horten/` (Horten, Oslofjord, Norway).

Land: OpenStreetMap coastline polygons as published in the npm package `@geo-maps/countries-coastline-1m`
0.6.0 (`map.geo.json`, © OpenStreetMap contributors, ODbL 1.0), clipped to a box around the scenario's
origin. That package simplifies OSM's coastline (vertices every ~100-500 m here): good for coastal
navigation at fjord scale, too coarse for quays. Everything else is SYNTHETIC and labelled so:
`depth.tif` (0.5 m at the shore deepening to 40 m over 600 m), `marks.geojson` (a fairway of green and red
marks), `quays.geojson` (a quay and a jetty drawn out from the shore). Needs shapely, pyogrio, rasterio, pyproj.

    npm pack @geo-maps/countries-coastline-1m && tar xzf geo-maps-countries-coastline-1m-0.6.0.tgz
    python scripts/make_horten_place.py package/map.geo.json src/usvsim/scenarios/geo/horten
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np
import pyogrio
import shapely
from pyproj import Transformer

ORIGIN = (59.4100, 10.5100)  # lat, lon: in the fjord east of Horten
BOX = (10.43, 59.38, 10.57, 59.44)  # lon/lat box kept (a bit larger than the scene)
UTM = "EPSG:25832"


def write_fc(path: Path, features: list) -> None:
    path.write_text(json.dumps({"type": "FeatureCollection", "features": features}, separators=(",", ":")))


def feature(geom, **props) -> dict:
    return {"type": "Feature", "properties": props, "geometry": shapely.geometry.mapping(geom)}


def main(source: Path, out: Path) -> None:
    import rasterio
    from rasterio.transform import from_origin

    out.mkdir(parents=True, exist_ok=True)
    _, _, wkb, _ = pyogrio.raw.read(source, bbox=BOX)
    land = shapely.intersection(shapely.union_all(shapely.from_wkb(wkb)), shapely.box(*BOX))
    land = shapely.set_precision(land, 1e-7)
    write_fc(out / "land.geojson", [feature(p) for p in shapely.get_parts(land)])
    to_utm = Transformer.from_crs("EPSG:4326", UTM, always_xy=True)
    land_utm = shapely.transform(land, lambda xy: np.column_stack(to_utm.transform(xy[:, 0], xy[:, 1])))
    e0, n0 = to_utm.transform(BOX[0], BOX[3])
    e1, n1 = to_utm.transform(BOX[2], BOX[1])
    cell = 20.0
    east = np.arange(e0, e1, cell) + cell / 2
    north = np.arange(n0, n1, -cell) - cell / 2
    ge, gn = np.meshgrid(east, north)
    dist = shapely.distance(shapely.points(ge, gn), land_utm.boundary)
    depth = np.clip(0.5 + 39.5 * dist / 600.0, 0.5, 40.0)
    with rasterio.open(out / "depth.tif", "w", driver="GTiff", height=depth.shape[0], width=depth.shape[1],
                       count=1, dtype="float32", crs=UTM, compress="deflate",
                       transform=from_origin(e0, n0, cell, cell)) as ds:
        ds.write(depth.astype(np.float32), 1)
    from_utm = Transformer.from_crs(UTM, "EPSG:4326", always_xy=True)
    oe, on = to_utm.transform(ORIGIN[1], ORIGIN[0])
    marks = [(oe + dx, on + dy, c) for dy in (150.0, 450.0, 750.0) for dx, c in ((-40.0, "red"), (40.0, "green"))]
    write_fc(out / "marks.geojson", [feature(shapely.Point(*from_utm.transform(e, n)), color=c) for e, n, c in marks])
    quays = []
    for name, dy, width, length in (("quay_west", 300.0, 25.0, 120.0), ("jetty", -600.0, 12.0, 200.0)):
        line = shapely.LineString([(oe - 3000.0, on + dy), (oe, on + dy)]).intersection(land_utm)
        shore = shapely.bounds(line)[2]  # the easternmost land on that line: the shore
        corners = [(shore - 30.0, on + dy), (shore + length, on + dy), (shore + length, on + dy + width),
                   (shore - 30.0, on + dy + width)]
        lonlat = [from_utm.transform(e, n) for e, n in corners]
        quays.append(feature(shapely.Polygon(lonlat), name=name, height=1.5))
    write_fc(out / "quays.geojson", quays)


if __name__ == "__main__":
    main(Path(sys.argv[1]), Path(sys.argv[2]))
