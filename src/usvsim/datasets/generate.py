"""Generates a labelled data set from a scenario's cameras with domain randomization (`usvsim dataset`).

Run: the randomization's `environment` values are drawn once and merged into the scenario, which is built
without its sensors (only the dataset's cameras render, and only the frames written). Episode: the
simulation is reset, the scene and look values are drawn, buoys and each camera's vessel are moved by the drawn
offsets, and physics runs `settle_s`; later frames of the episode follow `frame_interval_s` apart. Frame:
each camera renders RGB, depth and segmentation from its (jittered) pose under the drawn look; masks and
labels come from the segmentation (datasets/labels.py); the look's image effects, masks and files
(datasets/writers.py) are done by worker threads. One generator seeded with `seed` draws every value in a
fixed order: the same seed gives the same bytes.
"""

from __future__ import annotations

import math
import numbers
from collections import deque
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from dataclasses import asdict, dataclass
from functools import partial
from pathlib import Path
from typing import TYPE_CHECKING, Any, cast

import mujoco
import numpy as np
import yaml
from pydantic import ValidationError

from usvsim.config.loader import parse_scenario, resolve
from usvsim.core.errors import ScenarioError, UsvsimError
from usvsim.core.transforms import quat_from_rpy, quat_multiply
from usvsim.datasets.amodal import AmodalCounter
from usvsim.datasets.fog_sight import FogSight
from usvsim.datasets.labels import Labeller
from usvsim.datasets.look import LookAdapter
from usvsim.datasets.randomization import (
    check_scene,
    draw,
    draw_all,
    load_randomization,
    nested,
    support_ends,
)
from usvsim.datasets.writers import (
    COCO_SEGMENTATIONS,
    FORMATS,
    SPLITS,
    YOLO_LABELS,
    DatasetWriter,
    WriteError,
)
from usvsim.sensors.base import OPTICAL_ROT
from usvsim.sensors.camera.clip import camera_planes
from usvsim.sensors.camera.sensor import Camera
from usvsim.sensors.objects import catalogue
from usvsim.simulation import Simulation

if TYPE_CHECKING:
    from usvsim.config.sensors import Camera as CameraConfig


