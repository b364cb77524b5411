"""Thrusters moving the WAM-V: steady speeds against the drag model's closed form, turning sign,
collisions with the dock and the berth, determinism, bad commands and the watchdog."""

from __future__ import annotations

import math

import numpy as np
import pytest
import trimesh
from shapely.geometry import Polygon

from usvsim.simulation import Simulation


def steady_speed(force_n: float, linear: float, quadratic: float) -> float:
    """u > 0 solving linear u + quadratic u^2 = force."""
    return (-linear + math.sqrt(linear**2 + 4 * quadratic * force_n)) / (2 * quadratic)


@pytest.fixture
def wamv(scenario_of):
    return Simulation(scenario_of({"vessels": [{"name": "wamv", "model": "wamv"}]}))


def drive(sim, seconds, u, angle=None, vessel="wamv", thrusters=None):
    boat = sim.vessels[vessel]
    for _ in range(round(seconds / sim.clock.dt)):
        for name, t in boat.thrusters.items():
            if thrusters is None or name in thrusters:
                t.command(u, angle)
        sim.step()


def test_full_thrust_reaches_the_drag_balance_speed(wamv):
    """4 x 250 N against VRX damping X_u = 100, X_uu = 150: u* = 2.2701 m/s."""
    drive(wamv, 40.0, 1.0)
    u = wamv.vessels["wamv"].velocity_body[0]
    assert u == pytest.approx(steady_speed(1000.0, 100.0, 150.0), rel=0.01)
    drive(wamv, 2.0, 1.0)
    assert wamv.vessels["wamv"].velocity_body[0] == pytest.approx(u, abs=1e-3)  # steady


def test_full_reverse(wamv):
    """4 x 100 N reverse (VRX measured curve): u* = -1.3333 m/s."""
    drive(wamv, 40.0, -1.0)
    assert wamv.vessels["wamv"].velocity_body[0] == pytest.approx(-steady_speed(400.0, 100.0, 150.0), rel=0.01)


def test_azimuth_turns_the_boat_with_rep103_sign(wamv):
    """Stern thrusters turned CCW (+0.5 rad) push the stern to port: the boat yaws clockwise (r < 0).
    Steady yaw rate balances the thrusters' yaw moment 2 (x_t - x_G) T sin(a) with N_r r + N_rr |r| r."""
    drive(wamv, 30.0, 1.0, angle=0.5, thrusters={"rear_left", "rear_right"})
    boat = wamv.vessels["wamv"]
    lever = -2.570 - boat.model.com[0]
    moment = 2 * lever * 250.0 * math.sin(0.5)
    r = boat.angular_velocity_body[2]
    assert r < 0
    assert 800.0 * r + 800.0 * abs(r) * r == pytest.approx(moment, rel=0.01)
    assert boat.thrusters["rear_left"].angle_rad == pytest.approx(0.5, abs=1e-6)


def test_hits_the_dock_without_passing_through():
    sim = Simulation.from_scenario("harbor")
    dock_face_x = 29.0  # dock centred at x = 30, 2 m long
    bow_x = 2.45  # WAM-V pontoon tips, base_link frame
    touched, max_x = False, -np.inf
    boat = sim.vessels["wamv"]
    for _ in range(3000):
        boat.command(1.0, 0.0)
        sim.step()
        max_x = max(max_x, boat.position[0] + bow_x)
        touched |= any({a, b} == {"wamv", "world"} for a, b, _ in sim.contacts())
    assert touched
    assert max_x < dock_face_x + 0.05  # penetration at most 5 cm
    assert boat.position[0] < dock_face_x


def test_boat_inside_berth_touches_nothing():
    """The U-shaped berth is three convex walls: a WAM-V floating in the slot has no contacts."""
    sim = Simulation.from_scenario("harbor")
    sim.data.qpos[0:3] = [22.0, -16.0, 0.0]
    sim.data.qpos[3:7] = [0.0, 0.0, 0.0, 1.0]  # yaw 180 degrees, bow into the slot
    for _ in range(300):
        sim.step()
        assert not [c for c in sim.contacts() if "wamv" in c[:2]]


def test_non_convex_mesh_obstacle_is_decomposed(scenario_of, tmp_path, monkeypatch):
    """A U-shaped mesh obstacle becomes convex parts: a boat in its slot touches nothing."""
    monkeypatch.setenv("USVSIM_CACHE", str(tmp_path / "cache"))
    outline = Polygon([(-4.6, -2.6), (4, -2.6), (4, -2.0), (-4.0, -2.0), (-4.0, 2.0), (4, 2.0), (4, 2.6),
                       (-4.6, 2.6)])  # fmt: skip
    u_mesh = trimesh.creation.extrude_polygon(outline, 2.0)
    u_mesh.apply_translation((0, 0, -1.4))
    u_mesh.export(tmp_path / "u.stl")
    sc = scenario_of({
        "vessels": [{"name": "wamv", "model": "wamv", "pose": {"position": [0.5, 0.0, 0.0]}}],
        "objects": [{"type": "mesh", "name": "u", "file": "u.stl"}],
    }, tmp_path)  # fmt: skip
    sim = Simulation(sc)
    assert sum(1 for i in range(sim.model.ngeom) if sim.model.geom_bodyid[i] == 0 and
               sim.model.geom_contype[i]) >= 3  # fmt: skip
    for _ in range(200):
        sim.step()
        assert not sim.contacts()


