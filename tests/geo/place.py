"""A small synthetic place written as real geospatial files (UTM 32N, EPSG:25832) around Horten's origin.

ENU (origin 59.42083 N, 10.43278 E): land north of a straight coastline y = 100 m (x from -600 to 600 m),
a quay (30 x 8 m, 1.5 m high) with its south face at y = -40 m, x from 40 to 70 m, a shoal (seabed at
-0.05 m) around (-80, -60), and a seabed at -10 m elsewhere sloping 1 cm per metre east (raster in UTM).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
from pyproj import Transformer

from usvsim.geo.frame import GeoFrame

ORIGIN = (59.42083, 10.43278, 0.0)
CRS = "EPSG:25832"
COAST_Y = 100.0
QUAY = (40.0, 70.0, -40.0, -32.0)  # x0, x1, y0, y1 (ENU m)
SHOAL = (-80.0, -60.0)


def to_utm(x, y):
    geo = GeoFrame(*ORIGIN).to_geodetic(np.asarray(x, float), np.asarray(y, float), 0.0)
    e, n = Transformer.from_crs("EPSG:4326", CRS, always_xy=True).transform(geo[:, 1], geo[:, 0])
    return np.column_stack([e, n])


def _ring(x0, x1, y0, y1, step=10.0):
    xs = np.arange(x0, x1 + 1e-9, step)
    ys = np.arange(y0, y1 + 1e-9, step)
    pts = [(x, y0) for x in xs] + [(x1, y) for y in ys[1:]] + [(x, y1) for x in xs[::-1][1:]] + [(x0, y) for y in ys[::-1][1:]]
    return to_utm(*np.array(pts).T).tolist()


def _feature_collection(polygons, crs=CRS, props=None):
    feats = [{"type": "Feature", "properties": (props or [{}] * len(polygons))[i],
              "geometry": {"type": "Polygon", "coordinates": [ring + [ring[0]]]}} for i, ring in enumerate(polygons)]
    fc = {"type": "FeatureCollection", "features": feats}
    if crs:
        fc["crs"] = {"type": "name", "properties": {"name": f"urn:ogc:def:crs:EPSG::{crs.split(':')[1]}"}}
    return json.dumps(fc)


def write_place(folder: Path) -> dict[str, Path]:
    """Write land.geojson, quays.geojson, marks.geojson and depth.tif; return their paths."""
    import rasterio
    from rasterio.transform import from_origin

    folder.mkdir(parents=True, exist_ok=True)
    paths = {k: folder / n for k, n in (("land", "land.geojson"), ("quays", "quays.geojson"),
                                       ("marks", "marks.geojson"), ("depth", "depth.tif"))}
    paths["land"].write_text(_feature_collection([_ring(-600, 600, COAST_Y, 600)]))
    paths["quays"].write_text(_feature_collection([_ring(*QUAY, step=2.0)], props=[{"height": "1.5", "name": "quay"}]))
    marks = to_utm([20.0, 20.0], [10.0, -10.0])
    paths["marks"].write_text(json.dumps({"type": "FeatureCollection", "crs": {"type": "name", "properties": {
        "name": "urn:ogc:def:crs:EPSG::25832"}}, "features": [
        {"type": "Feature", "properties": {"color": c}, "geometry": {"type": "Point", "coordinates": list(p)}}
        for p, c in zip(marks.tolist(), ("green", "red"))]}))
    e0, n0 = to_utm([-700.0], [700.0])[0]
    cell = 5.0
    rows = cols = 280
    east = e0 + cell * (np.arange(cols) + 0.5)
    elevation = np.tile(-10.0 + 0.01 * (east - east[0] - 700.0), (rows, 1))
    centers_n = n0 - cell * (np.arange(rows) + 0.5)
    ce, cn = np.meshgrid(east, centers_n)
    se, sn = to_utm([SHOAL[0]], [SHOAL[1]])[0]
    elevation[np.hypot(ce - se, cn - sn) < 15.0] = -0.05
    with rasterio.open(paths["depth"], "w", driver="GTiff", height=rows, width=cols, count=1, dtype="float32",
                       crs=CRS, transform=from_origin(e0, n0, cell, cell), nodata=-9999.0) as ds:
        ds.write(elevation.astype(np.float32), 1)
    return paths


def geo_section(paths: dict[str, Path], **extra) -> dict:
    return {"extent_m": 400.0, "terrain_cell_m": 2.0,
            "land": {"file": str(paths["land"]), "height_m": 4.0},
            "bathymetry": {"file": str(paths["depth"])},
            "structures": [{"file": str(paths["quays"])}],
            "marks": [{"file": str(paths["marks"])}], **extra}