@dataclass(frozen=True)
class DatasetSpec:
    scenario: str
    frames: int
    out: Path
    formats: tuple[str, ...] = FORMATS
    seed: int = 0
    randomize: str | None = None  # preset name or YAML file
    resolution: tuple[int, int] | None = None  # (width, height) for every camera; None: the scenario's
    splits: tuple[float, float, float] = (0.8, 0.1, 0.1)
    min_visible_pixels: int = 20
    min_visible_fraction: float = 0.0
    settle_s: float = 0.5
    frame_interval_s: float = 0.2
    workers: int = 2
    horizontal_fov_deg: float | None = None  # for every camera; None: the scenario's
    amodal_masks: bool = True  # visible_fraction from amodal masks (extra passes); False: box area ratio
    renderer: str | None = None  # "shader" (the marine look) or "mujoco" for every camera; None: the scenario's
    coco_segmentation: str = "rle"  # COCO `segmentation`: "rle" (uncompressed), "compressed_rle" or "polygon"
    yolo_labels: str = "box"  # YOLO label lines: "box" (class cx cy w h) or "segment" (class and the polygon)

    def __post_init__(self):
        if isinstance(self.formats, str):  # "yolo,coco" was taken letter by letter
            object.__setattr__(self, "formats", tuple(f.strip() for f in self.formats.split(",")))
        object.__setattr__(self, "out", Path(self.out))  # a str made generate() return a str
        bad = set(self.formats) - set(FORMATS)
        if bad or not self.formats:
            raise UsvsimError(f"--format: unknown {sorted(bad)}; choose from {', '.join(FORMATS)}")
        for key in ("frames", "seed"):  # 1.5 frames was a TypeError, seed -1 numpy's 'expected non-negative integer'
            value = getattr(self, key)
            if isinstance(value, bool) or not isinstance(value, numbers.Integral) or value < (1 if key == "frames" else 0):
                raise UsvsimError(f"{key} must be a whole number >= {1 if key == 'frames' else 0}, got {value!r}")
            object.__setattr__(self, key, int(value))  # numpy's int64 failed writing dataset.json, after the frames
        if (len(self.splits) != 3 or not all(math.isfinite(f) and f >= 0 for f in self.splits)
                or abs(sum(self.splits) - 1.0) > 1e-9):  # fmt: skip
            raise UsvsimError(f"splits must be three non-negative fractions (train, val, test) summing to 1, "
                              f"got {tuple(self.splits)}")  # fmt: skip
        for key in ("settle_s", "frame_interval_s"):
            value = getattr(self, key)
            if not (isinstance(value, numbers.Real) and math.isfinite(value) and float(value) >= 0):
                raise UsvsimError(f"{key} must be a finite number of seconds >= 0, got {value!r}")
        if self.resolution and not all(isinstance(n, numbers.Integral) and 8 <= n <= 4096 for n in self.resolution):
            raise UsvsimError(
                f"--resolution {self.resolution[0]}x{self.resolution[1]}: width and height are 8-4096 px"
            )
        if self.resolution:
            object.__setattr__(self, "resolution", (int(self.resolution[0]), int(self.resolution[1])))
        if not 0.0 <= self.min_visible_fraction <= 1.0:  # NaN fails too
            raise UsvsimError(f"--min-visible-fraction must be in [0, 1], got {self.min_visible_fraction}")
        if self.coco_segmentation not in COCO_SEGMENTATIONS:
            raise UsvsimError(f"--coco-segmentation: {self.coco_segmentation!r} is not one of "
                              f"{', '.join(COCO_SEGMENTATIONS)}")  # fmt: skip
        if self.yolo_labels not in YOLO_LABELS:
            raise UsvsimError(f"--yolo-labels: {self.yolo_labels!r} is not one of {', '.join(YOLO_LABELS)}")
        if self.yolo_labels != "box" and "yolo" not in self.formats:  # it would write nothing
            raise UsvsimError(f"--yolo-labels {self.yolo_labels} needs yolo in --format (got {','.join(self.formats)})")
        if self.renderer not in (None, "shader", "mujoco"):
            raise UsvsimError(f"--renderer: {self.renderer!r} is not one of shader, mujoco")
        if self.min_visible_pixels < 0:
            raise UsvsimError(f"--min-visible-pixels must be >= 0, got {self.min_visible_pixels}")


def _scenario(spec: DatasetSpec, environment: dict, drawn: str = "the drawn values make"):
    """The scenario with the drawn environment merged in, sensors removed; and its camera configs. `drawn` names
    the environment values in an error they cause."""
    text, base = resolve(spec.scenario)
    data = yaml.safe_load(text)
    env = data.setdefault("environment", {})
    for key, value in nested(environment).items():
        env[key] = (
            {**env[key], **value} if isinstance(value, dict) and key in env and "type" not in value else value
        )
    if spec.renderer:
        data["rendering"] = {**(data.get("rendering") or {}), "renderer": spec.renderer}
    cameras = []
    for v in data.get("vessels", []):
        for s in v.pop("sensors", []) or []:
            if s.get("type") == "camera":
                s = {**s, "streams": ["rgb", "depth", "segmentation"], "detections": None}  # the scenario's rate: a
                # forced 10 Hz was no whole number of steps at 128 Hz physics (a ValueError traceback); frames are
                # rendered on demand, so the rate changes nothing else
                if spec.resolution:
                    s["width"], s["height"] = spec.resolution
                if spec.horizontal_fov_deg:
                    s["horizontal_fov_deg"] = spec.horizontal_fov_deg
                cameras.append((v["name"], s))
    if not cameras:
        raise UsvsimError(f"scenario {spec.scenario}: no camera sensor to render a data set from")
    try:
        return parse_scenario(data, spec.scenario, base), cameras
    except ScenarioError as exc:  # blamed the scenario file for a key the randomization's environment set
        if environment and exc.key_path.startswith("environment"):
            raise UsvsimError(f"randomization {spec.randomize}: environment: {drawn} the scenario's "
                              f"{exc.key_path} invalid: {exc.message}") from None  # fmt: skip
        raise


