"""Vector files (pyogrio: GeoJSON, GeoPackage, shapefile...) → shapely geometries in world ENU metres.

Each file is checked: it exists and opens, it has a CRS (or the scenario names one), its polygons are valid
(a self-intersecting ring is an error naming the file and the place), and something of it lies within the
scene's extent (a wrong CRS usually puts the data elsewhere on the Earth).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
import shapely

from usvsim.geo.frame import GeoError, GeoFrame, require, same_crs


@dataclass(frozen=True)
class Features:
    """Geometries (ENU m, clipped to the extent) and their properties (one dict per geometry)."""

    geometries: list
    properties: list[dict]


def read_features(path: Path, layer: str | None, crs: str | None, frame: GeoFrame, extent_m: float,
                  kinds: tuple[str, ...]) -> Features:  # fmt: skip
    """Features of `path` whose geometry type is one of `kinds` ("Polygon", "Point"), in ENU."""
    pyogrio = require("pyogrio")
    if not path.is_file():
        raise GeoError(f"{path}: no such file")
    try:
        meta, _, wkb, fields = _read_raw(pyogrio, path, layer)
    except GeoError:
        raise
    except Exception as exc:  # GDAL reports every unreadable file its own way
        reason = str(exc).splitlines()[0].split("; ")[0].rstrip(".")  # GDAL's first clause (its advice was cut off)
        raise GeoError(f"{path}: not a vector file pyogrio can read ({reason[:200]})") from None
    names = list(meta[1]) if meta[1] is not None else []
    file_crs = meta[0]
    if file_crs and crs and not same_crs(file_crs, crs, str(path)):
        raise GeoError(f"{path}: the file's CRS is {file_crs} but the scenario says crs: {crs}; drop one")
    if not (file_crs or crs):
        raise GeoError(f"{path}: the file has no CRS; give one with `crs:` (e.g. EPSG:4326)")
    if len(wkb) == 0:  # an export or clip that missed the area read as "no land" (soundings: a ValueError), silently
        what = f"its layer {layer!r}" if layer is not None else "the file"
        raise GeoError(f"{path}: {what} holds no features (empty; an export or clip that missed the area?); "
                       "if the place has none, drop this entry from geo:")
    with np.errstate(invalid="ignore"):  # NaN coordinates: shapely warned "invalid value encountered in from_wkb"
        geoms = shapely.from_wkb(wkb)
    coords, owner = shapely.get_coordinates(geoms, return_index=True)
    bad = owner[~np.isfinite(coords).all(axis=1)]
    if len(bad):  # they read as "coordinates outside the area of its CRS; is the CRS right?" (QA)
        raise GeoError(f"{path}: feature {bad[0]} has coordinates that are not finite numbers (NaN or inf)")
    convert = frame.from_crs(file_crs, str(path)) if file_crs else frame.from_crs(crs, f"{path}: crs")
    geoms = shapely.transform(geoms, lambda xy: np.column_stack(convert(xy[:, 0], xy[:, 1])))
    _check_valid(geoms, path)
    extent = shapely.box(-extent_m, -extent_m, extent_m, extent_m)
    keep_geoms, keep_props = [], []
    for i, geom in enumerate(geoms):
        if geom is None or shapely.get_type_id(geom) < 0:
            continue
        clipped = shapely.intersection(geom, extent)
        for part in _parts(clipped, kinds):
            keep_geoms.append(part)
            keep_props.append({n: _plain(f[i]) for n, f in zip(names, fields)})
    present = {int(shapely.get_type_id(g)) for g in geoms if g is not None}
    wanted = {int(shapely.GeometryType[name + k.upper()]) for k in kinds for name in ("", "MULTI")}
    if len(geoms) and not present & (wanted | {int(shapely.GeometryType.GEOMETRYCOLLECTION)}):
        found = sorted(shapely.GeometryType(t).name.lower() for t in present if t >= 0)
        raise GeoError(f"{path}: holds no {'/'.join(kinds).lower()} (its features are: {', '.join(found) or 'empty'})")
    if len(geoms) and not keep_geoms:
        lo, hi = shapely.total_bounds(geoms).reshape(2, 2)
        raise GeoError(f"{path}: no {'/'.join(kinds).lower()} within {extent_m:g} m of the origin (the data lies "
                       f"between ENU ({lo[0]:.0f}, {lo[1]:.0f}) and ({hi[0]:.0f}, {hi[1]:.0f}) m); wrong CRS or origin?")
    return Features(keep_geoms, keep_props)


CSV_COLUMNS = {"X_POSSIBLE_NAMES": "lon,longitude,x,easting", "Y_POSSIBLE_NAMES": "lat,latitude,y,northing"}


def _read_raw(pyogrio, path: Path, layer: str | None):
    options = CSV_COLUMNS if path.suffix.lower() == ".csv" else {}  # GDAL's CSV driver: points from these columns
    if layer is not None:  # a misspelt layer read "not a vector file pyogrio can read (Layer 'x' could not be opened)"
        layers = [str(name) for name, _ in pyogrio.list_layers(path)]
        if layer not in layers:
            raise GeoError(f"{path}: has no layer {layer!r} (its layers: {', '.join(layers[:20]) or 'none'})")
    meta, fids, wkb, fields = pyogrio.raw.read(path, layer=layer, **options)
    if wkb is None:  # a CSV without such columns, a table without geometry: it crashed in the loop below (QA)
        raise GeoError(f"{path}: has no geometry (a CSV needs coordinate columns named lon/lat, longitude/latitude, "
                       "x/y or easting/northing)")
    return (meta["crs"], meta["fields"]), fids, wkb, fields


def _check_valid(geoms: np.ndarray, path: Path) -> None:
    polygons = np.isin(shapely.get_type_id(geoms), (3, 6))  # Polygon, MultiPolygon
    bad = np.flatnonzero(polygons & ~shapely.is_valid(geoms))
    if len(bad):
        reason = shapely.is_valid_reason(geoms[bad[0]])
        raise GeoError(f"{path}: feature {bad[0]} is not a valid polygon ({reason}); repair it (e.g. shapely.make_valid)")


def _parts(geom, kinds: tuple[str, ...]) -> list:
    """The single parts of a geometry whose type is in `kinds` (multi-parts and collections split)."""
    if geom.is_empty:
        return []
    if hasattr(geom, "geoms"):
        return [p for g in geom.geoms for p in _parts(g, kinds)]
    return [geom] if geom.geom_type in kinds else []


def _plain(value):
    return value.item() if isinstance(value, np.generic) else value
