"""2D boxes of partly visible objects: the projected 3D box clipped against the view frustum equals an independent
reference (OpenCV's projectPoints of densely sampled box faces, kept where in front of the camera and inside
the image), and in a rendered frame a wall crossing the image edge or reaching behind the camera gets the box
of its rendered pixels."""

from __future__ import annotations

import numpy as np
import pytest
from sensor_rig import make_sim, sensor_configs

from usvsim.sensors import SensorSuite
from usvsim.sensors.camera.clip import camera_planes, image_box
from usvsim.sensors.camera.intrinsics import Intrinsics

cv2 = pytest.importorskip("cv2")
NEAR = 0.05
SIGNS = np.array([[a, b, c] for a in (-1, 1) for b in (-1, 1) for c in (-1, 1)], dtype=float)


def _corners(center, size, rot=None):
    rot = np.eye(3) if rot is None else rot
    return np.asarray(center, float) + (SIGNS * np.asarray(size, float) / 2) @ rot.T


def _planes(cam):
    return camera_planes(cam, NEAR)


def _reference(corners, cam, spacing_m=0.02, most=1000):
    """Bounds of OpenCV-projected samples of the box's faces that lie in front of the camera and in the image."""
    c0, ex, ey, ez = corners[0], corners[4] - corners[0], corners[2] - corners[0], corners[1] - corners[0]
    faces = []
    for e1, e2, e3 in ((ex, ey, ez), (ey, ez, ex), (ez, ex, ey)):
        n1, n2 = (min(most, int(np.linalg.norm(e) / spacing_m) + 2) for e in (e1, e2))
        a, b = (g.reshape(-1, 1) for g in np.meshgrid(np.linspace(0, 1, n1), np.linspace(0, 1, n2)))
        for off in (0.0, 1.0):
            faces.append(c0 + off * e3 + a * e1 + b * e2)
    pts = np.concatenate(faces)
    pts = pts[pts[:, 2] > NEAR]
    uv, _ = cv2.projectPoints(pts, np.zeros(3), np.zeros(3), cam.K, np.asarray(cam.D))
    uv = uv.reshape(-1, 2)
    inside = (
        (uv[:, 0] >= -0.5)
        & (uv[:, 0] <= cam.width - 0.5)
        & (uv[:, 1] >= -0.5)
        & (uv[:, 1] <= cam.height - 0.5)
    )
    if not inside.any():
        return None
    uv = uv[inside]
    return np.array([uv[:, 0].min(), uv[:, 1].min(), uv[:, 0].max(), uv[:, 1].max()])


CASES = {  # optical frame: z forward, x right, y down (m)
    "in_view": ((0.5, 0.2, 8.0), (1.0, 1.0, 1.0)),
    "wall_across_left_edge": ((-6.0, 0.0, 10.0), (6.0, 2.0, 0.5)),
    "half_behind_camera": ((2.0, 0.5, 0.0), (1.0, 1.0, 20.0)),
    "low_wall_along_view_reaching_behind": ((4.0, 1.5, 0.0), (0.5, 0.3, 16.0)),
    "above_and_beside_corner": ((-9.0, -7.0, 10.0), (4.0, 4.0, 2.0)),
}


@pytest.mark.parametrize("case", list(CASES))
def test_clipped_box_equals_opencv_reference(case):
    cam = Intrinsics.from_fov(640, 480, 90.0)
    corners = _corners(*CASES[case])
    box, ref = image_box(corners, cam, _planes(cam)), _reference(corners, cam)
    assert box is not None and ref is not None
    assert np.all(box[:2] <= ref[:2] + 1e-6) and np.all(ref[2:] <= box[2:] + 1e-6), (box, ref)
    assert np.abs(box - ref).max() < 3.0, (
        box,
        ref,
    )  # the samples' spacing (up to ~3 px 1.5 m from the camera)
    if case in EXACT:  # by hand: f = 320 px, c = (319.5, 239.5), extreme points on the image edge x/z = 1
        assert np.allclose(box, EXACT[case], atol=1e-6)


