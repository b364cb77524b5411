"""Frustum culling of the scene's geoms (rendering/cull.py): which geoms a view skips. That the frames keep their
bytes is checked on the harbour in tests/viewer/test_rendering.py."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

from usvsim.rendering.cull import FrustumCull, frustum_planes

# a fixed camera at the origin looking along +x (fovy 45°); spheres ahead, behind, at and beyond the left edge
XML = """
<mujoco>
  <visual><global fovy="45"/></visual>
  <worldbody>
    <camera name="eye" pos="0 0 0" xyaxes="0 -1 0 0 0 1"/>
    <light name="sun" pos="0 0 30" dir="0 0 -1" directional="true" castshadow="false"/>
    <geom name="ahead" type="sphere" pos="10 0 0" size="0.5"/>
    <geom name="behind" type="sphere" pos="-10 0 0" size="0.5"/>
    <geom name="edge" type="sphere" pos="10 7.9 0" size="1"/>
    <geom name="beyond" type="sphere" pos="10 12 0" size="1"/>
    <geom name="long_capsule" type="capsule" fromto="-10 0 -1 10 0 -1" size="0.1"/>
    <geom name="box_below" type="box" pos="3 0 -20" size="1 1 1"/>
    <geom name="plane_behind" type="plane" pos="-50 0 0" size="5 5 0.1"/>
  </worldbody>
</mujoco>
"""


def scene_and_cull(shadows: bool = False):
    model = mujoco.MjModel.from_xml_string(XML)
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    scene = mujoco.MjvScene(model, maxgeom=50)
    camera = mujoco.MjvCamera()
    camera.type, camera.fixedcamid = mujoco.mjtCamera.mjCAMERA_FIXED, 0
    mujoco.mjv_updateScene(model, data, mujoco.MjvOption(), None, camera, mujoco.mjtCatBit.mjCAT_ALL, scene)
    scene.flags[mujoco.mjtRndFlag.mjRND_SHADOW] = int(shadows)
    scene.flags[mujoco.mjtRndFlag.mjRND_REFLECTION] = 0  # both are on in a new scene
    return model, scene, FrustumCull(scene)


def culled_names(model, scene) -> set[str]:
    none = int(mujoco.mjtGeom.mjGEOM_NONE)
    return {model.geom(scene.geoms[i].objid).name for i in range(scene.ngeom) if int(scene.geoms[i].type) == none}


def test_only_geoms_wholly_outside_the_view_are_culled():
    model, scene, cull = scene_and_cull()
    # 16:9: the half width at 10 m is 10 tan(22.5°) 16/9 = 7.36 m, so the sphere at y = 7.9 (r 1) reaches into view
    assert cull(1600, 900) == 3
    assert culled_names(model, scene) == {"behind", "beyond", "box_below"}  # planes are never culled


def sun_along(scene, direction) -> None:
    """The scene's one light (after the headlight) directional, casting shadows, shining along `direction`."""
    lamp = scene.lights[scene.nlight - 1]
    assert not lamp.headlight
    lamp.type, lamp.castshadow = mujoco.mjtLightType.mjLIGHT_DIRECTIONAL, 1
    lamp.dir[:] = np.asarray(direction, float) / np.linalg.norm(direction)


def test_with_shadows_only_geoms_whose_shadow_stays_out_of_view_are_culled():
    """A geom out of view still darkens what the camera sees if the sun's rays carry its shadow into the view."""
    model, scene, cull = scene_and_cull(shadows=True)
    sun_along(scene, (1.0, 0.0, -0.2))  # low, from behind the camera: the shadow of "behind" falls ahead, in view
    assert cull(1600, 900) == 0
    model, scene, cull = scene_and_cull(shadows=True)
    sun_along(scene, (1.0, 0.0, -1.0))  # 45° high: it passes under the view (22.5° down at its edge), as box_below's
    assert cull(1600, 900) == 2
    assert culled_names(model, scene) == {"behind", "box_below"}
    model, scene, cull = scene_and_cull(shadows=True)
    sun_along(scene, (-1.0, 1.0, -1.0))  # from ahead and the right: "behind" and "beyond" shade nothing in view
    assert cull(1600, 900) == 3
    assert culled_names(model, scene) == {"behind", "beyond", "box_below"}
    model, scene, cull = scene_and_cull(shadows=True)
    sun_along(scene, (-1.0, 1.0, -1.0))
    scene.lights[scene.nlight - 1].type = mujoco.mjtLightType.mjLIGHT_SPOT  # a spot casting shadows: they spread, nothing is culled
    assert cull(1600, 900) == 0


def test_planes_point_into_the_view():
    _, scene, _ = scene_and_cull()
    planes = frustum_planes(scene.camera[0], 1600, 900)
    ahead = planes[:, :3] @ np.array([10.0, 0.0, 0.0]) + planes[:, 3]
    assert (ahead > 0).all()
    left = planes[:, :3] @ np.array([10.0, 7.7, 0.0]) + planes[:, 3]  # inside only by the 5 % widening
    assert (left > 0).all()
    assert (planes[:, :3] @ np.array([10.0, 8.0, 0.0]) + planes[:, 3] < 0).any()


@pytest.mark.parametrize("shadows", [False, True])
def test_a_camera_culls_and_keeps_its_bytes(shadows):
    """The onboard camera (shader look, with and without the sun's shadows): RGB, depth and labels the same with and
    without culling."""
    pytest.importorskip("moderngl")
    from usvsim.rendering.gallery import load, scenario_dict

    sim = load(scenario_dict(4, {"fog": {"visibility_m": 2000.0}, "shadows": shadows}, 320, 240))
    sim.run(3.0)  # the mooring lines are drawn in segments by then
    camera = sim.sensors["wamv/camera"]
    culled = camera.render(sim)
    renderer = camera.renderer
    scene, none = renderer.scene, int(mujoco.mjtGeom.mjGEOM_NONE)
    count = sum(int(scene.geoms[i].type) == none for i in range(scene.ngeom))
    renderer._cull = lambda width, height: 0
    full = camera.render(sim)
    sim.close()
    assert count > (20 if shadows else 40)  # mooring-line segments behind and beside the boat (62 of them)
    for stream in ("rgb", "depth", "segmentation"):
        assert np.array_equal(culled[stream], full[stream], equal_nan=True), stream
