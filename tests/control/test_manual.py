"""Manual driving maps: keys and gamepad → axes → thruster commands with the right physical effect."""

from __future__ import annotations

import math

import numpy as np
import pytest

from usvsim.control import DriveAxes, ThrusterLayout, gamepad_axes, keyboard_axes, manual_commands
from usvsim.control.manual import axes_to_velocity, should_reset
from usvsim.vessels import otter, wamv


def test_keyboard_ramps_and_returns():
    axes = DriveAxes()
    for _ in range(5):
        axes = keyboard_axes({"w", "a"}, axes, 0.1)
    assert axes.throttle == pytest.approx(1.0) and axes.steering == pytest.approx(1.0)
    axes = keyboard_axes({"W"}, DriveAxes(0.0, 0.0), 0.1)
    assert axes.throttle == pytest.approx(0.2)
    axes = keyboard_axes(set(), DriveAxes(1.0, -1.0), 0.1)
    assert axes.throttle == pytest.approx(0.6) and axes.steering == pytest.approx(-0.6)
    assert keyboard_axes({"r"}, DriveAxes(), 0.1).reset


def test_gamepad_triggers_and_stick():
    axes = gamepad_axes(right_trigger=1.0, left_trigger=-1.0, stick_x=-1.0, trigger_rest=-1.0)
    assert axes.throttle == pytest.approx(1.0) and axes.steering == pytest.approx(1.0)  # stick left = port
    axes = gamepad_axes(0.0, 1.0, 0.05, trigger_rest=0.0)
    assert axes.throttle == pytest.approx(-1.0) and axes.steering == 0.0  # inside the dead zone
    assert gamepad_axes(-1, -1, 0, reset_button=True).reset


@pytest.mark.parametrize("build", [wamv.build, otter.build])
def test_steering_to_port_gives_positive_yaw_moment(build):
    model = build()
    layout = ThrusterLayout.from_thrusters(model.thrusters, model.com)
    cmds = manual_commands(DriveAxes(0.5, 1.0), model.thrusters, model.com)
    thrust = [cmds[n][0] * t.thrust.max_forward_n for n, t in zip(layout.names, model.thrusters, strict=True)]
    angle = [cmds[n][1] or 0.0 for n in layout.names]
    tau = layout.tau_from_thrusts(thrust, angle)
    assert tau[2] > 0 and tau[0] > 0
    if build is wamv.build:  # stern engines turn one way, bow engines the other, within ±25°
        assert cmds["rear_left"][1] == pytest.approx(-math.radians(25)) and cmds["front_left"][
            1
        ] == pytest.approx(math.radians(25))
    else:
        assert all(abs(u) <= 1.0 for u, _ in cmds.values())


@pytest.mark.parametrize("model", ["wamv", "otter"])
def test_manual_driving_turns_to_port_in_the_simulation(closed_loop, model):
    loop = closed_loop(model)
    vessel, sim = loop.vessel, loop.sim
    for _ in range(800):
        for name, (u, angle) in manual_commands(
            DriveAxes(0.6, 1.0), vessel.model.thrusters, vessel.model.com
        ).items():
            vessel.thrusters[name].command(u, angle)
        sim.step()
    assert vessel.angular_velocity_body[2] > 0.05 and vessel.velocity_body[0] > 0.2


def test_velocity_mapping_and_reset_rule():
    assert axes_to_velocity(DriveAxes(-1.0, 0.5), 2.0, 0.4) == (-1.0, 0.0, 0.2)
    assert not should_reset([1.0, 1.0, 0], 0.1, [0, 0, 0], 0.0)
    assert should_reset([2.0, 1.0, 0], 0.0, [0, 0, 0], 0.0) and should_reset([0, 0, 0], 0.2, [0, 0, 0], 0.0)
    np.testing.assert_allclose(axes_to_velocity(DriveAxes(), 2.0, 0.4), 0.0)
