"""Camera sensor: RGB (rgb8), depth (32FC1, REP 118) and segmentation (16UC1) images + CameraInfo.

Frames: mounted at `<vessel>/<name>` (FLU, looking along +x); images and CameraInfo are in
`<vessel>/<name>_optical` (z forward, x right, y down). Topics under `/<vessel>/<name>/`:
`image_raw` + `camera_info`, `depth/image_raw` + `depth/camera_info`, `segmentation/image_raw` +
`segmentation/label_info` (vision_msgs/LabelInfo: each id's "<class>:<object>", with every frame); all share one
stamp. Depth is metres along the optical z axis; NaN = no surface within `far_m` (sky),
and depth noise is added per pixel as N(0, depth_noise_stddev_m²). RGB noise is multiplicative:
out = clip(in·(1 + σ n)), n ~ N(0, 1) per pixel and channel. Segmentation holds MuJoCo geom id + 1 (0 =
background); no noise, no blending. With `detections`, `<topic>/detections` carries ground-truth 2D boxes
(vision_msgs/Detection2DArray, camera/boxes2d.py) with the same stamp and frame. The water surface is the
ocean's own height field (world/water_visual), refreshed around the vessel before each frame and uploaded to
GL only when it changed. With the shader look (`sim.look`, docs/rendering.md) the image also carries the
look's exposure, vignetting and blur, and its `camera.noise_stddev` adds to `rgb_noise_stddev`.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import mujoco
import numpy as np

from usvsim.messages.envelope import Envelope
from usvsim.messages.ros import image_msg
from usvsim.sensors.base import OPTICAL_ROT, Sensor
from usvsim.sensors.camera.boxes2d import BoxMaker
from usvsim.sensors.camera.intrinsics import Intrinsics, Remap
from usvsim.sensors.camera.kernels import apply_factors, rgb_gain_noise, vignette_factors
from usvsim.sensors.camera.render import PinholeRenderer, RenderContext
from usvsim.sensors.detections import selected, shared_objects
from usvsim.sensors.messages import camera_info_msg, detection_array_msg, label_classes, label_info_msg

if TYPE_CHECKING:
    from usvsim.config.sensors import Camera as CameraConfig
    from usvsim.world.world import World

GL_KEY = "camera/gl"  # the suite's one RenderContext in `shared`, closed by SensorSuite.close()


def lens_effects(rgb: np.ndarray, camera_look, intrinsics: Intrinsics, cache: dict | None = None) -> None:
    """In place: defocus blur, exposure (2^EV) and vignetting of an RGB image (config/rendering.CameraLook).
    `cache` (a dict the caller keeps) holds the exposure-vignetting factors between frames of the same look."""
    if camera_look.blur_sigma_px > 0:
        from scipy.ndimage import gaussian_filter

        rgb[:] = gaussian_filter(rgb, sigma=(camera_look.blur_sigma_px, camera_look.blur_sigma_px, 0), mode="nearest")
    if camera_look.exposure_ev != 0 or camera_look.vignetting > 0:
        k = intrinsics
        key = (rgb.shape[:2], camera_look.exposure_ev, camera_look.vignetting, k.fx, k.fy, k.cx, k.cy)
        cache = {} if cache is None else cache
        if cache.get("key") != key:
            cache["key"], cache["factors"] = key, vignette_factors(rgb.shape[0], rgb.shape[1],
                2.0**camera_look.exposure_ev, camera_look.vignetting, np.array([k.fx, k.fy, k.cx, k.cy]))  # fmt: skip
        apply_factors(rgb, cache["factors"])


class Camera(Sensor):
    cfg: CameraConfig

    optical = True

    def __init__(self, cfg: CameraConfig, vessel: str, sim: World, shared: dict):
        super().__init__(cfg, vessel, sim)
        d = cfg.distortion
        self.intrinsics = Intrinsics.from_fov(cfg.width, cfg.height, cfg.horizontal_fov_deg, (d.k1, d.k2, d.p1, d.p2, d.k3))
        self.remap = Remap(self.intrinsics) if self.intrinsics.distorted else None
        render_cam = self.remap.render if self.remap else self.intrinsics
        if GL_KEY not in shared:
            shared[GL_KEY] = RenderContext(sim.model, cfg.width, cfg.height)
        self.renderer = PinholeRenderer(sim.model, render_cam, cfg.near_m, cfg.far_m, cfg.shadows, cfg.fog, shared[GL_KEY])
        self.streams = set(cfg.streams)
        self.segmentation_ids: dict[int, tuple[str, str]] = {}  # segmentation id → (object name, class)
        if "segmentation" in self.streams:
            objects = shared_objects(sim, shared)
            self.segmentation_ids = {int(g) + 1: (o.name, o.label) for o in objects for g in o.geoms}
            for name in ("water_surface", "still_water"):  # the drawn waves, and the plane beyond them (plain look)
                geom = mujoco.mj_name2id(sim.model, mujoco.mjtObj.mjOBJ_GEOM, name)
                if geom >= 0:
                    self.segmentation_ids[geom + 1] = (name, "water")
        self._label_classes = label_classes(self.segmentation_ids)  # segmentation/label_info's class map
        self.boxes = None
        if cfg.detections is not None:  # 2D ground truth needs the segmentation pass, published or not
            objects = selected(shared_objects(sim, shared), cfg.detections, vessel)
            self.boxes = BoxMaker(cfg.detections, objects, sim.model, self.intrinsics, cfg.near_m)
        self._rgb_normal = np.empty((cfg.height, cfg.width, 3) if cfg.rgb_noise_stddev > 0 else 0, np.float32)
        self._lens: dict = {}  # exposure-vignetting factors of the current look (lens_effects)
        self._body_of_label: np.ndarray | None = None  # segmentation label → simulated body (motion blur)
        self._depth_normal = np.empty((cfg.height, cfg.width) if cfg.depth_noise_stddev_m > 0 else 0, np.float32)

    def render(self, sim: World, pose=None, streams=None, water: bool = True) -> dict[str, np.ndarray]:
        """Images of the current state: 'rgb' (H, W, 3) uint8, 'depth' (H, W) float32 m, 'segmentation' uint16
        (the configured `streams`, and segmentation when detections need it); `pose` (position ENU m, FLU →
        world rotation) replaces the mounted camera's. `water=False`: a segmentation without the shader's water
        (PinholeRenderer.capture; MuJoCo's water geom is hidden like any geom, by its alpha)."""
        pos, rot = pose if pose is not None else self.pose_world(sim)
        streams = self.streams if streams is None else set(streams)
        r = self.renderer
        center = sim.state.pos[self.body, :2]
        r.use_marine(sim, center)
        if self.cfg.water_surface and r.marine is None:  # centred on the vessel: its cameras share one upload per tick
            r.context.refresh_water(sim, center)
        r.update(sim.data.qpos, pos, rot @ OPTICAL_ROT)
        blur = r.marine is not None and "rgb" in streams and sim.look.camera.motion_blur_ms > 0  # needs the labels
        images = r.capture(rgb_depth=bool(streams & {"rgb", "depth"}),
                           segmentation="segmentation" in streams or self.boxes is not None or blur,
                           water=water)  # fmt: skip
        out = {k: v for k, v in images.items() if k in streams or k == "segmentation"}
        if self.remap is not None:
            out = {k: (self.remap.linear(v) if k == "rgb" else self.remap.closest(v)) for k, v in out.items()}
        if "rgb" in out and r.marine is not None:  # the shader look includes the camera's exposure and lens
            depth = out.get("depth", images.get("depth"))
            if depth is not None and "depth" not in out and self.remap is not None:
                depth = self.remap.closest(depth)
            self._weather(out["rgb"], sim, pos, rot, depth, out.get("segmentation"))
            lens_effects(out["rgb"], sim.look.camera, self.intrinsics, self._lens)
        return out

    def _weather(self, rgb: np.ndarray, sim, pos: np.ndarray, rot: np.ndarray, depth: np.ndarray | None,
                 labels: np.ndarray | None) -> None:  # fmt: skip
        """Motion blur, rain and lens droplets of the look (usvsim.rendering.weather), when it has any. The camera
        frame's velocity is its vessel's rigid-body motion at the camera's position `pos` (ENU, m); pixels of
        simulated bodies (`labels`: the segmentation image) add their body's motion at their surface point, so
        the camera's own vessel, moving with it, stays sharp."""
        look = sim.look
        if look.camera.motion_blur_ms <= 0 and look.rain.rate_mm_h <= 0 and look.camera.droplets <= 0:
            return
        from usvsim.rendering.weather import camera_weather

        s, b = sim.state, self.body
        omega_world = s.rot[b] @ s.omega_body[b]
        v_world = sim.point_velocity(b, pos)
        to_optical = (rot @ OPTICAL_ROT).T
        k = self.intrinsics
        moving = None
        if labels is not None and depth is not None and look.camera.motion_blur_ms > 0:
            moving = self._moving_points(sim, labels, depth, pos, to_optical)
        if labels is not None:  # for the blur's layers: the water, like the sky, is the background (label 0)
            from usvsim.rendering.frame import water_label

            labels = np.where(labels == water_label(sim.model), 0, labels)
        camera_weather(rgb, look, (k.fx, k.fy, k.cx, k.cy), sim.seed, self.topic, sim.clock.now_ns, depth,
                       to_optical @ v_world, to_optical @ omega_world, moving, labels)  # fmt: skip

    def _moving_points(self, sim, labels: np.ndarray, depth: np.ndarray, pos: np.ndarray, to_optical: np.ndarray):
        """(rows, cols, velocity (n, 3) in the optical frame, m/s) of the pixels that show a simulated body (its
        geoms and those of bodies under it): the rigid body's velocity at the pixel's surface point,
        v_com + ω × (P - com), from the same state as the camera's own motion."""
        model = sim.model
        if self._body_of_label is None:  # label (geom id + 1) → state index of its simulated body, -1: none
            root_state = np.full(model.nbody, -1, np.int64)
            for body in sim.bodies.values():
                root_state[model.body(body.name).id] = body.index
            self._body_of_label = np.concatenate([[-1], root_state[model.body_rootid[model.geom_bodyid]]])
        lut = self._body_of_label
        which = lut[labels.astype(np.int64)]  # labels are geom ids + 1 (0: background)
        rows, cols = np.nonzero((which >= 0) & np.isfinite(depth))
        b = which[rows, cols]
        k = self.intrinsics
        z = depth[rows, cols].astype(np.float64)
        p_optical = np.stack([(cols - k.cx) / k.fx * z, (rows - k.cy) / k.fy * z, z], axis=1)
        point = pos + p_optical @ to_optical  # world (to_optical.T maps optical → world)
        return rows, cols, sim.point_velocity(b, point) @ to_optical.T

    def _noisy(self, images: dict[str, np.ndarray], look=None) -> dict[str, np.ndarray]:
        c = self.cfg
        stddev = float(np.hypot(c.rgb_noise_stddev, look.camera.noise_stddev if look is not None else 0.0))
        if "rgb" in images and stddev > 0:
            if self._rgb_normal.shape != images["rgb"].shape:
                self._rgb_normal = np.empty(images["rgb"].shape, np.float32)
            self.rng.standard_normal(dtype=np.float32, out=self._rgb_normal)  # buffers reused every frame
            rgb_gain_noise(images["rgb"], self._rgb_normal, np.float32(stddev))
        if "depth" in images and c.depth_noise_stddev_m > 0:
            self.rng.standard_normal(dtype=np.float32, out=self._depth_normal)
            images["depth"] += np.float32(c.depth_noise_stddev_m) * self._depth_normal
        return images

    def sample(self, sim: World, stamp_ns: int) -> list[Envelope]:
        images = self._noisy(self.render(sim), getattr(sim, "look", None))
        frame, base, cam = self.optical_frame_id, self.topic, self.intrinsics
        info = camera_info_msg(stamp_ns, frame, cam.width, cam.height, cam.K, cam.D)
        out = []
        if "rgb" in self.streams:
            out += [Envelope(f"{base}/image_raw", stamp_ns, image_msg(stamp_ns, frame, images["rgb"], "rgb8")),
                    Envelope(f"{base}/camera_info", stamp_ns, info)]  # fmt: skip
        if "depth" in self.streams:
            out += [Envelope(f"{base}/depth/image_raw", stamp_ns, image_msg(stamp_ns, frame, images["depth"], "32FC1")),
                    Envelope(f"{base}/depth/camera_info", stamp_ns, info)]  # fmt: skip
        if "segmentation" in self.streams:
            seg = image_msg(stamp_ns, frame, images["segmentation"], "16UC1")
            out += [Envelope(f"{base}/segmentation/image_raw", stamp_ns, seg),
                    Envelope(f"{base}/segmentation/label_info", stamp_ns,
                             label_info_msg(stamp_ns, frame, self._label_classes))]  # fmt: skip
        if self.boxes is not None:
            out.append(Envelope(f"{base}/detections", stamp_ns, self._detections(sim, images["segmentation"], stamp_ns)))
        return out

    def _detections(self, sim: World, seg: np.ndarray, stamp_ns: int):
        pos, rot = self.pose_world(sim)
        frame = self.optical_frame_id
        assert self.boxes is not None, "called only with detections configured"
        boxes = self.boxes.detections(sim, seg, pos, rot @ OPTICAL_ROT, stamp_ns, frame)
        return detection_array_msg(stamp_ns, frame, boxes, 2)
