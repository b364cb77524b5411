"""Wakes: tracks sampled on simulated time, foam behind a moving hull in RGB only, none behind one at rest."""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("moderngl")

from usvsim.rendering.gallery import load, scenario_dict


def _run(wake_s: float, thrust: float, seed: int = 0):
    raw = scenario_dict(1, {"water": {"wake_s": wake_s}}, 160, 120)
    raw["vessels"][0]["pose"] = {"position": [0.0, -30.0, 0.0], "yaw_deg": 180.0}
    raw["vessels"][0]["sensors"][0]["mount"] = {
        "position": [-1.0, 0.0, 3.0],
        "yaw_deg": 180.0,
        "pitch_deg": 25.0,
    }
    sim = load(raw, seed)
    boat = sim.vessels["wamv"]
    for _ in range(600):
        boat.command(thrust, 0.0)
        sim.step()
    images = sim.sensors["wamv/camera"].render(sim.world)  # as the sensor suite samples it: with the World
    samples = len(sim.wakes.samples)
    ribbons = sim.wakes.ribbons(sim.time, wake_s)
    sim.close()
    return images, samples, ribbons


def test_wake_behind_a_moving_hull_changes_rgb_only():
    wake, samples, ribbons = _run(30.0, 1.0)
    none, _, _ = _run(0.0, 1.0)
    assert samples == 24  # 6 s at one sample per 0.25 s of simulated time
    assert len(ribbons) and ribbons[:, 3].max() <= 6.0  # ages within the track
    assert np.array_equal(wake["segmentation"], none["segmentation"])
    assert np.array_equal(wake["depth"], none["depth"], equal_nan=True)
    brighter = wake["rgb"].astype(int).sum(axis=2) - none["rgb"].astype(int).sum(axis=2)
    assert (brighter > 60).mean() > 0.02  # foam on the water astern
    again, _, _ = _run(30.0, 1.0)
    assert np.array_equal(again["rgb"], wake["rgb"])  # same seed, same bytes


def test_no_wake_at_rest():
    _, samples, ribbons = _run(30.0, 0.0)
    assert samples == 24 and len(ribbons) == 0
