"""Traffic tracks against closed forms: constant course/speed, routes, AIS CSV replay (exact at samples)."""

import math

import numpy as np
import pymap3d
import pytest

from usvsim.config.scenario import GeodeticOrigin
from usvsim.core.errors import ScenarioError
from usvsim.traffic.kernels import TrackTable
from usvsim.traffic.motion import KNOT_MPS, constant_track, read_ais_csv, route_track


def at(track, t):
    pos, vel, yaw = np.zeros((1, 2)), np.zeros((1, 2)), np.zeros(1)
    TrackTable.of([track]).evaluate(t, pos, vel, yaw)
    return pos[0], vel[0], yaw[0]


def test_constant_course_and_speed():
    # course 030° (nautical) at 4 m/s: velocity (east, north) = 4 (sin 30°, cos 30°), ENU yaw 60°
    pos, vel, yaw = at(constant_track((10.0, -5.0), math.radians(30.0), 4.0), 25.0)
    np.testing.assert_allclose(vel, [2.0, 4.0 * math.cos(math.radians(30))], atol=1e-12)
    np.testing.assert_allclose(pos, [10.0 + 50.0, -5.0 + 100.0 * math.cos(math.radians(30))], atol=1e-9)
    assert yaw == pytest.approx(math.radians(60.0))


def test_route_legs_speeds_and_stop():
    track = route_track([(0, 0), (100, 0), (100, 50)], [5.0, 2.0, 0.0])
    pos, vel, yaw = at(track, 10.0)  # 50 m along the first leg (east) at 5 m/s
    np.testing.assert_allclose(pos, [50, 0], atol=1e-9)
    np.testing.assert_allclose(vel, [5, 0], atol=1e-12)
    pos, vel, yaw = at(track, 20.0 + 12.5)  # second leg starts at 20 s, 2 m/s north
    np.testing.assert_allclose(pos, [100, 25], atol=1e-9)
    assert yaw == pytest.approx(math.pi / 2)
    pos, vel, _ = at(track, 1000.0)  # arrived and stopped at the last waypoint
    np.testing.assert_allclose(pos, [100, 50])
    np.testing.assert_allclose(vel, [0, 0])


def test_a_zero_speed_waypoint_stops_the_ship_there_for_good_and_it_never_jumps():
    """(0,300)@3 → (30,300)@0 → (300,300)@3 → (300,600): 10 s east at 3 m/s, then stopped at (30, 300) heading
    east (as it arrived) for good; the leg at speed 0 was dropped and the ship jumped 270 m at t = 10 s (QA)."""
    track = route_track([(0, 300), (30, 300), (300, 300), (300, 600)], [3.0, 0.0, 3.0, 3.0])
    times = np.arange(0.0, 400.0, 0.05)
    pos = np.array([at(track, t)[0] for t in times])
    assert np.abs(np.diff(pos, axis=0)).max() <= 3.0 * 0.05 + 1e-9  # never faster than the leg speed: no jump
    np.testing.assert_allclose(at(track, 5.0)[0], [15, 300], atol=1e-9)
    for t in (10.0, 11.0, 1e4):
        p, v, yaw = at(track, t)
        np.testing.assert_allclose(p, [30, 300], atol=1e-9)
        np.testing.assert_allclose(v, [0, 0])
        assert yaw == pytest.approx(0.0)  # ENU yaw 0: east, as it arrived
    looped = route_track([(0, 0), (10, 0), (10, 10)], [1.0, 0.0, 1.0], loop=True)  # a stop ends a loop too
    np.testing.assert_allclose(at(looped, 1e4)[0], [10, 0], atol=1e-9)


