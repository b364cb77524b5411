"""A propeller acts only where it is in the water: thrust times the wet fraction of its disc (hydro/thrusters.py)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from usvsim.hydro.thrusters import disc_wet_fraction
from usvsim.simulation import Simulation

SHORT_SEA = {"type": "jonswap", "hs_m": 1.0, "tp_s": 3.0, "realization": {"resolution": 64}}  # an FFT sea
SHORT_SWELL = {"type": "regular", "components": [{"amplitude_m": 0.4, "period_s": 2.0}]}  # summed directly


@pytest.mark.parametrize("depth_over_radius", [-1.2, -1.0, -0.7, -0.3, 0.0, 0.25, 0.6, 0.99, 1.0, 1.5])
def test_wet_fraction_is_the_disc_area_under_the_surface(depth_over_radius):
    """Against the area integral of the disc's chords under the surface (2 sqrt(R^2 - y^2) for y < depth)."""
    radius = 0.125
    depth = depth_over_radius * radius
    y = np.linspace(-radius, min(max(depth, -radius), radius), 200_001)  # heights from the disc's centre, m
    chord = 2 * np.sqrt(np.clip(radius**2 - y**2, 0.0, None))
    area = float(np.sum((chord[1:] + chord[:-1]) / 2 * np.diff(y)))
    assert disc_wet_fraction(depth, radius) == pytest.approx(area / (math.pi * radius**2), abs=1e-6)


def one_thruster_boat(scenario_of, z_m, diameter, environment=None):
    thruster = {"name": "main", "position": [-2.57, 0.0, z_m], "thrust": {"type": "linear", "max_forward_n": 400.0}}
    if diameter != "default":
        thruster["propeller_diameter_m"] = diameter
    data = {"vessels": [{"name": "boat", "model": "wamv", "thrusters": [thruster]}]}
    if environment:
        data["environment"] = environment
    return Simulation(scenario_of(data))


def surge_after(sim, seconds):
    boat = sim.vessels["boat"]
    boat.thrusters["main"].command(1.0)
    sim.run(seconds)
    return float(boat.velocity_body[0])


def test_a_propeller_in_the_air_pushes_nothing(scenario_of):
    """A propeller mounted 1 m above the keel (the WAM-V floats ~0.12 m deep) spins in the air: the boat stays put
    while the motor's thrust state follows the command; with no disc given (null) the same point pushes in full."""
    dry = one_thruster_boat(scenario_of, 1.0, 0.25)
    assert surge_after(dry, 5.0) == pytest.approx(0.0, abs=1e-3)
    main = dry.vessels["boat"].thrusters["main"]
    assert main.thrust_n == pytest.approx(400.0, rel=1e-3)
    assert main.immersion == 0.0
    point = one_thruster_boat(scenario_of, 1.0, None)
    assert surge_after(point, 5.0) > 0.5
    assert point.vessels["boat"].thrusters["main"].immersion == 1.0


def test_a_half_wet_propeller_gives_the_thrust_times_its_wet_area(scenario_of):
    """A disc whose centre sits near the waterline: the hull's thrust force is thrust x the disc area under the
    still-water level at the disc's centre, every step."""
    sim = one_thruster_boat(scenario_of, 0.12, 0.25)
    bank = sim.world.thrusters
    boat = sim.vessels["boat"]
    boat.thrusters["main"].command(1.0)
    fractions = []
    for _ in range(300):
        centre_z = (boat.position + sim.world.state.rot[boat.index] @ np.array([-2.57, 0.0, 0.12]))[2]  # step start
        sim.step()
        wet = disc_wet_fraction(sim.world.ocean.level_m - centre_z, 0.125)
        assert bank.wet[0] == pytest.approx(wet, abs=1e-12)
        assert bank.wrench_body[0, 0] == pytest.approx(bank.thrust[0] * wet, abs=1e-9)  # mount heading 0: +x
        fractions.append(wet)
    assert 0.2 < fractions[-1] < 0.95


@pytest.mark.parametrize("sea", [SHORT_SEA, SHORT_SWELL], ids=["fft", "regular"])
def test_in_waves_the_wet_fraction_follows_the_local_surface(scenario_of, sea):
    """In a short sea (JONSWAP Hs 1 m, Tp 3 s; a 0.8 m, 2 s regular wave) the WAM-V's propellers (0.34 m deep at
    rest) come out of the water: every step the wet fraction equals the disc's area under the surface height that
    `Ocean.elevation` gives at the disc's centre."""
    sim = Simulation(scenario_of({"vessels": [{"name": "wamv", "model": "wamv"}], "environment": {"sea": sea}}))
    boat, bank, ocean = sim.vessels["wamv"], sim.world.thrusters, sim.world.ocean
    local = np.array([t.position for t in boat.model.thrusters])
    lowest = 1.0
    for _ in range(1500):
        for t in boat.thrusters.values():
            t.command(1.0)
        centres = boat.position + local @ sim.world.state.rot[boat.index].T  # the pose and time the step starts at
        eta = ocean.elevation(centres[:, 0], centres[:, 1], sim.time)
        sim.step()
        expected = [disc_wet_fraction(e - c, 0.125) for e, c in zip(eta, centres[:, 2], strict=True)]
        np.testing.assert_allclose(bank.wet, expected, rtol=0, atol=1e-12)
        lowest = min(lowest, float(bank.wet.min()))
    assert lowest < 0.9  # a propeller did come out of the water


def test_reset_makes_every_propeller_wet_again(scenario_of):
    sim = one_thruster_boat(scenario_of, 1.0, 0.25)
    sim.run(0.1)
    assert sim.world.thrusters.wet[0] == 0.0
    sim.reset()
    assert sim.world.thrusters.wet[0] == 1.0
