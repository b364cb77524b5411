"""Real places fed wrong or unusual input (QA): one clear error instead of a crash or a silently wrong place."""

from __future__ import annotations

import numpy as np
import pytest
import shapely
from place import COAST_Y, ORIGIN, geo_section

from usvsim.config.loader import parse_scenario
from usvsim.core.errors import UsvsimError
from usvsim.geo.frame import GeoFrame
from usvsim.simulation import Simulation


def scenario_data(place, **geo):
    return {"version": 1, "world": {"origin": {"latitude_deg": ORIGIN[0], "longitude_deg": ORIGIN[1]}},
            "vessels": [{"name": "wamv", "model": "wamv"}], "geo": geo_section(place, **geo)}


def test_a_terrain_grid_too_fine_for_its_extent_is_refused_before_allocating_it(place):
    """terrain_cell_m 0.25 over ±20 km asked numpy for 160001² floats: a MemoryError traceback (191 GiB)."""
    with pytest.raises(UsvsimError, match=r"geo: the terrain grid would be 160001 vertices a side .* at least 10 "):
        parse_scenario(scenario_data(place, extent_m=20000.0, terrain_cell_m=0.25), "test.yaml")
    parse_scenario(scenario_data(place, extent_m=4000.0, terrain_cell_m=2.0), "test.yaml")  # 4001 a side: the limit


@pytest.mark.parametrize("key", ["land", "bathymetry"])
def test_a_crs_pyproj_does_not_know_is_one_line_naming_the_file(place, key):
    """`crs: EPSG:99999` on a file that has its own CRS ended in pyproj's CRSError traceback (exit status 1)."""
    geo = geo_section(place)
    geo[key] = {**geo[key], "crs": "EPSG:99999"}
    with pytest.raises(UsvsimError) as err:
        Simulation(parse_scenario({**scenario_data(place), "geo": geo}, "test.yaml"))
    message = str(err.value)
    assert "\n" not in message and message.startswith(str(place["land" if key == "land" else "depth"]))
    assert "crs: EPSG:99999 is not a coordinate reference system pyproj knows" in message


def test_bathymetry_read_with_the_wrong_sign_is_an_error_not_a_sea_0_m_deep(place):
    """The test place's raster holds elevations (-10 m ± slope, a -0.05 m shoal); read as depths every seabed
    vertex came out above still water, was clamped to min_depth_m 0 and the whole sea was 0 m deep, silently."""
    geo = geo_section(place)
    geo["bathymetry"] = {**geo["bathymetry"], "values": "depth"}
    with pytest.raises(UsvsimError) as err:
        Simulation(parse_scenario({**scenario_data(place), "geo": geo}, "test.yaml"))
    message = str(err.value)
    assert message.startswith(str(place["depth"])) and "\n" not in message
    assert "read as values: depth" in message and message.endswith("set values: elevation")
    sim = Simulation(parse_scenario(scenario_data(place), "test.yaml"))  # as elevations: ~10 m deep at the origin
    assert sim.world.depth_at([0.0], [0.0])[0] == pytest.approx(10.0, abs=0.2)  # 1 cm/m slope, UTM vs ENU
    sim.close()


