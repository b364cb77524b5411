"""Cameras (MuJoCo EGL offscreen): CameraInfo consistency, projection within 1 px, depth vs LiDAR, noise."""

from __future__ import annotations

import numpy as np
import pytest
from sensor_rig import make_sim, sensor_configs
from test_lidar import BOX, _box_distance, _world_points

from usvsim.config.loader import parse_scenario
from usvsim.sensors import SensorSuite
from usvsim.sensors.base import OPTICAL_ROT
from usvsim.sensors.camera.intrinsics import Intrinsics, Remap, distort, undistort

MOUNT = {"position": [0.7, 0.0, 1.2], "yaw_deg": 5.0}
DIST = {"k1": -0.15, "k2": 0.03, "p1": 0.001, "p2": -0.0015, "k3": 0.002}
CAM = {"type": "camera", "width": 320, "height": 240, "horizontal_fov_deg": 70.0, "streams": ["rgb", "depth", "segmentation"],
       "mount": MOUNT}  # fmt: skip


@pytest.fixture(scope="module")
def scene():
    sim = make_sim(objects=(BOX,))
    suite = SensorSuite(sim.world, {"wamv": sensor_configs({**CAM, "name": "pin"}, {**CAM, "name": "dist", "distortion": DIST},
                                                     {"type": "lidar", "name": "lidar", "preset": "os1_128",
                                                      "range_stddev_m": 0.0, "mount": MOUNT})})  # fmt: skip
    sim.run(0.5)
    yield sim, suite
    suite.close()


def _box_geom(sim):
    return int(np.argmax((sim.model.geom_group == 1) & (np.abs(sim.model.geom_size[:, 1] - 2.0) < 1e-9))) + 1


def _to_optical(cam, sim, world):
    pos, rot = cam.pose_world(sim)
    return (world - pos) @ (rot @ OPTICAL_ROT)


def test_strong_pincushion_has_a_ray_for_every_pixel():
    """k1 = 5 (and a mixed strong lens) at 80°: the inverse (Newton's method, core/lens.py) gives every output
    pixel a ray that the published model (OpenCV's projectPoints with the CameraInfo K and D) maps back onto that
    pixel; OpenCV's own fixed-point undistortPoints does not converge there."""
    cv2 = pytest.importorskip("cv2")
    for D in ((5.0, 0.0, 0.0, 0.0, 0.0), (0.8, 0.2, 0.004, -0.003, 0.05)):
        cam = Intrinsics.from_fov(160, 120, 80.0, D)
        rays = cam.rays().reshape(-1, 2)
        assert np.isfinite(rays).all()
        pts = np.column_stack([rays, np.ones(len(rays))])
        uv = cv2.projectPoints(pts, np.zeros(3), np.zeros(3), cam.K, np.asarray(D))[0].reshape(-1, 2)
        v, u = np.mgrid[0:120, 0:160]
        assert np.abs(uv - np.column_stack([u.ravel(), v.ravel()])).max() < 1e-6
    k1_5 = (5.0, 0.0, 0.0, 0.0, 0.0)
    cam = Intrinsics.from_fov(160, 120, 80.0, k1_5)
    corner = (np.array([[-0.5, -0.5]]) - [cam.cx, cam.cy]) / [cam.fx, cam.fy]  # the fixed-point iteration diverges
    xy = corner.copy()
    with np.errstate(all="ignore"):
        for _ in range(20):
            xy = xy + (corner - distort(xy, k1_5))
    assert not np.abs(distort(xy, k1_5) - corner).max() < 1e-6


def test_undistort_inverts_distort():
    xy = np.random.default_rng(0).uniform(-0.6, 0.6, (1000, 2))
    D = [DIST[k] for k in ("k1", "k2", "p1", "p2", "k3")]
    assert np.abs(undistort(distort(xy, D), D) - xy).max() < 1e-9


