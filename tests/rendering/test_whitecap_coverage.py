"""Rendered whitecap coverage follows Monahan's law W = 3.84e-6 U^3.41 (U: the wind of a fully developed sea of the
ocean's Hs, m/s at 10 m), after the whitecaps were broken into streaks.

The sea is seen straight down (camera 50 m and 150 m above still water, yawed 0.5 rad off the grid's axes so that
the pixel lattice does not beat with the noise textures), at 9 points spaced 93 m apart (the breaking noise
repeats every 278 m, the shortest tile every 84-166 m), 14 s after the start (the start-up ramp has 0.1 % left).
A pixel's foam share a comes from the frame drawn with `water.foam: 1` and the same frame with `water.foam: 0`:
in linear light (the display is gamma 2) the water pixel is c_off·(1 - a) + F·a, F the foam's light
(0.85·(2.5 ambient + sun·sin(elevation)), shaders.WATER_FS), so a = (c_on - c_off) / (F - c_off); a pixel half
foam counts a half. Coverage = mean a over the image (glint off, no vignetting; depth and labels are untouched
by foam). Tolerance: each sea state within 0.75-1.33 of W (a single instant of a 128² tile carries +-10 % of
tail statistics, Monahan's own data scatter by a factor 2-3), and the growth with wind within 15 % of U^3.41.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from usvsim.rendering.detail import resolved_statistics, whitecap_fraction
from usvsim.rendering.gallery import load, scenario_dict

pytest.importorskip("moderngl")

YAW = 0.5


def _down(yaw: float) -> np.ndarray:
    """FLU → world (ENU) rotation of a camera looking straight down, its image's right along (cos, sin)(yaw)."""
    c, s = math.cos(yaw), math.sin(yaw)
    return np.array([[0.0, -s, c], [0.0, c, s], [-1.0, 0.0, 0.0]])


def rendered_coverage(sea_state: int, heights=(50.0, 150.0), t_s: float = 14.0) -> tuple[float, float, dict]:
    """(wind U m/s, Monahan's W, {camera height m: rendered foam coverage}) of the harbour scenario's sea state."""
    look = {"water": {"glint": 0.0}, "camera": {"vignetting": 0.0}, "sun": {"elevation_deg": 45.0, "intensity": 0.5}}
    raw = scenario_dict(sea_state, look, 320, 240)
    raw["objects"] = []
    sim = load(raw, seed=3)
    try:
        sim.run(t_s)
        camera = sim.sensors["wamv/camera"]
        hs, _ = resolved_statistics(sim.ocean.waves)
        out = {}
        for height in heights:
            poses = [(np.array([300.0 + 93.0 * i, 300.0 + 93.0 * j, height]), _down(YAW)) for i in range(3) for j in range(3)]
            frames = {}
            for foam in (1.0, 0.0):
                sim.look = sim.look.updated({"water": {"foam": foam}})
                frames[foam] = np.array([camera.render(sim.world, pose=p)["rgb"] for p in poses]).astype(float) / 255.0
            light = camera.renderer.marine.daylight
            foam_light = 0.85 * (light.ambient * 2.5 + light.sun_color * max(float(light.sun_dir[2]), 0.0))
            on, off = frames[1.0] ** 2, frames[0.0] ** 2
            assert np.all(on < 0.999)  # nothing clipped: the foam's light is inside the 8-bit range
            share = (on - off) / (foam_light - off)
            out[height] = float(share.mean())
        return math.sqrt(hs * 9.81 / 0.21), whitecap_fraction(hs), out  # Hs = 0.21 U²/g (Pierson-Moskowitz)
    finally:
        sim.close()


@pytest.fixture(scope="module")
def coverage():
    return {ss: rendered_coverage(ss) for ss in (4, 5, 6)}


def test_rendered_whitecaps_cover_monahans_fraction(coverage):
    for sea_state, (_, w, by_height) in coverage.items():
        for height, rendered in by_height.items():
            assert 0.75 * w < rendered < 1.33 * w, (sea_state, height, rendered, w)
    print({ss: (round(u, 2), round(w, 5), {h: round(c / w, 3) for h, c in by.items()}) for ss, (u, w, by) in coverage.items()})


def test_rendered_whitecaps_grow_with_the_wind_as_monahan(coverage):
    lo, hi = coverage[min(coverage)], coverage[max(coverage)]  # sea states 4 and 6: U = 9.4 and 15.4 m/s
    for height in lo[2]:
        exponent = math.log(hi[2][height] / lo[2][height]) / math.log(hi[0] / lo[0])
        assert exponent == pytest.approx(3.41, rel=0.15), (height, exponent)
