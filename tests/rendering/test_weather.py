"""Camera weather: rain streaks, lens droplets and motion blur are reproducible, RGB-only, and do what they say."""

from __future__ import annotations

import numpy as np
import pytest

from usvsim.rendering.weather import extinction_per_m, lens_droplets, motion_blur, rain_streaks, rotation_flow


def _scene() -> np.ndarray:
    rng = np.random.default_rng(0)
    img = np.zeros((120, 160, 3), np.uint8)
    img[:60] = (170, 180, 200)  # sky
    img[60:] = (30, 50, 70) + rng.integers(0, 20, (60, 160, 3))  # sea
    return img


def test_rain_is_reproducible_per_frame_time_and_off_at_zero():
    a, b, c, dry = _scene(), _scene(), _scene(), _scene()
    rain_streaks(a, 10.0, 10.0, 100.0, 3, "/wamv/camera", 1_000_000_000)
    rain_streaks(b, 10.0, 10.0, 100.0, 3, "/wamv/camera", 1_000_000_000)
    rain_streaks(c, 10.0, 10.0, 100.0, 3, "/wamv/camera", 1_100_000_000)
    rain_streaks(dry, 0.0, 10.0, 100.0, 3, "/wamv/camera", 1_000_000_000)
    assert np.array_equal(a, b) and not np.array_equal(a, c)
    assert np.array_equal(dry, _scene())
    lit = a.astype(int).sum(axis=2) - _scene().astype(int).sum(axis=2)
    assert (lit[60:] > 10).mean() > 0.01  # streaks brighten the dark sea
    heavy = _scene()
    rain_streaks(heavy, 50.0, 10.0, 100.0, 3, "/wamv/camera", 1_000_000_000)
    assert (heavy != _scene()).mean() > (a != _scene()).mean()  # more rain, more streaks


def test_rain_extinction_gives_the_visibility_of_rain():
    assert 3.912 / extinction_per_m(10.0) == pytest.approx(3660.0, rel=0.01)  # 0.25 R^0.63 per km
    assert extinction_per_m(0.0) == 0.0


def test_droplets_persist_between_frames_and_come_and_go():
    a, b, later = _scene(), _scene(), _scene()
    lens_droplets(a, 0.5, 3, "/wamv/camera", 10.0)
    lens_droplets(b, 0.5, 3, "/wamv/camera", 10.1)
    lens_droplets(later, 0.5, 3, "/wamv/camera", 40.0)
    changed = (a != _scene()).any(axis=2)
    assert 0.01 < changed.mean() < 0.6
    assert np.array_equal(a, b)  # a tenth of a second later: the same drops
    assert not np.array_equal(a, later)  # half a minute later: some dried, others came


def test_motion_blur_spreads_along_the_flow_and_keeps_the_light():
    img = np.zeros((40, 60, 3), np.uint8)
    img[20, 30] = 240
    motion_blur(img, (8.0, 0.0))
    row = img[20, :, 0].astype(int)
    assert (row > 0).sum() == 8 and img[:, :, 0].sum() == pytest.approx(240, abs=8)
    assert img[19].sum() == 0 and img[21].sum() == 0  # horizontal flow: no vertical smear
    still = _scene()
    motion_blur(still, rotation_flow(np.zeros(3), 500.0, 0.03))
    assert np.array_equal(still, _scene())
    assert rotation_flow(np.array([0.0, 0.5, 0.0]), 400.0, 0.02) == pytest.approx(
        (-4.0, 0.0)
    )  # yawing: sideways


def test_camera_weather_changes_rgb_only():
    pytest.importorskip("moderngl")
    from usvsim.rendering.gallery import load, scenario_dict

    def frame(look):
        raw = scenario_dict(3, look, 160, 120)
        raw["objects"] = []
        sim = load(raw, seed=2)
        sim.run(0.5)
        images = sim.sensors["wamv/camera"].render(sim)
        sim.close()
        return images

    wet = frame({"rain": {"rate_mm_h": 20.0}, "camera": {"droplets": 0.8, "motion_blur_ms": 40.0}})
    again = frame({"rain": {"rate_mm_h": 20.0}, "camera": {"droplets": 0.8, "motion_blur_ms": 40.0}})
    dry = frame({})
    assert all(np.array_equal(wet[k], again[k], equal_nan=True) for k in wet)
    assert np.array_equal(wet["segmentation"], dry["segmentation"])
    assert np.array_equal(wet["depth"], dry["depth"], equal_nan=True)
    assert not np.array_equal(wet["rgb"], dry["rgb"])