def test_same_seed_same_trajectory():
    def trajectory():
        sim = Simulation.from_scenario("harbor", seed=7)
        out = []
        for k in range(500):
            sim.vessels["wamv"].command(1.0, 0.3 * math.sin(k / 50))
            sim.step()
            out.append(sim.data.qpos.copy())
        return np.array(out)

    assert np.array_equal(trajectory(), trajectory())


def test_nan_command_rejected_and_counted(wamv):
    t = wamv.vessels["wamv"].thrusters["rear_left"]
    assert t.command(0.5)
    assert not t.command(float("nan"))
    assert not t.command(0.5, float("inf"))
    assert not t.command(1.5)
    assert wamv.thrusters.rejected == 3
    wamv.run(1.0)
    assert np.isfinite(wamv.data.qpos).all() and t.thrust_n > 0


def test_watchdog_zeroes_thrust_after_silence(wamv):
    """A watched command (what network sources send) stops after the timeout; a Python one holds."""
    t, held = wamv.vessels["wamv"].thrusters["rear_left"], wamv.vessels["wamv"].thrusters["rear_right"]
    t.command(1.0, hold=False)
    held.command(1.0)
    wamv.run(0.9)
    assert t.thrust_n > 200.0
    wamv.run(2.0)  # timeout 1 s, then the 0.2 s lag decays
    assert abs(t.thrust_n) < 1.0 and held.thrust_n > 200.0


def test_thrust_and_azimuth_dynamics(scenario_of):
    """First-order thrust: 63.2 % of the step after one time constant; azimuth slews at its rate limit."""
    thruster = {"name": "t", "position": [-1.0, 0.0, 0.0], "time_constant_s": 0.5,
                "thrust": {"type": "linear", "max_forward_n": 100.0, "max_reverse_n": 50.0},
                "azimuth": {"min_deg": -90, "max_deg": 90, "time_constant_s": 0.05, "max_rate_deg_s": 30}}
    sim = Simulation(scenario_of({"vessels": [{"name": "b", "model": "otter", "thrusters": [thruster],
                                                  "command_timeout_s": 0.0}]}))
    t = sim.vessels["b"].thrusters["t"]
    t.command(1.0, math.radians(90))
    sim.run(0.5)
    assert t.thrust_n == pytest.approx(100.0 * (1 - math.exp(-1)), rel=1e-6)
    assert math.degrees(t.angle_rad) == pytest.approx(15.0, abs=1e-6)  # 30 deg/s for 0.5 s
    t.command(-1.0, math.radians(200))  # beyond the limit: clamped to 90 degrees
    sim.run(5.0)
    assert t.thrust_n == pytest.approx(-50.0, rel=1e-3)
    assert math.degrees(t.angle_rad) == pytest.approx(90.0, abs=1e-6)


def test_divergence_names_the_body_and_time(wamv):
    from usvsim.core.errors import DivergenceError

    wamv.run(0.5)
    wamv.data.qvel[0] = float("nan")
    with pytest.raises(DivergenceError, match=r"'wamv' at t = 0\.500 s"):
        wamv.step()


def test_realtime_pacing_follows_the_wall_clock(wamv):
    import time

    start = time.perf_counter()
    wamv.run(0.5, realtime=True)
    assert 0.5 <= time.perf_counter() - start < 0.8


def test_non_finite_force_is_a_divergence_not_a_silent_reset(wamv):
    from usvsim.core.errors import DivergenceError

    wamv.run(0.2)
    wamv.marine._state_space[0, 0] = float("inf")  # a broken coefficient: infinite surge damping force
    wamv.vessels["wamv"].command(1.0)
    with pytest.raises(DivergenceError, match="'wamv'"):
        wamv.run(1.0)


def test_reset_returns_to_the_initial_state(wamv):
    start = wamv.data.qpos.copy()
    drive(wamv, 3.0, 1.0, angle=0.3)
    wamv.reset()
    assert wamv.time == 0.0 and np.array_equal(wamv.data.qpos, start)
    assert all(t.thrust_n == 0.0 and t.angle_rad == 0.0 for t in wamv.vessels["wamv"].thrusters.values())
    drive(wamv, 0.5, 0.0)
    assert np.linalg.norm(wamv.data.qpos[:2] - start[:2]) < 0.01  # no memory of the old run
