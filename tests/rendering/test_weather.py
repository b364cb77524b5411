"""Camera weather: rain streaks, lens droplets and motion blur are reproducible, RGB-only, and do what they say."""

from __future__ import annotations

import numpy as np
import pytest

from usvsim.rendering.weather import blur_along, extinction_per_m, lens_droplets, motion_field, rain_streaks


def _scene() -> np.ndarray:
    rng = np.random.default_rng(0)
    img = np.zeros((120, 160, 3), np.uint8)
    img[:60] = (170, 180, 200)  # sky
    img[60:] = (30, 50, 70) + rng.integers(0, 20, (60, 160, 3))  # sea
    return img


def test_rain_is_reproducible_per_frame_time_and_off_at_zero():
    a, b, c, dry = _scene(), _scene(), _scene(), _scene()
    rain_streaks(a, 10.0, 10.0, 100.0, 3, "/wamv/camera", 1_000_000_000)
    rain_streaks(b, 10.0, 10.0, 100.0, 3, "/wamv/camera", 1_000_000_000)
    rain_streaks(c, 10.0, 10.0, 100.0, 3, "/wamv/camera", 1_100_000_000)
    rain_streaks(dry, 0.0, 10.0, 100.0, 3, "/wamv/camera", 1_000_000_000)
    assert np.array_equal(a, b) and not np.array_equal(a, c)
    assert np.array_equal(dry, _scene())
    lit = a.astype(int).sum(axis=2) - _scene().astype(int).sum(axis=2)
    assert (lit[60:] > 10).mean() > 0.01  # streaks brighten the dark sea
    heavy = _scene()
    rain_streaks(heavy, 50.0, 10.0, 100.0, 3, "/wamv/camera", 1_000_000_000)
    assert (heavy != _scene()).mean() > (a != _scene()).mean()  # more rain, more streaks


def test_rain_extinction_gives_the_visibility_of_rain():
    assert 3.912 / extinction_per_m(10.0) == pytest.approx(3660.0, rel=0.01)  # 0.25 R^0.63 per km
    assert extinction_per_m(0.0) == 0.0


def test_droplets_persist_between_frames_and_come_and_go():
    a, b, later = _scene(), _scene(), _scene()
    lens_droplets(a, 0.5, 3, "/wamv/camera", 10.0)
    lens_droplets(b, 0.5, 3, "/wamv/camera", 10.1)
    lens_droplets(later, 0.5, 3, "/wamv/camera", 40.0)
    changed = (a != _scene()).any(axis=2)
    assert 0.01 < changed.mean() < 0.6
    assert np.array_equal(a, b)  # a tenth of a second later: the same drops
    assert not np.array_equal(a, later)  # half a minute later: some dried, others came


def test_motion_blur_spreads_along_the_flow_and_keeps_the_light():
    img = np.zeros((40, 60, 3), np.uint8)
    img[20, 30] = 240
    h, w = img.shape[:2]
    blur_along(img, np.full((h, w), 8.0, np.float32), np.zeros((h, w), np.float32))
    row = img[20, :, 0].astype(int)
    assert (row > 0).sum() == 8 and img[:, :, 0].sum() == pytest.approx(240, abs=8)
    assert img[19].sum() == 0 and img[21].sum() == 0  # horizontal flow: no vertical smear
    still = _scene()
    far = np.full(still.shape[:2], np.inf)  # the sky: at infinity
    blur_along(still, *motion_field(far, np.zeros(3), np.zeros(3), 500.0, 500.0, 0.0, 0.0, 0.03))
    assert np.array_equal(still, _scene())
    du, dv = motion_field(np.full((1, 1), np.inf), np.zeros(3), np.array([0.0, 0.5, 0.0]), 400.0, 400.0, 0.0, 0.0,
                          0.02)  # fmt: skip
    assert (float(du[0, 0]), float(dv[0, 0])) == pytest.approx((-4.0, 0.0))  # yawing: sideways at the centre


def test_camera_weather_changes_rgb_only():
    pytest.importorskip("moderngl")
    from usvsim.rendering.gallery import load, scenario_dict

    def frame(look):
        raw = scenario_dict(3, look, 160, 120)
        raw["objects"] = []
        sim = load(raw, seed=2)
        sim.run(0.5)
        images = sim.sensors["wamv/camera"].render(sim)
        sim.close()
        return images

    wet = frame({"rain": {"rate_mm_h": 20.0}, "camera": {"droplets": 0.8, "motion_blur_ms": 40.0}})
    again = frame({"rain": {"rate_mm_h": 20.0}, "camera": {"droplets": 0.8, "motion_blur_ms": 40.0}})
    dry = frame({})
    assert all(np.array_equal(wet[k], again[k], equal_nan=True) for k in wet)
    assert np.array_equal(wet["segmentation"], dry["segmentation"])
    assert np.array_equal(wet["depth"], dry["depth"], equal_nan=True)
    assert not np.array_equal(wet["rgb"], dry["rgb"])


