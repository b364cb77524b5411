"""A real place as world geometry: land prisms, structure prisms, seabed tiles; water depth lookups.

`GeoScene.load(geo, origin, base_dir)` reads the files of a scenario's `geo:` section (see config/geo.py),
converts everything to world ENU metres at the geodetic origin and builds:
- land: one closed prism mesh per polygon, walls exactly on the coastline, drawn and seen by ray sensors
  (class `land`); solid through the terrain height field;
- structures: prisms drawn and seen (class `structure`) and solid as exact convex pieces;
- terrain: the seabed and land as height-field tiles (terrain.py), solid, and one coarse drawn seabed.
The result is cached on disk, keyed by the content of the section and of every file it names.
"""

from __future__ import annotations

import hashlib
import json
import os
from dataclasses import dataclass, field
from functools import lru_cache
from pathlib import Path

import numpy as np
import shapely

from usvsim.config.geo import Geo, is_raster
from usvsim.geo import extrude
from usvsim.geo.frame import GeoError, GeoFrame
from usvsim.geo.raster import Raster, read_raster
from usvsim.geo.soundings import Soundings, read_soundings
from usvsim.geo.terrain import Terrain, land_mask, vertex_grid
from usvsim.geo.vector import read_features
from usvsim.vessels.parts import Mesh

CACHE_VERSION = 3  # bump whenever the build gives another scene for the same files (3: antimeridian, raster edges, altitude)
BOTTOM_MARGIN_M = 1.0  # prisms reach this far below the deepest seabed
DEM_FLOOR_M = 0.1  # land under a DEM stands at least this high


@dataclass
class GeoScene:
    """World geometry of a place (ENU m): closed meshes of the land polygons and of the structures (with
    the convex pieces of each structure), the terrain grid, and what depth lookups need."""

    terrain: Terrain
    land: list[Mesh] = field(default_factory=list)  # one closed prism per land polygon
    land_polygons: list = field(default_factory=list)
    structures: list[tuple[str, Mesh, list[Mesh], str]] = field(default_factory=list)  # name, mesh, pieces, colour
    bathymetry: Raster | Soundings | None = None  # depth lookups on the source's own grid or soundings
    settings: Geo | None = None

    @classmethod
    def load(cls, geo: Geo, frame: GeoFrame, base_dir: Path) -> GeoScene:
        key = _cache_key(geo, frame, base_dir)
        path = _cache_dir() / f"{key}.npz"
        scene = _read_cache(path) if path.is_file() else None
        if scene is None:
            scene = _build(geo, frame, base_dir)
            _write_cache(path, scene)
        scene.settings = geo
        if geo.bathymetry is not None:  # lookups sample the source itself (cheap to re-read)
            scene.bathymetry = _bathymetry(geo, frame, base_dir)
        return scene

    def labels(self) -> list[tuple[str, str]]:
        """(name, class) of the drawn land and structure meshes, in the order they are built."""
        return [(f"land_{i}", "land") for i in range(len(self.land))] + [(s[0], "structure") for s in self.structures]

    def depth_at(self, x_m, y_m) -> np.ndarray:
        """Water depth (m, positive down from still water) at ENU points; on land minus the land height (`height_m`,
        or under a DEM the nearest terrain vertex's, at least the DEM's floor of 0.1 m): always negative on land.

        Under water: the bathymetry's value (a raster: bilinear within a cell, exact at pixel centres; soundings:
        linear between them, exact at each; at least `min_depth_m`), or the default depth where it has none."""
        x = np.atleast_1d(np.asarray(x_m, float))
        y = np.broadcast_to(np.asarray(y_m, float), x.shape)
        geo = self.settings
        depth = np.full(x.shape, geo.default_depth_m if geo else 20.0)
        if self.bathymetry is not None:
            assert geo is not None and geo.bathymetry is not None  # the raster came from these settings
            raw = self.bathymetry.sample(x, y)
            raw = -raw if geo.bathymetry.values == "elevation" else raw
            depth = np.where(np.isnan(raw), depth, np.maximum(raw, geo.min_depth_m))
        on_land = np.zeros(x.shape, bool)
        for polygon in self.land_polygons:
            on_land |= shapely.contains_xy(polygon, x, y)
        if on_land.any():
            depth[on_land] = -self._land_height(x[on_land], y[on_land])
        return depth

    def _land_height(self, x: np.ndarray, y: np.ndarray) -> np.ndarray:
        land = self.settings.land if self.settings else None
        if land is not None and land.dem is None:
            return np.full(x.shape, land.height_m)
        t = self.terrain  # the nearest terrain vertex's height; a vertex off the coast holds the seabed: it read
        cx = np.clip(np.interp(x, t.xs, np.arange(len(t.xs))), 0, len(t.xs) - 1)
        cy = np.clip(np.interp(y, t.ys, np.arange(len(t.ys))), 0, len(t.ys) - 1)
        return np.maximum(t.z[np.round(cy).astype(int), np.round(cx).astype(int)], DEM_FLOOR_M)  # -0.0 m deep (QA)