@pytest.mark.parametrize("name", ["pin", "dist"])
def test_camera_info_and_projection_within_one_pixel(scene, name):
    sim, suite = scene
    cam = suite[f"wamv/{name}"]
    envs = {e.topic: e for e in cam.sample(sim, sim.clock_ns)}
    info = envs[f"/wamv/{name}/camera_info"].msg
    seg_msg = envs[f"/wamv/{name}/segmentation/image_raw"].msg
    assert info.distortion_model == "plumb_bob" and info.header.frame_id == "wamv/" + name + "_optical"
    assert info.header.stamp == seg_msg.header.stamp and info.header.frame_id == seg_msg.header.frame_id
    K, D = np.asarray(info.k).reshape(3, 3), np.asarray(info.d)
    assert np.allclose(np.asarray(info.p).reshape(3, 4)[:, :3], K) and np.allclose(info.r, np.eye(3).ravel())
    published = Intrinsics(info.width, info.height, K[0, 0], K[1, 1], K[0, 2], K[1, 2], tuple(D))
    seg = np.frombuffer(bytes(seg_msg.data), np.uint16).reshape(info.height, info.width)
    box = _box_geom(sim)
    # points on the box's surface, from the LiDAR (independent ray caster), projected with the published info
    lidar = suite["wamv/lidar"]
    world, _ = _world_points(sim, lidar, lidar.sample(sim, 1)[0].msg)
    world = world[_box_distance(world) < 1e-3]
    uv = published.project(_to_optical(cam, sim, world))
    inside = (uv[:, 0] > 1) & (uv[:, 0] < info.width - 2) & (uv[:, 1] > 1) & (uv[:, 1] < info.height - 2)
    assert inside.sum() > 200
    u, v = np.rint(uv[inside]).astype(int).T
    window = np.stack([seg[v + dv, u + du] for dv in (-1, 0, 1) for du in (-1, 0, 1)])
    assert (window == box).any(axis=0).all()  # every projected box point has a box pixel within 1 px


