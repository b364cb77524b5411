"""`usvsim map` as a chart (qa20): a latitude/longitude graticule true far from the origin (checked against
pyproj's geocentric conversion, independent of usvsim's frame), depth contour levels of the user's choice,
and a recorded run's tracks drawn and written as GeoJSON/CSV with latitudes and longitudes (against pymap3d)."""

from __future__ import annotations

import csv
import json
import math
import re

import numpy as np
import pymap3d
import pytest
import yaml
from place import ORIGIN, geo_section
from typer.testing import CliRunner

from usvsim.cli.app import app
from usvsim.geo.frame import GeoFrame
from usvsim.geo.graticule import dm_label, graticule


def _latlon_of_enu(x, y, origin, level: bool = True):
    """Latitude, longitude of ENU points by hand to ECEF, then pyproj's geocentric → geodetic: the point of the
    level surface at the origin's height under (x, y), where geodata sit (docs/geo.md), or with level=False the
    tangent plane's point (z = 0), whose latitude and longitude GNSS fixes report."""
    from pyproj import Transformer

    lat0, lon0, h0 = origin
    to_ecef = Transformer.from_crs("EPSG:4979", "EPSG:4978")
    to_geo = Transformer.from_crs("EPSG:4978", "EPSG:4979")
    x0, y0, z0 = to_ecef.transform(lat0, lon0, h0)
    p, lam = math.radians(lat0), math.radians(lon0)
    east = np.array([-math.sin(lam), math.cos(lam), 0.0])
    north = np.array([-math.sin(p) * math.cos(lam), -math.sin(p) * math.sin(lam), math.cos(p)])
    up = np.cross(east, north)
    z = np.zeros(len(x))
    for _ in range(3 if level else 0):  # Newton on the height: the local vertical is within d/R of `up`
        _, _, h = to_geo.transform(*(np.array([x0, y0, z0]) + np.outer(x, east) + np.outer(y, north) + np.outer(z, up)).T)
        z = z - (np.asarray(h) - h0)
    ecef = np.array([x0, y0, z0]) + np.outer(x, east) + np.outer(y, north) + np.outer(z, up)
    lat, lon, _ = to_geo.transform(*ecef.T)
    return np.asarray(lat), np.asarray(lon)


def _parse(label: str) -> float:
    deg, minutes, hemisphere = re.fullmatch(r"(\d+)°([\d.]+)′([NSEW]?)", label).groups()
    return (int(deg) + float(minutes) / 60.0) * (-1.0 if hemisphere in ("S", "W") else 1.0)


@pytest.mark.parametrize("origin", [(59.41, 10.51, 0.0), (-16.8, 179.995, 0.0), (0.01, -0.02, 372.0)])
def test_graticule_lines_lie_on_their_latitude_and_longitude_20_km_from_the_origin(origin):
    frame = GeoFrame(*origin)
    lines = graticule(frame, (-20000.0, 20000.0), (-20000.0, 20000.0))
    for kind in ("lat", "lon"):
        mine = [line for line in lines if line.kind == kind]
        assert 3 <= len(mine) <= 7
        for line in mine:
            lat, lon = _latlon_of_enu(*line.xy.T, origin)
            got = lat if kind == "lat" else (lon - line.value_deg + 180.0) % 360.0 + line.value_deg - 180.0
            assert np.abs(got - line.value_deg).max() < 1e-8  # 1 mm
            lat_plane, lon_plane = _latlon_of_enu(*line.xy.T, origin, level=False)
            plane = lat_plane if kind == "lat" else (lon_plane - line.value_deg + 180.0) % 360.0 + line.value_deg - 180.0
            metres = np.abs(plane - line.value_deg) * 111_320.0 * (math.cos(math.radians(origin[0])) if kind == "lon" else 1)
            assert metres.max() < 0.3  # GNSS's reading (the tangent plane's point): 0.2 m off 28 km from the origin
            assert (_parse(line.label) - line.value_deg) % 360.0 == pytest.approx(0.0, abs=1e-9)
            spans = line.xy[:, 0] if kind == "lat" else line.xy[:, 1]
            assert spans.min() <= -20000.0 and spans.max() >= 20000.0  # across the whole view
    if origin[0] > 50:  # meridians lean by the convergence, Δλ·sin φ: 0.3° 20 km east at 59.4° N
        east = max((line for line in lines if line.kind == "lon"), key=lambda line: line.xy[0, 0])
        lean = math.degrees(math.atan2(east.xy[-1, 0] - east.xy[0, 0], east.xy[-1, 1] - east.xy[0, 1]))
        dlon = math.radians(east.value_deg - origin[1])
        assert lean == pytest.approx(-math.degrees(dlon * math.sin(math.radians(origin[0]))), rel=0.05)


