"""Real places: geodesy against pymap3d, depth against the raster, LiDAR against the coastline, hulls against
quays and shoals, and one clear error per kind of bad geodata."""

from __future__ import annotations

import json
import math

import numpy as np
import pymap3d
import pytest
from place import COAST_Y, CRS, ORIGIN, QUAY, SHOAL, geo_section, to_utm

from usvsim.config.loader import parse_scenario
from usvsim.core.errors import UsvsimError
from usvsim.geo.frame import GeoFrame
from usvsim.simulation import Simulation


def scenario(place, vessels=(), sensors=(), **geo):
    data = {"version": 1, "world": {"origin": {"latitude_deg": ORIGIN[0], "longitude_deg": ORIGIN[1]}},
            "vessels": [dict(v) for v in vessels], "geo": geo_section(place, **geo)}
    if sensors:
        data["vessels"][0]["sensors"] = list(sensors)
    return parse_scenario(data, "test.yaml")


def test_enu_round_trip_within_10_km_and_pymap3d_agrees():
    frame = GeoFrame(*ORIGIN)
    rng = np.random.default_rng(1)
    enu = np.column_stack([rng.uniform(-1e4, 1e4, 500), rng.uniform(-1e4, 1e4, 500), rng.uniform(-30, 30, 500)])
    geo = frame.to_geodetic(*enu.T)
    assert np.abs(frame.to_enu(*geo.T) - enu).max() < 1e-3
    independent = np.column_stack(pymap3d.geodetic2enu(geo[:, 0], geo[:, 1], geo[:, 2], *ORIGIN))
    assert np.abs(independent - enu).max() < 1e-3


def test_latlon_and_heading_place_objects_where_pymap3d_says(place):
    lat, lon = 59.4215, 10.4335
    sim = Simulation(scenario(place, vessels=[{"name": "wamv", "model": "wamv",
                                                "pose": {"latlon": [lat, lon], "heading_deg": 45.0}}]))
    x, y, _ = pymap3d.geodetic2enu(lat, lon, 0.0, *ORIGIN)
    pose = sim.scenario.vessels[0].pose
    assert pose.position[:2] == pytest.approx((x, y), abs=1e-3)
    yaw = np.radians(pose.yaw_deg)  # a compass heading at the placed point: 1 m along the bow, pyproj's azimuth
    lat2, lon2, _ = pymap3d.enu2geodetic(x + np.cos(yaw), y + np.sin(yaw), 0.0, *ORIGIN)
    from pyproj import Geod

    assert Geod(ellps="WGS84").inv(lon, lat, lon2, lat2)[0] == pytest.approx(45.0, abs=1e-5)
    assert pose.yaw_deg == pytest.approx(45.0 + 6.2e-4, abs=1e-5)  # 41 m east of the origin the meridian has turned
    assert sim.vessels["wamv"].position[:2] == pytest.approx((x, y), abs=0.05)
    marks = {o.name: o for o in sim.scenario.objects}
    assert marks["mark0_0"].color == "green" and marks["mark0_0"].position[:2] == pytest.approx((20, 10), abs=1e-3)
    sim.close()


def test_depth_equals_the_raster_at_pixel_centres_and_is_bilinear_between(place):
    import rasterio

    sim = Simulation(scenario(place))
    with rasterio.open(place["depth"]) as ds:
        values, transform = ds.read(1), ds.transform
    rows, cols = np.array([130, 160, 161, 200]), np.array([90, 140, 141, 150])
    e, n = transform @ (cols + 0.5, rows + 0.5)
    from pyproj import Transformer

    lon, lat = Transformer.from_crs(CRS, "EPSG:4326", always_xy=True).transform(e, n)
    x, y, _ = pymap3d.geodetic2enu(lat, lon, np.zeros_like(lat), *ORIGIN)
    assert sim.place.depth_at(x, y) == pytest.approx(-values[rows, cols], abs=1e-4)
    mid = sim.place.depth_at((x[1] + x[2]) / 2, (y[1] + y[2]) / 2)[0]  # halfway between two diagonal centres
    assert mid == pytest.approx(-(values[160, 140] + values[161, 141]) / 2, abs=1e-3)
    assert sim.place.depth_at(0.0, COAST_Y + 50)[0] == pytest.approx(-4.0)  # land: minus its height
    assert sim.world.depth_at(x, y) == pytest.approx(sim.place.depth_at(x, y))
    sim.close()


