"""Scenario keys of sensors (`vessels[i].sensors`), a tagged union on `type`.

Frames: a sensor's mount pose is given in its vessel's body frame `base_link` (FLU: x forward, y left,
z up; metres, degrees roll/pitch/yaw per REP 103). The sensor frame is `<vessel>/<name>` (FLU); cameras
also get `<vessel>/<name>_optical` (z forward, x right, y down). Rates are in simulation time and must be
whole multiples of the physics step, and so are latencies (neither is rounded: a scenario error names the
nearest valid values).
"""

from __future__ import annotations

import math
from typing import Annotated, Literal

import numpy as np
from pydantic import AfterValidator, Field, model_validator

from usvsim.config.base import (
    KeyedValueError,
    NonNegativeFloat,
    PoseDeg,
    PositiveFloat,
    Section,
    TupleOf,
    Vec2,
    Vec3,
)
from usvsim.core.lens import inverse_error

Name = Annotated[str, Field(pattern=r"^[A-Za-z][A-Za-z0-9_]*$")]
TOPIC_PATTERN = r"^/?[A-Za-z_][A-Za-z0-9_]*(/[A-Za-z_][A-Za-z0-9_]*)*$"  # ROS 2 topic name rules
TOPIC_FILTER_PATTERN = r"^!?/\S*$"  # a topic name or a shell-style pattern of them, '!' to exclude (recording.topics)


def _absolute(topic: str) -> str:
    """A relative name resolves in the root namespace, as ROS 2 resolves it for a node there: `my_imu` is `/my_imu`
    (it was recorded, and served to Foxglove, as `my_imu`, while DDS published `rt/my_imu`)."""
    return topic if topic.startswith("/") else "/" + topic


TopicName = Annotated[str, Field(pattern=TOPIC_PATTERN, max_length=256), AfterValidator(_absolute)]
FRAME_PATTERN = r"^[A-Za-z_][A-Za-z0-9_]*(/[A-Za-z_][A-Za-z0-9_]*)*$"
MAX_LIDAR_RAYS = 1 << 22  # rays per revolution (channels x columns), ~4 M: 16x an OS1-128 at 2048 columns
MAX_LATENCY_S = 3600.0  # an hour: beyond it nothing would be published in any run worth the name
Probability = Annotated[float, Field(ge=0.0, lt=1.0)]
# Marine radar: X-band marine radars display at most 96 NM (177.792 km); real ones send 1440-8192 spokes of
# 512-1024 samples a turn (Garmin xHD 1440 x 733, Navico 2048 x 512/1024, Furuno DRS-NXT 8192), so a turn of
# at most 2^23 cells (8192 x 1024) covers them (one turn of 8192 x 8192 would hold 0.5 GB per float64 array).
MAX_RADAR_RANGE_M = 96 * 1852  # m
MAX_RADAR_CELLS = 1 << 23


class Mount(PoseDeg):
    """Pose of the sensor frame in the vessel's `base_link` (FLU, m; degrees, REP 103 roll/pitch/yaw)."""

    position: Vec3 = Field(default=(0.0, 0.0, 0.0), description="[x forward, y left, z up] in base_link (FLU; origin "
                           "on the centreline at mid-length, at the keel), m")


class SensorBase(Section):
    """Fields every sensor has. `topic` defaults to `/<vessel>/<name>`; `frame_id` to `<vessel>/<name>`."""

    name: Name
    rate_hz: PositiveFloat = 10.0
    latency_s: Annotated[float, Field(ge=0, le=MAX_LATENCY_S)] = Field(
        default=0.0, description="publish this long after sampling (stamp = sample time); a whole number of physics steps"
    )
    mount: Mount = Mount()
    topic: TopicName | None = Field(
        default=None, description="default /<vessel>/<name>; the sensor publishes on it or under it "
        "(a LiDAR on <topic>/points, a camera on <topic>/image_raw, odometry on <topic>: docs/ros2.md)")
    frame_id: Annotated[str, Field(pattern=FRAME_PATTERN, max_length=256)] | None = Field(
        default=None, description="default <vessel>/<name>")


