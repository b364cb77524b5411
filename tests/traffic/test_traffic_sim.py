"""Traffic in a running simulation: kinematic ships (world-body geoms) on their tracks, collisions, LiDAR returns, ground-truth
situation (CPA/TCPA vs closed form) in an MCAP read back by rosbags and mcap-ros2, reset = fresh start."""

import math

import mujoco
import numpy as np
import pymap3d
import pytest
from readers import read_with_mcap_ros2, read_with_rosbags

from usvsim.config.scenario import GeodeticOrigin
from usvsim.core.errors import ScenarioError
from usvsim.io.mcap_recorder import McapRecorder
from usvsim.sensors.base import OPTICAL_ROT
from usvsim.simulation import Simulation
from usvsim.traffic.motion import KNOT_MPS
from usvsim.world.builder import STRUCK_BY_KINEMATIC, kinematic_geoms
from usvsim.world.checks import setup_warnings

OWN = {"name": "wamv", "model": "wamv", "command_timeout_s": 0.0}
PIER = {"type": "pier", "name": "pier", "position": [-20.0, 12.0, 0.8], "length_m": 16.0, "width_m": 3.0}


def ship(name, mmsi, motion, **kw):
    return {"name": name, "mmsi": mmsi, "motion": motion, **kw}


@pytest.fixture
def crossing(scenario_of):
    """Own ship at rest at the origin heading north; a ferry from 200 m north heading south at 5 m/s, 20 m east of the own ship
    (CPA 20 m at t = 40 s); a tug crossing west at 3 m/s 100 m north."""
    return scenario_of({
        "world": {"physics_rate_hz": 50},
        "outputs": {"recording": {"clock_rate_hz": 10, "ground_truth_rate_hz": 10}},
        "vessels": [{**OWN, "pose": {"yaw_deg": 90}}],  # heading north
        "traffic": {"awareness": {"rate_hz": 2}, "ais": {"enabled": False}, "ships": [
            ship("ferry", 257000001, {"type": "constant", "position": [20, 200], "course_deg": 180, "speed_mps": 5}),
            ship("tug", 257000002, {"type": "constant", "position": [300, 100], "course_deg": 270, "speed_mps": 3},
                 ship_type="tug", length_m=12, beam_m=4)]},
    })  # fmt: skip


def test_kinematic_ships_follow_their_tracks_and_situation_matches_closed_form(crossing, tmp_path):
    sim = Simulation(crossing)
    path = tmp_path / "run.mcap"
    with McapRecorder(path) as rec:
        sim.subscribe(rec.write)
        sim.run(10.0)
    t = sim.time
    house = sim.model.geom("kinematic/ferry/vis0").id  # its deckhouse (a box), a quarter length (5 m) aft
    np.testing.assert_allclose(sim.data.geom_xpos[house, :2], [20, 200 - 5 * t + 5], atol=1e-9)  # where the track is
    np.testing.assert_allclose(sim.data.geom_xmat[house].reshape(3, 3)[:2, 0], [0, -1], atol=1e-9)  # heading south
    np.testing.assert_allclose(sim.traffic.fleet.pos_enu[1], [300 - 3 * t, 100], atol=1e-9)
    for messages in (read_with_rosbags(path), read_with_mcap_ros2(path)):
        situations = [m for topic, _, m in messages if topic == "/traffic/situation"]
        assert len(situations) == 20
        last = situations[-1]
        own = np.array([last.own_position.x, last.own_position.y])
        f = last.targets[0]
        rel, vel = np.array([20.0, 200 - 5 * t]) - own, np.array([0.0, -5.0]) - [last.own_velocity.x, last.own_velocity.y]
        tcpa = -rel @ vel / (vel @ vel)  # closed form from the true states
        assert f.name == "ferry" and f.mmsi == 257000001
        assert f.tcpa == pytest.approx(tcpa, rel=1e-6) and f.tcpa == pytest.approx(30.0, abs=0.5)
        assert f.cpa == pytest.approx(np.linalg.norm(rel + vel * tcpa), rel=1e-6)
        assert f.cpa == pytest.approx(20.0, abs=0.5)
        assert f.range == pytest.approx(np.linalg.norm(rel)) and f.bearing == pytest.approx(math.atan2(rel[0], rel[1]))
        assert f.encounter == 1  # HEAD_ON: 7.6° off the bow, reciprocal course
        assert f.course == pytest.approx(math.pi) and f.speed == pytest.approx(5.0)
    sim.close()


def test_report_has_min_distance_per_target(crossing):
    sim = Simulation(crossing)
    sim.run(50.0)
    report = sim.traffic.report()
    assert report["ferry"]["min_distance_m"] == pytest.approx(20.0, abs=1.0)  # the pass at t = 40 s
    assert report["ferry"]["t_min_distance_s"] == pytest.approx(40.0, abs=0.5)
    assert report["tug"]["min_distance_m"] == pytest.approx(math.hypot(150.0, 100.0), abs=2.0)  # still closing