def test_a_place_across_the_antimeridian_reads_rasters_and_polygons_past_180_degrees(tmp_path):
    """A GEBCO-like raster cut at 179.97..180.03° E (GDAL keeps longitudes past 180) was NaN east of 180°, so the
    seabed there was the default depth; land in the 0..360° convention was refused as outside its CRS."""
    import json

    import pymap3d
    import rasterio
    from rasterio.transform import from_origin

    origin = (-16.8, 179.995)
    cols, rows, cell = 60, 40, 0.001  # degrees
    lon = 179.97 + cell * (np.arange(cols) + 0.5)
    elevation = np.tile(-10.0 - 200.0 * (lon - 179.97), (rows, 1))  # linear in longitude: bilinear is exact
    with rasterio.open(tmp_path / "gebco.tif", "w", driver="GTiff", height=rows, width=cols, count=1, dtype="float64",
                       crs="EPSG:4326", transform=from_origin(179.97, -16.78, cell, cell)) as ds:
        ds.write(elevation, 1)
    ring = [[180.005, -16.802], [180.01, -16.802], [180.01, -16.798], [180.005, -16.798], [180.005, -16.802]]
    (tmp_path / "land.geojson").write_text(json.dumps({"type": "FeatureCollection", "features": [
        {"type": "Feature", "properties": {}, "geometry": {"type": "Polygon", "coordinates": [ring]}}]}))
    data = {"version": 1, "world": {"origin": {"latitude_deg": origin[0], "longitude_deg": origin[1]}},
            "vessels": [{"name": "wamv", "model": "wamv", "pose": {"position": [-500.0, 0.0, 0.0]}}],
            "geo": {"extent_m": 2000.0, "terrain_cell_m": 5.0, "land": {"file": str(tmp_path / "land.geojson")},
                    "bathymetry": {"file": str(tmp_path / "gebco.tif")}}}  # fmt: skip
    sim = Simulation(parse_scenario(data, "test.yaml"))
    x, y = np.array([-800.0, 0.0, 520.0, 600.0, 900.0]), np.full(5, -500.0)  # 180° E is at x ≈ 533 m
    lat, lon, _ = pymap3d.enu2geodetic(x, y, 0.0, *origin, 0.0)
    expected = 10.0 + 200.0 * (np.where(lon < 0, lon + 360.0, lon) - 179.97)
    assert np.allclose(sim.world.depth_at(x, y), expected, atol=1e-6)
    t = sim.place.terrain  # the solid seabed too (it samples through a lattice of exact transforms)
    row = int(np.argmin(np.abs(t.ys + 500.0)))
    columns = [int(np.argmin(np.abs(t.xs - v))) for v in x]
    assert np.allclose(-t.z[row, columns], 10.0 + 200.0 * (np.where(lon < 0, lon + 360.0, lon) - 179.97), atol=0.05)
    land_x, land_y, _ = pymap3d.geodetic2enu(-16.8, -179.9925, 0.0, *origin, 0.0)  # the land square's centre
    assert sim.world.depth_at([land_x], [land_y])[0] < 0.0
    sim.close()


def test_the_map_title_gives_hemispheres_by_letter():
    """The plan view's title read 'origin -16.80000° N, -179.99500° E' for a place in the South Pacific."""
    from usvsim.geo.plan import latlon_text

    assert latlon_text(-16.8, -179.995) == "16.80000° S, 179.99500° W"
    assert latlon_text(59.41, 10.51) == "59.41000° N, 10.51000° E"


def test_soundings_from_a_csv_file_with_lon_lat_columns(place, tmp_path):
    """A CSV of soundings (the commonest form) crashed with "TypeError: 'NoneType' object is not iterable":
    GDAL reads no points from a CSV unless told its coordinate columns."""
    import pymap3d

    rng = np.random.default_rng(0)
    x, y = rng.uniform(-380, 380, 60), rng.uniform(-380, 80, 60)
    lat, lon, _ = GeoFrame(*ORIGIN).to_geodetic(x, y).T
    depth = 5.0 + 0.01 * (x + 400.0)
    rows = ["Longitude,Latitude,depth"] + [f"{a:.9f},{b:.9f},{d:.4f}" for a, b, d in zip(lon, lat, depth)]
    (tmp_path / "soundings.csv").write_text("\n".join(rows) + "\n")
    geo = geo_section(place)
    geo["bathymetry"] = {"file": str(tmp_path / "soundings.csv"), "crs": "EPSG:4326", "values": "depth"}
    sim = Simulation(parse_scenario({**scenario_data(place), "geo": geo}, "test.yaml"))
    k = int(np.argmin(np.hypot(x, y)))
    px, py, _ = pymap3d.geodetic2enu(lat[k], lon[k], 0.0, *ORIGIN)
    assert sim.world.depth_at([px], [py])[0] == pytest.approx(depth[k], abs=1e-3)  # exact at a sounding
    sim.close()
    (tmp_path / "bad.csv").write_text("a,b,depth\n1,2,3\n")
    geo["bathymetry"]["file"] = str(tmp_path / "bad.csv")
    with pytest.raises(UsvsimError, match=r"bad.csv: has no geometry \(a CSV needs coordinate columns"):
        Simulation(parse_scenario({**scenario_data(place), "geo": geo}, "test.yaml"))


