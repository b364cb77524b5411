"""COLREG collision avoidance (usvsim.traffic.colav): the velocity-obstacle geometry against hand computations, and
Imazu cases under full physics with avoidance: no hull contact, every target passed farther than the safety
distance, starboard alterations where rules 14, 15 and 17(c) ask for them, a stand-on ship that holds on."""

import math

import numpy as np
import pytest
import yaml

from usvsim.config.loader import parse_scenario
from usvsim.config.traffic import Avoidance
from usvsim.core.errors import ScenarioError
from usvsim.simulation import Simulation
from usvsim.traffic.colav import choose, collision_cone, min_distance
from usvsim.traffic.imazu import encounter_time_s, imazu_scenario


def test_collision_cone_of_one_target_is_the_hand_computation():
    axis, half = collision_cone((100.0, 100.0), 50.0)  # 141.4 m north-east, 50 m radius
    assert axis == pytest.approx(math.radians(45.0))
    assert half == pytest.approx(math.asin(50.0 / math.sqrt(2.0e4)))  # 20.70°
    assert math.degrees(half) == pytest.approx(20.705, abs=1e-3)
    assert collision_cone((30.0, 0.0), 50.0)[1] == math.pi  # inside the radius: every direction


@pytest.mark.parametrize("theta_deg", [0.0, 10.0, 29.0, 31.0, 60.0])
def test_min_distance_is_range_times_sine_of_the_angle_off_the_cone_axis(theta_deg):
    """Own ship relative to a still target 100 m east at 2 m/s, theta off the line of sight: the closest pass is
    100 sin(theta) (before passing), so it is inside 50 m exactly within the 30° half angle of the cone."""
    t = math.radians(theta_deg)
    d = min_distance([[100.0, 0.0]], [[0.0, 0.0]], [[2.0 * math.cos(t), 2.0 * math.sin(t)]], 1e6)[0, 0]
    assert d == pytest.approx(100.0 * math.sin(t), abs=1e-9)
    assert (d < 50.0) == (theta_deg < math.degrees(collision_cone((100.0, 0.0), 50.0)[1]))


def test_min_distance_is_truncated_at_the_horizon():
    # head-on, 100 m apart, closing at 2 m/s: 60 m left after 20 s, contact after 50 s; opening: the range now
    head_on = ([[0.0, 100.0]], [[0.0, -1.0]], [[0.0, 1.0]])
    assert min_distance(*head_on, 20.0)[0, 0] == pytest.approx(60.0)
    assert min_distance(*head_on, 100.0)[0, 0] == pytest.approx(0.0, abs=1e-9)
    assert min_distance([[0.0, -100.0]], [[0.0, -1.0]], [[0.0, 1.0]], 100.0)[0, 0] == pytest.approx(100.0)


def test_head_on_choice_is_a_substantial_starboard_turn_outside_the_obstacle():
    cfg = Avoidance()
    north = math.pi / 2
    rel, tgt = np.array([[0.0, 400.0]]), np.array([[0.0, -2.0]])
    course, speed = choose(north, 2.0, rel, tgt, [True], True, north, cfg)
    alteration = math.degrees(north - course)  # starboard +
    assert alteration == pytest.approx(cfg.min_turn_deg) and speed == 2.0  # the least turn that clears: 30°
    vel = [[speed * math.cos(course), speed * math.sin(course)]]
    assert min_distance(rel, tgt, vel, cfg.horizon_s)[0, 0] >= cfg.safety_m
    # by hand: relative velocity (1, -3.73) m/s from 400 m dead ahead passes 400 sin(15°) = 103.5 m off
    assert min_distance(rel, tgt, vel, 1e6)[0, 0] == pytest.approx(
        400.0 * math.sin(math.radians(15.0)), rel=1e-9
    )


