"""The drawn water surface is the ocean the physics queries."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

from usvsim.simulation import Simulation
from usvsim.viewer.demo import harbor_with_waves
from usvsim.world.water_visual import (
    SURFACE_POINTS,
    SURFACE_SIZE_M,
    WaterSurfaceIds,
    drawn_heights,
    grid_points,
    height_colors,
    snapped_center,
    update_water_visual,  # fmt: skip
)


@pytest.fixture(scope="module")
def waves():
    sim = Simulation(harbor_with_waves())
    sim.run(1.0)
    return sim


def test_drawn_heights_equal_ocean_elevation(waves):
    heights = update_water_visual(waves, None, (7.3, -4.1))
    gx, gy = grid_points(waves.model)
    truth = waves.ocean.elevation(gx, gy, waves.time)
    assert np.ptp(truth) > 0.3  # a real sea
    span = waves.model.hfield_size[WaterSurfaceIds.of(waves.model).hfield, 2]
    quantum = span * np.finfo(np.float32).eps * 4  # float32 storage of the normalized heights
    assert np.abs(drawn_heights(waves.model) - truth).max() <= quantum + 1e-9
    centre = snapped_center((7.3, -4.1), SURFACE_SIZE_M, SURFACE_POINTS)  # snapped to the grid spacing
    assert np.array_equal(heights, waves.ocean.height_grid(centre, SURFACE_SIZE_M, SURFACE_POINTS, waves.time))


def test_ray_cast_onto_the_drawn_surface_finds_the_ocean(waves):
    """What MuJoCo draws (the hfield geom) and what the physics feels (Ocean.elevation) are one surface."""
    waves.step()
    update_water_visual(waves, None, waves.vessels["wamv"].position[:2])
    gx, gy = grid_points(waves.model)
    water_only = np.array([0, 0, 1, 0, 0, 0], dtype=np.uint8)
    hit = np.zeros(1, dtype=np.int32)
    rng = np.random.default_rng(0)
    for i, j in rng.integers(5, SURFACE_POINTS - 5, size=(25, 2)):
        origin = np.array([gx[i, j] + 1e-6, gy[i, j] + 1e-6, 10.0])
        dist = mujoco.mj_ray(
            waves.model, waves.data, origin, np.array([0.0, 0.0, -1.0]), water_only, 1, -1, hit
        )
        assert hit[0] == WaterSurfaceIds.of(waves.model).geom
        z = waves.ocean.elevation(np.array([origin[0]]), np.array([origin[1]]), waves.time)[0]
        assert 10.0 - dist == pytest.approx(z, abs=1e-4)


def test_still_water_plane_goes_below_the_field(waves):
    heights = update_water_visual(waves, None, (0.0, 0.0))
    ids = WaterSurfaceIds.of(waves.model)
    waves.step()
    assert waves.data.geom_xpos[ids.plane, 2] < heights.min()


def test_flat_sea_is_flat_and_physics_untouched():
    sim = Simulation.from_scenario("harbor")
    sim.run(0.5)
    qpos = sim.data.qpos.copy()
    heights = update_water_visual(sim, None, (0.0, 0.0))
    assert np.all(heights == 0.0) and np.allclose(drawn_heights(sim.model), 0.0)
    ids = WaterSurfaceIds.of(sim.model)
    assert sim.model.geom_contype[ids.geom] == sim.model.geom_conaffinity[ids.geom] == 0
    assert np.array_equal(sim.data.qpos, qpos)


def test_height_colors_dark_troughs_light_crests():
    x = np.linspace(0, 4 * np.pi, 64)
    h = np.tile(0.3 * np.sin(x), (64, 1))
    rgb = height_colors(h, 0.2).astype(int).sum(axis=2)
    assert rgb.shape == (64, 64)
    crest, trough = np.argmax(h[0]), np.argmin(h[0])
    assert rgb[10, crest] > rgb[10, trough]