def test_a_misspelt_layer_names_the_layers_the_file_has(place, tmp_path):
    """It said the GeoPackage was "not a vector file pyogrio can read (Layer 'lnd' could not be opened)"."""
    import pyogrio

    from usvsim.geo.vector import read_features

    feats = read_features(place["land"], None, None, GeoFrame(*ORIGIN), 400.0, ("Polygon",))
    wkb = np.array([shapely.to_wkb(g) for g in feats.geometries], dtype=object)
    for name in ("land", "quays"):
        pyogrio.raw.write(tmp_path / "place.gpkg", wkb, field_data=[], fields=[], geometry_type="Polygon", driver="GPKG",
                          layer=name, crs="EPSG:4326", append=name != "land")  # fmt: skip
    geo = geo_section(place)
    geo["land"] = {"file": str(tmp_path / "place.gpkg"), "layer": "lnd"}
    with pytest.raises(UsvsimError, match=r"place.gpkg: has no layer 'lnd' \(its layers: land, quays\)$"):
        Simulation(parse_scenario({**scenario_data(place), "geo": geo}, "test.yaml"))


def test_nan_coordinates_are_named_as_such(place, tmp_path):
    """A NaN in a polygon was reported as "coordinates outside the area of its CRS; is the CRS right?", after a
    RuntimeWarning from shapely."""
    ring = '[[10.43, 59.42], [NaN, 59.43], [10.44, 59.43], [10.43, 59.42]]'
    (tmp_path / "nan.geojson").write_text('{"type": "FeatureCollection", "features": [{"type": "Feature", "properties": {},'
                                          f' "geometry": {{"type": "Polygon", "coordinates": [{ring}]}}}}]}}')
    geo = {**geo_section(place), "land": {"file": str(tmp_path / "nan.geojson")}}
    with pytest.raises(UsvsimError, match=r"nan.geojson: feature 0 has coordinates that are not finite numbers"):
        Simulation(parse_scenario({**scenario_data(place), "geo": geo}, "test.yaml"))


def test_the_outer_half_of_an_edge_pixel_has_the_edge_pixels_value(place):
    """Samples between the outermost pixel centres and the raster's edge were NaN, so the default depth applied
    in a band half a pixel wide all along the edge (225 m for GEBCO; at the North Pole for a lat/lon raster)."""
    import rasterio

    with rasterio.open(place["depth"]) as ds:
        values, transform = ds.read(1), ds.transform
    sim = Simulation(parse_scenario(scenario_data(place), "test.yaml"))
    convert = GeoFrame(*ORIGIN).from_crs("EPSG:25832", "test")
    for col, expected in ((-0.3 + 0.5, -values[100, 0]), (-0.7 + 0.5, 20.0)):  # inside the edge pixel; off the raster
        e, n = transform @ (np.array([col]), np.array([100.5]))
        x, y = convert(e, n)
        assert sim.place.depth_at(x, y)[0] == pytest.approx(expected, abs=1e-4)
    sim.close()


def test_depth_is_negative_everywhere_on_land_even_next_to_the_coast(place):
    """Within half a terrain cell inside the coastline depth_at read -0.0 (the nearest terrain vertex held the
    seabed, clamped at 0), so `depth < 0` called that strip of land water. The place's land is 4 m high; with
    3.2 m cells the vertices nearest the coast (y = 100 m) are at 99.2 m (water) and 102.4 m."""
    sim = Simulation(parse_scenario(scenario_data(place, terrain_cell_m=3.2), "test.yaml"))
    x = np.linspace(-300.0, 300.0, 61)
    for y in (COAST_Y + 0.3, COAST_Y + 0.9, COAST_Y + 50.0):
        assert np.all(sim.world.depth_at(x, np.full_like(x, y)) == -4.0)
    assert np.all(sim.world.depth_at(x, np.full_like(x, COAST_Y - 0.3)) > 0.0)  # the water side
    sim.close()