def _move(sim: Simulation, body_index: int, dx: float, dy: float, dyaw_rad: float) -> None:
    """Shift a floating body horizontally and turn it about world z (its free joint's qpos)."""
    adr = sim.model.jnt_qposadr[sim.model.body_jntadr[body_index + 1]]
    sim.data.qpos[adr : adr + 2] += (dx, dy)
    turn = quat_from_rpy(0.0, 0.0, dyaw_rad)
    sim.data.qpos[adr + 3 : adr + 7] = quat_multiply(turn, sim.data.qpos[adr + 3 : adr + 7])


def draw_scene(scene: dict, buoys: list[str], rng: np.random.Generator, randomize: str | None = None,
               vessels: tuple[str, ...] = ()) -> dict:  # fmt: skip
    """Concrete scene values: per buoy [dx, dy], per camera vessel [dx, dy] and yaw (each vessel its own draws),
    and the camera jitter (0 where not given); a UsvsimError naming the key when a draw (a normal without clip)
    falls outside its bounds. With one vessel the draws are those of the first version (same seed, same set)."""

    def one(key):
        if key not in scene:
            return 0.0
        value = cast(float, draw(scene[key], rng))  # a number: the file's scene values are checked at load
        try:
            check_scene(key, value)
        except ValueError as exc:
            raise UsvsimError(f"randomization {randomize}: {exc} (drawn; give the normal a clip: [low, high])") from None
        return value

    out: dict[str, Any] = {"buoy_offset_m": {b: [one("buoy_offset_m"), one("buoy_offset_m")] for b in buoys}}
    out["vessel_offset_m"] = {v: [one("vessel_offset_m"), one("vessel_offset_m")] for v in vessels}
    out["vessel_yaw_deg"] = {v: one("vessel_yaw_deg") for v in vessels}
    for key in ("camera_height_m", "camera_pitch_deg"):
        out[key] = one(key)
    return out


def apply_scene(sim: Simulation, values: dict) -> None:
    """Moves the buoys and every camera's vessel by drawn scene values (only the first camera's vessel moved: a
    second vessel's camera saw its own vessel and the scene from the same place every frame, qa20)."""
    for name, (dx, dy) in values["buoy_offset_m"].items():
        _move(sim, sim.model.body(name).id - 1, dx, dy, 0.0)
    for vessel, (dx, dy) in values["vessel_offset_m"].items():
        _move(sim, sim.vessels[vessel].index, dx, dy, math.radians(values["vessel_yaw_deg"][vessel]))
    mujoco.mj_forward(sim.model, sim.data)
    sim.world._update_kinematics()  # until [api]'s vessel.teleport lands: the one place that places bodies


def jittered_pose(cam: Camera, sim: Simulation, values: dict):
    """Camera position (ENU, m) and optical → world rotation with the height and pitch jitter."""
    pos, rot = cam.pose_world(sim.world)
    pitch = math.radians(values["camera_pitch_deg"])
    c, s = math.cos(pitch), math.sin(pitch)
    pos = pos + sim.state.rot[cam.body][:, 2] * values["camera_height_m"]
    rot = rot @ np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])  # FLU pitch: positive looks down
    return pos, rot


