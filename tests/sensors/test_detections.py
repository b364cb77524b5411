"""Ground-truth detections: 3D boxes equal the objects' true poses and extents; a camera's 2D boxes contain the
object's rendered pixels, match the projection of its 3D box with the published CameraInfo, and leave out
occluded objects; vision_msgs go through CDR and MCAP."""

from __future__ import annotations

import math

import numpy as np
import pytest
from readers import read_with_mcap_ros2
from sensor_rig import make_sim, sensor_configs

from usvsim.core.transforms import matrix_from_quat
from usvsim.io.mcap_recorder import McapRecorder
from usvsim.messages import ros
from usvsim.messages.envelope import Envelope
from usvsim.sensors import SensorSuite
from usvsim.sensors.base import OPTICAL_ROT
from usvsim.sensors.camera.intrinsics import Intrinsics

TARGET = {"type": "buoy", "name": "target", "position": [12.0, 0.5, 0.0], "radius_m": 0.4, "color": "red"}
HIDDEN = {"type": "buoy", "name": "hidden", "position": [30.0, 0.0, 0.0], "color": "green"}  # behind the wall
WALL = {"type": "wall", "name": "wall", "position": [22.0, 0.0, 0.5], "size": [1.0, 8.0, 4.0]}
DOCK = {"type": "dock", "name": "dock", "position": [-5.0, 25.0, -0.5], "size": [2.0, 12.0, 2.0], "yaw_deg": 30.0}
MOUNT = {"position": [0.7, 0.0, 1.2], "yaw_deg": 2.0}
DIST = {"k1": -0.15, "k2": 0.03, "p1": 0.001, "p2": -0.0015, "k3": 0.002}
CAM = {"type": "camera", "width": 320, "height": 240, "horizontal_fov_deg": 70.0, "streams": ["rgb", "segmentation"],
       "mount": MOUNT}  # fmt: skip


@pytest.fixture(scope="module")
def scene():
    sim = make_sim(objects=(TARGET, HIDDEN, WALL, DOCK))
    suite = SensorSuite(sim.world, {"wamv": sensor_configs(
        {**CAM, "name": "pin", "detections": {}}, {**CAM, "name": "dist", "distortion": DIST, "detections": {}},
        {**CAM, "name": "vis", "detections": {"box": "visible", "include_own_vessel": True}},
        {"type": "detections", "name": "detections_3d"},
        {"type": "detections", "name": "local", "frame": "sensor", "mount": MOUNT, "range_max_m": 40.0})})  # fmt: skip
    sim.run(0.5)
    yield sim, suite
    suite.close()


def _camera_frame(sim, suite, name):
    cam = suite[f"wamv/{name}"]
    envs = {e.topic: e.msg for e in cam.sample(sim, sim.clock_ns)}
    info, seg_msg = envs[f"/wamv/{name}/camera_info"], envs[f"/wamv/{name}/segmentation/image_raw"]
    seg = np.frombuffer(bytes(seg_msg.data), np.uint16).reshape(info.height, info.width)
    dets = {d.id: d for d in envs[f"/wamv/{name}/detections"].detections}
    return cam, info, seg, dets, envs[f"/wamv/{name}/detections"]


def _box(det):
    c, sx, sy = det.bbox.center.position, det.bbox.size_x, det.bbox.size_y
    return np.array([c.x - sx / 2, c.y - sy / 2, c.x + sx / 2, c.y + sy / 2])


def _pixels_of(sim, seg, body_name):
    body = sim.model.body(body_name).id
    labels = np.flatnonzero(sim.model.geom_bodyid == body) + 1
    v, u = np.nonzero(np.isin(seg, labels))
    return u, v


def _true_box_3d(sim, suite, object_id):
    envs = suite["wamv/detections_3d"].sample(sim, sim.clock_ns)
    return {d.id: d for d in envs[0].msg.detections}[object_id]


def test_3d_boxes_equal_true_pose_and_extent(scene):
    sim, suite = scene
    env = suite["wamv/detections_3d"].sample(sim, sim.clock_ns)[0]
    assert env.topic == "/wamv/detections_3d" and env.msg.header.frame_id == "world"
    dets = {d.id: d for d in env.msg.detections}
    assert set(dets) == {"target", "hidden", "wall", "dock"}  # not the own vessel by default
    buoy = dets["target"]
    index = sim.model.body("target").id - 1
    c = buoy.bbox.center.position
    assert np.allclose([c.x, c.y, c.z], sim.state.pos[index], atol=1e-9)  # the sphere's centre, moving with it
    assert np.allclose([buoy.bbox.size.x, buoy.bbox.size.y, buoy.bbox.size.z], 0.8, atol=1e-9)
    assert buoy.results[0].hypothesis.class_id == "buoy_red" and buoy.results[0].hypothesis.score == 1.0
    dock = dets["dock"]
    p, q, s = dock.bbox.center.position, dock.bbox.center.orientation, dock.bbox.size
    assert np.allclose([p.x, p.y, p.z], DOCK["position"]) and np.allclose([s.x, s.y, s.z], DOCK["size"])
    yaw = math.radians(DOCK["yaw_deg"])
    assert abs(abs(q.w * math.cos(yaw / 2) + q.z * math.sin(yaw / 2)) - 1.0) < 1e-9
    assert dets["dock"].results[0].hypothesis.class_id == "dock"