def test_rasters_are_sampled_where_vector_data_lands_for_an_origin_above_sea_level(place):
    """With world.origin.altitude_m = h the raster was sampled h above the tangent plane, not at height h, so its
    lookups sat h·d/R farther out than the land polygons and `latlon` placements (0.58 m at 10 km for a lake at
    372 m). Pixel centres, placed by pymap3d at the origin's height, must read their pixels' values."""
    import pymap3d
    import rasterio
    from pyproj import Transformer

    data = scenario_data(place)
    data["world"]["origin"]["altitude_m"] = 5000.0  # exaggerated so that 300 m out the shift (0.24 m) shows
    sim = Simulation(parse_scenario(data, "test.yaml"))
    with rasterio.open(place["depth"]) as ds:
        values, transform = ds.read(1), ds.transform
    rows, cols = np.array([20, 40, 100, 259]), np.array([20, 250, 60, 259])  # corners ~ 300-550 m out
    e, n = transform @ (cols + 0.5, rows + 0.5)
    lon, lat = Transformer.from_crs("EPSG:25832", "EPSG:4326", always_xy=True).transform(e, n)
    x, y, _ = pymap3d.geodetic2enu(lat, lon, np.full_like(lat, 5000.0), ORIGIN[0], ORIGIN[1], 5000.0)
    assert sim.place.depth_at(x, y) == pytest.approx(-values[rows, cols], abs=2e-5)  # the raster: 1 cm/m
    sim.close()


def test_a_raster_with_only_no_data_in_the_scene_is_an_error(place, tmp_path):
    """A raster whose pixels are all no-data (a wrong band, a wrong nodata value) gave the default depth
    everywhere, silently."""
    import rasterio

    with rasterio.open(place["depth"]) as ds:
        profile, values = ds.profile, ds.read(1)
    with rasterio.open(tmp_path / "empty.tif", "w", **profile) as ds:
        ds.write(np.full_like(values, profile["nodata"]), 1)
    geo = {**geo_section(place), "bathymetry": {"file": str(tmp_path / "empty.tif")}}
    with pytest.raises(UsvsimError, match=r"empty.tif: no value within the scene \(400 m around the origin\)"):
        Simulation(parse_scenario({**scenario_data(place), "geo": geo}, "test.yaml"))


def test_ais_reports_and_replayed_tracks_agree_with_latlon_placements_for_an_origin_above_sea_level(tmp_path):
    """With world.origin.altitude_m = h, AIS reports and AIS replay tracks took the origin at height 0 while geo
    data, `latlon` placements and GNSS take it at h: 10 km out they disagreed by h·d/R (0.58 m for a lake at
    372 m; 4.7 m at 3000 m, used here)."""
    from usvsim.config.scenario import GeodeticOrigin
    from usvsim.traffic import ais
    from usvsim.traffic.motion import read_ais_csv

    origin = GeodeticOrigin(latitude_deg=46.45, longitude_deg=6.6, altitude_m=3000.0)
    frame = GeoFrame(origin.latitude_deg, origin.longitude_deg, origin.altitude_m)
    x, y = 8000.0, 6000.0
    lat, lon = ais.enu_to_latlon(x, y, origin.latitude_deg, origin.longitude_deg, origin.altitude_m)
    back = frame.to_enu(lat, lon)[0]  # the way a latlon placement of that report would land
    assert np.hypot(back[0] - x, back[1] - y) < 0.02  # the tangent plane's point vs the level one: ~1 cm
    start = frame.level_to_geodetic(x, y)[0]
    end = frame.level_to_geodetic(x + 100.0, y)[0]
    (tmp_path / "track.csv").write_text(f"time,lat,lon,sog,cog,heading\n0,{start[0]:.10f},{start[1]:.10f},1.944,90,90\n"
                                        f"100,{end[0]:.10f},{end[1]:.10f},1.944,90,90\n")
    track = read_ais_csv(tmp_path / "track.csv", origin)
    assert track.p0[0] == pytest.approx((x, y), abs=1e-3)


