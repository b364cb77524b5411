"""Scenario placement by geography: `latlon` / `heading_deg` → ENU position and yaw; `geo.marks` → buoys.

Applied once when a simulation is built (and by `usvsim validate`): the scenario that every part of the
simulation sees has plain ENU positions, and the marks of the geo section are ordinary moored buoys.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

from usvsim.config.base import MAX_COORDINATE_M
from usvsim.config.loader import base_dir, source_of
from usvsim.config.objects import COLORS, Buoy
from usvsim.config.scenario import Scenario
from usvsim.core.errors import ScenarioError
from usvsim.geo.frame import GeoFrame
from usvsim.geo.vector import read_features
from usvsim.traffic.ais import grid_bearing_deg

if TYPE_CHECKING:
    from usvsim.geo.scene import GeoScene


def frame_of(scenario: Scenario) -> GeoFrame:
    o = scenario.world.origin
    return GeoFrame(o.latitude_deg, o.longitude_deg, o.altitude_m)


GEO_SUFFIXES = (".geojson", ".json", ".gpkg", ".shp", ".fgb", ".kml", ".gml", ".tif", ".tiff", ".csv")


def check_geo_files(scenario: Scenario) -> None:
    """Every file of the `geo:` section exists, or one line naming its key path, the file looked for and the
    geospatial files that are there (the readers only said `/abs/path: no such file`)."""
    geo = scenario.geo
    if geo is None:
        return
    files = [("geo.land.file", geo.land), ("geo.land.dem.file", geo.land.dem if geo.land else None),
             ("geo.bathymetry.file", geo.bathymetry)]  # fmt: skip
    files += [(f"geo.structures[{k}].file", s) for k, s in enumerate(geo.structures)]
    files += [(f"geo.marks[{k}].file", s) for k, s in enumerate(geo.marks)]
    folder = base_dir(scenario)
    for key, spec in files:
        if spec is None or (folder / spec.file).is_file():
            continue
        path = folder / spec.file
        what = "is a directory, not a file" if path.is_dir() else "not found"
        there = path.parent
        found = sorted(p.name for p in there.iterdir() if p.suffix.lower() in GEO_SUFFIXES) if there.is_dir() else []
        listing = (f"geospatial files there: {', '.join(found[:8])}{', ...' if len(found) > 8 else ''}" if found
                   else "no geospatial files there" if there.is_dir() else f"{there} does not exist")  # fmt: skip
        relative = "" if Path(spec.file).is_absolute() else "; a relative path is taken from the scenario file's folder"
        raise ScenarioError(source_of(scenario), key, f"{spec.file!r} {what} (looked for {path}{relative}; {listing})")


def resolve_geo(scenario: Scenario) -> Scenario:
    """The scenario with every geographic placement turned into ENU (the input itself when there is none)."""
    check_geo_files(scenario)
    placed = any(_placed(v.pose) for v in scenario.vessels) or any(_placed(o) for o in scenario.objects)
    marks = scenario.geo.marks if scenario.geo else ()
    if not placed and not marks:
        return scenario
    frame, source = frame_of(scenario), source_of(scenario)
    vessels = tuple(v.model_copy(update={"pose": _place(v.pose, frame, source, f"vessels[{i}].pose")})
                    for i, v in enumerate(scenario.vessels))  # fmt: skip
    objects = tuple(_place(o, frame, source, f"objects[{i}]") for i, o in enumerate(scenario.objects))
    for k, spec in enumerate(marks):
        assert scenario.geo is not None  # marks come from it
        extent = scenario.geo.extent_m
        feats = read_features(base_dir(scenario) / spec.file, spec.layer, spec.crs, frame, extent, ("Point",))
        for i, (point, props) in enumerate(zip(feats.geometries, feats.properties)):
            color = props.get(spec.color_property) if spec.color_property else None
            name = f"mark{k}_{i}"
            _check_free(scenario, name, f"geo.marks[{k}]")
            objects += (Buoy(name=name, position=(point.x, point.y, 0.0), radius_m=spec.radius_m,
                             color=color if color in COLORS else spec.color, mooring=spec.mooring),)  # fmt: skip
    return _updated(scenario, vessels=vessels, objects=objects)


def _check_free(scenario: Scenario, name: str, marks: str) -> None:
    """A mark's name taken by a vessel, object or ship: MuJoCo refused the second body with a traceback (QA)."""
    named = [(f"vessels[{i}]", v.name) for i, v in enumerate(scenario.vessels)]
    named += [(f"objects[{i}]", o.name) for i, o in enumerate(scenario.objects)]
    named += [(f"traffic.ships[{i}]", s.name) for i, s in enumerate(scenario.traffic.ships)]
    key = next((key for key, taken in named if taken == name), None)
    if key is not None:
        raise ScenarioError(source_of(scenario), f"{key}.name", f"{name!r} is also the name of a buoy of {marks} (marks "
                            "are named mark<k>_<i>: the k-th marks file, its i-th point); choose another name")  # fmt: skip


