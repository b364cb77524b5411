"""Water patch: correct triangle per cell, current sampling, bounds checks, direct mode."""

import math

import numpy as np
import pytest

from usvsim.ocean.components import from_arrays
from usvsim.ocean.direct import DirectWaveField
from usvsim.ocean.patch import WaterPatch


class Tent:
    """A surface that is linear on each triangle of a 1 m grid split along (i, j)–(i+1, j+1): z = min(fx, fy)."""

    def elevation(self, x, y, t):
        return np.where((np.asarray(x) == 1) & (np.asarray(y) == 1), 1.0, 0.0) + 0 * t


class Plane:
    def elevation(self, x, y, t):
        return 0.3 * np.asarray(x) - 0.2 * np.asarray(y) + 0.1 * t


def test_plane_is_reproduced_exactly_and_sampled_at_the_current_time():
    patch = WaterPatch(Plane(), resolution=4, margin_m=0.5)
    patch.update(np.array([[0.0, 0.0], [3.0, 2.0]]), t=2.0)
    rng = np.random.default_rng(0)
    x, y = rng.uniform(-0.5, 3.5, 100), rng.uniform(-0.5, 2.5, 100)
    np.testing.assert_allclose(patch.water_height(x, y), 0.3 * x - 0.2 * y + 0.2, atol=1e-12)
    pts = np.column_stack([x, y, np.zeros(100)])
    np.testing.assert_allclose(patch.height_above_water(pts), -(0.3 * x - 0.2 * y + 0.2), atol=1e-12)


def test_the_triangle_containing_the_point_is_used():
    patch = WaterPatch(Tent(), resolution=2, margin_m=0.0)
    patch.update(np.array([[0.0, 0.0], [2.0, 2.0]]), t=0.0)  # vertices at 0, 1, 2; only (1, 1) raised
    # cell (0, 0): lower triangle (00, 10, 11) for fx >= fy gives z = fy; upper (00, 11, 01) gives z = fx
    np.testing.assert_allclose(patch.water_height([0.8, 0.2], [0.2, 0.8]), [0.2, 0.2])
    np.testing.assert_allclose(patch.water_height([0.5], [0.5]), [0.5])


def test_points_outside_the_patch_raise():
    patch = WaterPatch(Plane(), resolution=3, margin_m=0.2)
    patch.update(np.array([[0.0, 0.0], [1.0, 1.0]]), 0.0)
    with pytest.raises(ValueError, match="outside the water patch"):
        patch.water_height([1.5], [0.5])


def test_direct_mode_queries_the_surface_and_grid_mode_is_close_on_a_smooth_sea():
    sea = DirectWaveField(
        from_arrays([0.5, 0.2], [2 * math.pi / 40, 2 * math.pi / 15], [0.3, -0.5], [0.0, 1.0], 0.7)
    )
    hull = np.array([[-2.5, -1.2], [2.5, 1.2]])
    direct, grid = WaterPatch(sea, mode="direct"), WaterPatch(sea, resolution=10, margin_m=0.5)
    direct.update(hull, 1.3)
    grid.update(hull, 1.3)
    rng = np.random.default_rng(1)
    x, y = rng.uniform(-2.5, 2.5, 200), rng.uniform(-1.2, 1.2, 200)
    np.testing.assert_array_equal(direct.water_height(x, y), sea.elevation(x, y, 1.3))
    assert np.abs(grid.water_height(x, y) - direct.water_height(x, y)).max() < 0.01