# -- navigation ------------------------------------------------------------------------------------
class AxisNoise(Section):
    """Gazebo-style noise of one triad (per axis, sensor units): white noise per sample (`stddev`; from a data sheet's
    noise density N per √Hz, `stddev` = N·√rate_hz: docs/sensor-realism.md), a turn-on bias
    drawn once as ±N(bias_mean, bias_stddev), and a first-order Gauss–Markov bias with correlation time
    `dynamic_bias_correlation_time_s` (τ) driven as in gz-sensors: `dynamic_bias_stddev` (σ_b) is the density of its
    driving noise (sensor units per √s), not the bias's own spread, which settles at σ_b·√(τ/2) (VRX's gyro: 2e-5 ·
    √200 = 2.8e-4 rad/s). From a datasheet's bias instability B at correlation time τ, set σ_b = B·√(2/τ)."""

    stddev: NonNegativeFloat = 0.0
    bias_mean: float = 0.0
    bias_stddev: NonNegativeFloat = 0.0
    dynamic_bias_stddev: NonNegativeFloat = 0.0
    dynamic_bias_correlation_time_s: PositiveFloat = 400.0


VRX_GYRO = AxisNoise(stddev=0.009, bias_mean=0.00075, bias_stddev=0.005, dynamic_bias_stddev=2e-5,
                     dynamic_bias_correlation_time_s=400.0)  # fmt: skip
VRX_ACCEL = AxisNoise(stddev=0.021, bias_mean=0.05, bias_stddev=0.0075, dynamic_bias_stddev=3.75e-4,
                      dynamic_bias_correlation_time_s=175.0)  # fmt: skip


class Imu(SensorBase):
    """sensor_msgs/Imu per REP 145: orientation w.r.t. ENU, gyro rad/s and specific force m/s^2 in the
    sensor frame (+g on z when level at rest). `preset: vrx` takes VRX's WAM-V noise (peer-simulators §2.8)."""

    type: Literal["imu"]
    rate_hz: PositiveFloat = 100.0
    preset: Literal["none", "vrx"] = "none"
    gyro: AxisNoise | None = None
    accel: AxisNoise | None = None
    orientation_stddev_rad: NonNegativeFloat = 0.0

    def gyro_noise(self) -> AxisNoise:
        return self.gyro or (VRX_GYRO if self.preset == "vrx" else AxisNoise())

    def accel_noise(self) -> AxisNoise:
        return self.accel or (VRX_ACCEL if self.preset == "vrx" else AxisNoise())


class Odometry(SensorBase):
    """nav_msgs/Odometry of base_link in `<vessel>/odom` with noise and its covariance.

    `mode: noise` (default): the pose is the true pose plus white noise (`position_stddev_m`,
    `orientation_stddev_rad`), the twist the true twist plus white noise. `mode: dead_reckoning`: the pose is
    integrated from the measured motion, as a DVL, wheel or visual odometry's is, so its error grows without bound:
    each sample adds the true displacement since the last one, measured in the body frame (times 1 +
    `velocity_scale_error`) and turned by the odometry's own heading, plus the twist's velocity noise over the
    sample period; the heading integrates the yaw-rate error (`yaw_rate_bias_radps` plus the twist's z rate
    noise); roll and pitch are true (as from an AHRS). The pose covariance grows with the integrated white noise."""

    type: Literal["odometry"]
    rate_hz: PositiveFloat = 50.0
    mode: Literal["noise", "dead_reckoning"] = "noise"
    position_stddev_m: NonNegativeFloat = Field(default=0.0, description="mode noise: white noise per axis, m")
    orientation_stddev_rad: NonNegativeFloat = Field(default=0.0, description="mode noise: white noise per axis, rad")
    linear_velocity_stddev_mps: NonNegativeFloat = Field(
        default=0.0, description="white noise per axis of the reported linear velocity, m/s (dead_reckoning "
        "integrates it)")  # fmt: skip
    angular_velocity_stddev_radps: NonNegativeFloat = Field(
        default=0.0, description="white noise per axis of the reported angular velocity, rad/s (dead_reckoning "
        "integrates its z part into the heading)")  # fmt: skip
    velocity_scale_error: float = Field(
        default=0.0, ge=-0.5, le=0.5, description="dead_reckoning: the fraction by which distances over-read (0.01: "
        "1 %; a DVL's or wheel's calibration error)")  # fmt: skip
    yaw_rate_bias_radps: float = Field(default=0.0, ge=-0.1, le=0.1, description="dead_reckoning: constant yaw-rate "
                                       "error integrated into the heading, rad/s")  # fmt: skip

    @model_validator(mode="after")
    def _no_mount(self):
        if "mount" in self.model_fields_set and self.mount != Mount():
            raise ValueError("odometry reports base_link in <vessel>/odom: a mount does not apply (remove it; a "
                             "ground_truth sensor reports a mounted frame)")  # fmt: skip
        if self.mode == "dead_reckoning" and (self.position_stddev_m or self.orientation_stddev_rad):
            key = "position_stddev_m" if self.position_stddev_m else "orientation_stddev_rad"
            raise KeyedValueError(key, f"{key} is for mode: noise; a dead-reckoning pose drifts from its integrated "
                                  "twist noise, velocity_scale_error and yaw_rate_bias_radps")  # fmt: skip
        if self.mode == "noise" and (self.velocity_scale_error or self.yaw_rate_bias_radps):
            key = "velocity_scale_error" if self.velocity_scale_error else "yaw_rate_bias_radps"
            raise KeyedValueError(key, f"{key} is for mode: dead_reckoning (a noise-mode pose does not drift)")
        return self


