"""Rings of raindrops on the water: RGB only, reproducible from the seed and time, compiled out without rain."""

from __future__ import annotations

import math

import numpy as np
import pytest

from usvsim.rendering.rain import ring_chance, ringing_drop_flux


def test_ringing_drop_flux_is_the_marshall_palmer_closed_form():
    from scipy.special import gamma, gammaincc

    for rate in (1.0, 2.5, 10.0, 50.0):
        lam = 4.1 * rate**-0.21  # 1/mm
        # ∫_2^∞ 8000 e^(-ΛD) 3.78 D^0.67 dD = 8000·3.78·Γ(1.67)·Q(1.67, 2Λ) / Λ^1.67
        closed = 8000.0 * 3.78 * gamma(1.67) * gammaincc(1.67, 2.0 * lam) / lam**1.67
        assert ringing_drop_flux(rate) == pytest.approx(closed, rel=1e-3)
    assert ringing_drop_flux(0.0) == 0.0 and ring_chance(0.0) == 0.0
    assert ring_chance(2.5) == pytest.approx(0.29, abs=0.01) and ring_chance(10.0) == 1.0


def _looking_down(pitch: float) -> np.ndarray:
    c, s = math.cos(pitch), math.sin(pitch)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])  # FLU → world: forward +x, pitched down


@pytest.fixture
def frames(monkeypatch):
    pytest.importorskip("moderngl")
    from usvsim.rendering.gallery import load, scenario_dict

    monkeypatch.setattr("usvsim.rendering.weather.rain_streaks", lambda *a, **k: None)  # the rings alone

    def frame(rate: float, seed: int, t: float = 3.0, then_dry: bool = False):
        raw = scenario_dict(0, {"sun": {"azimuth_deg": 270.0, "elevation_deg": 35.0}, "rain": {"rate_mm_h": rate}}, 320, 240)
        raw["objects"] = []
        sim = load(raw, seed=seed)
        try:
            sim.run(t)
            camera = sim.sensors["wamv/camera"]
            pose = (np.array([20.0, 20.0, 2.0]), _looking_down(0.6))
            images = camera.render(sim.world, pose=pose)
            if then_dry:  # the same renderer, rain off again: back to the programs without rings
                sim.look = sim.look.updated({"rain": {"rate_mm_h": 0.0}})
                images = camera.render(sim.world, pose=pose)
            return images
        finally:
            sim.close()

    return frame


def _texture(rgb: np.ndarray) -> float:
    y = rgb.astype(float) @ np.array([0.3, 0.6, 0.1])
    high = y - 0.25 * (np.roll(y, 1, 0) + np.roll(y, -1, 0) + np.roll(y, 1, 1) + np.roll(y, -1, 1))
    return float(np.mean(np.abs(high[120:230, 10:310])))  # the near water (rows 120+: within ~6 m)


def test_rain_rings_change_rgb_only_and_are_reproducible(frames):
    dry, wet, again, other_seed, later = frames(0.0, 1), frames(8.0, 1), frames(8.0, 1), frames(8.0, 2), frames(8.0, 1, 3.1)
    for images in (wet, again, other_seed, later):
        assert np.array_equal(images["segmentation"], dry["segmentation"])
        assert np.array_equal(images["depth"], dry["depth"], equal_nan=True)
    assert all(np.array_equal(wet[k], again[k], equal_nan=True) for k in wet)  # same seed and time: same bytes
    near = (slice(120, 230), slice(10, 310))
    assert not np.array_equal(wet["rgb"][near], other_seed["rgb"][near])  # the seed places the drops
    assert not np.array_equal(wet["rgb"][near], later["rgb"][near])  # they come and go
    assert _texture(wet["rgb"]) > 2.0 * _texture(dry["rgb"])  # rings on the calm sea


def test_rain_off_draws_the_water_without_rings(frames):
    dry, dried = frames(0.0, 1), frames(8.0, 1, then_dry=True)
    assert all(np.array_equal(dry[k], dried[k], equal_nan=True) for k in dry)