def test_the_cache_key_follows_the_geo_code(place, monkeypatch):
    """The key was the section, the origin and the files' bytes: after a fix to the build an old entry was still
    read (a wrong-sign bathymetry kept validating from ~/.cache) unless someone remembered CACHE_VERSION."""
    from usvsim.geo import scene

    geo = parse_scenario(scenario_data(place), "test.yaml").geo
    frame = GeoFrame(*ORIGIN)
    before = scene._cache_key(geo, frame, place["land"].parent)
    monkeypatch.setattr(scene, "_code_digest", lambda: "another version of usvsim/geo")
    assert scene._cache_key(geo, frame, place["land"].parent) != before


@pytest.mark.parametrize("key", ["land", "structures", "marks", "bathymetry"])
@pytest.mark.parametrize("kind", ["geojson", "shp", "csv"])
def test_an_empty_file_is_an_error_not_a_place_without_it(place, tmp_path, key, kind):
    """An empty land file (a clip that missed the area) was taken as "no land", silently; empty soundings were
    numpy's "ValueError: need at least one array to concatenate"."""
    import pyogrio

    path = tmp_path / f"empty.{kind}"
    if kind == "geojson":
        path.write_text('{"type": "FeatureCollection", "features": []}')
    elif kind == "csv":
        path.write_text("lon,lat,depth,height,color\n")
    else:
        geometry = "Point" if key in ("marks", "bathymetry") else "Polygon"
        pyogrio.raw.write(path, np.array([], dtype=object), field_data=[], fields=[], geometry_type=geometry,
                          crs="EPSG:4326")  # fmt: skip
    geo = geo_section(place)
    spec = {"file": str(path), "crs": "EPSG:4326"} if kind == "csv" else {"file": str(path)}
    geo[key] = [spec] if key in ("structures", "marks") else {**spec, "values": "depth"} if key == "bathymetry" else spec
    with pytest.raises(UsvsimError, match=rf"empty.{kind}: the file holds no features \(empty; .*drop this entry"):
        Simulation(parse_scenario({**scenario_data(place), "geo": geo}, "test.yaml"))


def test_soundings_default_to_depths_like_their_default_depth_column(place, tmp_path):
    """`value_property` defaulted to `depth` but `values` to `elevation`: a CSV with the default column and no
    `values:` was read as elevations and the run stopped ('are they depths? then set values: depth'). A raster
    without `values:` still holds elevations (GEBCO)."""
    from usvsim.config.geo import Bathymetry

    x, y = np.meshgrid(np.linspace(-380, 380, 8), np.linspace(-380, 80, 6))
    lat, lon, _ = GeoFrame(*ORIGIN).to_geodetic(x.ravel(), y.ravel()).T
    rows = ["lon,lat,depth"] + [f"{a:.9f},{b:.9f},7.5" for a, b in zip(lon, lat)]
    (tmp_path / "soundings.csv").write_text("\n".join(rows) + "\n")
    geo = {**geo_section(place), "bathymetry": {"file": str(tmp_path / "soundings.csv"), "crs": "EPSG:4326"}}
    scenario = parse_scenario({**scenario_data(place), "geo": geo}, "test.yaml")
    assert scenario.geo.bathymetry.values == "depth"
    sim = Simulation(scenario)
    assert sim.world.depth_at([0.0], [-100.0])[0] == pytest.approx(7.5, abs=1e-9)
    sim.close()
    assert Bathymetry(file="gebco.tif").values == "elevation"
    assert Bathymetry(file="soundings.gpkg").values == "depth"
    assert Bathymetry(file="soundings.gpkg", values="elevation").values == "elevation"  # an explicit choice stays
