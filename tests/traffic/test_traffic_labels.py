"""Traffic ships are labelled objects: class `vessel`, named as in `traffic.ships`, in a camera's segmentation_ids,
its 2D detections (boxes holding the ship's pixels), the 3D detections (box centred on the ship's track) and the
data set labels (YOLO/COCO/masks), their boxes moving with the kinematic ship."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
import yaml
from PIL import Image

from usvsim.datasets.generate import DatasetSpec, generate
from usvsim.datasets.labels import CLASSES, DETECTABLE
from usvsim.datasets.rerender import labels_of, rerender
from usvsim.sensors.base import OPTICAL_ROT
from usvsim.sensors.camera.intrinsics import Intrinsics
from usvsim.simulation import Simulation

L, B, H, DRAFT = 20.0, 6.0, 4.0, 1.5  # the ferry: length, beam, hull top above the waterline, draft (m)
START, SPEED = (50.0, -4.0), 2.0  # ENU m at t = 0; north (course 0) at m/s, across the own ship's bow
CAM = {"type": "camera", "name": "cam", "width": 320, "height": 240, "horizontal_fov_deg": 70.0,
       "streams": ["rgb", "segmentation"], "mount": {"position": [0.7, 0.0, 1.2]}}  # fmt: skip


def _scenario(sensors):
    return {"version": 1, "name": "ship_labels", "world": {"physics_rate_hz": 100},
            "vessels": [{"name": "wamv", "model": "wamv", "command_timeout_s": 0.0, "sensors": sensors}],  # east
            "traffic": {"ais": {"enabled": False}, "ships": [
                {"name": "ferry", "mmsi": 257000001, "ship_type": "passenger", "length_m": L, "beam_m": B,
                 "height_m": H, "draft_m": DRAFT,
                 "motion": {"type": "constant", "position": list(START), "course_deg": 0.0, "speed_mps": SPEED}}]}}  # fmt: skip


def _track(t):
    return np.array([START[0], START[1] + SPEED * t])


def _ferry_ids(sim):
    return {g + 1 for g in range(sim.model.ngeom) if sim.model.geom(g).name.startswith("kinematic/ferry/")}


@pytest.fixture(scope="module")
def run():
    from usvsim.config.loader import parse_scenario

    sensors = [{**CAM, "detections": {}}, {"type": "detections", "name": "detections_3d"}]
    sim = Simulation(parse_scenario(_scenario(sensors), "test"))
    got = []
    sim.subscribe(got.append)
    sim.run(1.0)
    yield sim, got
    sim.close()


def _last(got, topic):
    return [e for e in got if e.topic == topic][-1]


def test_segmentation_ids_and_2d_detection_name_the_ship(run):
    sim, got = run
    ids = sim.sensors["wamv/cam"].segmentation_ids
    ferry = _ferry_ids(sim)
    assert len(ferry) == 2 and all(ids[i] == ("ferry", "vessel") for i in ferry)  # hull and deckhouse
    seg_env = _last(got, "/wamv/cam/segmentation/image_raw")
    seg = np.frombuffer(bytes(seg_env.msg.data), np.uint16).reshape(240, 320)
    det_env = _last(got, "/wamv/cam/detections")
    assert det_env.stamp_ns == seg_env.stamp_ns
    dets = {d.id: d for d in det_env.msg.detections}
    assert set(dets) == {"ferry"}
    det = dets["ferry"]
    assert det.results[0].hypothesis.class_id == "vessel"
    v, u = np.nonzero(np.isin(seg, list(ferry)))
    assert len(u) > 200  # about 22 deg wide, 5 deg high at 50 m in a 70 deg, 320 px image
    c, sx, sy = det.bbox.center.position, det.bbox.size_x, det.bbox.size_y
    box = np.array([c.x - sx / 2, c.y - sy / 2, c.x + sx / 2, c.y + sy / 2])  # pixel-centre coordinates
    assert box[0] <= u.min() and box[1] <= v.min() and u.max() <= box[2] and v.max() <= box[3]
    # the box projected from the ship's 3D box (amodal): its hull below the waterline reaches below the pixels
    assert box[3] > v.max() + 1.0


def test_3d_detection_is_centred_on_the_ship_track(run):
    """The box is the tight box of the ship's geoms in its frame: the hull prism spans x in [-L/2, L/2] (pointed
    bow at +L/2) and y in [-B/2, B/2] about midship, z from -draft to the deckhouse's top at 1.5 H. So its centre
    is the track's position (x, y) and (1.5 H - draft) / 2 up; the hull's mesh vertices are float32 (about 1e-6 m
    at 10 m), hence 1e-4 m."""
    sim, got = run
    for env in [e for e in got if e.topic == "/wamv/detections_3d"][-3:]:  # moving with the ship, step by step
        t = env.stamp_ns / 1e9
        det = {d.id: d for d in env.msg.detections}["ferry"]
        c, s, q = det.bbox.center.position, det.bbox.size, det.bbox.center.orientation
        assert det.results[0].hypothesis.class_id == "vessel"
        np.testing.assert_allclose([c.x, c.y], _track(t), atol=1e-4)
        assert c.z == pytest.approx((1.5 * H - DRAFT) / 2, abs=1e-4)
        np.testing.assert_allclose([s.x, s.y, s.z], [L, B, 1.5 * H + DRAFT], atol=1e-4)
        assert abs(2 * math.atan2(q.z, q.w) - math.pi / 2) < 1e-6  # heading north: ENU yaw 90 deg
    fleet = sim.traffic.fleet
    assert env.stamp_ns == sim.clock_ns
    np.testing.assert_allclose(fleet.pos_enu[0], [c.x, c.y], atol=1e-4)  # the fleet's state agrees


def test_dataset_labels_name_the_ship(tmp_path):
    cam = {**CAM, "streams": ["rgb"]}
    scenario = tmp_path / "ship_labels.yaml"
    scenario.write_text(yaml.safe_dump(_scenario([cam])))
    spec = DatasetSpec(str(scenario), 2, tmp_path / "ds", seed=3, splits=(1.0, 0.0, 0.0), settle_s=1.0,
                       frame_interval_s=0.5, workers=1)  # fmt: skip
    root = generate(spec)
    coco = json.loads((root / "annotations" / "train.json").read_text())
    names = {c["id"]: c["name"] for c in coco["categories"]}
    anns = coco["annotations"]
    assert len(anns) == 2
    for ann in anns:
        assert names[ann["category_id"]] == "vessel" and ann["object"] == "ferry"
        image = next(i for i in coco["images"] if i["id"] == ann["image_id"])
        stem = image["file_name"].rsplit("/", 1)[-1].rsplit(".", 1)[0]
        instance = np.array(Image.open(root / "masks" / "instance" / image["file_name"]))
        semantic = np.array(Image.open(root / "masks" / "semantic" / image["file_name"]))
        v, u = np.nonzero(instance == ann["instance"])
        assert len(u) == ann["area"] and len(u) > 200
        assert np.all(semantic[v, u] == CLASSES.index("vessel"))
        x, y, w, h = ann["bbox"]
        assert x <= u.min() and y <= v.min() and u.max() + 1 <= x + w and v.max() + 1 <= y + h
        ax, ay, aw, ah = ann["amodal_bbox"]
        assert ax <= x and ay <= y and x + w <= ax + aw and y + h < ay + ah  # amodal: the hull below the water
        yolo = (root / "labels" / "train" / f"{stem}.txt").read_text().split()
        assert DETECTABLE[int(yolo[0])] == "vessel"
        # the amodal box is the ship's box where its track puts it at the frame's time, projected with the
        # camera's pinhole model (pixel centres at integers; the box's edges half a pixel out)
        meta = json.loads((root / "meta" / f"{stem}.json").read_text())
        assert meta["time_s"] == pytest.approx(1.0)  # a new episode every frame: reset, then settle_s
        signs = np.array([[a, b, d] for a in (-1, 1) for b in (-1, 1) for d in (-1, 1)])
        corners = np.r_[_track(meta["time_s"]), 0.0] + signs * [B / 2, L / 2, 0.0] + [0.0, 0.0, (1.5 * H - DRAFT) / 2]
        corners[:, 2] += signs[:, 2] * (1.5 * H + DRAFT) / 2  # heading north: the ship's x along ENU y
        pos, rot = np.array(meta["camera_position_m"]), np.array(meta["camera_rotation_flu_to_world"]) @ OPTICAL_ROT
        uv = Intrinsics.from_fov(320, 240, 70.0).project((corners - pos) @ rot)
        expected = [uv[:, 0].min() + 0.5, uv[:, 1].min() + 0.5, uv[:, 0].max() + 0.5, uv[:, 1].max() + 0.5]
        np.testing.assert_allclose([ax, ay, ax + aw, ay + ah], expected, atol=0.05)
    # re-rendered from its metadata (the clock set by hand), the frame has the ship where it was: same labels
    again = rerender(root, stem)
    assert again["labels"] == labels_of(meta) and np.array_equal(again["instance"], instance)
    assert np.array_equal(again["rgb"], np.array(Image.open(root / "images" / image["file_name"])))
