"""A scenario mistake is one line that points at the value to fix and shows it (QA of writing scenarios)."""

from __future__ import annotations

import pytest

from usvsim.config.loader import parse_scenario
from usvsim.core.errors import ScenarioError

SEA = {"type": "jonswap", "hs_m": 1.0, "tp_s": 5.0}


def _ship(name: str, mmsi: int = 257000001) -> dict:
    return {"name": name, "mmsi": mmsi, "motion": {"type": "constant", "position": [0, 0], "course_deg": 0, "speed_mps": 1}}


def _error(data: dict) -> ScenarioError:
    with pytest.raises(ScenarioError) as info:
        parse_scenario({"version": 1, **data}, "s.yaml")
    return info.value


@pytest.mark.parametrize("realization, path", [
    ({"res": 64}, "environment.sea.realization.res"),  # was environment.sea.realization.fft.res
    ({"resolution": 100}, "environment.sea.realization.resolution"),
    ({"method": "direct", "components": 0}, "environment.sea.realization.components"),  # was ...realization.direct.components
])  # fmt: skip
def test_a_realization_error_has_no_branch_name_in_its_path(realization, path):
    assert _error({"environment": {"sea": {**SEA, "realization": realization}}}).key_path == path


@pytest.mark.parametrize("data, path, words", [
    ({"vessels": [{"name": "a", "model": "wamv", "mass": {"mass_kg": -5}}]}, "vessels[0].mass.mass_kg",
     "greater than or equal to 0.001 (got -5; allowed: ≥ 0.001, ≤ 1000000000)"),  # the bound alone named no value
    ({"world": {"physics_rate_hz": 1e9}}, "world.physics_rate_hz", "(got 1000000000.0; allowed: ≥ 20, ≤ 10000)"),
    ({"vessels": [{"name": "a", "model": "wamv", "water_sampling": {"mode": "patch"},
                   "buoyancy": {"type": "triangles", "wave_pressure": "froude_krylov"}}]},
     "vessels[0].buoyancy.wave_pressure", "froude_krylov needs water_sampling.mode: direct"),  # was ignored
    ({"vessels": [{"name": "my boat", "model": "wamv"}]}, "vessels[0].name",
     "should start with a letter and hold only letters, digits and '_' (got 'my boat')"),  # was the regex
    ({"vessels": [{"name": "a", "model": "wamv", "sensors": [{"type": "imu", "name": "i", "topic": "/bad topic"}]}]},
     "vessels[0].sensors[0].topic", "should be a ROS 2 topic name"),
    ({"traffic": {"ships": [{**_ship("s"), "motion": {"type": "route", "waypoints": [
        {"position": [0, 0], "speed_mps": 1}]}}]}}, "traffic.ships[0].motion.waypoints",
     "should have at least 2 items, got 1"),  # was "Tuple should have at least 2 items after validation, not 1"
    ({"vessels": [{"name": "a", "model": "wamv", "sensors": [{"type": "lidar", "name": "l",
                                                              "elevations_deg": [-5, 0, 0, 5, -5]}]}]},
     "vessels[0].sensors[0]", "elevations_deg holds -5, 0 more than once"),  # was two identical rings, silently
])  # fmt: skip
def test_a_bad_value_is_shown_in_plain_words(data, path, words):
    err = _error(data)
    assert err.key_path == path
    assert words in err.message
    assert "pattern" not in err.message and "after validation" not in err.message


