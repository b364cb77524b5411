"""The plain look's fog (datasets/look_kernels.finish_look) against Koschmieder's law in linear light: the fog colour
is linear RGB (docs/rendering.md), the 8-bit image is display gamma 2 (MuJoCo's space, the shader's `display`)."""

from __future__ import annotations

import math

import numpy as np

from usvsim.datasets.look import KOSCHMIEDER
from usvsim.datasets.look_kernels import finish_look

FOG = np.array([0.72, 0.76, 0.80], np.float32)


def fogged(value: int, distance_m: float, visibility_m: float) -> np.ndarray:
    rgb = np.full((1, 1, 3), value, np.uint8)
    depth = np.array([[distance_m]], np.float32)
    out = np.empty((1, 1, 3), np.float32)
    finish_look(rgb, depth, np.ones((1, 1), np.float32), KOSCHMIEDER / visibility_m, FOG, 1000.0, 1.0,
                np.zeros((1, 1), np.float32), out)  # fmt: skip
    return out[0, 0]


def test_fog_blends_in_linear_light_and_reaches_the_linear_fog_colour():
    far = fogged(0, 1e5, 50.0)  # fully fogged: the fog colour, encoded for display (QA: it came out as 0.72 * 255)
    assert np.allclose(far, np.sqrt(FOG), atol=1e-6)
    for d in (12.1, 44.7, 50.0):  # the linear radiance of black and white objects keeps exp(-σ d) of its contrast
        keep = math.exp(-KOSCHMIEDER / 50.0 * d)
        black, white = fogged(0, d, 50.0) ** 2, fogged(255, d, 50.0) ** 2
        assert np.allclose((white - black), keep, rtol=1e-5)
    assert abs((fogged(255, 50.0, 50.0) ** 2 - fogged(0, 50.0, 50.0) ** 2)[0] - 0.02) < 1e-3  # 2 % at the visibility


def test_no_fog_and_no_distance_leave_the_image_as_it_was():
    assert np.allclose(fogged(200, 0.0, 50.0), 200 / 255.0, atol=1e-6)
    rgb = np.full((1, 1, 3), 77, np.uint8)
    out = np.empty((1, 1, 3), np.float32)
    finish_look(rgb, np.array([[30.0]], np.float32), np.ones((1, 1), np.float32), 0.0, FOG, 1000.0, 1.0,
                np.zeros((1, 1), np.float32), out)  # fmt: skip
    assert np.allclose(out, 77 / 255.0)