def run_case(case: int, **avoidance) -> tuple[Simulation, dict]:
    """Imazu case `case` with avoidance, physics at 20 Hz (the own ship's controller rate), until 150 s after the
    last nominal encounter."""
    sc = imazu_scenario(case, avoid=True)
    sc["world"] = {"physics_rate_hz": 20.0}
    sc["traffic"]["ships"][0]["avoidance"].update(avoidance)
    sim = Simulation(parse_scenario(sc, f"imazu_{case:02d}"))
    return sim, sc


@pytest.mark.parametrize(("case", "roles"), [
    (1, {"target_1": "head_on"}),
    (2, {"target_1": "crossing_give_way"}),
    (4, {"target_1": "crossing_stand_on"}),  # the target (give-way) never acts: rule 17
    (14, {"target_3": "crossing_give_way"}),  # three ships
])  # fmt: skip
def test_imazu_cases_with_avoidance_pass_clear_and_turn_to_starboard(case, roles):
    sim, _ = run_case(case)
    safety = Avoidance().safety_m
    sim.run(max(encounter_time_s(case)) + 150.0)
    report = sim.traffic.report()
    for name, r in report.items():
        assert r["first_contact_s"] is None, (name, r)
        assert r["min_distance_m"] > safety, (name, r)
        assert r["starboard"] in (True, None), (name, r)
    for name, role in roles.items():
        assert report[name]["encounter"] == role
        assert (
            report[name]["starboard"] is True and report[name]["turn_deg"] >= Avoidance().min_turn_deg - 1e-6
        )
    sim.run(1300.0 - sim.time)  # the encounters cleared, the LOS pilot brought the own ship back to its track
    own = sim.vessels["own"]
    assert (
        abs(own.position[0]) < 5.0 and abs(math.degrees(own.rpy[2]) - 90.0) < 5.0
    )  # back on the track, north
    sim.close()


def test_stand_on_ship_holds_course_until_close_quarters():
    """Imazu 4: a crossing target from port that never gives way. The own ship keeps its course while the target
    is beyond close_quarters_m (rule 17(a)), then turns to starboard (17(b), (c)) and passes clear."""
    sim, _ = run_case(4)
    cfg = Avoidance()
    fleet, yaws = sim.traffic.fleet, []
    while float(np.hypot(*(fleet.pos_enu[1] - fleet.pos_enu[0]))) > cfg.close_quarters_m:
        yaws.append(math.degrees(fleet.yaw_rad[0]))
        sim.run(1.0)
    sim.run(300.0)
    assert len(yaws) > 200 and np.max(np.abs(np.array(yaws) - 90.0)) < 2.0
    r = sim.traffic.report()["target_1"]
    assert (
        r["encounter"] == "crossing_stand_on"
        and r["starboard"] is True
        and r["min_distance_m"] > cfg.safety_m
    )
    sim.close()


def test_without_avoidance_the_head_on_case_collides():
    """The baseline's baseline: imazu 1 without avoidance ends in hull contact (the report says when)."""
    sc = imazu_scenario(1)
    sc["world"] = {"physics_rate_hz": 20.0}
    sim = Simulation(parse_scenario(sc, "imazu_01"))
    sim.run(320.0)
    r = sim.traffic.report()["target_1"]
    assert r["first_contact_s"] is not None and 250.0 < r["first_contact_s"] < 320.0 and "encounter" not in r
    sim.close()


@pytest.mark.parametrize(("change", "message"), [
    ({"safety": 3}, "unknown key"),
    ({"safety_m": -1}, "greater than 0"),
    ({"safety_m": 200.0}, "close_quarters_m (150) must be at least safety_m (200)"),
    ({"min_turn_deg": 60.0, "max_turn_deg": 45.0}, "min_turn_deg (60) must not exceed max_turn_deg (45)"),
    ({"type": "vo"}, "velocity_obstacle"),
])  # fmt: skip
def test_bad_avoidance_config_is_one_clear_error(change, message):
    sc = imazu_scenario(1, avoid=True)
    sc["traffic"]["ships"][0]["avoidance"].update(change)
    with pytest.raises(ScenarioError, match="traffic.ships.0..avoidance") as err:
        parse_scenario(sc, "imazu_01")
    assert message in str(err.value)