def test_report_never_looks_past_the_end_of_the_run(crossing):
    """Both targets still closing at the end of a 30 s run: their least distance is the one at t = 30 s, not an
    extrapolation to the next sample (the report said t = 31 s)."""
    sim = Simulation(crossing)
    sim.run(30.0)
    report, now = sim.traffic.report(), sim.traffic.situation.compute(sim.world)
    for j, name in enumerate(("ferry", "tug")):
        assert report[name]["t_min_distance_s"] == pytest.approx(30.0, abs=1e-9)
        assert report[name]["min_distance_m"] == pytest.approx(now["range"][j], rel=1e-9)


def test_report_least_distance_of_a_straight_pass_is_exact(scenario_of):
    """A ship crossing 30 m north of the WAM-V (at rest) westward at 5 m/s from 100 m east: 30 m at t = 20 s (the
    WAM-V settles by µm): at 1 Hz a sample; at 0.4 Hz (2.5 s) also a sample; at 0.25 Hz between the samples at 16
    and 24 s, found on the straight line between them."""
    for rate in (1.0, 0.4, 0.25):
        sim = Simulation(scenario_of({"vessels": [OWN], "traffic": {"awareness": {"rate_hz": rate}, "ais": {"enabled": False},
            "ships": [ship("crosser", 257000010, {"type": "constant", "position": [100, 30], "course_deg": 270, "speed_mps": 5})]}}))  # fmt: skip
        sim.run(30.0)
        report = sim.traffic.report()["crosser"]
        assert report["min_distance_m"] == pytest.approx(30.0, abs=0.01)
        assert report["t_min_distance_s"] == pytest.approx(20.0, abs=0.01)
        sim.close()


def test_report_least_distance_is_never_extrapolated_past_a_turn(scenario_of):
    """A route ship north at 10 m/s along x = 40 m from (40, -105), turning east at (40, 0) at t = 10.5 s, between
    two 1 Hz messages: the report samples at 10 Hz whatever the message rate, so it finds the truth, 40 m at
    10.5 s. With samples only at the messages it said hypot(40, 5) = 40.31 m at 10 s; before that it looked back
    from the sample at 11 s along the velocity then (east) and said 35 m: a distance that never happened."""
    route = {"type": "route", "waypoints": [{"position": [40, -105], "speed_mps": 10},
             {"position": [40, 0], "speed_mps": 10}, {"position": [1040, 0], "speed_mps": 10}]}  # fmt: skip
    sim = Simulation(scenario_of({"vessels": [OWN], "traffic": {"ais": {"enabled": False},
                                  "ships": [ship("turner", 257000011, route)]}}))  # fmt: skip
    sim.run(20.0)
    report = sim.traffic.report()["turner"]
    assert sim.traffic.situation.every == 100 and sim.traffic.situation.sample_every == 10  # 1 Hz, 10 Hz
    assert report["min_distance_m"] == pytest.approx(40.0, abs=0.01)
    assert report["t_min_distance_s"] == pytest.approx(10.5, abs=0.01)
    sim.close()


def test_quiet_steps_skip_nothing(scenario_of):
    """Traffic.on_step does nothing between due times; the situation and AIS messages (noise, dropouts, a turning
    route: 3⅓ s reports) and the run report are exactly those of calling it every step, also after a reset."""
    route = {"type": "route", "loop": True, "waypoints": [{"position": [100, 0], "speed_mps": 5},
             {"position": [100, 100], "speed_mps": 5}, {"position": [0, 100], "speed_mps": 5}]}  # fmt: skip
    sc = scenario_of({"vessels": [OWN], "traffic": {
        "awareness": {"rate_hz": 2}, "ais": {"position_noise_m": 3, "dropout_probability": 0.2},
        "ships": [ship("ferry", 257000001, {"type": "constant", "position": [20, 200], "course_deg": 180, "speed_mps": 5}),
                  ship("tug", 257000002, route, ais={"ais_class": "B"})]}})  # fmt: skip

    def messages(every_step):
        sim = Simulation(sc)
        if every_step:
            sim.traffic._next_busy_step = lambda world: world.clock.steps + 1
        out = []
        sim.subscribe(lambda env: out.append((env.topic, env.stamp_ns, repr(env.msg))) if env.topic in
                      ("/ais", "/traffic/situation") else None)  # fmt: skip
        sim.run(40.0)
        report = sim.traffic.report()
        sim.reset()
        sim.run(15.0)
        sim.close()
        return out, report, sim.traffic.report()

    quiet, busy = messages(False), messages(True)
    assert len([m for m in quiet[0] if m[0] == "/ais"]) >= 10
    assert quiet == busy


def test_reset_equals_fresh_start(crossing):
    a = Simulation(crossing)
    a.run(3.0)
    a.reset()
    a.run(2.0)
    b = Simulation(crossing)
    b.run(2.0)
    np.testing.assert_array_equal(a.model.geom_pos, b.model.geom_pos)  # the kinematic ships' geoms
    np.testing.assert_array_equal(a.model.geom_quat, b.model.geom_quat)
    np.testing.assert_array_equal(a.data.qpos, b.data.qpos)