@pytest.mark.parametrize("data, path, words", [
    ({"vessels": [{"name": "a", "model": "wamv"}, {"name": "a", "model": "otter"}]}, "vessels[1].name",
     "'a' is already the name of vessels[0]"),  # was at the top level: "names of vessels and objects must be unique"
    ({"vessels": [{"name": "a", "model": "wamv"}], "objects": [{"type": "buoy", "name": "a", "position": [0, 0, 0]}]},
     "objects[0].name", "already the name of vessels[0]"),
    ({"vessels": [{"name": "a", "model": "wamv"}], "traffic": {"ships": [_ship("a")]}}, "traffic.ships[0].name",
     "already the name of vessels[0]"),  # the message said "vessels and objects" of a traffic ship
    ({"traffic": {"ships": [_ship("a"), _ship("b", 257000001)]}}, "traffic.ships[1].mmsi", "already the mmsi of ships[0]"),
    ({"vessels": [{"name": "v", "model": "wamv"}], "traffic": {"ships": [_ship("a")], "ais": {"own_ship": {
        "vessel": "v", "mmsi": 257000001}}}}, "traffic.ais.own_ship.mmsi",
     "already the mmsi of ships[0], which transmits too"),  # was accepted: two transmitters under one MMSI (qa19)
    ({"vessels": [{"name": "a", "model": "wamv", "sensors": [{"type": "imu", "name": "i"}, {"type": "gnss", "name": "i"}]}]},
     "vessels[0].sensors[1].name", "already the name of sensors[0]"),
    ({"vessels": [{"name": "a", "model": "wamv", "hull_mesh": "x.stl"}]}, "vessels[0].hull_mesh", "only for model 'custom'"),
])  # fmt: skip
def test_a_repeated_name_points_at_the_repeat(data, path, words):
    err = _error(data)
    assert err.key_path == path
    assert words in err.message


def test_latlon_is_bounded_as_latitude_and_longitude(scenario_of):
    """`latlon` took any number up to 1e5 in the schema (editors accepted [95, 10]); the loader refused it later
    with the key path 'latlon' and the file name 'file: objects[0]' (QA)."""
    from usvsim.config.schema import scenario_schema
    from usvsim.simulation import Simulation

    buoy = {"type": "buoy", "name": "b", "position": [0, 0, 0]}
    err = _error({"objects": [{**buoy, "latlon": [95, 10]}]})
    assert err.key_path == "objects[0].latlon[0]" and "less than or equal to 90 (got 95; allowed: ≥ -90, ≤ 90)" in err.message
    assert _error({"objects": [{**buoy, "latlon": [59, -190]}]}).key_path == "objects[0].latlon[1]"
    latlon = scenario_schema()["$defs"]["Buoy"]["properties"]["latlon"]["anyOf"][0]["prefixItems"]
    assert [(i["minimum"], i["maximum"]) for i in latlon] == [(-90, 90), (-180, 180)]
    with pytest.raises(ScenarioError) as info:  # checked when the world is built: the path names the key
        Simulation(scenario_of({"objects": [{**buoy, "position": [5, 0, 0], "latlon": [59.42, 10.43]}]}))
    assert info.value.key_path == "objects[0].latlon" and info.value.source == "test"


def test_a_centre_of_mass_outside_the_hull_is_warned_about(scenario_of, box_stl):
    """`mass.com: [50, 0, 0]` on a 2 m hull validated and ran without a word (QA); inside the hull it is quiet."""
    from usvsim.simulation import Simulation
    from usvsim.world.checks import setup_warnings

    def warnings(com, thruster_x=-1.2):
        boat = {"name": "boat", "model": "custom", "hull_mesh": str(box_stl), "mass": {"mass_kg": 300.0, "com": com},
                "thrusters": [{"name": "main", "position": [thruster_x, 0.0, 0.1]}]}
        sim = Simulation(scenario_of({"vessels": [boat]}))
        try:
            return [w for w in setup_warnings(sim.world) if "outside its hull" in w]
        finally:
            sim.close()

    (line,) = warnings([50.0, 0.0, 0.3])
    assert line.startswith("vessels[0].mass.com: 'boat' has its centre of mass at [50, 0, 0.3] m (base_link, FLU)")
    assert "outside its hull (x -1..1, y -0.5..0.5, z 0..1 m)" in line
    assert warnings([0.2, 0.0, 0.3]) == [] and warnings([0.0, 0.0, 1.2]) != []
    (line,) = warnings([0.2, 0.0, 0.3], thruster_x=50.0)  # a thruster 49 m beyond the transom: not an outboard motor
    assert line.startswith("vessels[0].thrusters[0].position: 'boat' thruster 'main' at [50, 0, 0.1] m")


@pytest.mark.parametrize("data, path", [
    ({"vessels": [{"name": "world", "model": "otter"}]}, "vessels[0].name"),  # was a MuJoCo traceback
    ({"objects": [{"type": "buoy", "name": "world", "position": [0, 0, 0]}]}, "objects[0].name"),  # the same
    ({"objects": [{"type": "dock", "name": "world", "position": [9, 0, 0], "size": [1, 1, 1]}]}, "objects[0].name"),
    ({"traffic": {"ships": [_ship("world")]}}, "traffic.ships[0].name"),
])  # fmt: skip
def test_the_name_world_is_reserved(data, path):
    err = _error(data)
    assert err.key_path == path and "'world' is reserved" in err.message