@pytest.mark.parametrize("name", ["pin", "dist"])
def test_depth_back_projected_matches_lidar_surface(scene, name):
    sim, suite = scene
    cam = suite[f"wamv/{name}"]
    images = cam.render(sim)
    depth, seg = images["depth"], images["segmentation"]
    box = (seg == _box_geom(sim)) & np.isfinite(depth)
    assert box.sum() > 500
    xy = cam.intrinsics.rays()[box]
    pts_opt = np.concatenate([xy, np.ones((len(xy), 1))], axis=1) * depth[box, None]
    pos, rot = cam.pose_world(sim)
    world = pts_opt @ (rot @ OPTICAL_ROT).T + pos
    d = _box_distance(world)
    assert np.percentile(d, 99) < 0.02 and np.median(d) < 0.005
    sky = seg == 0
    assert np.isnan(depth[sky & (np.arange(depth.shape[0])[:, None] < depth.shape[0] // 3)]).all()


def test_noise_is_applied_and_seeded():
    sim = make_sim(objects=(BOX,))
    cams = sensor_configs({**CAM, "name": "clean", "streams": ["rgb", "depth"]},
                          {**CAM, "name": "noisy", "streams": ["rgb", "depth"], "rgb_noise_stddev": 0.05,
                           "depth_noise_stddev_m": 0.01})  # fmt: skip
    suite = SensorSuite(sim.world, {"wamv": cams})
    sim.step()
    try:
        a = {e.topic.split("/", 3)[-1]: e.msg for e in suite["wamv/clean"].sample(sim, 10)}
        b = {e.topic.split("/", 3)[-1]: e.msg for e in suite["wamv/noisy"].sample(sim, 10)}
    finally:
        suite.close()
    rgb_a, rgb_b = (np.frombuffer(bytes(m["image_raw"].data), np.uint8).astype(float) for m in (a, b))
    assert a["image_raw"].encoding == "rgb8" and a["depth/image_raw"].encoding == "32FC1"
    ratio = (rgb_b / np.maximum(rgb_a, 1))[rgb_a > 100]
    assert ratio.std() == pytest.approx(0.05, rel=0.15)
    da, db = (np.frombuffer(bytes(m["depth/image_raw"].data), np.float32) for m in (a, b))
    ok = np.isfinite(da)
    assert (db - da)[ok].std() == pytest.approx(0.01, rel=0.1)


@pytest.mark.parametrize("renderer", ["mujoco", "shader"])
def test_a_simulation_collected_without_close_leaves_the_others_cameras_alone(scenario_of, renderer):
    """A dropped simulation's GL objects are freed in its own GL context: MuJoCo's context freed whatever
    context was current, the other simulation's (same object ids), whose camera then drew wrong images (MuJoCo's
    look) or raised GLError (the shader look)."""
    import gc

    from usvsim.simulation import Simulation

    if renderer == "shader":
        pytest.importorskip("moderngl")
    camera = {"type": "camera", "name": "camera", "width": 96, "height": 72, "streams": ["rgb", "depth", "segmentation"],
              "mount": {"position": [0.3, 0.0, 1.3]}}  # fmt: skip
    sc = scenario_of({"name": "gc", "environment": {"sea": {"type": "sea_state", "code": 4}}, "rendering": {"renderer": renderer},
                      "vessels": [{"name": "wamv", "model": "wamv", "sensors": [camera]}],
                      "objects": [{"type": "buoy", "name": "red", "position": [12.0, 1.0, 0.0], "color": "red"}]})  # fmt: skip

    def render(sim):
        return sim.sensors["wamv/camera"].render(sim)

    dropped, kept = Simulation(sc, seed=1), Simulation(sc, seed=1)
    render(dropped)
    before = render(kept)  # the kept one's GL context is current when the other goes
    del dropped
    gc.collect()
    after = render(kept)
    for name in before:
        assert np.array_equal(before[name], after[name], equal_nan=True), name
    kept.close()


@pytest.mark.parametrize("east_m", [0.0, 900.0])
def test_plain_look_far_water_has_depth_and_colour(east_m):
    """MuJoCo's look: beyond the 120 m drawn field the still-water plane is water to `far_m`, wherever the vessel
    is. Before, the plane was a translucent 1 km square around the origin: from 10 m up its pixels had NaN depth
    and the sky painted over them (the horizon 8 degrees low), and 900 m east there was no plane at all. The plane
    is drawn under the field's troughs; its depth is the still water's, at the mean level."""
    sim = make_sim(vessel_pose={"position": [east_m, 0.0, 0.0]})
    cam_cfg = {
        **CAM,
        "name": "mast",
        "far_m": 400.0,
        "mount": {"position": [0.0, 0.0, 10.0], "pitch_deg": 8.0},
    }
    suite = SensorSuite(sim.world, {"wamv": sensor_configs(cam_cfg)})
    try:
        sim.run(0.2)
        cam = suite["wamv/mast"]
        images = cam.render(sim)
        depth, seg, rgb = images["depth"], images["segmentation"], images["rgb"]
        pos, rot = cam.pose_world(sim)
        rays = (
            np.concatenate([cam.intrinsics.rays(), np.ones((*depth.shape, 1))], axis=2)
            @ (rot @ OPTICAL_ROT).T
        )
        with np.errstate(divide="ignore"):
            expected = -pos[2] / rays[..., 2]  # optical z of the ray's hit on the still water, z = 0
        far = (rays[..., 2] < 0) & (expected > 80.0) & (expected < 0.95 * cam.cfg.far_m)  # beyond the field
        assert far.sum() > 1000
        water = {i for i, (_, cls) in cam.segmentation_ids.items() if cls == "water"}
        assert np.isin(seg[far], list(water)).all()
        assert np.isfinite(depth[far]).all()
        assert np.abs(depth[far] / expected[far] - 1.0).max() < 1e-3
        assert (rgb[far][:, 0] < 100).all()  # the water's colour, not the sky's (~240 in red)
        field = (rays[..., 2] < 0) & (expected > 20.0) & (expected < 40.0)  # the drawn field, flat sea
        seam = np.abs(np.median(rgb[far], axis=0) - np.median(rgb[field], axis=0))
        assert seam.max() <= 10  # the plane in the flat field's colour: a faint edge (was the sky, or 47 levels)
    finally:
        suite.close()


def test_plain_look_still_water_beyond_the_waves_is_at_the_mean_level():
    """With waves the plane is drawn below the field's lowest trough (here ~1 m below the mean level of 1.5 m);
    the depth of its pixels is the still water's at the mean level, so their points lie at z = 1.5 m."""
    from usvsim.simulation import Simulation

    cam = {**CAM, "name": "mast", "far_m": 400.0, "mount": {"position": [0.5, 0.0, 3.0], "pitch_deg": 15.0}}
    data = {"version": 1, "environment": {"sea": {"type": "sea_state", "code": 4}, "water_level_m": 1.5},
            "vessels": [{"name": "wamv", "model": "wamv", "pose": {"position": [0.0, 0.0, 1.5]}, "sensors": [cam]}]}  # fmt: skip
    sim = Simulation(parse_scenario(data, "test"), seed=0)
    sim.run(3.0)
    camera = sim.sensors["wamv/mast"]
    images = camera.render(sim)
    depth, seg = images["depth"], images["segmentation"]
    pos, rot = camera.pose_world(sim)
    rays = (
        np.concatenate([camera.intrinsics.rays(), np.ones((*depth.shape, 1))], axis=2) @ (rot @ OPTICAL_ROT).T
    )
    still = [i for i, (name, _) in camera.segmentation_ids.items() if name == "still_water"]
    plane = np.isin(seg, still) & np.isfinite(depth)
    assert plane.sum() > 500
    z = pos[2] + depth[plane] * rays[plane][:, 2]
    assert np.abs(z - 1.5).max() < 1e-3
    plane_z = sim.model.geom_pos[sim.model.geom("still_water").id, 2]
    assert plane_z < 1.5 - 0.3  # drawn under the troughs: the depth is not the drawn plane's


def test_a_lens_without_inverse_over_the_image_is_refused():
    """k1 = -0.25 on an 80 deg, 640x480 camera segfaulted the run: the radial term r (1 + k1 r^2) peaks at
    r = sqrt(-1 / (3 k1)) below the corners' radius, so no ray reaches them, the inverse diverged to NaN and the
    remap indexed outside the image. The threshold from that closed form: k1* = -1 / (6.75 r_c^2) = -0.135 for
    the corner pixel's normalized radius r_c; the config accepts k1 a little above it and refuses it below."""
    from usvsim.core.errors import UsvsimError

    f = 320 / np.tan(np.radians(40.0))
    r_c2 = (319.5 / f) ** 2 + (239.5 / f) ** 2
    threshold = -1.0 / (6.75 * r_c2)
    assert -0.137 < threshold < -0.133

    def scenario(k1):
        cam = {
            **CAM,
            "name": "wide",
            "width": 640,
            "height": 480,
            "horizontal_fov_deg": 80.0,
            "distortion": {"k1": k1},
        }
        data = {"version": 1, "vessels": [{"name": "wamv", "model": "wamv", "sensors": [cam]}]}
        return parse_scenario(data, "lens.yaml")

    scenario(threshold + 0.01)
    for k1 in (threshold - 0.01, -0.25):
        with pytest.raises(UsvsimError, match=r"vessels\[0\]\.sensors\[0\]: distortion has no inverse"):
            scenario(k1)
    scenario(5.0)  # strong pincushion is invertible: it was refused (the fixed-point inverse diverged there)
    remap = Remap(Intrinsics.from_fov(640, 480, 80.0, (-0.25, 0, 0, 0, 0)))  # the Python API: no config check
    assert 0 <= remap.nearest.min() and remap.nearest.max() < 640 * 480
    assert 0 <= remap.corners.min() and remap.corners.max() < 640 * 480


def test_plain_look_cameras_are_lit_by_the_sun_and_cast_shadows():
    """The camera's private MjData had its bodies posed but not its lights (no mj_camlight): the sun's direction
    was (0, 0, 0), so the sun lit nothing and `shadows: true` gave the same bytes as without; the headlight kept
    the unused free camera's direction (north and down) whatever way the camera looked."""
    sim = make_sim(objects=(BOX,))
    cams = sensor_configs({**CAM, "name": "plain", "streams": ["rgb"]},
                          {**CAM, "name": "shadowed", "streams": ["rgb"], "shadows": True})  # fmt: skip
    suite = SensorSuite(sim.world, {"wamv": cams})
    try:
        sim.run(0.3)
        plain, shadowed = suite["wamv/plain"], suite["wamv/shadowed"]
        a, b = plain.render(sim)["rgb"], shadowed.render(sim)["rgb"]
        assert (a != b).any(axis=-1).sum() > 100  # the shadows' pixels
        scene = plain.renderer.scene
        lights = [scene.lights[i] for i in range(scene.nlight)]
        sun = next(lamp for lamp in lights if not lamp.headlight)
        np.testing.assert_allclose(sun.dir, sim.data.light_xdir[0], atol=1e-6)
        head = next(lamp for lamp in lights if lamp.headlight)
        _, rot = plain.pose_world(sim)
        np.testing.assert_allclose(head.dir, (rot @ OPTICAL_ROT)[:, 2], atol=1e-6)
    finally:
        suite.close()


def test_segmentation_ids_are_named_in_a_label_info_a_ros_reader_decodes(scene, tmp_path):
    """With every segmentation image, `segmentation/label_info` (vision_msgs/LabelInfo, same stamp and frame) maps
    each pixel value to "<class>:<object>", as `segmentation_ids` does in Python; read back from an MCAP by the
    independent mcap + mcap-ros2 reader (the ids were opaque geom numbers to every ROS or bag user)."""
    from mcap.reader import make_reader
    from mcap_ros2.decoder import DecoderFactory

    from usvsim.io.mcap_recorder import McapRecorder

    sim, suite = scene
    cam = suite["wamv/pin"]
    path = tmp_path / "labels.mcap"
    with McapRecorder(path) as rec:
        for env in cam.sample(sim, sim.clock_ns):
            env.publish_ns = sim.clock_ns
            rec.write(env)
    with path.open("rb") as f:
        got = {ch.topic: (schema.name, msg) for schema, ch, _, msg in
               make_reader(f, decoder_factories=[DecoderFactory()]).iter_decoded_messages()}  # fmt: skip
    schema, info = got["/wamv/pin/segmentation/label_info"]
    seg = got["/wamv/pin/segmentation/image_raw"][1]
    assert schema == "vision_msgs/msg/LabelInfo" and info.header.frame_id == seg.header.frame_id == "wamv/pin_optical"
    assert (info.header.stamp.sec, info.header.stamp.nanosec) == (seg.header.stamp.sec, seg.header.stamp.nanosec)
    names = {c.class_id: c.class_name for c in info.class_map}
    assert names == {k: f"{cls}:{name}" for k, (name, cls) in cam.segmentation_ids.items()}
    pixels = set(np.unique(np.frombuffer(bytes(seg.data), np.uint16)).tolist()) - {0}
    assert pixels and pixels <= set(names)  # every labelled pixel is named
    assert names[_box_geom(sim)] == "box:crate" and "vessel:wamv" in names.values()
