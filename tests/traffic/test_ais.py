"""AIS: every sentence decodes with pyais to the true MMSI, position (within the noise), SOG, COG and heading;
reporting intervals follow ITU-R M.1371 table 1 by speed; static data (types 5, 24); UDP on loopback."""

import math
import socket

import numpy as np
import pymap3d
import pytest
from pyais import decode

from usvsim.simulation import Simulation
from usvsim.traffic import ais

KN = 1852.0 / 3600.0


def test_class_a_intervals_follow_the_table():
    assert ais.class_a_interval(0.0, False) == 180.0
    assert ais.class_a_interval(0.0, False, moored=False) == 10.0  # stopped, not moored: the own ship
    assert ais.class_a_interval(2.0, False, moored=True) == 180.0  # moored, not faster than 3 kn
    assert ais.class_a_interval(4.0, False, moored=True) == 10.0
    assert ais.class_a_interval(10.0, False) == 10.0
    assert ais.class_a_interval(10.0, True) == pytest.approx(10.0 / 3.0)
    assert ais.class_a_interval(18.0, False) == 6.0
    assert ais.class_a_interval(18.0, True) == 2.0
    assert ais.class_a_interval(30.0, False) == 2.0
    assert ais.class_b_interval(1.0) == 180.0 and ais.class_b_interval(8.0) == 30.0


def scenario(scenario_of, noise=0.0, dropout=0.0, udp_port=None):
    ships = [
        {"name": "slow", "mmsi": 257000001, "motion": {"type": "constant", "position": [0, 500], "course_deg": 45,
                                                       "speed_mps": 8 * KN}},
        {"name": "fast", "mmsi": 257000002, "ship_type": "high_speed", "length_m": 40, "beam_m": 9,
         "motion": {"type": "constant", "position": [500, 0], "course_deg": 300, "speed_mps": 18 * KN}},
        {"name": "yacht", "mmsi": 257000003, "ship_type": "sailing", "ais": {"ais_class": "B", "callsign": "LH2211"},
         "motion": {"type": "constant", "position": [-300, 0], "course_deg": 10, "speed_mps": 6 * KN}},
    ]  # fmt: skip
    return scenario_of({"world": {"physics_rate_hz": 20}, "outputs": {"recording": {"clock_rate_hz": 10, "ground_truth_rate_hz": 10}},
                        "vessels": [{"name": "wamv", "model": "wamv"}],
                        "traffic": {"ships": ships, "ais": {"position_noise_m": noise, "dropout_probability": dropout,
                                                            "udp_port": udp_port}}})  # fmt: skip


def collect(sim, seconds):
    out = []
    sim.subscribe(lambda e: out.append((e.stamp_ns / 1e9, e.msg.sentence)) if e.topic == "/ais" else None)
    sim.run(seconds)
    return out


def truth(t, start, course_deg, speed_kn, origin):
    c = math.radians(course_deg)
    e, n = start[0] + speed_kn * KN * t * math.sin(c), start[1] + speed_kn * KN * t * math.cos(c)
    lat, lon, _ = pymap3d.enu2geodetic(e, n, 0.0, origin.latitude_deg, origin.longitude_deg, 0.0)
    return lat, lon


TRUE = {257000001: ((0, 500), 45, 8), 257000002: ((500, 0), 300, 18), 257000003: ((-300, 0), 10, 6)}


