"""Material classes: each visual geom gets a gloss from what it is; the look changes RGB only."""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("moderngl")

from usvsim.rendering.frame import water_label
from usvsim.rendering.gallery import load, scenario_dict
from usvsim.rendering.materials import geom_classes


def test_classes_of_the_harbour():
    sim = load(scenario_dict(1, {}, 64, 48))
    classes = geom_classes(sim.model, list(sim.vessels), list(sim.bodies))
    by_body: dict[str, set] = {}
    for g, cls in classes.items():
        by_body.setdefault(sim.model.body(int(sim.model.geom_bodyid[g])).name, set()).add(cls)
    sim.close()
    assert by_body["wamv"] == {"rubber", "metal"}  # pontoons, frame
    assert "paint" in by_body["otter"]  # the orange hulls
    assert by_body["red_1"] == {"plastic"}
    assert {"wood", "concrete"} <= by_body["world"]  # pier deck, quay


def test_materials_change_rgb_only():
    def frame(materials: bool):
        raw = scenario_dict(
            1, {"materials": materials, "sun": {"elevation_deg": 30.0, "azimuth_deg": 90.0}}, 160, 120
        )
        raw["vessels"][0]["sensors"][0]["mount"] = {
            "position": [-1.0, 0.0, 2.5],
            "pitch_deg": 40.0,
            "yaw_deg": 180.0,
        }
        sim = load(raw, seed=0)
        sim.run(0.2)
        images = sim.sensors["wamv/camera"].render(sim)
        sim.close()
        return images

    glossy, matte = frame(True), frame(False)
    assert np.array_equal(glossy["segmentation"], matte["segmentation"])
    assert np.array_equal(glossy["depth"], matte["depth"], equal_nan=True)
    assert not np.array_equal(glossy["rgb"], matte["rgb"])


def test_shadows_on_the_water_are_the_geoms_shadows_along_the_sun_and_change_rgb_only():
    """The water takes the sun away where MuJoCo's shadow map of the geoms (their meshes as drawn) covers the
    surface point. Independent reference: a ray from each water pixel's surface point (from the depth image)
    toward the sun, against the same geoms (mujoco.mj_ray, exact mesh and primitive intersection)."""
    import mujoco

    from usvsim.sensors.base import OPTICAL_ROT

    sun = {"elevation_deg": 40.0, "azimuth_deg": 270.0}  # from the west: shadows fall east
    down = np.array([[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]])  # FLU → world: straight down

    def frame(shadows: bool):
        raw = scenario_dict(1, {"shadows": shadows, "sun": sun}, 320, 240)
        raw["objects"] = []
        sim = load(raw, seed=0)
        sim.run(0.5)
        camera = sim.sensors["wamv/camera"]
        boat = sim.state.pos[camera.body]
        pose = (np.array([boat[0] + 1.5, boat[1], boat[2] + 9.0]), down)
        images = camera.render(sim.world, pose=pose)
        out = images, pose, camera.intrinsics, camera.renderer.marine.daylight.sun_dir.copy(), water_label(sim.model)
        if shadows:  # the reference: rays toward the sun from the surface points
            (pos, rot), k = pose, camera.intrinsics
            depth = images["depth"]
            v, u = np.nonzero(images["segmentation"] == out[4])
            d = depth[v, u].astype(np.float64)
            optical = np.stack([(u - k.cx) / k.fx * d, (v - k.cy) / k.fy * d, d], axis=1)
            points = pos + optical @ (rot @ OPTICAL_ROT).T
            groups = np.array([1, 1, 0, 0, 0, 0], np.uint8)  # the geoms the scene draws (group 2: MuJoCo's water)
            geom = np.zeros(1, np.int32)
            hits = np.zeros((len(points), 5), bool)
            for i, p in enumerate(points):
                for j, offset in enumerate(((0, 0), (0.05, 0), (-0.05, 0), (0, 0.05), (0, -0.05))):
                    start = p + np.array([*offset, 0.01])
                    hits[i, j] = mujoco.mj_ray(sim.model, sim.data, start, out[3], groups, 1, -1, geom) >= 0
            out = (*out, (v, u, hits))
        sim.close()
        return out

    lit, _, _, _, _, (v, u, hits) = frame(True)
    plain = frame(False)[0]
    assert np.array_equal(lit["segmentation"], plain["segmentation"])
    assert np.array_equal(lit["depth"], plain["depth"], equal_nan=True)
    luminance = np.array([0.3, 0.6, 0.1])
    darker = (plain["rgb"][v, u].astype(float) - lit["rgb"][v, u].astype(float)) @ luminance
    sure = hits.all(axis=1) | ~hits.any(axis=1)  # 5 cm from an edge of the shadow either way: left out
    shade = hits[:, 0]
    assert (shade & sure).sum() > 300 and (~shade & sure).sum() > 300
    assert (darker[shade & sure] > 2.0).mean() > 0.9  # in the geoms' shadow: the sun's share is gone
    assert (np.abs(darker[~shade & sure]) < 1.0).mean() > 0.95  # in the sun: as without shadows


