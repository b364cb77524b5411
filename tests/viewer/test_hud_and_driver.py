"""HUD text and the key → axes → thruster command path (no window)."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from usvsim.simulation import Simulation
from usvsim.viewer.demo import HARBOR_LAP, HARBOR_LAP_SECONDS
from usvsim.viewer.driver import ManualDriver
from usvsim.viewer.hud import RateMeter, compass_heading_deg, hud_lines, overlay_columns


@pytest.fixture(scope="module")
def harbor():
    return Simulation.from_scenario("harbor")


def test_compass_heading():
    assert compass_heading_deg(0.0) == pytest.approx(90.0)  # east
    assert compass_heading_deg(math.pi / 2) == pytest.approx(0.0)  # north
    assert compass_heading_deg(-math.pi / 2) == pytest.approx(180.0)


def test_hud_rows(harbor):
    harbor.reset()
    driver = ManualDriver(harbor, "wamv", [(0.0, "w", "press")])
    for _ in range(200):
        driver.step()
    rates = RateMeter()
    rates.update(0.05, 0.05)
    rows = dict(hud_lines(harbor, "wamv", rates, paused=True, follow=True, axes=driver.axes))
    assert set(harbor.vessels["wamv"].thrusters) <= set(rows)
    speed = float(rows["Speed"].split()[0])
    assert (
        speed == pytest.approx(np.linalg.norm(harbor.vessels["wamv"].velocity_body[:2]), abs=0.01)
        and speed > 0.5
    )
    assert rows["Sim time"].strip() == "2.00 s"
    assert (
        "PAUSED" in rows["Mode"] and rows["FPS"].strip() == "20.0" and rows["Real-time"].strip() == "1.00 x"
    )
    assert float(rows["rear_left"].split()[0]) > 0  # thrust in N
    left, right = overlay_columns(list(rows.items()))
    assert left.count("\n") == right.count("\n") == len(rows) - 1


def test_keys_drive_the_thrusters_with_bow_counter_steer(harbor):
    harbor.reset()
    driver = ManualDriver(harbor, "wamv")
    driver.key("w", "press")
    driver.key("a", "press")  # turn to port
    for _ in range(100):
        driver.step()
    t = harbor.vessels["wamv"].thrusters
    assert driver.axes.throttle == pytest.approx(1.0) and driver.axes.steering == pytest.approx(1.0)
    assert all(t[n].thrust_n > 0 for n in t)
    assert (
        t["rear_left"].angle_rad < 0 < t["front_left"].angle_rad
    )  # stern and bow engines turn opposite ways
    assert harbor.vessels["wamv"].angular_velocity_body[2] > 0  # yawing to port (CCW)
    driver.key("w", "release")
    driver.key("s", "press")
    for _ in range(100):
        driver.step()
    assert all(t[n].thrust_n < 0 for n in t)


def test_pause_single_step_and_reset(harbor):
    harbor.reset()
    driver = ManualDriver(harbor, "wamv", physics_budget_s=60.0)  # count steps, whatever the machine's load
    driver.key("w", "press")
    assert driver.advance(0.2) == 20
    for _ in range(300):
        driver.step()
    driver.key("space", "press")
    assert driver.paused and driver.advance(1.0) == 0
    driver.key("n", "press")
    driver.key("right", "press")
    assert driver.advance(1.0) == 2
    driver.key("space", "press")
    assert driver.advance(10.0) == driver.max_steps_per_frame  # a long hiccup is capped, not caught up
    seed = harbor.seed
    driver.key("r", "press")  # the boat moved > 2 m: the reset acts
    driver.step()
    assert harbor.time == pytest.approx(0.01) and driver.was_reset  # reset, then this step
    assert harbor.seed == seed + 1  # as a /reset: the run's next seed (it replayed the same sea every time)
    harbor.reset(seed=seed)
    driver.key("r", "release")
    driver.key("escape", "press")
    assert driver.quit


def test_reset_ignored_near_the_start(harbor):
    harbor.reset()
    driver = ManualDriver(harbor, "wamv")
    for _ in range(20):
        driver.step()
    driver.key("r", "press")
    driver.step()
    assert harbor.time == pytest.approx(0.21) and not driver.was_reset


def lap(sim, time_scale_frames=None):
    """Drive the scripted lap; returns path length, closest return to the start, contacts with the boat."""
    driver = ManualDriver(sim, "wamv", HARBOR_LAP)
    boat = sim.vessels["wamv"]
    start = prev = boat.position[:2]
    path, closest, hits = 0.0, np.inf, []
    while sim.time < HARBOR_LAP_SECONDS:
        driver.step()
        p = boat.position[:2]
        path += float(np.linalg.norm(p - prev))
        prev = p
        if path > 40.0:
            closest = min(closest, float(np.linalg.norm(p - start)))
        hits += [c for c in sim.contacts() if "wamv" in c[:2]]
    return path, closest, hits


def test_scripted_harbor_lap_closes(harbor):
    harbor.reset()
    path, closest, hits = lap(harbor)
    assert path >= 60.0
    assert closest < 3.0
    assert not hits


def _thrust(value):
    return SimpleNamespace(data=value)


def test_untouched_keys_leave_the_thrusters_to_bridge_commands(harbor):
    """`usvsim run --view --ros2`: the viewer zeroed every thruster at every step, so thrust commands from ROS
    lasted one step (u 0.18 m/s after 5 s of 0.6 thrust, against 1.5 m/s)."""
    harbor.reset()
    driver = ManualDriver(harbor, "wamv")
    boat = harbor.vessels["wamv"]
    for k in range(500):
        if k % 20 == 0:  # 5 Hz, inside the thrusters' watchdog
            for name in boat.thrusters:
                assert harbor.commands.post(f"/wamv/thrusters/{name}/thrust", _thrust(0.6))
        driver.step()
    assert all(t.thrust_n > 100.0 for t in boat.thrusters.values())
    assert boat.velocity_body[0] > 1.0
    driver.key("s", "press")  # the keys take over once touched
    for _ in range(100):
        driver.step()
    assert all(t.thrust_n < 0.0 for t in boat.thrusters.values())


def harbor_with_controller():
    from importlib import resources

    import yaml

    from usvsim.config.loader import parse_scenario

    data = yaml.safe_load((resources.files("usvsim.scenarios") / "harbor.yaml").read_text())
    data["vessels"][0]["controller"] = {"type": "velocity", "rate_hz": 20}
    return Simulation(parse_scenario(data, "harbor+controller"), 0)


def test_keys_drive_a_vessel_under_a_controller_through_its_reference():
    """The controller overwrote the keys' thruster commands at its rate; now the keys set its velocity reference
    (throttle → surge up to its top speed, steering → yaw rate), and a reference set before is kept until then."""
    sim = harbor_with_controller()
    loop, boat = sim.controllers["wamv"], sim.vessels["wamv"]
    top = loop.controller.velocity.max_velocity
    loop.reference = (1.0, 0.0, 0.0)  # e.g. a cmd_vel: not the viewer's until a key is pressed
    driver = ManualDriver(sim, "wamv")
    for _ in range(300):
        driver.step()
    assert loop.reference == (1.0, 0.0, 0.0)
    driver.key("d", "press")  # turn to starboard at speed
    for _ in range(300):
        driver.step()
    assert loop.reference[0] == pytest.approx(0.0) and loop.reference[2] == pytest.approx(-top[2])
    assert boat.angular_velocity_body[2] < -0.2
    driver.key("d", "release")
    driver.key("w", "press")
    for _ in range(300):
        driver.step()
    assert loop.reference == pytest.approx((top[0], 0.0, 0.0))
    assert boat.velocity_body[0] > 0.7 * top[0]
    driver.key("w", "release")
    for _ in range(30):  # the axes return to zero: the reference follows, then the viewer lets go
        driver.step()
    assert loop.reference == pytest.approx((0.0, 0.0, 0.0))
    sim.close()