def test_every_sentence_decodes_to_the_truth(scenario_of):
    sim = Simulation(scenario(scenario_of, noise=3.0))
    sentences = collect(sim, 61.0)
    origin = sim.scenario.world.origin
    times: dict[int, list[float]] = {}
    pending: list[str] = []
    statics = set()
    for t, s in sentences:
        pending.append(s)
        fields = s.split(",")
        if fields[1] != fields[2]:  # a fragment of a multi-sentence message: wait for the last
            continue
        msg, pending = decode(*pending).asdict(), []
        mmsi = msg["mmsi"]
        start, course, speed = TRUE[mmsi]
        if msg["msg_type"] in (5, 24):
            statics.add((mmsi, msg["msg_type"], msg.get("partno")))
            if msg["msg_type"] == 5:
                assert msg["shipname"] == "SLOW" or msg["shipname"] == "FAST"
                assert msg["to_bow"] + msg["to_stern"] == (40 if mmsi == 257000002 else 20)
            continue
        assert msg["msg_type"] == (18 if mmsi == 257000003 else 1)
        lat, lon = truth(t, start, course, speed, origin)
        north = (msg["lat"] - lat) * 111_320.0
        east = (msg["lon"] - lon) * 111_320.0 * math.cos(math.radians(lat))
        assert math.hypot(north, east) < 5 * 3.0 + 0.3  # 5 sigma of the configured noise + AIS resolution
        assert msg["speed"] == pytest.approx(speed, abs=0.051)
        assert msg["course"] == pytest.approx(course, abs=0.051)
        assert msg["heading"] == course
        times.setdefault(mmsi, []).append(t)
    gaps = {m: np.diff(ts) for m, ts in times.items()}
    np.testing.assert_allclose(gaps[257000001], 10.0, atol=0.051)  # 8 kn: 10 s
    np.testing.assert_allclose(gaps[257000002], 6.0, atol=0.051)  # 18 kn: 6 s
    np.testing.assert_allclose(gaps[257000003], 30.0, atol=0.051)  # class B (CS) above 2 kn: 30 s
    assert {(257000001, 5, None), (257000002, 5, None), (257000003, 24, 0), (257000003, 24, 1)} <= statics
    sim.close()


def test_reports_alternate_between_channels_a_and_b(scenario_of):
    """Every sentence went out on channel A; transponders alternate A and B (ITU-R M.1371). pyais reads each
    sentence's channel field: each ship's reports (position and static, in time order) take A and B in turn, the
    two sentences of a type 5 report share one (as do a class B static report's parts A and B), and every
    sentence's checksum holds."""
    from pyais import NMEAMessage

    sim = Simulation(scenario(scenario_of))
    sentences = collect(sim, 61.0)
    sim.close()
    per_ship: dict[int, list[str]] = {}
    pending: list[NMEAMessage] = []
    for _, s in sentences:
        nmea = NMEAMessage(s.encode())
        assert nmea.is_valid
        pending.append(nmea)
        if nmea.frag_cnt != nmea.frag_num:
            continue
        assert len({p.channel for p in pending}) == 1  # one report, one channel
        msg = decode(*[p.raw for p in pending])
        if msg.msg_type == 24 and msg.partno == 1:  # class B's static report: parts A and B, on part A's channel
            assert per_ship[msg.mmsi][-1] == pending[0].channel
        else:
            per_ship.setdefault(msg.mmsi, []).append(pending[0].channel)
        pending = []
    assert set(per_ship) == set(TRUE)
    for channels in per_ship.values():
        assert len(channels) >= 3  # the class B yacht: two position reports (30 s) and its static report
        assert channels == ["AB"[k % 2] for k in range(len(channels))]


def test_dropouts_lose_reports(scenario_of):
    sim = Simulation(scenario(scenario_of, dropout=0.5))
    collect(sim, 60.0)
    publisher = sim.traffic.ais
    assert publisher.dropped > 3 and publisher.sent > 3


def test_udp_datagrams_on_loopback(scenario_of):
    rx = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    rx.bind(("127.0.0.1", 0))
    rx.settimeout(2.0)
    sim = Simulation(scenario(scenario_of, udp_port=rx.getsockname()[1]))
    sentences = collect(sim, 12.0)
    got = [rx.recv(1024).decode("ascii") for _ in sentences]
    assert [g.rstrip("\r\n") for g in got] == [s for _, s in sentences]
    sim.close()
    rx.close()


def test_enu_to_latlon_matches_pymap3d():
    rng = np.random.default_rng(0)
    for lat0, lon0 in ((59.42, 10.43), (-33.9, 151.2), (0.0, 0.0), (78.2, 15.6)):
        for e, n in rng.uniform(-20_000, 20_000, (20, 2)):
            lat, lon, _ = pymap3d.enu2geodetic(e, n, 0.0, lat0, lon0, 0.0)
            got = ais.enu_to_latlon(e, n, lat0, lon0)
            assert got == pytest.approx((lat, lon), abs=1e-8)  # ~1 mm