def test_reset_restarts_the_ais_sentences(scenario_of):
    """After `reset` the AIS sentences are the bytes of a fresh start, the multi-sentence message id included (it
    went on from the earlier episode's count of sentences)."""

    def ais(sim):
        out = []
        unsubscribe = sim.subscribe(lambda env: out.append(bytes(env.cdr)) if env.topic == "/ais" else None)
        sim.run(20.0)
        unsubscribe()
        return out

    sc = scenario_of({"vessels": [OWN], "traffic": {"ships": [
        ship("ferry", 257000001, {"type": "constant", "position": [20, 200], "course_deg": 180, "speed_mps": 5}),
        ship("tug", 257000002, {"type": "constant", "position": [300, 100], "course_deg": 270, "speed_mps": 3})]}})  # fmt: skip
    a = Simulation(sc)
    a.run(20.0)
    a.reset()
    again, fresh = ais(a), ais(Simulation(sc))
    assert len(fresh) > 4 and any(b"AIVDM,2,1," in s for s in fresh)  # a two-sentence static report among them
    assert again == fresh


def test_a_ship_that_runs_into_the_own_ship_collides(scenario_of):
    sc = scenario_of({"vessels": [OWN], "traffic": {"ships": [
        ship("ferry", 257000001, {"type": "constant", "position": [0, 30], "course_deg": 180, "speed_mps": 4},
             length_m=20, beam_m=6)]}})  # fmt: skip
    sim = Simulation(sc)
    touched = set()
    sim.run(9.0, on_step=lambda s: touched.update((a, b) for a, b, _ in s.contacts()))
    assert ("wamv", "ferry") in touched or ("ferry", "wamv") in touched
    assert sim.vessels["wamv"].position[1] < -3.0  # pushed south by the ship


def test_the_report_says_when_a_ships_hull_touched_the_own_ship(scenario_of):
    """The report's distances are between reference points (a 25 m ship passes 8 m off through the own ship), so it
    also gives the first and last samples (>= 10 Hz) at which a target's hull touched the own ship, against
    MuJoCo's contacts of every step (`Simulation.contacts`); a ship that never touched has None, and a reset clears
    them. A 20 m ferry from 30 m north at 4 m/s meets the WAM-V after ~4.4 s and shoves it south."""
    sc = scenario_of({"vessels": [OWN], "traffic": {"ships": [
        ship("ferry", 257000001, {"type": "constant", "position": [0, 30], "course_deg": 180, "speed_mps": 4},
             length_m=20, beam_m=6),
        ship("tug", 257000002, {"type": "constant", "position": [300, 100], "course_deg": 270, "speed_mps": 3})]}})  # fmt: skip
    sim = Simulation(sc)
    times = []
    sim.run(9.0, on_step=lambda s: times.extend(s.time for a, b, _ in s.contacts() if {a, b} == {"wamv", "ferry"}))
    report = sim.traffic.report()
    assert times and 3.0 < times[0] < 6.0
    assert report["ferry"]["first_contact_s"] == pytest.approx(times[0], abs=0.1 + 1e-9)
    assert report["ferry"]["last_contact_s"] == pytest.approx(times[-1], abs=0.1 + 1e-9)
    assert report["tug"]["first_contact_s"] is None and report["tug"]["last_contact_s"] is None
    sim.reset()
    sim.run(1.0)
    assert sim.traffic.report()["ferry"]["first_contact_s"] is None


def test_overlap_warning_names_the_ship_not_the_static_world(scenario_of):
    # the ferry (40 x 10 m) starts on top of the own ship; a tug far away overlaps nothing
    sc = scenario_of({"vessels": [OWN], "traffic": {"ships": [
        ship("ferry", 257000001, {"type": "constant", "position": [0, 0], "course_deg": 0, "speed_mps": 1},
             length_m=40, beam_m=10),
        ship("tug", 257000002, {"type": "constant", "position": [300, 0], "course_deg": 0, "speed_mps": 1})]}})  # fmt: skip
    sim = Simulation(sc)
    warnings = setup_warnings(sim.world)
    sim.close()
    assert warnings == ["'wamv' and the moving 'ferry' overlap at the start: they will be pushed apart"]