@pytest.mark.parametrize(("points", "course_deg"), [
    ([(0, 300), (300, 300), (300, 600)], 90.0),  # waits at the start heading along its first leg, east
    ([(-300, 0), (-200, 0)], 90.0),  # the stopped ship of docs/traffic.md: two waypoints at speed 0
    ([(0, 0), (0, 0), (-50, -50)], 225.0),  # a first leg of zero length: the route's first real leg
    ([(5, 5), (5, 5)], 0.0),  # nowhere to head: north
])  # fmt: skip
def test_a_route_stopped_at_its_start_stays_there_heading_along_its_route(points, course_deg):
    """A route whose first waypoint has speed 0 stays there (it started at the second waypoint, moving, and
    headed north whatever the route's direction: QA)."""
    track = route_track(points, [0.0] + [3.0] * (len(points) - 1))
    for t in (0.0, 50.0, 1e4):
        p, v, yaw = at(track, t)
        np.testing.assert_allclose(p, points[0], atol=1e-12)
        np.testing.assert_allclose(v, [0, 0])
        assert math.degrees(math.remainder(yaw - math.radians(90.0 - course_deg), 2 * math.pi)) == pytest.approx(0.0, abs=1e-9)


def test_looped_route_starts_over():
    track = route_track([(0, 0), (10, 0), (10, 10)], [1.0, 1.0, 1.0], loop=True)
    period = 10 + 10 + math.hypot(10, 10)
    for t in (3.0, 17.0, 25.0):
        np.testing.assert_allclose(at(track, t)[0], at(track, t + 2 * period)[0], atol=1e-9)


def test_many_tracks_in_one_table():
    tracks = [constant_track((k, 0.0), 0.0, float(k)) for k in range(50)]
    pos, vel, yaw = np.zeros((50, 2)), np.zeros((50, 2)), np.zeros(50)
    TrackTable.of(tracks).evaluate(2.0, pos, vel, yaw)
    np.testing.assert_allclose(pos[:, 1], 2.0 * np.arange(50))


def write_csv(path, origin, rows):
    lines = ["time,lat,lon,sog,cog,heading"]
    for t, e, n, sog, cog, hdg in rows:
        lat, lon, _ = pymap3d.enu2geodetic(e, n, 0.0, origin.latitude_deg, origin.longitude_deg, 0.0)
        lines.append(f"{t},{lat:.9f},{lon:.9f},{sog},{cog},{hdg}")
    path.write_text("\n".join(lines) + "\n")


def test_ais_csv_replay_exact_at_samples_and_smooth_between(tmp_path):
    origin = GeodeticOrigin()
    v = 10.0 * KNOT_MPS  # a ship turning from north to east at 10 kn on a 300 m circle
    rows = []
    for k in range(7):
        a = k * math.pi / 12
        t = 300.0 * a / v
        rows.append((t, 300 * (1 - math.cos(a)), 300 * math.sin(a), 10.0, math.degrees(a), 511 if k == 3 else math.degrees(a)))
    write_csv(tmp_path / "track.csv", origin, rows)
    track = read_ais_csv(tmp_path / "track.csv", origin)
    for t, e, n, *_ in rows:
        np.testing.assert_allclose(at(track, t)[0], [e, n], atol=1e-3)  # exact at the samples (float round-off)
    t_mid = 0.5 * (rows[2][0] + rows[3][0])
    a = v * t_mid / 300.0
    np.testing.assert_allclose(at(track, t_mid)[0], [300 * (1 - math.cos(a)), 300 * math.sin(a)], atol=0.5)


def test_ais_csv_course_360_is_not_available_not_north(tmp_path):
    """ITU-R M.1371 codes "course not available" as 360.0; a replayed row with COG 360 was taken as north, so a
    ship sailing east at 10 kn was given a northward velocity at each row (and, heading 511, a northward bow).
    Now the course there is the track's own direction: east, and the heading follows it."""
    origin = GeodeticOrigin()
    v = 10.0 * KNOT_MPS
    rows = [(t, v * t, 0.0, 10.0, 360, 511) for t in (0.0, 30.0, 60.0, 90.0)]
    write_csv(tmp_path / "track.csv", origin, rows)
    track = read_ais_csv(tmp_path / "track.csv", origin)
    for t in (30.0, 45.0, 60.0):
        p, vel, yaw = at(track, t)
        np.testing.assert_allclose(p, [v * t, 0.0], atol=0.01)  # on the straight track between the rows too
        np.testing.assert_allclose(vel, [v, 0.0], atol=1e-3)  # east at 10 kn (it was [0, 5.14]: north)
        assert math.degrees(math.remainder(yaw, 2 * math.pi)) == pytest.approx(0.0, abs=0.01)  # bow east (ENU yaw 0)