def test_fast_position_sentence_is_pyais_bit_for_bit():
    """The publisher's own packing of types 1 and 18 against pyais's encoder: random reports, edge values
    (moored, 102.2 kn cap, COG 359.95, heading n/a, poles, date line), both classes and channels."""
    rng = np.random.default_rng(5)
    reports = [ais.Report(int(rng.integers(200_000_000, 800_000_000)), float(rng.uniform(-90, 90)),
                          float(rng.uniform(-180, 180)), float(rng.uniform(0, 40)), float(rng.uniform(0, 360)),
                          int(rng.integers(0, 360)), int(rng.integers(0, 60))) for _ in range(400)]  # fmt: skip
    reports += [ais.Report(257000001, 59.42083, 10.43278, 0.05, 0.0, ais.HEADING_NA, 59),
                ais.Report(999999999, 90.0, 180.0, 150.0, 359.95, 359, 0),
                ais.Report(100000000, -90.0, -180.0, 102.2, 0.04, 0, 1),
                ais.Report(257000002, -0.000001, -0.000001, 14.0, 180.0, 180, 30)]  # fmt: skip
    for k, r in enumerate(reports):
        for cls in ("A", "B"):
            channel = "AB"[k % 2]
            assert ais.position_sentence(r, cls, channel) == ais.position_sentences(r, cls, channel)[0]


@pytest.mark.parametrize("ais_class", ["A", "B"])
@pytest.mark.parametrize(("length", "beam", "expected"), [
    (25.0, 6.25, (25, 6)),  # half-length 12.5 rounded half-to-even to 12 on each side: 24 m (QA)
    (5.0, 2.0, (5, 2)),  # 2.5 -> 2 each side: 4 m
    (4.9, 2.49, (5, 2)),
    (41.0, 9.0, (41, 9)),  # 20.5 / 4.5 each side: 40 x 8 m
    (20.0, 6.0, (20, 6)),
    (7.5, 3.5, (8, 4)),  # halves round up
    (1200.0, 140.0, (1022, 126)),  # beyond the fields: 511 + 511 and 63 + 63 ("that or more")
])  # fmt: skip
def test_static_report_dimensions_decode_to_the_configured_length_and_beam(ais_class, length, beam, expected):
    """ITU-R M.1371: to_bow + to_stern is the length, to_port + to_starboard the beam (pyais decodes); each reads
    back as the configured one rounded to the nearest metre."""
    sentences = ais.static_sentences(257000001, "x", 70, "", length, beam, 1.5, ais_class, 0)
    if ais_class == "A":
        (msg,) = [decode(*sentences).asdict()]
    else:  # type 24: part A (name), part B (type, dimensions)
        msg = [decode(s).asdict() for s in sentences][1]
        assert msg["partno"] == 1
    assert (msg["to_bow"] + msg["to_stern"], msg["to_port"] + msg["to_starboard"]) == expected
    assert abs(msg["to_bow"] - msg["to_stern"]) <= 1 and abs(msg["to_port"] - msg["to_starboard"]) <= 1  # midship


def test_true_bearings_turn_with_the_meridians_as_pyproj_geod_measures():
    """The true bearing of a world direction, away from the origin, against pyproj's geodesic azimuth between the
    point and a point 1 m along that direction (both through pymap3d); and grid_bearing_deg inverts it."""
    geod = pytest.importorskip("pyproj").Geod(ellps="WGS84")
    rng = np.random.default_rng(2)
    for lat0, lon0 in ((59.42, 10.43), (-33.9, 151.2), (0.0, 0.0), (78.2, 15.6)):
        for e, n in rng.uniform(-20_000, 20_000, (10, 2)):
            grid = rng.uniform(0.0, 360.0)
            g = math.radians(grid)
            lat, lon, _ = pymap3d.enu2geodetic(e, n, 0.0, lat0, lon0, 0.0)
            lat2, lon2, _ = pymap3d.enu2geodetic(e + math.sin(g), n + math.cos(g), 0.0, lat0, lon0, 0.0)
            azimuth = geod.inv(lon, lat, lon2, lat2)[0] % 360.0
            got = float(ais.true_bearing_deg(lat, lon, grid, lat0, lon0))
            assert abs((got - azimuth + 180.0) % 360.0 - 180.0) < 1e-5, (lat0, e, n, grid, got, azimuth)
            back = float(ais.grid_bearing_deg(lat, lon, got, lat0, lon0))
            assert abs((back - grid + 180.0) % 360.0 - 180.0) < 1e-9
    lat, lon, _ = pymap3d.enu2geodetic(20_000.0, 0.0, 0.0, 59.4, 10.4, 0.0)  # 20 km east, 59.4° N: the y axis
    assert float(ais.true_bearing_deg(lat, lon, 0.0, 59.4, 10.4)) == pytest.approx(0.30, abs=0.01)  # points east of north


