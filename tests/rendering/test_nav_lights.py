"""Navigation lights: COLREG arcs seen from around a vessel, lit at dusk, RGB only (depth and labels exact)."""

from __future__ import annotations

import math

import numpy as np
import pytest

pytest.importorskip("moderngl")

from usvsim.rendering.gallery import load, scenario_dict
from usvsim.rendering.lights import GREEN, RED, WHITE, NavigationLights, lights_on


@pytest.fixture(scope="module")
def harbour():
    sim = load(scenario_dict(0, {}, 160, 120))
    sim.run(0.1)
    yield sim
    sim.close()


def _seen_from(sim, lights, bearing_deg: float) -> set:
    """The lamp colours of the WAM-V seen from 200 m at a relative bearing (counter-clockwise from its bow)."""
    body = sim.model.body("wamv").id
    rot, pos = sim.data.xmat[body].reshape(3, 3), sim.data.xpos[body]
    b = math.radians(bearing_deg)
    eye = pos + rot @ np.array([200 * math.cos(b), 200 * math.sin(b), 0.0]) + np.array([0, 0, 3.0])
    lamps = lights.world(sim.data.xpos, sim.data.xmat.reshape(-1, 3, 3), eye, 0.0, 1.0)
    near = np.linalg.norm(lamps[:, :3] - pos, axis=1) < 10.0
    return {_key(c) for c in lamps[near, 3:]}


def _key(color) -> tuple:
    """The lamp's hue (a sidelight seen exactly along its arc's edge is dimmer, not another colour)."""
    return tuple(round(float(x) / float(max(color)), 2) for x in color)


def test_colreg_arcs(harbour):
    lights = NavigationLights(harbour.model, ["wamv"], [])
    white, red, green = (_key(c) for c in (WHITE, RED, GREEN))
    assert _seen_from(harbour, lights, 0.0) == {white, red, green}  # head-on: masthead and both sidelights
    assert _seen_from(harbour, lights, 90.0) == {white, red}  # from port: masthead and red
    assert _seen_from(harbour, lights, -90.0) == {white, green}  # from starboard
    assert _seen_from(harbour, lights, 180.0) == {white}  # from astern: the sternlight only
    assert _seen_from(harbour, lights, 120.0) == {white}  # abaft the sidelights' 112.5°: the sternlight


def test_buoys_flash_their_paint(harbour):
    buoys = [n for n in harbour.bodies if n not in harbour.vessels]
    lights = NavigationLights(harbour.model, [], buoys)
    assert len(lights.lamps) == len(buoys)  # red, green and yellow buoys all carry a light
    d = harbour.data
    counts = [len(lights.world(d.xpos, d.xmat.reshape(-1, 3, 3), np.array([0.0, 0.0, 10.0]), t, 1.0))
              for t in np.arange(0, 2.5, 0.1)]  # fmt: skip
    assert min(counts) < max(counts) < len(buoys)  # flashing, each in its own phase: never all at once


def test_lit_at_dusk_and_in_fog_only_in_auto(harbour):
    look = harbour.look
    assert not lights_on(look, 30.0) and lights_on(look, -1.0)
    assert lights_on(look.updated({"fog": {"visibility_m": 500.0}}), 30.0)
    assert lights_on(look.updated({"lights": {"navigation": "on"}}), 30.0)
    assert not lights_on(look.updated({"lights": {"navigation": "off"}}), -10.0)


def test_lights_change_rgb_only_and_are_reproducible():
    def frame(navigation: str):
        raw = scenario_dict(
            2, {"sun": {"elevation_deg": -4.0}, "lights": {"navigation": navigation}}, 160, 120
        )
        raw["vessels"][0]["sensors"][0]["mount"] = {"position": [-12.0, 3.0, 2.0], "yaw_deg": -10.0}
        sim = load(raw, seed=1)
        sim.run(0.5)
        images = sim.sensors["wamv/camera"].render(sim)
        sim.close()
        return images

    lit, again, dark = frame("on"), frame("on"), frame("off")
    assert all(np.array_equal(lit[k], again[k], equal_nan=True) for k in lit)
    assert np.array_equal(lit["segmentation"], dark["segmentation"])
    assert np.array_equal(lit["depth"], dark["depth"], equal_nan=True)
    assert (lit["rgb"].astype(int) - dark["rgb"]).max() > 100  # the lamps


def test_traffic_ships_carry_lights_and_leave_wakes():
    """Imazu 1, head-on: the kinematic target shows its masthead light and both sidelights to the own ship."""
    from importlib.resources import files

    import yaml

    from usvsim.rendering.frame import lamps
    from usvsim.rendering.sky import daylight

    raw = yaml.safe_load((files("usvsim.scenarios") / "imazu_01.yaml").read_text())
    raw["rendering"] = {"renderer": "shader", "sun": {"elevation_deg": -5.0}}
    sim = load(raw)
    sim.run(2.0)
    nav, pos, rot, t, intensity = lamps({}, sim, daylight(sim.look))
    own = sim.vessels["own"].position
    seen = nav.world(pos, rot, own + np.array([0.0, 0.0, 2.0]), t, intensity)
    far = seen[np.linalg.norm(seen[:, :2] - own[:2], axis=1) > 500.0]  # the target, about 1 km ahead
    assert {_key(c) for c in far[:, 3:]} == {_key(WHITE), _key(RED), _key(GREEN)}
    track = np.stack(sim.wakes.samples)  # (samples, hulls, 5): the own ship's and the target's
    assert track.shape[1] == 2 and np.all(track[:, 1, 3] > 1.5)  # the target makes 2 m/s
    sim.close()