def test_lidar_beam_hits_the_straight_coastline_at_the_predicted_range(place):
    mount_z = 3.0
    sensors = [{"type": "lidar", "name": "scan", "output": "scan", "channels": 1, "elevations_deg": [0.0],
                "columns": 720, "rate_hz": 10, "range_max_m": 300.0, "range_stddev_m": 0.0,
                "mount": {"position": [0.0, 0.0, mount_z]}}]
    sim = Simulation(scenario(place, [{"name": "wamv", "model": "wamv", "pose": {"yaw_deg": 90.0}}], sensors,
                              structures=[], marks=[]))
    scans = []
    sim.subscribe(lambda env: scans.append(env) if env.topic.endswith("/scan") else None)
    sim.run(0.3)
    scan = scans[-1].msg
    boat = sim.vessels["wamv"]
    lidar = boat.position + sim.state.rot[boat.index] @ np.array([0.0, 0.0, mount_z])
    ranges = np.asarray(scan.ranges)
    angles = scan.angle_min + scan.angle_increment * np.arange(len(ranges))
    yaw = boat.rpy[2]
    for k in np.flatnonzero(np.abs(angles) < math.radians(30)):  # beams toward the coast (north)
        heading = yaw + angles[k]
        predicted = (COAST_Y - lidar[1]) / math.sin(heading)
        assert ranges[k] == pytest.approx(predicted, abs=0.05)
    sim.close()


def test_a_vessel_driven_at_the_quay_stops_at_it(place):
    x0, x1, y0, _ = QUAY
    start = {"position": [(x0 + x1) / 2, y0 - 15.0, 0.0], "yaw_deg": 90.0}
    sim = Simulation(scenario(place, [{"name": "wamv", "model": "wamv", "pose": start, "command_timeout_s": 0}],
                              marks=[]))
    boat = sim.vessels["wamv"]
    boat.command(1.0)
    sim.run(20.0)
    bow = boat.position[1] + 2.5  # WAM-V base_link is at mid-length; the hull is ~4.9 m long
    assert y0 - 0.6 < bow < y0 + 0.3
    assert any({a, b} == {"wamv", "world"} for a, b, _ in sim.contacts())
    sim.close()


def test_a_vessel_on_a_shoal_grounds(place):
    sim = Simulation(scenario(place, [{"name": "wamv", "model": "wamv",
                                        "pose": {"position": [SHOAL[0], SHOAL[1], 0.0]}}], marks=[]))
    sim.run(3.0)
    assert any({a, b} == {"wamv", "world"} for a, b, _ in sim.contacts())
    assert sim.vessels["wamv"].displaced_volume < 0.9 * 2.0 * 180 / 1025  # the ground carries part of it
    sim.close()


def _write(path, text):
    path.write_text(text)
    return path


@pytest.mark.parametrize("case", ["no_crs", "wrong_crs", "self_intersecting", "raster_outside", "missing", "points_as_land",
                                  "not_geodata"])  # fmt: skip
