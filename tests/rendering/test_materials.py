"""Material classes: each visual geom gets a gloss from what it is; the look changes RGB only."""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("moderngl")

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


def test_shadows_on_the_water_are_cast_along_the_sun_and_change_rgb_only():
    from usvsim.rendering.shadows import shadow_triangles

    def frame(shadows: bool):
        raw = scenario_dict(1, {"shadows": shadows, "sun": {"elevation_deg": 30.0, "azimuth_deg": 270.0}}, 160, 120)
        sim = load(raw, seed=0)
        sim.run(0.5)
        images = sim.sensors["wamv/camera"].render(sim)
        west = shadow_triangles(sim.model, sim.data, np.array([-0.866, 0.0, 0.5]), 0.0, (0.0, 0.0))
        east = shadow_triangles(sim.model, sim.data, np.array([0.866, 0.0, 0.5]), 0.0, (0.0, 0.0))
        sim.close()
        return images, west, east

    lit, west, east = frame(True)
    plain, _, _ = frame(False)
    assert len(west) and len(west) % 3 == 0 and len(west) == len(east)
    # the same boxes: with the sun in the west their shadows lie further east than with the sun in the east
    shift = west.reshape(-1, 36, 2)[:, :, 0].mean(axis=1) - east.reshape(-1, 36, 2)[:, :, 0].mean(axis=1)
    assert np.all(shift >= -1e-4) and shift.max() > 1.0
    assert np.array_equal(lit["segmentation"], plain["segmentation"])
    assert np.array_equal(lit["depth"], plain["depth"], equal_nan=True)