def test_a_kinematic_ship_cannot_avoid():
    sc = imazu_scenario(1)
    sc["traffic"]["ships"][1]["avoidance"] = {}
    with pytest.raises(ScenarioError, match=r"traffic.ships\[1\].avoidance: only a physics ship"):
        parse_scenario(sc, "imazu_01")


def test_usvsim_imazu_avoid_runs_and_the_run_prints_the_score(tmp_path):
    from typer.testing import CliRunner

    from usvsim.cli.app import app

    scenario = tmp_path / "imazu01_avoid.yaml"
    runner = CliRunner()
    assert runner.invoke(app, ["imazu", "1", "--avoid", "--out", str(scenario)]).exit_code == 0
    assert "avoidance: {type: velocity_obstacle}" in scenario.read_text()
    result = runner.invoke(app, ["run", str(scenario), "--duration", "400"], env={"COLUMNS": "120"})
    assert result.exit_code == 0, result.output
    rows = [line.split() for line in result.stdout.splitlines()]
    assert ["target", "COLREG", "role", "turn", "(deg)", "starboard"] in rows
    assert ["target_1", "head_on", "30.0", "yes"] in rows
    assert not any(line.startswith("hull contact") for line in result.stdout.splitlines())


def test_a_ship_replaying_a_recorded_track_cannot_avoid(tmp_path):
    from usvsim.config.loader import load_scenario
    from usvsim.config.scenario import GeodeticOrigin

    lat, lon = GeodeticOrigin().latitude_deg, GeodeticOrigin().longitude_deg
    (tmp_path / "track.csv").write_text(
        f"time,lat,lon,sog,cog,heading\n0,{lat},{lon},2,0,0\n60,{lat + 0.001},{lon},2,0,0\n"
    )
    sc = imazu_scenario(1, avoid=True)
    sc["traffic"]["ships"][0]["motion"] = {"type": "ais_replay", "path": "track.csv"}
    (tmp_path / "s.yaml").write_text(yaml.safe_dump(sc))
    with pytest.raises(
        ScenarioError, match=r"traffic.ships\[0\].avoidance: a ship replaying a recorded track"
    ):
        Simulation(load_scenario(tmp_path / "s.yaml"))


def test_a_stand_on_ship_keeps_its_distance_from_a_fast_overtaker():
    """An 8 m/s ship overtaking from dead astern that never gives way (rule 13): with close quarters as a distance
    only, the own ship (2 m/s) acted ~25 s before the closest approach and passed 31.7 m off (QA); acting also once
    the closest approach is within close_quarters_s, it keeps safety_m, turning to starboard."""
    sc = imazu_scenario(1, avoid=True)
    sc["world"] = {"physics_rate_hz": 20.0}
    target = dict(sc["traffic"]["ships"][1], motion={"type": "constant", "position": [0.0, 600.0 - 8.0 * 300.0],
                                                     "course_deg": 0.0, "speed_mps": 8.0})  # fmt: skip
    sc["traffic"]["ships"] = [sc["traffic"]["ships"][0], target]
    for cq_s, passes in ((0.0, False), (60.0, True)):  # 0: the distance alone
        sc["traffic"]["ships"][0]["avoidance"]["close_quarters_s"] = cq_s
        sim = Simulation(parse_scenario(sc, "overtaken"))
        sim.run(450.0)
        r = sim.traffic.report()["target_1"]
        sim.close()
        assert r["encounter"] == "overtaken" and (r["min_distance_m"] > Avoidance().safety_m) is passes, r
        if passes:
            assert r["first_contact_s"] is None and r["turn_deg"] > 0.0  # to starboard