def test_waypoints_after_a_stop_are_warned_about(scenario_of):
    """A waypoint of speed 0 is where a route ship stops for good: validate names the waypoints it never reaches
    (QA's route_jump meant to go on). A ship stopped at its start with one waypoint for its heading, a route that
    stops at its last waypoint, and one that never stops are fine."""
    def route(*legs, loop=False):
        return {"type": "route", "loop": loop, "waypoints": [{"position": list(p), "speed_mps": v} for p, v in legs]}

    sc = scenario_of({"vessels": [OWN], "traffic": {"ais": {"enabled": False}, "ships": [
        ship("jumper", 257000001, route(((0, 300), 3), ((30, 300), 0), ((300, 300), 3), ((300, 600), 3))),
        ship("waiter", 257000002, route(((0, -300), 0), ((300, -300), 3), ((300, -600), 3))),
        ship("looper", 257000003, route(((500, 0), 3), ((500, 100), 3), ((600, 100), 0), loop=True)),
        ship("still", 257000004, route(((-300, 0), 0), ((-200, 0), 0))),
        ship("ender", 257000005, route(((-300, 300), 3), ((-300, 400), 0))),
        ship("goer", 257000006, route(((-500, 300), 3), ((-500, 400), 3), ((-400, 400), 3), loop=True))]}})  # fmt: skip
    sim = Simulation(sc)
    warnings = setup_warnings(sim.world)
    sim.close()
    assert warnings == [
        "traffic.ships[0] 'jumper': waypoint 1 (30, 300) has speed_mps 0, where the ship stops for good: waypoints 2, 3 "
        "never reached",
        "traffic.ships[1] 'waiter': waypoint 0 (0, -300) has speed_mps 0, where the ship stops for good: waypoint 2 never "
        "reached",
        "traffic.ships[2] 'looper': waypoint 2 (600, 100) has speed_mps 0, where the ship stops for good: no loop",
    ]


def test_ship_boxes_stay_out_of_the_world_bvh_and_pair_only_when_near(scenario_of):
    """The world body's bounding volume tree (built once, at compile time) holds no ship geom, so a far ship costs
    the midphase nothing; a ship's box pairs with floating bodies (conaffinity set) only while it is near one."""
    far = ship("far", 257000001, {"type": "constant", "position": [0, 500], "course_deg": 0, "speed_mps": 2})
    near = ship("near", 257000002, {"type": "constant", "position": [10, 10], "course_deg": 180, "speed_mps": 2})
    plain = Simulation(scenario_of({"vessels": [OWN], "objects": [PIER]}))
    sim = Simulation(scenario_of({"vessels": [OWN], "objects": [PIER], "traffic": {"ships": [far, near]}}))
    assert sim.world.model.body_bvhnum[0] == plain.world.model.body_bvhnum[0]
    m, geoms = sim.world.model, sim.traffic.fleet._geoms
    box = dict(zip(["far", "near"], geoms.box))
    assert m.geom_conaffinity[box["far"]] == 0 and m.geom_conaffinity[box["near"]] == STRUCK_BY_KINEMATIC
    sim.run(20.0)  # "near" has passed the own ship, 10 m to its east, and is 30 m south now: beyond reach
    assert m.geom_conaffinity[box["near"]] == 0
    assert not m.opt.disableflags & mujoco.mjtDisableBit.mjDSBL_MIDPHASE  # nothing near: midphase back on
    plain.close()
    sim.close()