EXACT = {"half_behind_camera": [320 * 1.5 / 10 + 319.5, 239.5, 639.5, 320 * 1.0 / 1.5 + 239.5],
         "low_wall_along_view_reaching_behind": [320 * 3.75 / 8 + 319.5, 320 * 1.35 / 8 + 239.5, 639.5,
                                                 320 * 1.65 / 3.75 + 239.5]}  # fmt: skip


def test_random_boxes_match_reference_and_unseen_ones_are_none():
    rng = np.random.default_rng(3)
    cams = [
        Intrinsics.from_fov(320, 240, 80.0),
        Intrinsics.from_fov(320, 240, 70.0, (-0.15, 0.03, 0.001, -0.0015, 0.002)),
    ]
    for i in range(24):
        cam = cams[i % 2]
        q = rng.normal(size=4)
        rot = cv2.Rodrigues(q[:3] / np.linalg.norm(q[:3]) * rng.uniform(0, np.pi))[0]
        center, size = rng.uniform([-8, -6, -2], [8, 6, 15]), rng.uniform(0.3, 8.0, 3)
        if np.all(
            np.abs(rot.T @ center) < size / 2 + 1.0
        ):  # the camera inside or within 1 m: samples too sparse
            continue
        corners = _corners(center, size, rot)
        box, ref = image_box(corners, cam, _planes(cam)), _reference(corners, cam, spacing_m=0.04, most=250)
        if ref is None:
            assert box is None or min(box[2] - box[0], box[3] - box[1]) < 2.0
            continue
        assert box is not None and np.all(box[:2] <= ref[:2] + 1e-6) and np.all(ref[2:] <= box[2:] + 1e-6), (
            i,
            box,
            ref,
        )
        assert np.abs(box - ref).max() < 3.0, (
            i,
            box,
            ref,
        )  # the samples' spacing, up to ~2 px near the camera
    assert image_box(_corners((0.0, 0.0, -5.0), (2.0, 2.0, 2.0)), cams[0], _planes(cams[0])) is None  # behind


WALL_EDGE = {"type": "wall", "name": "edge_wall", "position": [15.0, 9.0, 2.0], "size": [1.0, 10.0, 2.0]}
WALL_BESIDE = {"type": "wall", "name": "side_wall", "position": [2.0, -5.0, 2.2], "size": [30.0, 0.5, 1.6]}
CAM = {"type": "camera", "name": "cam", "width": 320, "height": 240, "horizontal_fov_deg": 80.0,
       "streams": ["segmentation"], "mount": {"position": [0.7, 0.0, 1.5]}, "detections": {}}  # fmt: skip


@pytest.mark.parametrize("distortion", [None, {"k1": -0.1, "k2": 0.02}])
def test_rendered_walls_cut_by_edge_and_camera_get_their_pixels_box(distortion):
    sim = make_sim(objects=(WALL_EDGE, WALL_BESIDE))
    cfg = {**CAM, **({"distortion": distortion} if distortion else {})}
    suite = SensorSuite(sim, {"wamv": sensor_configs(cfg)})
    try:
        cam = suite["wamv/cam"]
        envs = {e.topic: e.msg for e in cam.sample(sim, sim.clock_ns)}
        seg = np.frombuffer(bytes(envs["/wamv/cam/segmentation/image_raw"].data), np.uint16).reshape(240, 320)
        dets = {d.id: d for d in envs["/wamv/cam/detections"].detections}
        assert {"edge_wall", "side_wall"} <= set(dets)
        for name in ("edge_wall", "side_wall"):
            obj = next(o for o in cam.boxes.objects if o.name == name)
            v, u = np.nonzero(np.isin(seg, obj.geoms + 1))
            pixels = np.array([u.min() - 0.5, v.min() - 0.5, u.max() + 0.5, v.max() + 0.5])
            d = dets[name].bbox
            box = np.array([d.center.position.x - d.size_x / 2, d.center.position.y - d.size_y / 2,
                            d.center.position.x + d.size_x / 2, d.center.position.y + d.size_y / 2])  # fmt: skip
            assert np.abs(box - pixels).max() <= 1.5, (name, box, pixels)
        assert dets["side_wall"].bbox.size_y < 200  # a low wall, not the full image height
    finally:
        suite.close()