def test_bad_geodata_is_one_clear_error_naming_the_file(place, tmp_path, case):
    ring = to_utm([0, 100, 0, 100], [200, 300, 300, 200]).tolist()  # a bow tie
    square = to_utm([0, 100, 100, 0], [200, 200, 300, 300]).tolist()
    def poly(r):
        return {"type": "Feature", "properties": {}, "geometry": {"type": "Polygon", "coordinates": [r + [r[0]]]}}

    crs = {"type": "name", "properties": {"name": "urn:ogc:def:crs:EPSG::25832"}}
    geo = {}
    if case == "no_crs":  # a shapefile without its .prj
        import pyogrio
        import shapely

        wkb = np.array([shapely.to_wkb(shapely.Polygon(square))], dtype=object)
        pyogrio.raw.write(tmp_path / "a.shp", wkb, field_data=[], fields=[], geometry_type="Polygon",
                          driver="ESRI Shapefile")
        geo["land"] = {"file": str(tmp_path / "a.shp")}
    elif case == "wrong_crs":  # UTM numbers read as if they were EPSG:3006 (Sweden): the land lands elsewhere
        text = json.dumps({"type": "FeatureCollection", "features": [poly(square)], "crs": {
            "type": "name", "properties": {"name": "urn:ogc:def:crs:EPSG::3006"}}})
        geo["land"] = {"file": str(_write(tmp_path / "a.geojson", text))}
    elif case == "self_intersecting":
        text = json.dumps({"type": "FeatureCollection", "features": [poly(ring)], "crs": crs})
        geo["land"] = {"file": str(_write(tmp_path / "a.geojson", text))}
    elif case == "raster_outside":
        geo["bathymetry"] = {"file": str(place["depth"]), "crs": "EPSG:25832"}
        sc = scenario(place, **geo, land=None, structures=[], marks=[])
        sc = sc.model_copy(update={"world": sc.world.model_copy(update={"origin": sc.world.origin.model_copy(
            update={"latitude_deg": 60.5})})})
        with pytest.raises(UsvsimError, match="depth.tif.*does not cover"):
            Simulation(sc)
        return
    elif case == "points_as_land":  # said "no polygon within 3000 m (the data lies between (0, 0) and (0, 0))"
        point = {"type": "Feature", "properties": {}, "geometry": {"type": "Point", "coordinates": square[0]}}
        text = json.dumps({"type": "FeatureCollection", "features": [point], "crs": crs})
        geo["land"] = {"file": str(_write(tmp_path / "a.geojson", text))}
    elif case == "not_geodata":  # GDAL's advice was cut off mid-sentence: "It might help to )"
        geo["land"] = {"file": str(_write(tmp_path / "a.geojson", "hello"))}
    else:
        geo["structures"] = [{"file": str(tmp_path / "nowhere.geojson")}]
    with pytest.raises(UsvsimError) as err:
        Simulation(scenario(place, **geo))
    message = str(err.value)
    assert "\n" not in message and any(f"{n}." in message for n in ("a", "nowhere"))
    assert {"no_crs": "no CRS", "wrong_crs": "wrong CRS", "self_intersecting": "not a valid polygon",
            "missing": "geo.structures[0].file: ", "points_as_land": "holds no polygon (its features are: point)",
            "not_geodata": "not recognized as being in a supported file format)"}[case] in message  # fmt: skip


def test_land_and_structures_are_detected_with_their_classes(place):
    sensors = [{"type": "detections", "name": "objects", "rate_hz": 10, "frame": "world"}]
    sim = Simulation(scenario(place, [{"name": "wamv", "model": "wamv"}], sensors, marks=[]))
    seen = []
    sim.subscribe(lambda env: seen.append(env.msg) if env.topic.endswith("/objects") else None)
    sim.run(0.2)
    found = {(d.id, d.results[0].hypothesis.class_id): d.bbox for d in seen[-1].detections}
    assert ("land_0", "land") in found and ("quay", "structure") in found
    quay = found[("quay", "structure")]
    x0, x1, y0, y1 = QUAY
    assert quay.center.position.x == pytest.approx((x0 + x1) / 2, abs=0.05)
    assert quay.size.x == pytest.approx(x1 - x0, abs=0.1) and quay.size.y == pytest.approx(y1 - y0, abs=0.1)
    sim.close()