def _build(geo: Geo, frame: GeoFrame, base_dir: Path) -> GeoScene:
    extent = geo.extent_m
    xs = ys = vertex_grid(extent, geo.terrain_cell_m)
    seabed = np.full((len(ys), len(xs)), -geo.default_depth_m)
    values = None
    if geo.bathymetry is not None:
        values = _bathymetry(geo, frame, base_dir).sample_grid(xs, ys)
        values = values if geo.bathymetry.values == "elevation" else -values
        seabed = np.where(np.isnan(values), seabed, values)
    seabed = np.minimum(seabed, -geo.min_depth_m)
    bottom = float(seabed.min()) - BOTTOM_MARGIN_M
    z, land, polygons, on_land = seabed, [], [], np.zeros(seabed.shape, bool)
    if geo.land is not None:
        z, land, polygons, on_land = _land(geo, frame, base_dir, xs, ys, seabed, bottom)
    if values is not None:
        _check_water(geo, base_dir, values, on_land)
    structures = _structures(geo, frame, base_dir, bottom)
    return GeoScene(Terrain(xs, ys, z), land, polygons, structures)


def _bathymetry(geo: Geo, frame: GeoFrame, base_dir: Path):
    b = geo.bathymetry
    assert b is not None, "called for a Geo with bathymetry"
    path = base_dir / b.file
    if is_raster(path):
        return read_raster(path, b.band, b.crs, frame, geo.extent_m)
    return read_soundings(path, b.layer, b.crs, frame, geo.extent_m, b.value_property)


def _land(geo: Geo, frame: GeoFrame, base_dir: Path, xs, ys, seabed, bottom):
    spec = geo.land
    assert spec is not None, "called for a Geo with land"
    polygons = read_features(base_dir / spec.file, spec.layer, spec.crs, frame, geo.extent_m, ("Polygon",)).geometries
    heights = None
    if spec.dem is not None:
        dem = read_raster(base_dir / spec.dem.file, spec.dem.band, spec.dem.crs, frame, geo.extent_m)

        def land_height(values):
            return np.nan_to_num(np.maximum(values, DEM_FLOOR_M), nan=spec.height_m)

        def dem_heights(x, y):
            return land_height(dem.sample(x, y))

        heights = dem_heights

        land_z = land_height(dem.sample_grid(xs, ys))
    else:
        land_z = np.full(seabed.shape, spec.height_m)
    mask = land_mask(polygons, xs, ys)
    z = np.where(mask, land_z, seabed)
    prisms = [extrude.to_mesh(extrude.prism(p, bottom, spec.height_m, heights, spec.top_resolution_m))
              for p in polygons]  # fmt: skip
    return z, prisms, polygons, mask


def _check_water(geo: Geo, base_dir: Path, elevation: np.ndarray, on_land: np.ndarray) -> None:
    """The bathymetry puts some of the scene's water (off the land polygons) below still water, or it was read
    with the wrong sign: a depth raster under the default `values: elevation` made all the sea 0 m deep, silently."""
    b = geo.bathymetry
    assert b is not None, "called for a Geo with bathymetry"
    if np.isnan(elevation).all():  # an all no-data raster: the default depth everywhere, silently (QA)
        raise GeoError(f"{base_dir / b.file}: no value within the scene ({geo.extent_m:g} m around the origin): every "
                       "pixel there is no-data (or no sounding's triangle covers it); wrong file, band or nodata value?")
    water = elevation[~on_land & ~np.isnan(elevation)]
    if len(water) == 0 or (water < 0.0).any():
        return
    shown = water if b.values == "elevation" else -water
    other = "depth" if b.values == "elevation" else "elevation"
    raise GeoError(f"{base_dir / b.file}: no value puts the seabed below still water anywhere in the scene's water "
                   f"(read as values: {b.values}, they range from {shown.min():g} to {shown.max():g} there); "
                   f"are they {other}s? then set values: {other}")