def test_ais_csv_errors_name_the_file(tmp_path):
    (tmp_path / "bad.csv").write_text("t,lat\n0,1\n")
    with pytest.raises(ScenarioError, match="header row"):
        read_ais_csv(tmp_path / "bad.csv", GeodeticOrigin(), "s.yaml", "traffic.ships[0].motion")
    with pytest.raises(ScenarioError, match="not found"):
        read_ais_csv(tmp_path / "none.csv", GeodeticOrigin(), "s.yaml", "traffic.ships[0].motion")


@pytest.mark.parametrize(
    ("row", "message"),
    [
        ("0,nan,10.43,5,180,511", "lat must be finite"),  # was a ValueError traceback from the AIS encoder mid-run
        ("0,59.43,10.43,inf,180,511", "sog must be finite"),
        ("0,99,10.43,5,180,511", r"lat must be in \[-90, 90\]"),  # values out of range were replayed as given
        ("0,59.43,10.43,-5,180,511", r"sog must be in \[0, 102.2\]"),
        ("0,59.43,10.43,5,999,511", r"cog must be in \[0, 360\]"),
        ("0,59.43,10.43,5,180,400", r"heading must be in \[0, 360\) or 511"),
        ("0,0,0,5,180,511", "more than 100 km from the world origin"),  # 5000 km away, past the limit of positions
    ],
)
def test_ais_csv_values_that_cannot_be_replayed_name_the_row(tmp_path, row, message):
    (tmp_path / "t.csv").write_text(f"time,lat,lon,sog,cog,heading\n{row}\n60,59.425,10.43,5,180,180\n")
    with pytest.raises(ScenarioError, match=message) as info:
        read_ais_csv(tmp_path / "t.csv", GeodeticOrigin(), "s.yaml", "traffic.ships[0].motion.path")
    assert "(row 2)" in str(info.value) or "row 2 " in str(info.value)


@pytest.mark.parametrize(
    ("text", "message"),
    [  # the first two were TypeError / UnicodeDecodeError tracebacks; the third was read with the extra field dropped
        (b"time,lat,lon,sog,cog,heading\n0,59.43,10.43,5,180,511\n60,59.425,10.43,5,180\n", "row 3 has 5 fields, the header 6"),
        (b"\xff\xfe time,lat", "not a UTF-8 text"),
        (b"time,lat,lon,sog,cog,heading\n0,59.43,10.43,5,180,511\n\n60,59.425,10.43,5,180,180,9\n",
         "row 4 has 7 fields, the header 6"),  # a blank line counts as a row of the file
        (b"time,lat,lon,sog,cog,heading\n0,59.43,10.43,5,180,511\n60,abc,10.43,5,180,180\n", "row 3: lat 'abc' is not a number"),
        (b"time,lat,lon,sog,cog,heading\n0,59.43,10.43,5,180,511\n60,59.425,10.43,5,180,180\n30,59.42,10.43,5,180,180\n",
         r"time must increase from row to row \(row 4\)"),
        (b"time,lat,lon,sog,cog,heading\n2026-01-01T00:00:00Z,59.43,10.43,5,180,511\n60,59.425,10.43,5,180,180\n",
         "row 3: time '60' is not an ISO 8601 time"),
    ],
)
def test_ais_csv_malformed_rows_are_one_error_naming_the_row(tmp_path, text, message):
    (tmp_path / "t.csv").write_bytes(text)
    with pytest.raises(ScenarioError, match=message) as info:
        read_ais_csv(tmp_path / "t.csv", GeodeticOrigin(), "s.yaml", "traffic.ships[0].motion.path")
    assert str(info.value).startswith("s.yaml: traffic.ships[0].motion.path: ") and "\n" not in str(info.value)
    (tmp_path / "d.csv").mkdir()
    with pytest.raises(ScenarioError, match="cannot read it"):
        read_ais_csv(tmp_path / "d.csv", GeodeticOrigin(), "s.yaml", "traffic.ships[0].motion.path")