# (horizontal σ per axis m, vertical σ m, correlation time s) of receiver presets: σ_axis = CEP / 1.1774
# (circular Gaussian); u-blox NEO-M8N data sheet: GPS 2.5 m CEP; ZED-F9P: RTK 0.01 m + 1 ppm CEP. The data
# sheets give no vertical figure for the M8 nor a correlation time: vertical = 2x horizontal and τ = 60 s
# are assumptions from measured stand-alone receivers (docs/sensor-realism.md).
GNSS_PRESETS = {"ublox_m8": (2.5 / 1.1774, 2.0 * 2.5 / 1.1774, 60.0), "ublox_f9p_rtk": (0.01 / 1.1774, 0.02, 60.0)}


class Gnss(SensorBase):
    """sensor_msgs/NavSatFix of the antenna (mount point) via the scenario's geodetic origin (WGS-84);
    optional geometry_msgs/TwistWithCovarianceStamped ENU velocity on `<topic>/vel`.

    Position error per ENU axis: a first-order Gauss–Markov process with stationary stddev
    `horizontal_stddev_m` (east, north) / `vertical_stddev_m` (up) and correlation time `correlation_time_s`
    (0 = white noise, a new draw per fix). `preset` fills the three from a receiver; explicit values win."""

    type: Literal["gnss"]
    rate_hz: PositiveFloat = 10.0
    preset: Literal["none", "ublox_m8", "ublox_f9p_rtk"] = "none"
    horizontal_stddev_m: NonNegativeFloat | None = None
    vertical_stddev_m: NonNegativeFloat | None = None
    correlation_time_s: NonNegativeFloat | None = Field(default=None, description="Gauss–Markov τ of the position error; 0 = white")
    velocity_stddev_mps: NonNegativeFloat = 0.0
    fix: Literal["no_fix", "fix", "sbas_fix", "gbas_fix"] = "fix"
    velocity: bool = False

    def error_model(self) -> tuple[float, float, float]:
        """(horizontal σ per axis m, vertical σ m, correlation time s), explicit values over the preset's."""
        h, v, tau = GNSS_PRESETS.get(self.preset, (0.0, 0.0, 0.0))
        pick = lambda x, d: d if x is None else x  # noqa: E731
        return pick(self.horizontal_stddev_m, h), pick(self.vertical_stddev_m, v), pick(self.correlation_time_s, tau)


class GroundTruth(SensorBase):
    """Exact nav_msgs/Odometry of the mount frame in `world` (ENU), twist in the sensor frame."""

    type: Literal["ground_truth"]
    rate_hz: PositiveFloat = 50.0