def _updated(scenario: Scenario, **update) -> Scenario:
    """A copy with `update`, keeping where the scenario came from (for relative paths and messages)."""
    out = scenario.model_copy(update=update)
    for attr in ("_base_dir", "_source"):
        if hasattr(scenario, attr):
            object.__setattr__(out, attr, getattr(scenario, attr))
    return out


def _placed(section) -> bool:
    return getattr(section, "latlon", None) is not None or getattr(section, "heading_deg", None) is not None


def _place(section, frame: GeoFrame, where: str, path: str):
    """`section` with its `latlon` / `heading_deg` turned into ENU; errors name `where` (the file) and the key under
    `path` (the file and path were the error's source: 'objects[0]: latlon', key path 'latlon')."""
    if not _placed(section):
        return section
    update: dict[str, Any] = {"heading_deg": None, "latlon": None}
    if section.latlon is not None:
        if tuple(section.position[:2]) != (0.0, 0.0):
            raise ScenarioError(where, f"{path}.latlon", "give either latlon or the position's x, y, not both")
        lat, lon = section.latlon
        if not (-90.0 <= lat <= 90.0 and -180.0 <= lon <= 180.0):
            raise ScenarioError(where, f"{path}.latlon", f"[{lat}, {lon}] is not a latitude and longitude in degrees")
        x, y, _ = frame.to_enu(lat, lon)[0]
        if max(abs(x), abs(y)) > MAX_COORDINATE_M:  # the limit every position has (docs/limits.md)
            raise ScenarioError(where, f"{path}.latlon", f"[{lat}, {lon}] is {max(abs(x), abs(y)) / 1000:.0f} km from the "
                                f"world origin; positions must be within {MAX_COORDINATE_M / 1000:.0f} km (world.origin)")  # fmt: skip
        update["position"] = (float(x), float(y), section.position[2])
    if getattr(section, "heading_deg", None) is not None:
        if "yaw_deg" in section.model_fields_set:
            raise ScenarioError(where, f"{path}.heading_deg", "give either heading_deg or yaw_deg, not both")
        x, y = update.get("position", section.position)[:2]  # the compass's north there: the world's y axis turned
        lat, lon = frame.to_geodetic(x, y)[0, :2]  # by the meridians' convergence (0.3° 20 km east, at 59° N)
        grid = float(grid_bearing_deg(lat, lon, section.heading_deg, *frame.origin[:2]))
        update["yaw_deg"] = 90.0 - grid  # compass (CW from north) → ENU yaw (CCW from east)
    return section.model_copy(update=update)


def load_place(scenario: Scenario) -> GeoScene | None:
    """The GeoScene of the scenario's `geo:` section (None without one)."""
    if scenario.geo is None:
        return None
    from usvsim.geo.scene import GeoScene

    return GeoScene.load(scenario.geo, frame_of(scenario), base_dir(scenario))


def with_local_depth(scenario: Scenario, place) -> Scenario:
    """The scenario whose waves feel the water depth under the origin (finite-depth dispersion in direct
    sums), unless the environment sets `water_depth_m` itself."""
    env = scenario.environment
    if place is None or env.water_depth_m is not None:
        return scenario
    depth = float(place.depth_at(0.0, 0.0)[0])
    if depth <= 0.0:
        return scenario
    return _updated(scenario, environment=env.model_copy(update={"water_depth_m": depth}))