def test_a_misspelt_builtin_name_gets_a_suggestion_and_a_short_list():
    """`usvsim run harbour` listed 27 names, imazu_01 to imazu_22 one by one, and no suggestion (QA)."""
    from usvsim.config.loader import load_scenario

    with pytest.raises(ScenarioError) as info:
        load_scenario("harbour")
    text = str(info.value)
    assert "did you mean 'harbor'?" in text and "imazu_01 .. imazu_22" in text and "imazu_05" not in text
    with pytest.raises(ScenarioError, match=r"\(built-ins: buoy_field, harbor"):
        load_scenario("xyz")


def _radar(**keys) -> dict:
    return {"vessels": [{"name": "a", "model": "wamv", "sensors": [{"type": "radar", "name": "r", **keys}]}]}


def _moving(speed_mps: float, **keys) -> dict:
    motion = {"type": "constant", "position": [0, 400], "course_deg": 0, "speed_mps": speed_mps}
    return {"traffic": {"ships": [{**_ship("s"), "motion": motion, **keys}]}}


@pytest.mark.parametrize("data, line", [
    (_moving(1e6), "traffic.ships[0].motion.speed_mps: Input should be less than or equal to 100 "
     "(got 1000000.0; allowed: ≥ 0, ≤ 100)"),
    ({"traffic": {"ships": [{**_ship("s"), "motion": {"type": "route", "waypoints": [
        {"position": [0, 0], "speed_mps": 2}, {"position": [0, 100], "speed_mps": 1e6}]}}]}},
     "traffic.ships[0].motion.waypoints[1].speed_mps: Input should be less than or equal to 100 "
     "(got 1000000.0; allowed: ≥ 0, ≤ 100)"),  # and no "(+1 more error)": pydantic's echo, a list too short
    (_moving(5, length_m=1e6), "traffic.ships[0].length_m: Input should be less than or equal to 500 "
     "(got 1000000.0; allowed: > 0, ≤ 500)"),
    (_moving(5, draft_m=100), "traffic.ships[0].draft_m: Input should be less than or equal to 30 "
     "(got 100; allowed: ≥ 0, ≤ 30)"),
    (_radar(range_max_m=1e7), "vessels[0].sensors[0].range_max_m: Input should be less than or equal to 177792 "
     "(got 10000000.0; allowed: > 0, ≤ 177792)"),
    (_radar(spokes=8192, range_bins=8192), "vessels[0].sensors[0].range_bins: spokes x range_bins must be at most "
     "8,388,608 cells a turn (8192 x 1024; real radars send up to 8192 spokes of 1024 samples), got 8192 x 8192 = "
     "67,108,864"),
    (_radar(range_min_m=2000, range_max_m=1000), "vessels[0].sensors[0].range_min_m: 2000 m must be less than "
     "range_max_m (1000 m): the radar would show nothing"),
    (_radar(range_max_m=20), "vessels[0].sensors[0].arpa.range_min_m: 30 m must be less than range_max_m (20 m): "
     "ARPA would plot nothing"),
])  # fmt: skip
def test_traffic_speeds_ship_sizes_and_radar_turns_beyond_real_ones_are_refused(data, line):
    """A 1e6 m/s ferry, a 1000 km ship, a radar of 10,000 km range or 67 M cells a turn were accepted (QA)."""
    assert str(_error(data)) == f"s.yaml: {line}"


def test_real_ships_and_radars_pass_the_bounds():
    """The bounds never refuse a real vessel or radar: a 58 kn fast ferry, the longest and the widest ships built,
    a 96 NM radar range, a Furuno DRS-NXT turn of 8192 spokes x 1024 samples."""
    parse_scenario({"version": 1, **_radar(range_max_m=96 * 1852.0, spokes=8192, range_bins=1024), **_moving(
        58 * 1852 / 3600, length_m=458.45, beam_m=124.0, draft_m=24.6, height_m=72.0)})  # fmt: skip
