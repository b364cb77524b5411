"""Vessels in the ocean: they ride the same wave field the ocean reports, and drift with the current."""

from __future__ import annotations

import math

import numpy as np
import pytest

from usvsim.simulation import Simulation


def test_drifts_at_the_current_speed(scenario_of):
    """Zero thrust in a 0.5 m/s current toward 30 degrees: the hull ends up moving with the water."""
    sc = scenario_of({
        "environment": {"current": {"speed_mps": 0.5, "direction_deg": 30.0}},
        "vessels": [{"name": "wamv", "model": "wamv"}, {"name": "otter", "model": "otter",
                                                        "pose": {"position": [0.0, 20.0, 0.0]}}],
    })  # fmt: skip
    sim = Simulation(sc)
    sim.run(60.0)
    for boat in sim.vessels.values():
        v = sim.origin_velocity(boat.index)[:2]
        assert np.linalg.norm(v) == pytest.approx(0.5, rel=0.02)
        assert math.degrees(math.atan2(v[1], v[0])) == pytest.approx(30.0, abs=1.0)


def test_rides_the_waves_it_is_told_about(scenario_of):
    """Regular 1 m, 6 s waves from the west: the boat heaves with about the wave amplitude at the wave
    period, pitches, and stays upright; its heave follows the ocean's own elevation at its position."""
    sc = scenario_of({
        "environment": {"sea": {"type": "regular", "components": [
            {"amplitude_m": 0.5, "period_s": 6.0, "direction_deg": 0.0}]}, "ramp_time_s": 2.0},
        "vessels": [{"name": "wamv", "model": "wamv"}],
    })  # fmt: skip
    sim = Simulation(sc)
    sim.run(20.0)
    boat = sim.vessels["wamv"]
    z, eta, pitch, roll = [], [], [], []
    for _ in range(1200):  # two wave periods at 100 Hz
        sim.step()
        z.append(boat.position[2])
        eta.append(float(sim.ocean.elevation(np.array([boat.position[0]]), np.array([boat.position[1]]), sim.time)[0]))
        pitch.append(boat.rpy[1])
        roll.append(boat.rpy[0])
    z, eta = np.array(z), np.array(eta)
    heave = (z.max() - z.min()) / 2
    assert 0.35 < heave < 0.6  # a 4.9 m boat in 56 m waves follows the surface
    assert np.corrcoef(z, eta)[0, 1] > 0.95
    assert 0.02 < np.ptp(pitch) / 2 < 0.2  # pitches in head seas
    assert np.max(np.abs(roll)) < 0.02  # and barely rolls
    assert abs(boat.displaced_volume * sim.rho - boat.model.mass_kg) / boat.model.mass_kg < 0.5


def test_irregular_sea_is_repeatable_and_stays_afloat(scenario_of):
    sc = scenario_of({
        "environment": {"sea": {"type": "jonswap", "hs_m": 1.0, "tp_s": 5.0, "realization": {"resolution": 64}}},
        "vessels": [{"name": "otter", "model": "otter"}],
    })  # fmt: skip

    def run():
        sim = Simulation(sc, seed=4)
        sim.run(30.0)
        return sim.data.qpos.copy(), sim.vessels["otter"]

    (q1, otter), (q2, _) = run(), run()
    assert np.array_equal(q1, q2)
    assert abs(otter.rpy[0]) < 0.5 and abs(otter.rpy[1]) < 0.5 and otter.displaced_volume > 0.01


def test_water_patch_and_direct_sampling_agree(scenario_of):
    """The same boat in the same sea, hull heights from a 12 x 12 patch vs every vertex queried."""
    sea = {"type": "regular", "components": [{"amplitude_m": 0.4, "period_s": 5.0, "direction_deg": 20.0}]}

    def heave(mode):
        vessel = {"name": "wamv", "model": "wamv", "water_sampling": {"mode": mode, "resolution": 12}}
        sim = Simulation(scenario_of({"environment": {"sea": sea}, "vessels": [vessel]}))
        zs = []
        for _ in range(1000):
            sim.step()
            zs.append(sim.vessels["wamv"].position[2])
        return np.array(zs)

    direct, patch = heave("direct"), heave("patch")
    assert np.max(np.abs(direct - patch)) < 0.02
    assert np.ptp(direct) > 0.3


def test_wind_alone_pushes_the_boat_downwind(scenario_of):
    """10 m/s wind blowing toward 240 degrees, no waves, no current: the hull drifts toward 240 degrees."""
    sc = scenario_of({"environment": {"wind": {"speed_mps": 10.0, "direction_deg": 240.0}},
                      "vessels": [{"name": "wamv", "model": "wamv"}]})  # fmt: skip
    sim = Simulation(sc)
    sim.run(120.0)
    v = sim.origin_velocity(0)[:2]
    assert np.linalg.norm(v) > 0.05
    downwind = np.array([math.cos(math.radians(240.0)), math.sin(math.radians(240.0))])
    assert v @ downwind / np.linalg.norm(v) > 0.8


def test_fossen_hull_pitches_with_the_slope_of_a_long_swell(scenario_of):
    """A 2 m hull in a 200 m regular wave pitches with the surface slope a k (the long-wave limit, RAO -> 1: the
    state-space Otter does, 0.997). Fossen's added mass acts on the acceleration relative to the water; with the
    water's part of its armature share missing, the Otter with Fossen's model pitched at 0.93 of the slope."""
    a, wavelength = 0.5, 200.0
    k = 2 * math.pi / wavelength
    omega = math.sqrt(9.81 * k)
    sc = scenario_of({
        "environment": {"ramp_time_s": 5.0, "sea": {"type": "regular", "components": [
            {"amplitude_m": a, "wavelength_m": wavelength}]}},
        "vessels": [{"name": "o", "model": "otter", "hydrodynamics": {"type": "fossen", "parameters": "otter"}}],
    })  # fmt: skip
    sim = Simulation(sc)
    boat = sim.vessels["o"]
    sim.run(25.0)
    times, pitch = [], []
    for _ in range(round(2 * (2 * math.pi / omega) / 0.01)):  # two wave periods
        sim.step()
        times.append(sim.time)
        pitch.append(boat.rpy[1])
    times, pitch = np.asarray(times), np.asarray(pitch)
    amplitude = 2 * abs(np.mean((pitch - pitch.mean()) * np.exp(1j * omega * times)))
    assert amplitude / (a * k) == pytest.approx(1.0, abs=0.015)  # 0.997 (0.933 before)
    sim.close()