def _structures(geo: Geo, frame: GeoFrame, base_dir: Path, bottom: float):
    out = []
    for k, spec in enumerate(geo.structures):
        feats = read_features(base_dir / spec.file, spec.layer, spec.crs, frame, geo.extent_m, ("Polygon",))
        for i, (polygon, props) in enumerate(zip(feats.geometries, feats.properties)):
            height = _number(props.get(spec.height_property) if spec.height_property else None, spec.height_m)
            base = max(spec.base_m, bottom)
            mesh = extrude.to_mesh(extrude.prism(polygon, base, height))
            pieces = [extrude.to_mesh(extrude.prism(p, base, height)) for p in extrude.convex_footprints(polygon)]
            name = str(props.get("name") or f"structure{k}_{i}")
            out.append((name, mesh, pieces, spec.color))
    return out


def _number(value, default: float) -> float:
    try:
        v = float(str(value).split()[0]) if value is not None else default
    except ValueError:
        return default
    return v if np.isfinite(v) and v > 0 else default


# -- cache ------------------------------------------------------------------------------------------
def _cache_dir() -> Path:
    return Path(os.environ.get("USVSIM_CACHE", Path.home() / ".cache" / "usvsim")) / "geo"


@lru_cache(maxsize=1)
def _code_digest() -> str:
    """The geo package's source: a fix to the build invalidates old entries even when nobody bumps
    CACHE_VERSION (a stale entry kept a wrong seabed and hid a new error, QA)."""
    h = hashlib.sha256()
    for module in sorted(Path(__file__).parent.glob("*.py")):
        h.update(module.read_bytes())
    return h.hexdigest()


def _cache_key(geo: Geo, frame: GeoFrame, base_dir: Path) -> str:
    h = hashlib.sha256(json.dumps([CACHE_VERSION, _code_digest(), geo.model_dump(mode="json"), frame.origin]).encode())
    for spec in [geo.land, geo.land.dem if geo.land else None, geo.bathymetry, *geo.structures]:
        if spec is not None and (base_dir / spec.file).is_file():
            h.update((base_dir / spec.file).read_bytes())
    return h.hexdigest()[:32]


def _write_cache(path: Path, scene: GeoScene) -> None:
    wkb = [shapely.to_wkb(p) for p in scene.land_polygons]
    arrays = {"xs": scene.terrain.xs, "ys": scene.terrain.ys, "z": scene.terrain.z,
              "land_wkb": np.frombuffer(b"".join(wkb), np.uint8), "land_wkb_sizes": np.array([len(w) for w in wkb])}
    meshes = {f"land{i}": m for i, m in enumerate(scene.land)}
    meta = []
    for i, (name, mesh, pieces, color) in enumerate(scene.structures):
        meshes[f"s{i}"] = mesh
        meshes |= {f"s{i}_{j}": p for j, p in enumerate(pieces)}
        meta.append([name, len(pieces), color])
    for key, mesh in meshes.items():
        arrays[f"{key}_v"], arrays[f"{key}_f"] = mesh.vertices, mesh.faces
    arrays["meta"] = np.array(json.dumps({"land": len(scene.land), "structures": meta}))
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_suffix(".tmp.npz")
    np.savez(tmp, **arrays)
    tmp.replace(path)


def _read_cache(path: Path) -> GeoScene | None:
    try:
        with np.load(path) as data:
            meta = json.loads(str(data["meta"]))
            terrain = Terrain(data["xs"], data["ys"], data["z"])
            mesh = lambda key: Mesh(data[f"{key}_v"], data[f"{key}_f"])  # noqa: E731
            land = [mesh(f"land{i}") for i in range(meta["land"])]
            blob, ends = data["land_wkb"].tobytes(), np.cumsum(data["land_wkb_sizes"])
            polygons = [shapely.from_wkb(blob[e - n : e]) for e, n in zip(ends, data["land_wkb_sizes"])]
            structures = [(name, mesh(f"s{i}"), [mesh(f"s{i}_{j}") for j in range(n)], color)
                          for i, (name, n, color) in enumerate(meta["structures"])]  # fmt: skip
        return GeoScene(terrain, land, polygons, structures)
    except (OSError, KeyError, ValueError):
        return None  # a damaged or old cache entry is rebuilt