# -- LiDAR -----------------------------------------------------------------------------------------
class Lidar(SensorBase):
    """A spinning LiDAR. `preset` fills the pattern; explicit `channels`/`columns`/`elevations_deg` win.

    3D (`output: points`): sensor_msgs/PointCloud2 with x, y, z, intensity (FLOAT32), ring (UINT16),
    time (FLOAT32, s after the header stamp). 2D (`output: scan`): sensor_msgs/LaserScan from the single
    channel at elevation 0, N ranges, no return = +inf. Water gives no returns unless `water_returns`.
    """

    type: Literal["lidar"]
    preset: Literal["vlp16", "os1_64", "os1_128", "vrx", "seed_3d", "seed_2d", "custom"] = "custom"
    output: Literal["points", "scan"] | None = None
    channels: Annotated[int, Field(ge=1, le=1024)] | None = None
    columns: Annotated[int, Field(ge=1, le=100_000)] | None = None
    elevations_deg: Annotated[TupleOf[float], Field(min_length=1)] | None = None
    vertical_fov_deg: Vec2 | None = Field(default=None, description="(lowest, highest) elevation, evenly spaced")
    horizontal_fov_deg: Annotated[float, Field(gt=0, le=360)] | None = None
    range_min_m: NonNegativeFloat | None = None
    range_max_m: PositiveFloat | None = None
    range_stddev_m: NonNegativeFloat | None = Field(default=None, description="Gaussian range noise; default from the preset")
    dropout: Probability = 0.0
    organized: bool = False
    motion_distortion: bool = False
    water_returns: bool = Field(default=False, description="incidence-dependent returns from the ocean surface")
    spin: Literal["counter_clockwise", "clockwise"] = Field(
        default="counter_clockwise", description="the sweep's direction seen from above: columns fire in order of "
        "rising azimuth (counter_clockwise, REP 103) or falling (clockwise, as Velodyne and Ouster sensors turn; "
        "LOAM-family tools that infer a point's time from its azimuth expect it)")  # fmt: skip
    water_reflectivity: Annotated[float, Field(ge=0, le=1)] = 0.02
    self_returns: bool = Field(default=True, description="false: beams that hit the own vessel give no return (crop)")
    geometry: Literal["visual", "collision"] = "visual"
    reflectivity: dict[str, Annotated[float, Field(ge=0, le=1)]] = Field(
        default_factory=dict, description="per body name ('world' = static objects); default from colour"
    )

    @model_validator(mode="after")
    def _bounded_rays(self):
        if self.elevations_deg is not None and any(not -90.0 <= e <= 90.0 for e in self.elevations_deg):
            raise ValueError("elevations_deg must lie within -90..90 degrees")
        if self.elevations_deg is not None and len(set(self.elevations_deg)) < len(self.elevations_deg):
            twice = sorted({e for e in self.elevations_deg if self.elevations_deg.count(e) > 1})
            raise ValueError(f"elevations_deg holds {', '.join(f'{e:g}' for e in twice)} more than once: two rings "
                             f"would be one (the same rays twice); give each ring its own elevation")  # fmt: skip
        if self.vertical_fov_deg is not None:
            low, high = self.vertical_fov_deg
            if not -90.0 <= low <= high <= 90.0:
                raise ValueError("vertical_fov_deg is (lowest, highest) elevation within -90..90 degrees, lowest first")
        rows = self.channels or len(self.elevations_deg or ()) or 128
        if rows * (self.columns or 2048) > MAX_LIDAR_RAYS:
            raise ValueError(f"channels x columns must be at most {MAX_LIDAR_RAYS} rays per revolution")
        return self


# -- cameras ---------------------------------------------------------------------------------------
class Distortion(Section):
    """Brown–Conrady (plumb_bob) coefficients on normalized image coordinates, published as D = [k1 k2 p1 p2 k3].
    Every pixel of the camera's image must have a ray: a lens whose polynomial turns back inside the image (e.g.
    k1 below -0.135 at 80° and 4:3) is refused; strong pincushion (k1 > 0) is invertible and taken."""

    k1: float = 0.0
    k2: float = 0.0
    p1: float = 0.0
    p2: float = 0.0
    k3: float = 0.0


Category = Literal["vessel", "buoy", "static"]
ALL_CATEGORIES = ("vessel", "buoy", "static")


class ObjectFilter(Section):
    """Which objects are reported: by category (static = docks, walls, piers, berths, mesh obstacles)."""

    categories: TupleOf[Category] = ALL_CATEGORIES
    include_own_vessel: bool = False


class CameraDetections(ObjectFilter):
    """Ground-truth 2D boxes with every frame on `<camera topic>/detections` (vision_msgs/Detection2DArray, same
    stamp and optical frame as the image). An object is reported when at least `min_visible_pixels` of its pixels
    are visible in the frame's segmentation (occluders and the image border hide the rest). `box: projected`: the
    box around its 3D box projected with the published CameraInfo model (distortion included), clipped to the
    image; `box: visible`: the tight box around its visible pixels."""

    box: Literal["projected", "visible"] = "projected"
    min_visible_pixels: Annotated[int, Field(ge=1)] = 10