class DatasetGenerator:
    """Renders and writes the frames of a `DatasetSpec`; `run(progress)` calls progress(frames_done)."""

    def __init__(self, spec: DatasetSpec, environment: dict | None = None):
        """`environment`: drawn environment values to use instead of drawing them (re-rendering a frame)."""
        self.spec = spec
        self.rnd = load_randomization(spec.randomize)
        self.rng = np.random.default_rng(spec.seed)
        self.environment = draw_all(self.rnd.environment, self.rng) if environment is None else environment
        scenario, camera_cfgs = _scenario(spec, self.environment)
        if environment is None:  # every end of a range too: whether a run started depended on its seed (qa20)
            for key, value in self.rnd.environment.items():
                for end in support_ends(value):
                    _scenario(spec, {**self.environment, key: end}, f"{key}: {end!r} (an end of its range) makes")
        # a wrong key path in `look`, or a range reaching past a key's bounds, fails here, before any frame
        for key, value in self.rnd.look.items():
            for end in support_ends(value):
                updated_look(scenario.rendering, {key: end}, spec.randomize)
        updated_look(scenario.rendering, draw_all(self.rnd.look, np.random.default_rng(0)), spec.randomize)
        self.sim = Simulation(scenario, seed=spec.seed)
        self.shared: dict = {}
        self.cameras = [
            (v, Camera(_camera_config(cfg), v, self.sim.world, self.shared)) for v, cfg in camera_cfgs
        ]
        self.stems = _camera_stems([(v, cam.cfg.name) for v, cam in self.cameras])
        objects = catalogue(self.sim.world)
        self.buoys = [o.name for o in objects if o.category == "buoy"]
        self.labellers, self.looks, self.amodals, self.fogs = [], [], [], []
        for vessel, cam in self.cameras:
            mine = [o for o in objects if o.name != vessel]
            self.labellers.append(Labeller(self.sim.model, mine, cam.intrinsics, cam.cfg.near_m,
                                           camera_planes(cam.intrinsics, cam.cfg.near_m)))  # fmt: skip
            self.looks.append(LookAdapter(self.sim.world, cam.renderer, cam.intrinsics))
            self.amodals.append(AmodalCounter(self.sim.model, mine, self.labellers[-1].owner))
            self.fogs.append(FogSight(cam.intrinsics))
        self.writer = DatasetWriter(spec.out, spec.formats, spec.coco_segmentation, spec.yolo_labels)
        self.frames_written = 0

    def run(self, progress: Callable[[int], None] | None = None, stop: Callable[[], str | None] | None = None) -> Path:
        """Writes the frames; `stop()` is asked before each frame: a reason (e.g. "SIGTERM") ends the run there,
        with the frames begun written in full and the annotations, data.yaml and dataset.json of those frames
        (dataset.json: `frames` written, `frames_requested`, `stopped`). `self.frames_written` counts them. A file
        that cannot be written (a full disk) stops the run with a WriteError naming it."""
        spec = self.spec
        try:
            return self._run(progress, stop)
        except WriteError as exc:  # a full disk: no file looks complete that is not (writers.write_atomic)
            raise WriteError(f"{exc}; {spec.out} holds an incomplete set, without dataset.json (written last): "
                             "remove it, or run again with --force") from None  # fmt: skip

    def _run(self, progress, stop) -> Path:
        spec, per_episode = self.spec, (1 if self.rnd.per == "frame" else self.rnd.frames_per_episode)
        workers = max(1, spec.workers)
        stopped, failed = None, None
        with ThreadPoolExecutor(workers) as pool:
            pending: deque = deque()
            for i in range(spec.frames):
                if stop is not None and (stopped := stop()):
                    break
                if i % per_episode == 0:
                    try:
                        look, scene = self._episode()
                    except UsvsimError as exc:  # a draw outside a key's bounds (a normal without clip)
                        stopped, failed = "error", exc
                        break
                    # one split per episode: its frames, 0.2 s apart, are near-duplicates (drawn per frame, they
                    # went to train and val alike)
                    split = SPLITS[
                        int(np.searchsorted(np.cumsum(spec.splits), self.rng.random(), side="right").clip(0, 2))
                    ]
                else:
                    self.sim.run(spec.frame_interval_s)
                pending += self._frame(i, split, look, scene, pool)
                self.frames_written = i + 1
                while len(pending) > 2 * workers:  # bounded: each frame in flight holds ~3.5 MB of images
                    self.writer.add_coco(pending.popleft().result())
                if progress:
                    progress(i + 1)
            while pending:
                self.writer.add_coco(pending.popleft().result())
        settings = {**asdict(spec), "out": str(spec.out), "environment": self.environment,
                    "randomization": self.rnd.model_dump(mode="json"), "cameras": self.camera_records()}  # fmt: skip
        if stopped:
            settings |= {"frames": self.frames_written, "frames_requested": spec.frames, "stopped": stopped}
        self.writer.finish(settings)
        if failed is not None:  # the frames before it are a complete, smaller set
            raise UsvsimError(f"{failed}; stopped at frame {self.frames_written}: the {self.frames_written} frames "
                              f"before it are in {spec.out} (dataset.json: stopped)")  # fmt: skip
        return spec.out

    def camera_records(self) -> list[dict]:
        """Each camera's intrinsics for dataset.json: width, height, fx, fy, cx, cy (px; cx, cy in pixel-centre
        coordinates, OpenCV's: the first pixel's centre is 0), K, horizontal_fov_deg, distortion (plumb_bob k1, k2,
        p1, p2, k3; the images are the distorted ones) and the camera's meta name (vessel/camera)."""
        out = []
        for vessel, cam in self.cameras:
            k = cam.intrinsics
            out.append({"camera": f"{vessel}/{cam.cfg.name}", "width": k.width, "height": k.height, "fx": k.fx,
                        "fy": k.fy, "cx": k.cx, "cy": k.cy, "K": k.K.tolist(),
                        "horizontal_fov_deg": cam.cfg.horizontal_fov_deg, "distortion": list(k.D)})  # fmt: skip
        return out

    def close(self) -> None:
        for _, cam in self.cameras:
            cam.renderer.close()
        gl = self.shared.pop("camera/gl", None)
        if gl is not None:
            gl.close()
        self.sim.close()

    def _episode(self):
        sim = self.sim
        sim.reset(seed=int(self.rng.integers(2**31)))  # a new ocean (wave phases) every episode
        look = updated_look(sim.scenario.rendering, draw_all(self.rnd.look, self.rng), self.spec.randomize)
        vessels = tuple(dict.fromkeys(vessel for vessel, _ in self.cameras))  # each camera's vessel, once
        scene = draw_scene(self.rnd.scene, self.buoys, self.rng, self.spec.randomize, vessels)
        apply_scene(sim, scene)
        sim.run(self.spec.settle_s)
        return look, scene

    def _frame(self, i: int, split: str, look, scene: dict, pool) -> list:
        """Renders and labels frame i on this thread (the GL context and the simulation state live here);
        the look's image effects, masks, COCO RLE and file writing run on the pool (numba, OpenCV and zlib
        release the GIL). Returns the jobs' futures (each gives the frame's COCO records)."""
        jobs, sim = [], self.sim
        for k, (vessel, cam) in enumerate(self.cameras):
            stem = f"{i:06d}{self.stems[k]}"
            pos, rot = jittered_pose(cam, sim, scene)
            images, labels = self.render(k, pos, rot, look)
            meta = frame_metadata(
                sim, i, f"{vessel}/{cam.cfg.name}", split, look, scene, self.environment, pos, rot
            )
            meta["objects"] = [asdict(x) for x in labels]
            image_id = i * len(self.cameras) + k + 1
            jobs.append(pool.submit(self._finish, self.looks[k], self.labellers[k], look, images, labels,
                                    (split, stem, image_id), meta, [self.spec.seed, i, k]))  # fmt: skip
        return jobs

    def render(self, k: int, pos, rot, look):
        """Camera k's images (rgb, depth, segmentation) from pose (pos ENU m, FLU → world rotation) under
        `look`, and its object labels (amodal masks rendered for the visible fractions; only the pixels the fog
        leaves visible, datasets/fog_sight.py: images['fog_hidden'] marks the others when there is fog)."""
        (_, cam), lab, sim = self.cameras[k], self.labellers[k], self.sim
        self.looks[k].before(look)
        images = cam.render(sim.world, pose=(pos, rot), streams=("rgb", "depth", "segmentation"))
        rot_optical = rot @ OPTICAL_ROT
        fog = self.fogs[k].frame(look, images["depth"], pos, rot_optical, sim.world.ocean.level_m)
        labels = lab.objects_in(sim, images["segmentation"], pos, rot_optical, self.spec.min_visible_pixels,
                                self.spec.min_visible_fraction,
                                partial(self.amodals[k].counts, cam, sim, (pos, rot)) if self.spec.amodal_masks else None,
                                fog)  # fmt: skip
        if fog is not None:
            images["fog_hidden"] = fog.hidden
        return images, labels

    def _finish(self, adapter, lab, look, images, labels, where, meta, rng_key):
        """Worker thread: look on the image, masks, COCO records, files."""
        split, stem, image_id = where
        rgb = adapter.after(look, images["rgb"], images["depth"], np.random.default_rng(rng_key))
        instance, semantic = lab.masks(images["segmentation"], labels, images.get("fog_hidden"))
        records = self.writer.coco_records(split, stem, image_id, rgb.shape, instance, labels)
        self.writer.frame(split, stem, image_id, rgb, instance, semantic, labels, meta)
        return records