def test_far_ships_report_true_course_and_heading(scenario_of):
    """A ship 20 km east of the origin sailing along the world's y axis: AIS (decoded with pyais) says its true
    course and heading, 0.3° east of north there, not 0.0 (the y axis is true north at the origin only)."""
    ship = {"name": "far", "mmsi": 257000009, "motion": {"type": "constant", "position": [20_000, 0], "course_deg": 0,
                                                         "speed_mps": 10 * KN}}  # fmt: skip
    sim = Simulation(scenario_of({"world": {"physics_rate_hz": 20, "origin": {"latitude_deg": 59.4, "longitude_deg": 10.4}},
                                  "outputs": {"recording": {"clock_rate_hz": 10, "ground_truth_rate_hz": 10}},
                                  "vessels": [{"name": "wamv", "model": "wamv"}], "traffic": {"ships": [ship]}}))  # fmt: skip
    reports = [decode(s).asdict() for _, s in collect(sim, 12.0)]
    positions = [r for r in reports if r["msg_type"] == 1]
    assert positions and all(r["course"] == pytest.approx(0.3, abs=0.051) for r in positions)
    sim.close()


def test_ais_messages_are_in_a_frame_of_the_recorded_tf_tree(scenario_of, tmp_path):
    """/ais was stamped in frame 'ais', which no transform names: tf2 and Foxglove could not place it. Its sentences
    carry geodetic positions; the frame is the world's (ENU at the scenario origin), as for /traffic/situation."""
    from readers import read_with_mcap_ros2

    sim = Simulation(scenario(scenario_of))
    with sim.record(tmp_path / "ais.mcap"):
        sim.run(12.0)
    sim.close()
    messages = read_with_mcap_ros2(tmp_path / "ais.mcap")  # an independent reader (mcap_ros2)
    edges = {(tf.header.frame_id, tf.child_frame_id) for topic, _, m in messages if topic in ("/tf", "/tf_static")
             for tf in m.transforms}  # fmt: skip
    tf_frames = {frame for edge in edges for frame in edge}
    ais_frames = {m.header.frame_id for topic, _, m in messages if topic == "/ais"}
    assert ais_frames and ais_frames <= tf_frames, (ais_frames, edges)


def test_the_own_ships_ais_may_share_the_mmsi_of_its_silent_traffic_entry(scenario_of):
    """An Imazu scenario's own ship is a traffic entry (ais disabled) with OWN_MMSI: its AIS (traffic.ais.own_ship)
    under that MMSI is one transmitter, accepted; only a second *transmitting* ship with it is refused."""
    from usvsim.traffic.imazu import OWN_MMSI, imazu_scenario

    data = imazu_scenario(1)
    data["traffic"]["ais"] = {"own_ship": {"vessel": "own", "mmsi": OWN_MMSI}}
    scenario = scenario_of({k: v for k, v in data.items() if k != "version"})
    assert scenario.traffic.ais.own_ship.mmsi == scenario.traffic.ships[0].mmsi == OWN_MMSI


def test_static_voyage_data_has_no_eta_and_this_ais_version():
    """Type 5 (ITU-R M.1371-5 annex 8, message 5): ETA not available is month 0, day 0, hour 24, minute 60 (it was hour 0 and
    minute 0: an ETA of midnight), AIS version 2 (M.1371-5; it was 0, M.1371-1); pyais decodes them."""
    msg = decode(*ais.static_sentences(257000001, "x", 70, "CALL", 20.0, 6.0, 1.5, "A", 0)).asdict()
    assert (msg["month"], msg["day"], msg["hour"], msg["minute"]) == (0, 0, 24, 60)
    assert msg["ais_version"] == 2 and msg["callsign"] == "CALL" and msg["draught"] == 1.5