def test_3d_boxes_in_sensor_frame_and_range(scene):
    sim, suite = scene
    local = suite["wamv/local"]
    env = local.sample(sim, sim.clock_ns)[0]
    assert env.msg.header.frame_id == "wamv/local"
    dets = {d.id: d for d in env.msg.detections}
    assert "target" in dets and "dock" in dets and "hidden" in dets  # all within 40 m
    pos, rot = local.pose_world(sim)
    for name, det in dets.items():
        p, q = det.bbox.center.position, det.bbox.center.orientation
        world = _true_box_3d(sim, suite, name).bbox.center
        assert np.allclose(rot @ [p.x, p.y, p.z] + pos, [world.position.x, world.position.y, world.position.z])
        axes = rot @ matrix_from_quat(np.array([q.w, q.x, q.y, q.z]))
        wq = world.orientation
        assert np.allclose(axes, matrix_from_quat(np.array([wq.w, wq.x, wq.y, wq.z])), atol=1e-9)


@pytest.mark.parametrize("name", ["pin", "dist"])
def test_2d_box_contains_pixels_and_matches_projection(scene, name):
    sim, suite = scene
    cam, info, seg, dets, _ = _camera_frame(sim, suite, name)
    assert set(dets) == {"target", "wall"}  # hidden is behind the wall, the dock is out of view, no own vessel
    det = dets["target"]
    box = _box(det)
    u, v = _pixels_of(sim, seg, "target")
    assert len(u) > 50
    assert box[0] <= u.min() and box[1] <= v.min() and u.max() <= box[2] and v.max() <= box[3]
    # independent projection of the 3D box's corners with the published CameraInfo
    K = np.asarray(info.k).reshape(3, 3)
    published = Intrinsics(info.width, info.height, K[0, 0], K[1, 1], K[0, 2], K[1, 2], tuple(info.d))
    truth = _true_box_3d(sim, suite, "target").bbox
    c, s, q = truth.center.position, truth.size, truth.center.orientation
    signs = np.array([[a, b, d] for a in (-1, 1) for b in (-1, 1) for d in (-1, 1)])
    axes = matrix_from_quat(np.array([q.w, q.x, q.y, q.z]))
    corners = np.array([c.x, c.y, c.z]) + (signs * np.array([s.x, s.y, s.z]) / 2) @ axes.T
    pos, rot = cam.pose_world(sim)
    uv = published.project((corners - pos) @ (rot @ OPTICAL_ROT))
    expected = np.array([uv[:, 0].min(), uv[:, 1].min(), uv[:, 0].max(), uv[:, 1].max()])
    assert np.abs(box - expected).max() < 1.0
    assert det.results[0].hypothesis.class_id == "buoy_red" and det.header.frame_id == f"wamv/{name}_optical"


def test_visible_boxes_are_tight_and_include_own_vessel_on_request(scene):
    sim, suite = scene
    _, info, seg, dets, msg = _camera_frame(sim, suite, "vis")
    assert {"target", "wall", "wamv"} <= set(dets) and "hidden" not in dets
    u, v = _pixels_of(sim, seg, "target")
    assert np.allclose(_box(dets["target"]), [u.min() - 0.5, v.min() - 0.5, u.max() + 0.5, v.max() + 0.5])
    assert msg.header.stamp == dets["target"].header.stamp


def test_vision_msgs_roundtrip_cdr_and_mcap(scene, tmp_path):
    sim, suite = scene
    assert ros.typestore() is ros.typestore() and "vision_msgs/msg/Detection3DArray" in ros.typestore().types
    envs = [e for e in suite["wamv/pin"].sample(sim, sim.clock_ns) if e.topic.endswith("detections")]
    envs += suite["wamv/detections_3d"].sample(sim, sim.clock_ns)
    for env in envs:
        back = Envelope(env.topic, env.stamp_ns, cdr=env.cdr, msgtype=env.msgtype).decoded()
        assert [d.id for d in back.detections] == [d.id for d in env.msg.detections]
    path = tmp_path / "detections.mcap"
    with McapRecorder(path) as rec:
        for env in envs:
            rec.write(env)
    decoded = read_with_mcap_ros2(path)  # an independent decoder, from the schema text in the file
    assert {t for t, _, _ in decoded} == {"/wamv/pin/detections", "/wamv/detections_3d"}
    three_d = next(m for t, _, m in decoded if t == "/wamv/detections_3d")
    assert {d.id for d in three_d.detections} == {"target", "hidden", "wall", "dock"}
    assert three_d.detections[0].bbox.size.x > 0