def updated_look(rendering, values: dict, randomize: str | None):
    """The scenario's `rendering:` with drawn `look` values; a UsvsimError naming the key and the drawn value."""
    try:
        return rendering.updated(nested(values))
    except ValidationError as exc:  # said "look: ('sun', 'azimuth_dg'): Extra inputs are not permitted"
        err = exc.errors()[0]
        path = ".".join(str(p) for p in err["loc"])
        what = "unknown key" if err["type"] == "extra_forbidden" else f"{err['msg']}, got {err.get('input')!r}"
        raise UsvsimError(f"randomization {randomize}: look.{path}: {what} (keys of the scenario's "
                          "rendering: section, docs/rendering.md)") from None  # fmt: skip


def _camera_stems(cameras: list[tuple[str, str]]) -> list[str]:
    """Each camera's file-name suffix after the frame number: none for a single camera, `_<camera>` when the
    cameras' names differ, `_<vessel>-<camera>` for all when two vessels' cameras share a name (names hold no
    '-', so these never collide)."""
    if len(cameras) == 1:
        return [""]
    names = [cam for _, cam in cameras]
    if len(set(names)) == len(names):
        return [f"_{cam}" for cam in names]
    return [f"_{vessel}-{cam}" for vessel, cam in cameras]


def _camera_config(cfg: dict) -> CameraConfig:
    from pydantic import TypeAdapter

    from usvsim.config.sensors import Camera as CameraConfig

    return TypeAdapter(CameraConfig).validate_python(cfg)