def test_ais_csv_with_a_bom_and_utc_times_without_a_zone(tmp_path, monkeypatch):
    """A spreadsheet's UTF-8 BOM is not part of the header ('needs a header row' before); a time without a zone
    is UTC (as with 'Z'), not the machine's local time (here Tokyo's: the second row was 9 h before the first)."""
    import time

    rows = "2026-01-01T00:00:00Z,59.43,10.43,5,180,511\n2026-01-01T00:01:00,59.425,10.43,5,180,180\n"
    (tmp_path / "t.csv").write_bytes(b"\xef\xbb\xbftime,lat,lon,sog,cog,heading\n" + rows.encode())
    monkeypatch.setenv("TZ", "Asia/Tokyo")
    time.tzset()
    try:
        track = read_ais_csv(tmp_path / "t.csv", GeodeticOrigin())
    finally:
        monkeypatch.undo()
        time.tzset()
    assert track.t1[-1] == 60.0


@pytest.mark.parametrize("course", [360.0, 400.0, -10.0])
def test_a_constant_course_outside_0_to_360_is_one_clear_error(course):
    """course_deg is in [0, 360) (400 was accepted: QA); the error names the key."""
    from usvsim.config.loader import parse_scenario

    data = {"version": 1, "vessels": [{"name": "wamv", "model": "wamv"}], "traffic": {"ships": [
        {"name": "s", "mmsi": 257000001, "motion": {"type": "constant", "position": [0, 0], "course_deg": course,
                                                    "speed_mps": 1}}]}}  # fmt: skip
    with pytest.raises(ScenarioError) as err:
        parse_scenario(data, "my.yaml")
    text = str(err.value)
    assert "traffic.ships[0].motion.course_deg" in text and ("360" in text or " 0" in text)
    assert len(text.splitlines()) == 1


def test_a_physics_ships_pilot_stops_at_a_zero_speed_waypoint_and_holds():
    """The LOS pilot of a full-physics ship ends its route at the first waypoint of speed 0, as a kinematic ship
    does: it sails the leg before it at full speed to its end (it switched to the speed-0 leg `accept_m` early, so
    stopped short) and then holds (no surge, no turning towards the next leg); one stopped at its start holds."""
    from usvsim.traffic.pilot import LosPilot

    pilot = LosPilot([(0, 0), (100, 0), (100, 100), (200, 100)], [2.0, 0.0, 2.0, 2.0], lookahead_m=20.0, accept_m=20.0)
    assert pilot.reference((50.0, 0.0), 0.0) == (2.0, 0.0, 0.0)
    assert pilot.reference((95.0, 0.0), 0.0)[0] == 2.0  # within accept_m of the stop: still sailing to it
    for pos in ((100.5, 0.0), (100.0, 30.0), (0.0, 0.0)):
        assert pilot.reference(pos, 0.3) == (0.0, 0.0, 0.0)
    assert LosPilot([(0, 0), (100, 0)], [0.0, 0.0], 20.0, 20.0).reference((0.0, 0.0), 1.0) == (0.0, 0.0, 0.0)


def test_an_ais_csv_position_jump_is_one_error_naming_the_row(tmp_path):
    """A row 11 km from the one before it 1 s earlier (a 0.1° latitude glitch) was replayed at 11 km/s; a ship
    sails at most 100 m/s (the limit of every ship speed), so it is refused naming the row. 99 m/s passes."""
    text = "time,lat,lon,sog,cog,heading\n0,59.42083,10.43278,5,90,90\n1,59.52083,10.43278,5,90,90\n"
    (tmp_path / "t.csv").write_text(text)
    with pytest.raises(ScenarioError, match=r"row 3 is 11\d{3} m from row 2 only 1 s before .*a position jump") as info:
        read_ais_csv(tmp_path / "t.csv", GeodeticOrigin(), "s.yaml", "traffic.ships[0].motion.path")
    assert str(info.value).startswith("s.yaml: traffic.ships[0].motion.path: ") and "\n" not in str(info.value)
    origin = GeodeticOrigin()
    write_csv(tmp_path / "ok.csv", origin, [(0, 0.0, 0.0, 5, 0, 0), (10, 0.0, 990.0, 5, 0, 0)])
    track = read_ais_csv(tmp_path / "ok.csv", origin)
    np.testing.assert_allclose(at(track, 10.0)[0], [0.0, 990.0], atol=1e-3)