def test_graticule_labels_name_degrees_minutes_and_hemisphere():
    assert dm_label(59 + 25 / 60, "lat", 1.0) == "59°25′N"
    assert dm_label(-(16 + 48.25 / 60), "lat", 0.05) == "16°48.25′S"
    assert dm_label(10.5 + 0.5 / 60, "lon", 0.5) == "10°30.5′E"
    assert dm_label(190.0, "lon", 60.0) == "170°0′W"  # past the antimeridian
    assert dm_label(-0.5, "lon", 30.0) == "0°30′W"


def _place_scenario(tmp_path, place):
    path = tmp_path / "s.yaml"
    path.write_text(yaml.safe_dump({"version": 1, "world": {"origin": {"latitude_deg": ORIGIN[0],
                                                                       "longitude_deg": ORIGIN[1]}},
                                    "vessels": [{"name": "wamv", "model": "wamv",
                                                 "pose": {"position": [-150.0, -120.0, 0.0], "yaw_deg": 35.0}}],
                                    "geo": geo_section(place)}))  # fmt: skip
    return path


def test_contour_levels_are_the_users(tmp_path, place, monkeypatch):
    from matplotlib.axes import Axes

    drawn = []
    contour = Axes.contour
    monkeypatch.setattr(Axes, "contour", lambda self, *a, **k: drawn.append(list(k["levels"])) or contour(self, *a, **k))
    path = _place_scenario(tmp_path, place)
    result = CliRunner().invoke(app, ["map", str(path), "--out", str(tmp_path / "m.png"), "--contours", "7,3,300"])
    assert result.exit_code == 0, result.output
    assert drawn == [[3.0, 7.0]]  # the place's water is 0.05 to 17 m deep
    assert "note: --contours: no contour at 300 m: the place's water is" in result.output
    for bad, words in (("2,x", "--contours '2,x': give depths in metres"), ("5,-1", "-1 is no depth"),
                       ("nan", "nan is no depth")):  # fmt: skip
        result = CliRunner().invoke(app, ["map", str(path), "--out", str(tmp_path / "m.png"), "--contours", bad])
        assert result.exit_code == 2 and words in result.output
    result = CliRunner().invoke(app, ["map", "harbor", "--out", str(tmp_path / "h.png"), "--contours", "5"])
    assert result.exit_code == 2 and "--contours: harbor has no geo: section" in result.output


def test_the_graticule_is_drawn_unless_turned_off(tmp_path, monkeypatch):
    import usvsim.geo.graticule as module

    drawn = []
    real = module.draw_graticule
    monkeypatch.setattr(module, "draw_graticule", lambda ax, frame: drawn.append(real(ax, frame)))
    for flag in ([], ["--no-graticule"]):
        result = CliRunner().invoke(app, ["map", "harbor", "--out", str(tmp_path / "h.png"), *flag])
        assert result.exit_code == 0, result.output
    (lines,) = drawn  # harbor's 70 m: parallels and meridians every 0.01′ (18.5 m and 9.4 m)
    assert {line.kind for line in lines} == {"lat", "lon"} and "59°25.25′N" in [line.label for line in lines]