def _project(points: np.ndarray, fx: float, fy: float, cx: float, cy: float) -> np.ndarray:
    return np.stack([fx * points[:, 0] / points[:, 2] + cx, fy * points[:, 1] / points[:, 2] + cy], axis=1)


@pytest.mark.parametrize(
    "v, omega",
    [((1.5, 0.0, 0.0), (0.0, 0.0, 0.0)), ((0.0, -0.4, 3.0), (0.0, 0.0, 0.0)), ((0.0, 0.0, 0.0), (0.3, 0.0, 0.0)),
     ((0.0, 0.0, 0.0), (0.0, 0.0, 0.8)), ((2.0, 0.5, 4.0), (0.2, -0.3, 0.5))],
)  # fmt: skip
def test_motion_field_is_the_motion_of_projected_points(v, omega):
    """Against an independent reference: back-project pixels at depth Z, move the camera for a short dt (its
    rotation exact, scipy), project again; the flow over dt scaled to the exposure matches `motion_field`."""
    from scipy.spatial.transform import Rotation

    from usvsim.rendering.weather import motion_field

    fx, fy, cx, cy, z, exposure, dt = 400.0, 380.0, 79.5, 59.5, 7.0, 0.03, 1e-4
    depth = np.full((120, 160), z, np.float32)
    du, dv = motion_field(depth, v, omega, fx, fy, cx, cy, exposure)
    pixels = np.array([[10.0, 7.0], [79.5, 59.5], [150.0, 110.0], [30.0, 100.0], [140.0, 12.0]])
    points = np.stack([(pixels[:, 0] - cx) / fx * z, (pixels[:, 1] - cy) / fy * z, np.full(len(pixels), z)], axis=1)
    # the camera moves by v dt and turns by omega dt (its own frame): a static point in the new camera frame
    turn = Rotation.from_rotvec(np.array(omega) * dt).as_matrix()
    moved = (points - np.array(v) * dt) @ turn  # R^T (P - v dt), row vectors
    flow = (_project(moved, fx, fy, cx, cy) - pixels) / dt * exposure
    got = np.stack([du[pixels[:, 1].astype(int), pixels[:, 0].astype(int)],
                    dv[pixels[:, 1].astype(int), pixels[:, 0].astype(int)]], axis=1)  # fmt: skip
    # integer pixel lookup: the pixel centre is within 0.5 px of the reference point (cx, cy at .5 here)
    ref = np.stack([(np.floor(pixels[:, 0]) - cx) / fx, (np.floor(pixels[:, 1]) - cy) / fy], axis=1)
    pts = np.stack([ref[:, 0] * z, ref[:, 1] * z, np.full(len(ref), z)], axis=1)
    flow = (_project((pts - np.array(v) * dt) @ turn, fx, fy, cx, cy) - _project(pts, fx, fy, cx, cy)) / dt * exposure
    assert got == pytest.approx(flow, abs=2e-3 + 2e-3 * np.abs(flow).max())


