"""The shader look on real camera frames (EGL, llvmpipe): exact water depth, labels, no seam, reproducible."""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("moderngl")

from usvsim.rendering.frame import water_label
from usvsim.rendering.gallery import CAMERA, load, scenario_dict


def _sim(sea_state: int, look: dict | None = None, mount: dict | None = None, seed: int = 0):
    raw = scenario_dict(sea_state, look or {}, 160, 120)
    raw["vessels"][0]["sensors"][0]["mount"] = mount or CAMERA["mount"]
    raw["objects"] = []
    sim = load(raw, seed)
    sim.run(1.0)
    return sim, sim.sensors["wamv/camera"]


def test_flat_water_depth_is_the_plane_and_labelled_water():
    sim, cam = _sim(0, mount={"position": [0.0, 0.0, 3.0], "pitch_deg": 30.0})
    images = cam.render(sim)
    pos, rot = cam.pose_world(sim)
    from usvsim.sensors.base import OPTICAL_ROT

    rays = cam.intrinsics.rays()  # (h, w, 2): x/z, y/z in the optical frame
    dirs = np.concatenate([rays, np.ones(rays.shape[:2] + (1,))], axis=-1) @ (rot @ OPTICAL_ROT).T
    level = sim.ocean.level_m
    z_optical = np.where(dirs[..., 2] < 0, (pos[2] - level) / -dirs[..., 2], np.nan)  # depth along optical z
    water = images["segmentation"] == water_label(sim.model)
    near = water & (z_optical < 0.9 * cam.cfg.far_m)
    assert near.sum() > 3000
    assert np.allclose(images["depth"][near], z_optical[near], rtol=2e-4, atol=2e-3)
    sim.close()


@pytest.mark.parametrize("height_m", [0.5, 50.0])
def test_water_reaches_the_horizon_without_a_seam(height_m):
    sim, cam = _sim(4, mount={"position": [0.0, 0.0, height_m], "pitch_deg": 8.0})
    seg = cam.render(sim)["segmentation"]
    water = seg == water_label(sim.model)
    rows = np.arange(seg.shape[0])[:, None]
    first_water = np.where(water, rows, seg.shape[0]).min(axis=0)  # per column: where the sea begins
    assert (first_water < 0.8 * seg.shape[0]).all()  # every column sees the sea below its horizon
    assert not ((seg == 0) & (rows > first_water)).any()  # and no background (sky) below it: no hole, no seam
    sim.close()


def test_same_seed_same_bytes_and_look_changes_only_rgb():
    a_sim, a = _sim(4, seed=3)
    b_sim, b = _sim(4, seed=3)
    first, second = a.render(a_sim), b.render(b_sim)
    assert all(np.array_equal(first[k], second[k], equal_nan=True) for k in first)
    b_sim.look = b_sim.look.updated({"fog": {"visibility_m": 150.0}, "sun": {"elevation_deg": 5.0}})
    foggy = b.render(b_sim)
    assert np.array_equal(foggy["segmentation"], first["segmentation"])
    assert np.array_equal(foggy["depth"], first["depth"], equal_nan=True)
    assert np.abs(foggy["rgb"].astype(int) - first["rgb"]).mean() > 5
    a_sim.close(), b_sim.close()


def test_gallery_picture(tmp_path):
    from PIL import Image

    from usvsim.rendering.gallery import render_look

    path = render_look("dusk", tmp_path, 160, 90, settle_s=0.2)
    image = np.asarray(Image.open(path))
    assert image.shape == (90, 160, 3) and image.std() > 2


@pytest.mark.parametrize(("sea_state", "mount"), [(4, None), (5, {"position": [0.0, 0.0, 50.0], "pitch_deg": 20.0}),
                                                  (3, {"position": [0.0, 0.0, 0.5], "pitch_deg": -5.0})])  # fmt: skip
def test_water_labels_from_the_colour_pass_equal_the_label_pass(sea_state, mount):
    """A capture with RGB takes the water's labels from the stencil of its colour pass; a segmentation-only
    capture draws the label pass. Both must label exactly the same pixels (harbour geoms in view)."""
    sim, cam = _sim(sea_state, mount=mount)
    for _ in range(2):
        sim.step()
        with_rgb = cam.renderer  # the same renderer, posed for this frame by cam.render
        labels = cam.render(sim)["segmentation"]
        alone = with_rgb.capture(rgb_depth=False, segmentation=True)["segmentation"]
        water = labels == water_label(sim.model)
        assert water.sum() > 500 and (labels != water_label(sim.model)).sum() > 0
        assert np.array_equal(labels, alone)
    sim.close()


def test_a_new_sea_at_the_same_time_is_drawn_anew():
    """A reset with another seed (a new wave field) that reaches a time already drawn shows the new sea: the
    ocean's textures are keyed on the wave field as well as the time (they were on the time alone: every frame of
    a data set with an episode per frame, all drawn at the same settle time, showed the first episode's waves)."""
    sim = load(scenario_dict(4, {}, 160, 120), seed=1)
    fresh = load(scenario_dict(4, {}, 160, 120), seed=2)
    camera, other = sim.sensors["wamv/camera"], fresh.sensors["wamv/camera"]

    def at_half_a_second(s) -> None:  # the clock set as datasets/rerender.py does: no camera renders on the way
        s.world.clock.steps = 50
        s.world.clock.now_ns = 50 * s.world.clock.step_ns

    try:
        at_half_a_second(sim)
        first = camera.render(sim)["rgb"]
        sim.reset(seed=2)
        at_half_a_second(sim)
        at_half_a_second(fresh)
        again, expected = camera.render(sim)["rgb"], other.render(fresh)["rgb"]
        assert np.array_equal(again, expected)
        assert (again != first).any(axis=-1).mean() > 0.1  # another sea
    finally:
        sim.close()
        fresh.close()