def test_marks_of_the_harbour():
    """Hull numbers on each vessel's hulls (fore and aft, numbered in order), a band on each buoy."""
    from usvsim.rendering.materials import MAX_MARKS, mark_geoms

    sim = load(scenario_dict(1, {}, 64, 48))
    model = sim.model
    marks = mark_geoms(model, list(sim.vessels), list(sim.bodies))
    by_body: dict[str, list[float]] = {}
    for g, basis, _, kind in marks:
        by_body.setdefault(model.body(int(model.geom_bodyid[g])).name, []).append(kind)
        assert np.allclose(basis.T @ basis, np.eye(3))  # an orthonormal frame in the geom's
    sim.close()
    assert len(marks) <= MAX_MARKS
    assert by_body["wamv"] == [1.0, 1.0]  # the two pontoons carry number 1
    assert by_body["red_1"] == [0.0]  # a band


def test_sun_and_sky_keep_the_fixed_function_brightness_at_both_ends():
    """levels(): a face the sun lights fully and a face in the sky's light alone come out as bright as MuJoCo's
    fixed-function look drew them (display = sqrt of linear)."""
    from usvsim.config.rendering import Rendering
    from usvsim.rendering.materials import levels
    from usvsim.rendering.sky import daylight

    light = daylight(Rendering(), 45.0, 10.0)
    sun, sky = levels(light)
    sky_level = float(light.ambient @ (0.3, 0.6, 0.1))
    ambient = min(1.1 * sky_level, 0.4) * (0.75 + 0.25 * light.ambient / sky_level)
    assert np.allclose(np.sqrt(sky), ambient)
    assert np.allclose(np.sqrt(sky + sun), ambient + np.clip(0.62 * light.sun_color, 0, 1))


def test_the_shadow_pass_adds_up_to_the_unshadowed_look():
    """With shadows MuJoCo draws the sun in a second, additive pass (the program adds, on display, what the sun
    adds): on geoms it does not shadow, the result matches the single-pass look to rounding."""

    def frame(shadows: bool):
        raw = scenario_dict(1, {"shadows": shadows, "sun": {"elevation_deg": 50.0, "azimuth_deg": 200.0}}, 160, 120)
        raw["vessels"][0]["sensors"][0]["mount"] = {"position": [-1.0, 0.0, 2.5], "pitch_deg": 40.0, "yaw_deg": 180.0}
        sim = load(raw, seed=0)
        sim.run(0.2)
        images = sim.sensors["wamv/camera"].render(sim)
        water = sim.model.geom("water_surface").id + 1
        sim.close()
        return images, water

    (lit, water), (plain, _) = frame(True), frame(False)
    geoms = (plain["segmentation"] > 0) & (plain["segmentation"] != water)
    assert geoms.sum() > 500
    diff = lit["rgb"].astype(int) - plain["rgb"].astype(int)
    same = np.abs(diff).max(axis=-1) <= 2
    assert same[geoms].mean() > 0.9  # the boat is in the sun here (MuJoCo's map puts no shadow on it)
    assert (diff[geoms] <= 2).all()  # shadows only darken


def test_hull_number_is_painted_on_the_pontoon():
    """A camera beside the WAM-V's port pontoon, level with its bow, sees the white '01' on the black rubber
    with materials, and no near-white pixel on it without."""

    def frame(materials: bool):
        raw = scenario_dict(1, {"materials": materials, "sun": {"elevation_deg": 40.0, "azimuth_deg": 0.0}}, 160, 120)
        raw["vessels"][0]["sensors"][0]["mount"] = {"position": [1.6, 4.0, 0.6], "pitch_deg": 5.0, "yaw_deg": -90.0}
        sim = load(raw, seed=0)
        sim.run(0.2)
        images = sim.sensors["wamv/camera"].render(sim)
        model = sim.model
        hulls = [g + 1 for g in range(model.ngeom) if model.geom_bodyid[g] == model.body("wamv").id
                 and model.geom_group[g] == 1 and model.geom_type[g] == 7]  # fmt: skip
        sim.close()
        on_hull = np.isin(images["segmentation"], hulls)
        assert on_hull.sum() > 500
        return int(((images["rgb"].min(axis=-1) > 150) & on_hull).sum())

    assert frame(True) > 10
    assert frame(False) == 0