def test_map_command_draws_the_place(tmp_path, place):
    import yaml
    from PIL import Image
    from typer.testing import CliRunner

    from usvsim.cli.app import app

    path = tmp_path / "s.yaml"
    path.write_text(yaml.safe_dump({"version": 1, "vessels": [{"name": "wamv", "model": "wamv"}],
                                    "world": {"origin": {"latitude_deg": ORIGIN[0], "longitude_deg": ORIGIN[1]}},
                                    "geo": geo_section(place)}))
    result = CliRunner().invoke(app, ["map", str(path), "--out", str(tmp_path / "m.png")])
    assert result.exit_code == 0, result.output
    image = np.asarray(Image.open(tmp_path / "m.png").convert("RGB"))
    assert (np.abs(image.astype(int) - (0x8A, 0x9A, 0x6B)).sum(axis=2) < 10).mean() > 0.05  # land drawn


def test_waves_feel_the_depth_under_the_origin(place):
    sim = Simulation(scenario(place, [{"name": "wamv", "model": "wamv"}], marks=[]))
    assert sim.scenario.environment.water_depth_m == pytest.approx(sim.place.depth_at(0.0, 0.0)[0])
    sim.close()


def test_radar_sees_the_coast_at_its_range(place):
    radar = {"type": "radar", "name": "radar", "rpm": 60, "rate_hz": 10, "range_max_m": 400.0, "spokes": 256,
             "range_bins": 200, "image": "none", "arpa": None, "mount": {"position": [0.0, 0.0, 3.0]},
             "sea_clutter": {"sea_state": 0, "snr_at_100m_db": -60.0}}
    sim = Simulation(scenario(place, [{"name": "wamv", "model": "wamv", "pose": {"yaw_deg": 90.0}}], [radar],
                              structures=[], marks=[]))
    sim.run(1.2)
    sensor = sim.sensors["wamv/radar"]
    pos, _ = sensor.pose_world(sim)
    power = sensor.revolution.power
    bow = power[0]  # spoke 0 looks along the bow: north, at the coast
    first = int(np.argmax(bow > 0.5 * bow.max()))
    assert abs(first - int((COAST_Y - pos[1]) / sensor.bin_m)) <= 1
    stern = power[len(power) // 2]  # south: open water inside the 400 m range
    assert stern.max() < 0.1 * bow.max()
    sim.close()


def test_map_draws_traffic_routes(tmp_path):
    from PIL import Image
    from typer.testing import CliRunner

    from usvsim.cli.app import app

    result = CliRunner().invoke(app, ["map", "imazu_05", "--out", str(tmp_path / "m.png")])
    assert result.exit_code == 0, result.output
    image = np.asarray(Image.open(tmp_path / "m.png").convert("RGB")).astype(int)
    assert (np.abs(image - (0x7B, 0x3F, 0xA0)).sum(axis=2) < 30).sum() > 200  # the routes' dashed lines


def test_bathymetry_from_soundings_is_exact_at_them_and_linear_between(place, tmp_path):
    xy = np.array([[-300.0, -300.0], [300.0, -300.0], [300.0, 80.0], [-300.0, 80.0], [0.0, -100.0]])
    depth = np.array([12.0, 8.0, 3.0, 5.0, 9.5])
    utm = to_utm(*xy.T)
    crs = {"type": "name", "properties": {"name": "urn:ogc:def:crs:EPSG::25832"}}
    (tmp_path / "soundings.geojson").write_text(json.dumps({"type": "FeatureCollection", "crs": crs, "features": [
        {"type": "Feature", "properties": {"depth": float(d)}, "geometry": {"type": "Point", "coordinates": list(p)}}
        for p, d in zip(utm.tolist(), depth)]}))
    sim = Simulation(scenario(place, bathymetry={"file": str(tmp_path / "soundings.geojson"), "values": "depth"}))
    at = sim.place.bathymetry.points  # the soundings in ENU (hull corners must be met exactly, not 1e-9 m off)
    assert at == pytest.approx(xy, abs=1e-6)
    assert sim.world.depth_at(at[:, 0], at[:, 1]) == pytest.approx(depth, abs=1e-9)
    from scipy.spatial import Delaunay

    tri = Delaunay(xy)
    p = np.array([[-100.0, -200.0]])
    s = tri.find_simplex(p)[0]
    bary = tri.transform[s, :2] @ (p[0] - tri.transform[s, 2])
    weights = np.r_[bary, 1 - bary.sum()]
    assert sim.world.depth_at(*p.T)[0] == pytest.approx(weights @ depth[tri.simplices[s]], abs=1e-3)
    assert sim.world.depth_at(0.0, -390.0)[0] == pytest.approx(20.0)  # outside the soundings: the default
    sim.close()


def test_a_vessel_driven_at_the_coast_stops_at_it(place):
    start = {"position": [-200.0, COAST_Y - 20.0, 0.0], "yaw_deg": 90.0}  # bow toward the land, 17.5 m off
    sim = Simulation(scenario(place, [{"name": "wamv", "model": "wamv", "pose": start}], structures=[], marks=[]))
    boat = sim.vessels["wamv"]
    boat.command(1.0)
    sim.run(25.0)
    bow = boat.position[1] + 2.5
    cell = 2.0  # the solid coastline is the terrain grid's: within one cell of the drawn one
    assert COAST_Y - 1.5 * cell < bow < COAST_Y + 0.5
    assert any({a, b} == {"wamv", "world"} for a, b, _ in sim.contacts())
    sim.close()


def test_map_draws_a_tasks_goals(tmp_path):
    from PIL import Image
    from typer.testing import CliRunner

    from usvsim.cli.app import app

    result = CliRunner().invoke(app, ["map", "wayfinding", "--task", "--out", str(tmp_path / "m.png")])
    assert result.exit_code == 0, result.output
    image = np.asarray(Image.open(tmp_path / "m.png").convert("RGB")).astype(int)
    assert (np.abs(image - (0xE0, 0x7B, 0x00)).sum(axis=2) < 30).sum() > 100  # the three waypoints
    assert CliRunner().invoke(app, ["map", "nope", "--task"]).exit_code == 2


def test_every_tasks_plan_marks_name_what_to_do_where_its_scorer_looks():
    """`usvsim map --task` labels: each task's targets at the positions its scorer uses (world ENU m)."""
    from usvsim.tasks import TASKS
    from usvsim.tasks.animals import ANIMALS

    marks = {name: TASKS[name](0, 3).plan_marks() for name in TASKS}
    assert all(marks.values()), [name for name, m in marks.items() if not m]
    sk = TASKS["station_keeping"](0, 3)
    assert [m[:3] for m in sk.plan_marks()] == [sk.goal]
    wf = TASKS["wayfinding"](0, 3)
    assert [m[:3] for m in wf.plan_marks()] == wf.waypoints
    gym = TASKS["gymkhana"](0, 3)
    *gates, pinger = gym.plan_marks()
    assert [m[:2] for m in gates] == [g.centre for g in gym.gates]
    assert pinger[:3] == (gym.pinger[0], gym.pinger[1], None) and "pinger" in pinger[3]
    labels = {m[3].split(":")[0]: m for m in marks["wildlife"]}
    assert {name: labels[name][:2] for name in ANIMALS} == {name: xy for name, (xy, _) in ANIMALS.items()}
    assert "clockwise" in labels["platypus"][3] and "10 m" in labels["crocodile"][3]


def test_vessels_buoys_ships_and_route_legs_on_land_are_warnings_naming_them_and_the_point(place, tmp_path):
    """Land lies north of y = 100 m. On land: the WAM-V at (0, 150), a buoy at (50, 120), a moored ship at
    (-100, 300); a route from (-300, 0) north to (-300, 200) meets the coast at (-300, 100). Not: a vessel, a
    ship and a route at sea, nor a route stopped (speed 0) before the coast. `validate` and `run` print them
    (they said OK: QA)."""
    from typer.testing import CliRunner

    from usvsim.cli.app import app
    from usvsim.world.checks import land_warnings

    def ship(name, mmsi, motion):
        return {"name": name, "mmsi": mmsi, "motion": motion}

    def route(*legs):
        return {"type": "route", "waypoints": [{"position": list(p), "speed_mps": v} for p, v in legs]}

    data = {"version": 1, "world": {"origin": {"latitude_deg": ORIGIN[0], "longitude_deg": ORIGIN[1]}},
            "geo": geo_section(place),
            "vessels": [{"name": "wamv", "model": "wamv", "pose": {"position": [0, 150, 0]}},
                        {"name": "afloat", "model": "wamv", "pose": {"position": [-150, -50, 0]}}],
            "objects": [{"type": "buoy", "name": "b_land", "position": [50, 120, 0]},
                        {"type": "buoy", "name": "b_sea", "position": [-50, 0, 0]}],
            "traffic": {"ais": {"enabled": False}, "ships": [
                ship("moored", 257000001, {"type": "constant", "position": [-100, 300], "course_deg": 0, "speed_mps": 0}),
                ship("lander", 257000002, route(((-300, 0), 3), ((-300, 200), 3))),
                ship("stopper", 257000003, route(((200, 0), 3), ((200, 50), 0), ((200, 300), 3))),
                ship("seaway", 257000004, {"type": "constant", "position": [300, -100], "course_deg": 90, "speed_mps": 2})]}}  # fmt: skip
    sim = Simulation(parse_scenario(data, str(tmp_path / "land.yaml")))
    warnings = land_warnings(sim.world)
    sim.close()
    assert len(warnings) == 4, warnings
    frame = GeoFrame(*ORIGIN)

    def at(x, y):
        lat, lon, _ = frame.to_geodetic(x, y)[0]
        return f"({x:.1f}, {y:.1f}) m (lat {lat:.6f}, lon {lon:.6f})"

    assert warnings[0] == f"'wamv' starts on land at {at(0.0, 150.0)}"
    assert warnings[1] == f"'b_land' starts on land at {at(50.0, 120.0)}"
    assert warnings[2] == f"traffic.ships[0] 'moored' starts on land at {at(-100.0, 300.0)}"
    assert warnings[3].startswith("traffic.ships[1] 'lander': its route leg from waypoint 0 (-300, 0) to 1 (-300, 200) "
                                  "crosses land at (-300.0, 100.0) m")  # fmt: skip
    import yaml

    path = tmp_path / "land.yaml"
    path.write_text(yaml.safe_dump(data))
    runner = CliRunner()
    for args in (["validate", str(path)], ["run", str(path), "--duration", "0.02"]):
        result = runner.invoke(app, args)
        assert result.exit_code == 0, result.output
        assert sum("usvsim: warning:" in line and "land" in line for line in result.output.splitlines()) == 4, result.output


def test_an_object_named_like_a_mark_is_a_scenario_error(place):
    """A buoy named mark0_0 beside geo.marks ended validate in a MuJoCo traceback ("repeated name 'mark0_0' in
    body", QA); the line names the user's key."""
    from usvsim.core.errors import ScenarioError

    data = scenario(place, vessels=[{"name": "wamv", "model": "wamv"}]).model_dump()
    data["objects"] = [{"type": "buoy", "name": "mark0_1", "position": [5.0, 5.0, 0.0]}]
    with pytest.raises(ScenarioError) as info:
        Simulation(parse_scenario(data, "test.yaml"))
    assert info.value.key_path == "objects[0].name" and "geo.marks[0]" in info.value.message