def test_translation_blurs_along_the_image_flow_and_rest_is_untouched():
    from usvsim.rendering.weather import blur_along, motion_field

    fx = fy = 200.0
    cx, cy = 59.5, 39.5
    depth = np.full((80, 120), 10.0, np.float32)

    def dots() -> np.ndarray:
        img = np.zeros((80, 120, 3), np.uint8)
        for r, c in ((40, 60), (40, 100), (10, 60)):  # the centre, right of it, above it
            img[r, c] = 240
        return img

    # sideways (optical +x, to the right) at 20 m/s for 50 ms, all 10 m away: the image flows left by 200·1/10 px
    side = dots()
    du, dv = motion_field(depth, (20.0, 0.0, 0.0), (0.0, 0.0, 0.0), fx, fy, cx, cy, 0.05)
    assert np.allclose(du, -20.0) and np.allclose(dv, 0.0)
    blur_along(side, du, dv)
    assert (side[40, 45:75, 0] > 0).sum() == 20 and (side[40, 85:115, 0] > 0).sum() == 20  # horizontal streaks
    assert side[39].sum() == 0 and side[41].sum() == 0 and side[9].sum() == 0 and side[11].sum() == 0  # none vertical
    # forward (optical +z) at 20 m/s: radial flow from the principal point, none at the centre
    ahead = dots()
    du, dv = motion_field(depth, (0.0, 0.0, 20.0), (0.0, 0.0, 0.0), fx, fy, cx, cy, 0.05)
    blur_along(ahead, du, dv)
    right = ahead[:, 80:, 0] > 0
    assert right.any() and np.array_equal(np.unique(np.nonzero(right)[0]), [40])  # the right dot: along its row
    above = ahead[:25, 50:70, 0] > 0
    assert above.sum() > 3 and np.array_equal(np.unique(np.nonzero(above)[1]), [10])  # the upper one: its column
    assert ahead[40, 60, 0] == 240 and ahead[40, 55:58].sum() == 0 and ahead[40, 62:66].sum() == 0  # the centre stays
    # roll about the optical axis: the right dot moves vertically, the upper one horizontally
    roll = dots()
    du, dv = motion_field(depth, (0.0, 0.0, 0.0), (0.0, 0.0, 2.0), fx, fy, cx, cy, 0.05)
    blur_along(roll, du, dv)
    assert np.array_equal(np.unique(np.nonzero(roll[:, 80:, 0])[1]), [20])  # column 100: a vertical streak
    # at rest: the same bytes as without blur, wherever the depth is (the sky: NaN)
    still = _scene()
    sky = np.where(np.arange(120)[:, None] < 60, np.nan, 12.0) * np.ones((1, 160), np.float32)
    blur_along(still, *motion_field(sky.astype(np.float32), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), 100.0, 100.0, 80, 60, 0.04))
    assert np.array_equal(still, _scene())
    # translation leaves the sky (at infinity) sharp and smears the sea
    moving = _scene()
    du, dv = motion_field(sky.astype(np.float32), (6.0, 0.0, 0.0), (0.0, 0.0, 0.0), 100.0, 100.0, 80, 60, 0.04)
    blur_along(moving, du, dv)
    assert np.array_equal(moving[:60], _scene()[:60]) and not np.array_equal(moving[60:], _scene()[60:])


def test_motion_blur_of_a_vessel_under_way_changes_rgb_only_and_none_at_rest():
    pytest.importorskip("moderngl")
    from usvsim.rendering.gallery import load, scenario_dict

    raw = scenario_dict(0, {}, 160, 120)
    raw["objects"] = []
    sim = load(raw, seed=2)
    camera = sim.sensors["wamv/camera"]
    try:
        sim.run(10.0)  # dropped onto the calm sea at its pose: settled after ~10 s

        def both():
            sim.look = sim.look.updated({"camera": {"motion_blur_ms": 0.0}})
            sharp = camera.render(sim)
            sim.look = sim.look.updated({"camera": {"motion_blur_ms": 60.0}})
            return sharp, camera.render(sim)

        speed = float(np.linalg.norm(sim.state.vcom_world[camera.body]))
        sharp, blurred = both()
        assert speed < 0.01 and all(np.array_equal(sharp[k], blurred[k], equal_nan=True) for k in sharp)
        sim.vessels["wamv"].command(1.0, 0.0)
        sim.run(8.0)
        assert float(np.linalg.norm(sim.state.vcom_world[camera.body])) > 1.0
        sharp, blurred = both()
        assert np.array_equal(sharp["segmentation"], blurred["segmentation"])
        assert np.array_equal(sharp["depth"], blurred["depth"], equal_nan=True)
        assert not np.array_equal(sharp["rgb"], blurred["rgb"])
        model = sim.model
        root = model.body_rootid[model.body("wamv").id]
        own = np.isin(blurred["segmentation"], np.flatnonzero(model.body_rootid[model.geom_bodyid] == root) + 1)
        # its pontoons move with it: their own velocity cancels the camera's (no mask: the motion field's sum)
        assert own.sum() > 100 and np.array_equal(sharp["rgb"][own], blurred["rgb"][own])
        water = ~own & np.isfinite(blurred["depth"]) & (blurred["depth"] < 30.0)  # near water smears
        assert (sharp["rgb"][water] != blurred["rgb"][water]).any(axis=-1).mean() > 0.1
        again = camera.render(sim)
        assert np.array_equal(again["rgb"], blurred["rgb"])  # reproducible
    finally:
        sim.close()