def frame_metadata(sim, i, camera, split, look, scene, environment, pos, rot) -> dict:
    """Everything that made the frame, floats exact (JSON keeps a float's shortest round-trip form): look,
    drawn values, poses, the world's seed, clock steps and full qpos (datasets/rerender.py re-renders it)."""
    bodies = {name: {"position_m": sim.state.pos[v.index].tolist(), "quat_wxyz": sim.body_quat(v.index).tolist()}
              for name, v in sim.vessels.items()}  # fmt: skip
    return {"frame": i, "camera": camera, "split": split, "seed": sim.seed, "time_s": sim.time,
            "clock_steps": sim.world.clock.steps, "look": look.model_dump(mode="json"), "scene": scene,
            "environment": environment, "vessels": bodies, "camera_position_m": np.asarray(pos).tolist(),
            "camera_rotation_flu_to_world": np.asarray(rot).tolist(), "qpos": sim.data.qpos.tolist()}  # fmt: skip


def generate(spec: DatasetSpec, progress: Callable[[int], None] | None = None,
             stop: Callable[[], str | None] | None = None, force: bool = False) -> Path:  # fmt: skip
    """Python API of `usvsim dataset`: writes the data set and returns its folder (`stop`: see `run`). A folder
    already holding a data set is refused; `force=True` replaces it (its files only), as `--force` does."""
    gen = DatasetGenerator(spec)
    try:
        clear_previous(spec.out, force)
        return gen.run(progress, stop)
    finally:
        gen.close()


def clear_previous(out: Path, force: bool) -> None:
    """A data set already in `out` is refused, or with `force` its files (and only those) removed: written over,
    its frames beyond the new count stayed beside annotations that no longer listed them (generate() did so
    silently). A file in the set's folders that usvsim does not write (a user's images/holiday.jpg) is refused
    with or without `force`: --force deleted every file under images/, labels/, masks/, meta/ and annotations/."""
    from usvsim.datasets.writers import remove_set, set_files

    ours, foreign = set_files(out)
    if foreign:
        raise UsvsimError(f"{out} holds files usvsim did not write ({foreign[0]}{', ...' if len(foreign) > 1 else ''}): "
                          "--force removes only a data set's own files; give another --out, or move them")  # fmt: skip
    if not ours:
        return
    if not force:
        raise UsvsimError(f"{out} already holds a data set ({', '.join(str(p) for p in ours[:3])}); pass --force to "
                          "replace it, or give another --out")  # fmt: skip
    remove_set(out, ours)