class Camera(SensorBase):
    """Pinhole camera rendered by MuJoCo: RGB (rgb8), depth (32FC1, metres along the optical z axis;
    NaN = no surface within `far_m`) and segmentation (16UC1: geom id + 1, 0 = background). Looks along
    +x of its mount (FLU); images are in `<vessel>/<name>_optical`."""

    type: Literal["camera"]
    width: Annotated[int, Field(ge=8, le=4096)] = 640
    height: Annotated[int, Field(ge=8, le=4096)] = 480
    horizontal_fov_deg: Annotated[float, Field(gt=1, lt=179)] = 80.0
    near_m: PositiveFloat = 0.05
    far_m: PositiveFloat = 400.0
    streams: TupleOf[Literal["rgb", "depth", "segmentation"]] = ("rgb",)
    distortion: Distortion = Distortion()
    rgb_noise_stddev: NonNegativeFloat = Field(default=0.0, description="multiplicative Gaussian, out = in·(1 + σ n)")
    depth_noise_stddev_m: NonNegativeFloat = 0.0
    shadows: bool = Field(default=False, description="MuJoCo's shadow map of the sun on geoms (also `rendering.shadows`)")
    fog: bool = Field(
        default=False,
        description="MuJoCo's linear fog, from 3 to 10 times the scene's extent (510-1700 m in the harbour: mostly "
        "beyond far_m); visibility-based fog is `rendering.fog` with `renderer: shader`",
    )
    water_surface: bool = Field(default=True, description="draw the wave surface from the ocean (else the flat plane)")
    detections: CameraDetections | None = None

    @model_validator(mode="after")
    def _streams(self):
        if not self.streams or len(set(self.streams)) != len(self.streams):
            raise ValueError("streams must list each of rgb, depth, segmentation at most once (at least one)")
        if self.near_m >= self.far_m:
            raise ValueError(f"near_m ({self.near_m} m) must be less than far_m ({self.far_m} m)")
        d = self.distortion
        pixel = _pixel_without_ray(self.width, self.height, self.horizontal_fov_deg, (d.k1, d.k2, d.p1, d.p2, d.k3))
        if pixel is not None:  # the renderer found no ray for it: garbage indices, a segmentation fault
            raise ValueError(
                f"distortion has no inverse at pixel {pixel} of this {self.width}x{self.height} image at "
                f"horizontal_fov_deg {self.horizontal_fov_deg:g}: no ray found for it (the lens polynomial turns back inside "
                "the image, or is too strong for the renderer's inverse); a calibration is monotonic over its image: check "
                "the coefficients or the field of view"
            )
        return self


def _pixel_without_ray(width: int, height: int, fov_deg: float, D) -> tuple[int, int] | None:
    """The first image pixel (u, v) whose distorted normalized coordinates the camera's inverse (core/lens.py, what
    the renderer uses) does not invert to 0.1 px, or None. Checked on the image's border, where the radius is
    largest, and a grid every 16 pixels inside."""
    if not any(D):
        return None
    f = 0.5 * width / math.tan(math.radians(fov_deg) / 2)
    us, vs = np.arange(0, width, 16), np.arange(0, height, 16)
    border = [(u, v) for u in range(width) for v in (0, height - 1)] + [(u, v) for v in range(height) for u in (0, width - 1)]
    uv = np.array(border + [(u, v) for u in us for v in vs], dtype=float)
    xy_d = (uv - [(width - 1) / 2, (height - 1) / 2]) / f
    bad = ~(inverse_error(xy_d, D) * f < 0.1)  # NaN too
    return (int(uv[bad][0, 0]), int(uv[bad][0, 1])) if bad.any() else None


# -- ground-truth detections ------------------------------------------------------------------------
class Detections(SensorBase, ObjectFilter):
    """Ground-truth 3D boxes of the scene's objects (sensors/objects.py): vision_msgs/Detection3DArray on
    `/<vessel>/<name>`, one oriented box per object with id = object name and class label. `frame: world`:
    boxes in `world` (ENU); `frame: sensor`: in this sensor's frame `<vessel>/<name>` (FLU, at `mount`).
    `range_max_m` drops objects whose box centre is farther from the sensor."""

    type: Literal["detections"]
    frame: Literal["world", "sensor"] = "world"
    range_max_m: PositiveFloat | None = None


# -- marine radar ----------------------------------------------------------------------------------
class SeaClutter(Section):
    """Sea clutter: mean power (over receiver noise) `snr_at_100m_db` at 100 m (default: from the sea state,
    ~5 dB per Douglas state, after Nathanson's X-band low-grazing σ0 tables), falling as range^-`range_exponent`;
    K-distributed intensity (gamma texture of shape `shape` × exponential speckle)."""

    sea_state: Annotated[int, Field(ge=0, le=9)] | None = Field(default=None, description="default: the environment's")
    snr_at_100m_db: float | None = None
    range_exponent: PositiveFloat = 3.0
    shape: PositiveFloat = 2.0


