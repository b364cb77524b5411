"""Frustum culling of the scene's geoms (rendering/cull.py): which geoms a view skips. That the frames keep their
bytes is checked on the harbour in tests/viewer/test_rendering.py."""

from __future__ import annotations

import mujoco
import numpy as np

from usvsim.rendering.cull import FrustumCull, frustum_planes

# a fixed camera at the origin looking along +x (fovy 45°); spheres ahead, behind, at and beyond the left edge
XML = """
<mujoco>
  <visual><global fovy="45"/></visual>
  <worldbody>
    <camera name="eye" pos="0 0 0" xyaxes="0 -1 0 0 0 1"/>
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


def test_nothing_is_culled_while_shadows_are_drawn():
    _, scene, cull = scene_and_cull(shadows=True)
    assert cull(1600, 900) == 0  # the sun sees what the camera does not


def test_planes_point_into_the_view():
    _, scene, _ = scene_and_cull()
    planes = frustum_planes(scene.camera[0], 1600, 900)
    ahead = planes[:, :3] @ np.array([10.0, 0.0, 0.0]) + planes[:, 3]
    assert (ahead > 0).all()
    left = planes[:, :3] @ np.array([10.0, 7.7, 0.0]) + planes[:, 3]  # inside only by the 5 % widening
    assert (left > 0).all()
    assert (planes[:, :3] @ np.array([10.0, 8.0, 0.0]) + planes[:, 3] < 0).any()


def test_a_camera_culls_and_keeps_its_bytes():
    """The onboard camera (640x480, shader look): RGB, depth and labels the same with and without culling."""
    import pytest

    pytest.importorskip("moderngl")
    from usvsim.rendering.gallery import load, scenario_dict

    sim = load(scenario_dict(4, {"fog": {"visibility_m": 2000.0}}, 320, 240))
    sim.run(3.0)  # the mooring lines are drawn in segments by then
    camera = sim.sensors["wamv/camera"]
    culled = camera.render(sim)
    renderer = camera.renderer
    scene, none = renderer.scene, int(mujoco.mjtGeom.mjGEOM_NONE)
    count = sum(int(scene.geoms[i].type) == none for i in range(scene.ngeom))
    renderer._cull = lambda width, height: 0
    full = camera.render(sim)
    sim.close()
    assert count > 40  # mooring-line segments behind and beside the boat (62 of them)
    for stream in ("rgb", "depth", "segmentation"):
        assert np.array_equal(culled[stream], full[stream], equal_nan=True), stream