def test_a_recorded_track_is_drawn_and_written_with_latitudes_and_longitudes(tmp_path, place):
    from usvsim.simulation import Simulation

    path = _place_scenario(tmp_path, place)
    sim = Simulation.from_scenario(str(path))
    boat = sim.vessels["wamv"]
    with sim.record(tmp_path / "run.mcap"):
        boat.command(0.6)
        sim.run(seconds=4.0)
        end_xy, end_yaw = boat.position[:2].copy(), boat.rpy[2]
    sim.close()
    assert np.hypot(*(end_xy - (-150.0, -120.0))) > 2.0  # it moved
    args = ["map", str(path), "--out", str(tmp_path / "m.png"), "--track", str(tmp_path / "run.mcap")]
    for suffix in ("csv", "geojson"):
        result = CliRunner().invoke(app, [*args, "--track-out", str(tmp_path / f"t.{suffix}")])
        assert result.exit_code == 0, result.output
    rows = list(csv.DictReader((tmp_path / "t.csv").open()))
    assert len(rows) == 201 and rows[0]["vessel"] == "wamv" and float(rows[-1]["time_s"]) == 4.0
    first, last = ([float(r[k]) for k in ("x_m", "y_m", "latitude_deg", "longitude_deg", "heading_deg")]
                   for r in (rows[0], rows[-1]))  # fmt: skip
    assert first[:2] == pytest.approx([-150.0, -120.0], abs=0.05) and last[:2] == pytest.approx(end_xy, abs=1e-3)
    for x, y, lat, lon, _ in (first, last):
        ref_lat, ref_lon, _ = pymap3d.enu2geodetic(x, y, 0.0, *ORIGIN)
        assert (lat, lon) == pytest.approx((ref_lat, ref_lon), abs=2e-9)
    from pyproj import Geod  # the true heading: the geodesic azimuth to a point 10 m ahead along the yaw

    ahead = last[:2] + 10.0 * np.array([math.cos(end_yaw), math.sin(end_yaw)])
    lat2, lon2, _ = pymap3d.enu2geodetic(*ahead, 0.0, *ORIGIN)
    azimuth = Geod(ellps="WGS84").inv(last[3], last[2], lon2, lat2)[0] % 360.0
    grid = (90.0 - math.degrees(end_yaw)) % 360.0  # the bearing from the world's y axis: 0.002° off, 150 m west
    assert last[4] == pytest.approx(azimuth, abs=6e-4) and abs(grid - azimuth) > 1.5e-3  # written to 0.001°
    geo = json.loads((tmp_path / "t.geojson").read_text())
    (feature,) = geo["features"]
    assert feature["geometry"]["type"] == "LineString" and feature["properties"]["vessel"] == "wamv"
    assert feature["geometry"]["coordinates"][-1] == pytest.approx([last[3], last[2]], abs=1e-12)  # [lon, lat]
    assert len(feature["properties"]["time_s"]) == len(feature["geometry"]["coordinates"]) == 201


@pytest.mark.parametrize(
    ("extra", "words"),
    [(["--track-out", "t.csv"], "--track-out needs --track RECORDING"),
     (["--track", "missing.mcap"], "--track missing.mcap: no such recording"),
     (["--track", "s.yaml"], "--track s.yaml: cannot read it as an MCAP recording"),
     (["--track", "s.yaml", "--track-out", "t.kml"], "--track-out t.kml: unknown format '.kml'; use .geojson or .csv")],
)  # fmt: skip
def test_track_mistakes_are_one_line(tmp_path, place, monkeypatch, extra, words):
    monkeypatch.chdir(tmp_path)
    _place_scenario(tmp_path, place)
    result = CliRunner().invoke(app, ["map", "s.yaml", "--out", "m.png", *extra])
    assert result.exit_code == 2 and words in result.output and "Traceback" not in result.output


def test_tracks_split_at_resets_and_notes_name_a_missing_tf_static_or_another_scenario(tmp_path):
    from usvsim.simulation import Simulation

    sim = Simulation.from_scenario("harbor")
    boat = sim.vessels["wamv"]
    with sim.record(tmp_path / "two.mcap"):
        boat.command(0.5)
        sim.run(seconds=1.0)
        sim.reset(seed=3)
        sim.run(seconds=0.5)
    with sim.record(tmp_path / "odom_only.mcap", topics=["/wamv/ground_truth/odometry"]):
        sim.run(seconds=0.5)
    sim.close()
    args = ["map", "harbor", "--out", str(tmp_path / "m.png"), "--track"]
    result = CliRunner().invoke(app, [*args, str(tmp_path / "two.mcap"), "--track-out", str(tmp_path / "t.geojson")])
    assert result.exit_code == 0 and "note" not in result.output, result.output
    features = json.loads((tmp_path / "t.geojson").read_text())["features"]
    assert [(f["properties"]["vessel"], f["properties"]["episode"]) for f in features] == [
        ("wamv", 0), ("otter", 0), ("wamv", 1), ("otter", 1)]  # fmt: skip
    assert [len(f["geometry"]["coordinates"]) for f in features] == [51, 51, 26, 26]
    result = CliRunner().invoke(app, [*args, str(tmp_path / "odom_only.mcap")])
    assert result.exit_code == 0 and "has no /tf_static world → wamv/odom; wamv's track starts at the scenario's" in result.output
    result = CliRunner().invoke(app, [*args[:1], "harbor_geo", *args[2:], str(tmp_path / "two.mcap")])
    assert result.exit_code == 0 and "wamv starts elsewhere in" in result.output and "another scenario" in result.output