class Arpa(Section):
    """ARPA-style tracking on `<topic>/tracks` (usvsim_msgs/RadarTrackArray) once per revolution: CA-CFAR plots
    (`threshold_db` over the mean of `training_bins` range bins each side) → nearest-neighbour α-β tracks."""

    threshold_db: PositiveFloat = 12.0
    training_bins: Annotated[int, Field(ge=2, le=64)] = 16
    min_cells: Annotated[int, Field(ge=1)] = 3
    range_min_m: NonNegativeFloat = Field(default=30.0, description="no plots nearer (sea clutter around the own ship)")
    join_m: NonNegativeFloat = Field(default=50.0, description="plots of one turn closer than this are one target "
                                     "(a ship's echo breaks up along its length), m; 0: no joining")
    gate_m: PositiveFloat = 30.0
    alpha: Annotated[float, Field(gt=0, le=1)] = 0.6
    beta: Annotated[float, Field(gt=0, le=1)] = 0.3
    confirm_hits: Annotated[int, Field(ge=1)] = 3
    drop_misses: Annotated[int, Field(ge=1)] = 3


class Radar(SensorBase):
    """X-band marine radar (sensors/radar): a beam turning at `rpm` clockwise seen from above, as marine radars
    do (angles are REP 103 in the sensor frame, counter-clockwise from the bow = 0: spoke k points at
    -k·360°/`spokes`), `spokes` azimuths per turn, `range_bins` bins to `range_max_m`; each sample publishes
    the spokes swept since the last one as marine_sensor_msgs/RadarSector (echoes 0..1 = 0..`dynamic_range_db`
    over the noise floor). A 1 m² surface facing the radar at 1 km returns `reference_snr_db`. At most 8192 × 1024
    cells (`spokes` × `range_bins`) a turn; `range_min_m` and the ARPA's below `range_max_m`."""

    type: Literal["radar"]
    rate_hz: PositiveFloat = 10.0
    rpm: Annotated[float, Field(gt=0, le=120)] = 24.0
    spokes: Annotated[int, Field(ge=16, le=8192)] = 1024
    range_bins: Annotated[int, Field(ge=8, le=8192)] = 512
    range_max_m: float = Field(default=1500.0, gt=0, le=MAX_RADAR_RANGE_M,
                               description="the display's range (96 NM at most, as X-band marine radars)")
    range_min_m: NonNegativeFloat = Field(default=5.0, description="no echoes nearer (transmit pulse, own hull)")
    horizontal_beamwidth_deg: Annotated[float, Field(gt=0, le=30)] = 1.8
    vertical_beamwidth_deg: Annotated[float, Field(gt=0, le=60)] = 22.0
    elevation_rays: Annotated[int, Field(ge=2, le=128)] = 16
    azimuth_oversampling: Annotated[int, Field(ge=1, le=8)] = 2
    reference_snr_db: float = 20.0
    dynamic_range_db: PositiveFloat = 60.0
    sea_clutter: SeaClutter = SeaClutter()
    rain_rate_mm_h: NonNegativeFloat = 0.0
    blind_sectors_deg: TupleOf[Vec2] = Field(default=(), description="[from, to] CCW from the bow, degrees")
    image: Literal["polar", "cartesian", "none"] = "cartesian"
    image_size_px: Annotated[int, Field(ge=32, le=4096)] = 512
    arpa: Arpa | None = Arpa()

    @model_validator(mode="after")
    def _bounded_turn(self):
        if self.spokes * self.range_bins > MAX_RADAR_CELLS:
            raise KeyedValueError("range_bins", f"spokes x range_bins must be at most {MAX_RADAR_CELLS:,} cells a turn "
                                  f"(8192 x 1024; real radars send up to 8192 spokes of 1024 samples), got "
                                  f"{self.spokes} x {self.range_bins} = {self.spokes * self.range_bins:,}")  # fmt: skip
        for key, near, what in (("range_min_m", self.range_min_m, "the radar would show nothing"),
                                ("arpa.range_min_m", self.arpa and self.arpa.range_min_m, "ARPA would plot nothing")):
            if near is not None and near >= self.range_max_m:
                raise KeyedValueError(key, f"{near:g} m must be less than range_max_m ({self.range_max_m:g} m): {what}")
        return self


Sensor = Annotated[Imu | Odometry | Gnss | GroundTruth | Lidar | Camera | Detections | Radar,
                   Field(discriminator="type")]  # fmt: skip
Sensors = TupleOf[Sensor]