def test_lidar_sees_a_traffic_ship(scenario_of):
    lidar = {"type": "lidar", "name": "scan", "preset": "seed_2d", "rate_hz": 5, "mount": {"position": [0.701, 0, 1.031]}}
    sc = scenario_of({"vessels": [{**OWN, "sensors": [lidar]}], "traffic": {"ships": [
        ship("ferry", 257000001, {"type": "constant", "position": [40, 0], "course_deg": 0, "speed_mps": 0},
             length_m=20, beam_m=6)]}})  # fmt: skip
    sim = Simulation(sc)
    sim.run(0.2)
    scan = sim.sensors["wamv/scan"].released[0].msg
    ranges = np.asarray(scan.ranges)
    ahead = ranges[len(ranges) // 2 - 5 : len(ranges) // 2 + 5]  # angle 0 = forward (+x, east)
    assert np.all(np.abs(ahead - (40 - 3 - 0.701)) < 0.5)  # the ship's port side 3 m west of its centre


def test_camera_sees_a_traffic_ship_where_it_is_now(scenario_of):
    """A ship crossing 40 m ahead from south to north at 4 m/s: in the camera's segmentation its geoms fill a
    block whose centre column follows the projection of the ship's centre (±8 px of 320) at both frames."""
    cam = {"type": "camera", "name": "cam", "width": 320, "height": 240, "horizontal_fov_deg": 70.0, "rate_hz": 5,
           "streams": ["segmentation"], "mount": {"position": [0.7, 0.0, 1.5]}}  # fmt: skip
    sc = scenario_of({"vessels": [{**OWN, "sensors": [cam]}], "traffic": {"ships": [
        ship("ferry", 257000001, {"type": "constant", "position": [40, -6], "course_deg": 0, "speed_mps": 4},
             length_m=12, beam_m=4)]}})  # fmt: skip
    sim = Simulation(sc)
    ship_ids = kinematic_geoms(sim.world.model)[1] + 1  # segmentation labels: geom id + 1
    camera, columns = sim.sensors["wamv/cam"], []
    for _ in range(2):
        sim.run(1.0)
        envs = {e.topic: e.msg for e in camera.sample(sim, sim.clock_ns)}
        seg_msg = envs["/wamv/cam/segmentation/image_raw"]
        seg = np.frombuffer(bytes(seg_msg.data), np.uint16).reshape(seg_msg.height, seg_msg.width)
        rows, cols = np.nonzero(np.isin(seg, ship_ids))
        assert len(cols) > 500
        pos, rot = camera.pose_world(sim)
        centre = np.array([40.0, -6.0 + 4.0 * sim.time, 0.0])  # the ship now, at the waterline
        x, y, z = (centre - pos) @ (rot @ OPTICAL_ROT)
        fx = 160.0 / math.tan(math.radians(35.0))
        columns.append((0.5 * (cols.min() + cols.max()), 159.5 + fx * x / z))
    for seen, expected in columns:
        assert seen == pytest.approx(expected, abs=8.0)
    assert columns[1][0] < columns[0][0] - 15  # moved left (north) by 4 m in 1 s: 23 px at 40 m
    sim.close()


def test_kinematic_ship_on_a_replayed_ais_csv_passes_its_samples(scenario_of, tmp_path):
    """A kinematic ship on a recorded track turning from north to east (10 kn on a 300 m circle, one sample every
    ~15 s, heading n/a at one): at every sample time its state and its geoms (what contacts and sensors see) are at
    the sample within 1 m and head along its course."""
    v, origin = 10.0 * KNOT_MPS, GeodeticOrigin()
    rows = []
    for k in range(7):
        a = k * math.pi / 12
        e, n = 300 * (1 - math.cos(a)), 300 * math.sin(a)
        lat, lon, _ = pymap3d.enu2geodetic(e, n, 0.0, origin.latitude_deg, origin.longitude_deg, 0.0)
        rows.append((round(300.0 * a / v, 2), e, n, lat, lon, math.degrees(a)))
    lines = [f"{t},{lat:.9f},{lon:.9f},10.0,{c:.4f},{511 if k == 3 else round(c)}" for k, (t, _, _, lat, lon, c) in enumerate(rows)]
    (tmp_path / "turn.csv").write_text("time,lat,lon,sog,cog,heading\n" + "\n".join(lines) + "\n")
    sc = scenario_of({"world": {"physics_rate_hz": 100}, "vessels": [{**OWN, "pose": {"position": [-200, 0, 0]}}],
                      "traffic": {"ais": {"enabled": False}, "ships": [
                          ship("replayed", 257000009, {"type": "ais_replay", "path": "turn.csv"})]}}, tmp_path)  # fmt: skip
    sim = Simulation(sc)
    house = sim.model.geom("kinematic/replayed/vis0").id  # the deckhouse box: 5 m aft of the ship's centre
    for t, e, n, _, _, course in rows[1:]:
        sim.run(t - sim.time)
        assert sim.time == pytest.approx(t, abs=1e-9)
        np.testing.assert_allclose(sim.traffic.fleet.pos_enu[0], [e, n], atol=1.0)
        bow = np.array([math.sin(math.radians(course)), math.cos(math.radians(course))])
        np.testing.assert_allclose(sim.data.geom_xmat[house].reshape(3, 3)[:2, 0], bow, atol=0.02)  # its x axis
        np.testing.assert_allclose(sim.data.geom_xpos[house, :2], np.array([e, n]) - 5.0 * bow, atol=1.0)
    sim.close()


def test_physics_ship_needs_a_velocity_controller(scenario_of):
    sc = scenario_of({"vessels": [OWN, {"name": "other", "model": "otter", "pose": {"position": [50, 0, 0]}}],
                      "traffic": {"ships": [ship("other_ship", 257000003, {"type": "constant", "position": [50, 0],
                                                 "course_deg": 0, "speed_mps": 1}, vessel="other")]}})  # fmt: skip
    with pytest.raises(ScenarioError, match=r"traffic.ships\[0\].vessel.*velocity"):
        Simulation(sc)


def test_physics_ship_follows_its_route(scenario_of):
    other = {"name": "other", "model": "otter", "pose": {"position": [0, 20, 0], "yaw_deg": 0},
             "controller": {"type": "velocity"}, "command_timeout_s": 0.0}
    route = {"type": "route", "waypoints": [{"position": [0, 20], "speed_mps": 1.0}, {"position": [60, 20], "speed_mps": 1.0}]}
    sc = scenario_of({"vessels": [OWN, other], "traffic": {"ships": [ship("otter_ship", 257000004, route, vessel="other",
                                                                          length_m=2, beam_m=1)]}})  # fmt: skip
    sim = Simulation(sc)
    sim.run(30.0)
    x, y, _ = sim.vessels["other"].position
    assert 15.0 < x < 35.0 and abs(y - 20.0) < 2.0  # on the leg, at roughly the leg speed
    assert sim.traffic.fleet.vel_enu[0][0] == pytest.approx(1.0, abs=0.25)


def test_physics_ship_follows_a_replayed_ais_track(scenario_of, tmp_path):
    """An Otter (full physics, velocity controller) on a recorded track: 1.2 m/s north, then a turn to the east on
    a 40 m circle. At every AIS sample its position stays close to the recording's."""
    speed, radius = 1.2, 40.0
    rows = [(t, 0.0, speed * t, speed / KNOT_MPS, 0.0, 0.0) for t in range(0, 20, 5)]  # (t, east, north, kn, cog, hdg)
    for k in range(9):  # a quarter circle to the east from (0, 24)
        a = k * math.pi / 16
        t = 20.0 + radius * a / speed
        rows.append((t, radius * (1 - math.cos(a)), 24.0 + radius * math.sin(a), speed / KNOT_MPS, math.degrees(a), math.degrees(a)))
    lines = ["time,lat,lon,sog,cog,heading"]
    for t, e, n, sog, cog, hdg in rows:
        lat, lon, _ = pymap3d.enu2geodetic(e, n, 0.0, GeodeticOrigin().latitude_deg, GeodeticOrigin().longitude_deg, 0.0)
        lines.append(f"{t},{lat:.9f},{lon:.9f},{sog},{cog},{hdg}")
    (tmp_path / "track.csv").write_text("\n".join(lines) + "\n")
    other = {"name": "other", "model": "otter", "pose": {"position": [0, 0, 0], "yaw_deg": 90},
             "controller": {"type": "velocity"}, "command_timeout_s": 0.0}
    sc = scenario_of({"vessels": [{**OWN, "pose": {"position": [-60, 0, 0]}}, other], "traffic": {"ships": [
        ship("otter_ship", 257000005, {"type": "ais_replay", "path": "track.csv"}, vessel="other", length_m=2, beam_m=1)]}},
        base_dir=tmp_path)  # fmt: skip
    sim = Simulation(sc)
    errors = []
    for t, e, n, *_ in rows[1:]:
        sim.run(t - sim.time)
        errors.append(math.dist(sim.vessels["other"].position[:2], (e, n)))
    assert max(errors) < 3.0, errors  # bounded all along, the turn included
    assert errors[-1] < 2.0, errors


def test_situation_own_state_is_the_vessels(crossing):
    """The situation kernel's own-ship state (one numba call) equals Vessel.position, World.origin_velocity and
    Vessel.rpy of a turning, rolling own ship."""
    sim = Simulation(crossing)
    wamv = sim.vessels["wamv"]
    sim.world.teleport(wamv.index, (1.0, 2.0, 0.0, 0.2, 0.1, 0.7), [1.5, 0.4, 0.2, 0.1, 0.2, 0.3])
    sim.step()
    s = sim.traffic.situation.compute(sim.world)
    np.testing.assert_allclose(s["own_pos"], wamv.position[:2], atol=1e-12)
    np.testing.assert_allclose(s["own_vel"], sim.world.origin_velocity(wamv.index)[:2], atol=1e-12)
    assert s["own_yaw"] == pytest.approx(wamv.rpy[2], abs=1e-12)
    sim.close()


def test_packed_placement_equals_the_plain_kernel_call(crossing):
    """The per-step call (the kernel's arguments packed once, called through the compiled entry point for exactly
    their type) writes the same ship poses, geom poses and pairing as `evaluate_and_place` given the arrays, into
    the model's own arrays."""
    from usvsim.traffic.kernels import evaluate_and_place, place_fleet

    sim = Simulation(crossing)
    sim.run(1.0)
    geoms, m = sim.traffic.fleet._geoms, sim.world.model
    arrays = geoms.arrays
    assert arrays[8] is m.geom_pos and arrays[9] is m.geom_quat and arrays[12] is m.geom_conaffinity
    assert geoms._place is not place_fleet  # the compiled entry point (numba exposes it in the pinned version)
    written = (3, 4, 5, 8, 9, 12, 14)  # pos, vel, yaw, geom_pos, geom_quat, conaffinity, clearance
    nears = []
    for t_s in (0.0, 3.3, 38.0, 40.01, 95.0):  # the ferry passes the own ship (near) at ~40 s
        plain = [a.copy() if isinstance(a, np.ndarray) else a for a in arrays]  # the state before, for the plain call
        before = m.geom_pos.copy()
        nears.append(geoms._place(t_s, geoms._args))
        assert evaluate_and_place(t_s, *plain) == nears[-1]
        for k in written:
            np.testing.assert_array_equal(arrays[k], plain[k])
        assert not np.array_equal(before, m.geom_pos)  # the ships moved
    assert nears[0] == nears[-1] == 0 and max(nears) == 1
    sim.close()


def test_skipped_placements_change_nothing_anyone_sees(scenario_of):
    """Inside `run` the ships are placed only before steps someone looks after (a camera's, LiDAR's or radar's
    sample, the run's last step) or when one may be near a floating body; a run whose every step is watched (a
    step callback: every step placed) gives bit for bit the same body states, contacts, camera images with
    detections, LiDAR points and radar echoes, also across a ship passing the own ship, a ship running into
    it, and a teleport next to a far ship."""
    cam = {"type": "camera", "name": "cam", "width": 160, "height": 120, "horizontal_fov_deg": 90.0, "rate_hz": 4,
           "streams": ["rgb", "segmentation"], "detections": {}, "mount": {"position": [0.7, 0.0, 1.5]}}  # fmt: skip
    lidar = {"type": "lidar", "name": "scan", "preset": "seed_2d", "rate_hz": 6.25, "mount": {"position": [0.7, 0, 1.0]}}
    radar = {"type": "radar", "name": "radar", "rpm": 60, "spokes": 256, "range_bins": 128, "range_max_m": 400.0,
             "mount": {"position": [0.0, 0.0, 2.5]}}  # fmt: skip
    ships = [ship("ferry", 257000001, {"type": "constant", "position": [12, 60], "course_deg": 180, "speed_mps": 6},
                  length_m=20, beam_m=6),
             ship("rammer", 257000002, {"type": "constant", "position": [-45, 0], "course_deg": 90, "speed_mps": 5},
                  length_m=12, beam_m=4),
             ship("far", 257000003, {"type": "route", "loop": True, "waypoints": [
                 {"position": [300, 300], "speed_mps": 3}, {"position": [380, 300], "speed_mps": 3},
                 {"position": [380, 380], "speed_mps": 3}]})]  # fmt: skip
    sc = scenario_of({"vessels": [{**OWN, "sensors": [cam, lidar, radar]}], "traffic": {"ships": ships,
                      "ais": {"enabled": False}}})  # fmt: skip
    sims = [Simulation(sc), Simulation(sc)]
    placed = []
    for sim in sims:
        geoms, count = sim.traffic.fleet._geoms, [0]
        place = geoms._place

        def counted(t_s, a, place=place, count=count):
            count[0] += 1
            return place(t_s, a)

        geoms._place = counted
        placed.append(count)
    lazy, eager = sims
    touched = set()
    for k, seconds in enumerate([0.37, 1.1, 2.9, 4.13, 3.3, 5.0, 1.01, 2.0]):
        if k == 5:  # the own ship next to the far ship: it must be placed (and collide) from the next step on
            for sim in sims:  # 4 m ahead of its bow, on its course (east, on its route's first leg)
                x, y = sim.traffic.fleet.pos_enu[2] + [0.5 * sim.traffic.fleet.ships[2].length_m + 4.0, 0.0]
                sim.vessels["wamv"].teleport({"position": [float(x), float(y), 0], "yaw_deg": 0})
        lazy.run(seconds)
        eager.run(seconds, on_step=lambda s: touched.update(s.contacts()))
        np.testing.assert_array_equal(lazy.data.qpos, eager.data.qpos)
        np.testing.assert_array_equal(lazy.data.qvel, eager.data.qvel)
        np.testing.assert_array_equal(lazy.model.geom_pos, eager.model.geom_pos)
        np.testing.assert_array_equal(lazy.data.geom_xmat, eager.data.geom_xmat)
        assert lazy.contacts() == eager.contacts()
        seen, expected = lazy.observe(), eager.observe()
        assert seen.keys() == expected.keys()
        for name, r in expected.items():
            assert r is not None and seen[name] is not None, name
            assert set(r) == set(seen[name])
            for key in r:
                np.testing.assert_array_equal(seen[name][key], r[key], err_msg=f"{name} {key}")
    names = {n for c in touched for n in c[:2]}
    assert {"rammer", "far"} <= names  # collisions with ships happened (and came out the same)
    assert placed[0][0] < 0.85 * placed[1][0]  # the skipping is real (most steps here are watched or near)
    for sim in sims:
        sim.close()


def test_skipped_placements_without_sensors_teleport_and_reset(scenario_of):
    """Without sensors the ships are placed only near floating bodies and at each run's first and last steps; a
    teleport in the middle of a run (as a command would) just ahead of a far ship's bow, and a reset, must still
    give the same collision and states as placing every step."""
    ships = [ship("far", 257000003, {"type": "constant", "position": [400, 0], "course_deg": 90, "speed_mps": 4},
                  length_m=20, beam_m=6)]  # fmt: skip
    sc = scenario_of({"vessels": [OWN], "traffic": {"ships": ships, "ais": {"enabled": False}}})
    lazy, eager = Simulation(sc), Simulation(sc)

    class TeleportAt:  # called every step inside the loop like a controller (not a step callback)
        def __init__(self, sim, step):
            self.sim, self.step, self.quiet = sim, step, []

        def __call__(self, world):
            if world.clock.steps == self.step:
                self.quiet.append(self.sim.traffic.fleet._quiet_until_ns - world.clock.now_ns)
                pos, vel, yaw = np.zeros((1, 2)), np.zeros((1, 2)), np.zeros(1)  # the ship now (from its track)
                self.sim.traffic.fleet.table.evaluate(world.clock.now_ns / 1e9, pos, vel, yaw)
                x, y = pos[0] + [10.0 + 1.5, 0.0]  # 1.5 m ahead of its bow, on its course
                self.sim.vessels["wamv"].teleport({"position": [float(x), float(y), 0], "yaw_deg": 90})

        def reset(self):
            pass

    hooks = [TeleportAt(sim, 300) for sim in (lazy, eager)]
    for sim, hook in zip((lazy, eager), hooks):
        sim.controllers["teleport"] = hook
    touched = set()
    for _ in range(2):  # two episodes: a reset in between
        lazy.run(7.0)
        eager.run(7.0, on_step=lambda s: touched.update(s.contacts()))
        np.testing.assert_array_equal(lazy.data.qpos, eager.data.qpos)
        np.testing.assert_array_equal(lazy.data.qvel, eager.data.qvel)
        assert lazy.contacts() == eager.contacts()
        for sim in (lazy, eager):
            sim.reset()
    assert hooks[0].quiet[0] > 10**9 and hooks[1].quiet[0] < 0  # lazy would have skipped on for over a second
    assert any("far" in c[:2] for c in touched)
    lazy.close()
    eager.close()


def test_bodies_moved_by_hand_between_runs_meet_the_ships(scenario_of):
    """Moving a body by writing its qpos between two `run` calls (no teleport) still pairs it with the ship it
    now touches: the first step of a run places the ships."""
    ships = [ship("far", 257000003, {"type": "constant", "position": [400, 0], "course_deg": 90, "speed_mps": 4},
                  length_m=20, beam_m=6)]  # fmt: skip
    sc = scenario_of({"vessels": [OWN], "traffic": {"ships": ships, "ais": {"enabled": False}}})
    lazy, eager = Simulation(sc), Simulation(sc)
    touched = set()
    for sim in (lazy, eager):
        sim.run(3.0, on_step=None if sim is lazy else lambda s: None)
        adr = sim.model.jnt_qposadr[sim.model.body_jntadr[sim.vessels["wamv"].index + 1]]
        sim.data.qpos[adr : adr + 2] = sim.traffic.fleet.pos_enu[0] + [10.0 + 1.5, 0.0]  # ahead of the bow
        mujoco.mj_forward(sim.model, sim.data)
        sim.world._update_kinematics()
    lazy.run(3.0)
    eager.run(3.0, on_step=lambda s: touched.update(s.contacts()))
    np.testing.assert_array_equal(lazy.data.qpos, eager.data.qpos)
    assert any("far" in c[:2] for c in touched)
    lazy.close()
    eager.close()


@pytest.mark.parametrize(
    ("traffic", "sensor_topic", "where", "words"),
    [  # the traffic topic set to a sensor's: this blamed the sensor's topic as "one of the simulation's own"
        ({"ais": {"topic": "/wamv/imu/data"}}, None, "traffic.ais.topic", "is also the topic of sensor wamv/imu"),
        ({"awareness": {"own_ship": "wamv"}}, "/traffic/situation", "vessels[0].sensors[0].topic",
         r"is traffic.awareness.topic \(default\)"),  # the sensor set to a traffic default: the sensor is named
    ],
)
def test_a_topic_clash_with_traffic_names_the_key_that_was_set(scenario_of, traffic, sensor_topic, where, words):
    imu = {"type": "imu", "name": "imu", **({"topic": sensor_topic} if sensor_topic else {})}
    ship = {"name": "ferry", "mmsi": 257000001, "motion": {"type": "constant", "position": [0, 400], "course_deg": 180,
                                                          "speed_mps": 5}}  # fmt: skip
    scenario = scenario_of({"vessels": [{"name": "wamv", "model": "wamv", "sensors": [imu]}],
                            "traffic": {"ships": [ship], **traffic}})  # fmt: skip
    with pytest.raises(ScenarioError, match=words) as info:
        Simulation(scenario)
    assert info.value.key_path == where


def test_the_own_ship_at_rest_reports_under_way_and_a_stopped_ship_moored(scenario_of):
    """ITU-R M.1371 navigational status decoded by pyais: the own ship (a vehicle under its own control) at rest
    reports 'under way using engine' (0) every 10 s (the 0-14 kn row), not 'moored' every 3 min; a traffic ship
    at rest (a zero-speed constant motion) reports moored (5) (every 3 min: test_ais)."""
    from pyais import decode

    sc = scenario_of({"world": {"physics_rate_hz": 50}, "vessels": [OWN],
                      "outputs": {"recording": {"clock_rate_hz": 10, "ground_truth_rate_hz": 10}}, "traffic": {
        "ais": {"own_ship": {"vessel": "wamv", "mmsi": 257000009}},
        "ships": [ship("barge", 257000001, {"type": "constant", "position": [50, 50], "course_deg": 0, "speed_mps": 0})]}})  # fmt: skip
    sim = Simulation(sc)
    reports: dict[int, list[tuple[float, int]]] = {}
    sim.subscribe(lambda env: [reports.setdefault(m.mmsi, []).append((env.stamp_ns * 1e-9, m.status))
                               for m in [decode(env.msg.sentence)] if m.msg_type == 1]
                  if env.topic == "/ais" and env.msg.sentence.startswith("!AIVDM,1,1,") else None)  # fmt: skip
    sim.run(36.0)
    sim.close()
    own, barge = reports[257000009], reports[257000001]
    assert {status for _, status in own} == {0} and {status for _, status in barge} == {5}
    assert len(own) >= 3 and np.diff([t for t, _ in own]) == pytest.approx(10.0, abs=0.02)
    assert len(barge) == 1