def test_a_vessel_crossing_a_camera_at_rest_blurs_alone():
    """The Otter under way in front of the WAM-V's camera at rest: its pixels smear with its own motion and it
    sweeps over the still scene beside it, no farther than half its image motion during the exposure; the rest
    of the scene (at rest, seen from a camera at rest) keeps its bytes."""
    from scipy import ndimage

    pytest.importorskip("moderngl")
    from usvsim.rendering.gallery import load, scenario_dict

    raw = scenario_dict(0, {}, 320, 240)
    raw["objects"] = []
    sim = load(raw, seed=2)
    camera = sim.sensors["wamv/camera"]
    try:
        sim.run(6.0)  # both settle on the calm sea (dropped at their poses)
        sim.vessels["otter"].command(1.0, 0.0)
        sim.run(1.5)  # the Otter gets under way, westward across the view
        assert float(np.linalg.norm(sim.state.vcom_world[camera.body])) < 0.01
        assert float(np.linalg.norm(sim.state.vcom_world[sim.vessels["otter"].index])) > 0.5
        sim.look = sim.look.updated({"camera": {"motion_blur_ms": 0.0}})
        sharp = camera.render(sim)
        sim.look = sim.look.updated({"camera": {"motion_blur_ms": 80.0}})
        blurred = camera.render(sim)
        model = sim.model
        root = model.body_rootid[model.body("otter").id]
        otter = np.isin(sharp["segmentation"], np.flatnonzero(model.body_rootid[model.geom_bodyid] == root) + 1)
        assert otter.sum() > 50
        changed = (sharp["rgb"] != blurred["rgb"]).any(axis=-1)
        assert changed[otter].mean() > 0.2  # the Otter smears
        speed = float(np.linalg.norm(sim.state.vcom_world[sim.vessels["otter"].index]))
        reach = 0.5 * speed * 0.080 * camera.intrinsics.fx / float(np.nanmin(sharp["depth"][otter]))  # px
        spill = changed & ~otter
        assert spill.sum() > 10  # it sweeps over the water beside it
        distance = ndimage.distance_transform_edt(~otter)  # px to the nearest Otter pixel
        assert distance[spill].max() <= reach + 1.5  # and nowhere farther: the rest keeps its bytes
    finally:
        sim.close()


def test_a_moving_box_gives_its_exposure_ramps_and_a_still_one_stays_sharp():
    """Closed form: a box (grey 200, 5 m away) moving L = 16 px right during the exposure over a still background
    (grey 40, 50 m): at a pixel x (frame at mid-exposure, box on [a, b]) the box is seen for the part of the
    exposure s in [-L/2, L/2] with a + s <= x <= b + s, so the row is 40 + 160 * |[x - b, x - a] ∩ [-L/2, L/2]| / L:
    ramps of width L centred on both edges, on the box and beside it. The other way round (the box still, the
    background moving): the box keeps its bytes and its colour does not bleed into the background."""
    h, w, a, b, length = 24, 96, 40, 55, 16.0
    box = np.zeros((h, w), bool)
    box[6:18, a : b + 1] = True
    img = np.where(box[..., None], 200, 40).astype(np.uint8).repeat(3, axis=2)
    depth = np.where(box, 5.0, 50.0).astype(np.float32)
    moving = img.copy()
    ids = box.astype(np.int32)  # the box one label, the background another
    blur_along(moving, np.where(box, length, 0.0).astype(np.float32), np.zeros((h, w), np.float32), depth, ids)
    x = np.arange(w, dtype=float)
    # pixel x spans [x - 0.5, x + 0.5]: the box's edges at a - 0.5 and b + 0.5
    seen = np.clip(np.minimum(x - (a - 0.5), length / 2) - np.maximum(x - (b + 0.5), -length / 2), 0, None) / length
    expected = 40 + 160 * seen
    row = moving[12, :, 0].astype(float)
    assert np.abs(row - expected).max() <= 160 / length + 1  # within one pixel's share of the ramp
    assert np.abs(row - expected).mean() < 2.0
    assert np.array_equal(moving[:5], img[:5])  # rows the box does not cross keep their bytes
    still = img.copy()
    blur_along(still, np.where(box, 0.0, length).astype(np.float32), np.zeros((h, w), np.float32), depth, ids)
    assert np.array_equal(still[box], img[box])  # the still box is sharp
    assert (still[~box][:, 0] == 40).all()  # the background passing behind it takes none of its colour
    old = img.copy()  # without depth and labels (the blur along each pixel's flow): the background is untouched
    blur_along(old, np.where(box, length, 0.0).astype(np.float32), np.zeros((h, w), np.float32))
    assert (old[~box][:, 0] == 40).all()
