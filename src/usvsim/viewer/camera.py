"""Third-person follow camera with orbit and zoom that does not pass through obstacles (pure math).

The camera looks at a pivot above the followed vessel from `distance` metres away, at `pitch_deg` above the
horizon and at azimuth `yaw_deg` (ENU, CCW from +x; 0 looks east). In follow mode the azimuth trails the
vessel's heading (the seed's CameraController: pitch clamped to 1–70°, smooth return behind the boat after
1 s without mouse input); otherwise it stays where the user orbited it. A ray from the pivot toward the
ideal camera position (MuJoCo `mj_ray` against the solid objects in `mujoco_ray`) pulls the camera in in
front of the first obstacle, minus a margin of 0.25 m.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

Ray = Callable[[np.ndarray, np.ndarray, float], float | None]  # (origin, unit direction, max) → hit distance


def wrap_deg(angle: float) -> float:
    return (angle + 180.0) % 360.0 - 180.0


@dataclass(frozen=True)
class CameraPose:
    """What a MuJoCo free camera needs: lookat, distance, azimuth and elevation (degrees, MuJoCo's)."""

    lookat: np.ndarray
    distance: float
    azimuth_deg: float
    elevation_deg: float

    @property
    def eye(self) -> np.ndarray:
        return self.lookat - self.distance * view_direction(self.azimuth_deg, self.elevation_deg)

    def apply(self, cam) -> None:
        """Write into a `mujoco.MjvCamera` (FREE type)."""
        cam.type = 0  # mjCAMERA_FREE
        cam.lookat[:] = self.lookat
        cam.distance, cam.azimuth, cam.elevation = self.distance, self.azimuth_deg, self.elevation_deg


def view_direction(azimuth_deg: float, elevation_deg: float) -> np.ndarray:
    """Unit vector from the camera toward the lookat point (MuJoCo's convention)."""
    az, el = math.radians(azimuth_deg), math.radians(elevation_deg)
    return np.array([math.cos(el) * math.cos(az), math.cos(el) * math.sin(az), math.sin(el)])


@dataclass
class FollowCamera:
    distance: float = 14.0
    pitch_deg: float = 18.0
    yaw_offset_deg: float = 0.0  # follow mode: relative to the heading; else absolute azimuth
    follow: bool = True
    pivot_height_m: float = 1.2
    min_distance: float = 1.5
    max_distance: float = 150.0
    min_pitch_deg: float = 1.0
    max_pitch_deg: float = 70.0
    pull_in_margin_m: float = 0.25
    orbit_deg_per_px: float = 0.3
    zoom_per_click: float = 0.1
    heading_time_constant_s: float = 0.6
    recenter_delay_s: float = 1.0
    recenter_rate_per_s: float = 2.0

    def __post_init__(self):
        self._heading_deg: float | None = None
        self._idle_s = 0.0

    # -- user input ----------------------------------------------------------------------------
    def orbit(self, dx_px: float, dy_px: float) -> None:
        """Mouse drag: right moves the camera around the boat to the left (azimuth −), up lowers it."""
        self.yaw_offset_deg = wrap_deg(self.yaw_offset_deg - self.orbit_deg_per_px * dx_px)
        self.pitch_deg = min(
            max(self.pitch_deg + self.orbit_deg_per_px * dy_px, self.min_pitch_deg), self.max_pitch_deg
        )
        self._idle_s = 0.0

    def zoom(self, clicks: float) -> None:
        """Scroll: positive clicks move closer (geometric steps)."""
        self.distance = min(max(self.distance * (1.0 - self.zoom_per_click) ** clicks, self.min_distance),
                            self.max_distance)  # fmt: skip

    def toggle_follow(self, heading_deg: float) -> None:
        """Switch between trailing the heading and a fixed world azimuth, keeping the current view."""
        azimuth = self.azimuth_deg(heading_deg)
        self.follow = not self.follow
        self.yaw_offset_deg = wrap_deg(azimuth - (self._heading(heading_deg) if self.follow else 0.0))

    def reset_tracking(self) -> None:
        self._heading_deg = None

    # -- per frame -----------------------------------------------------------------------------
    def _heading(self, heading_deg: float) -> float:
        return heading_deg if self._heading_deg is None else self._heading_deg

    def update(self, heading_deg: float, dt: float) -> None:
        """Advance the heading smoothing and the return behind the boat over dt seconds."""
        if self._heading_deg is None:
            self._heading_deg = heading_deg
        alpha = 1.0 - math.exp(-max(dt, 0.0) / self.heading_time_constant_s)
        self._heading_deg = wrap_deg(self._heading_deg + alpha * wrap_deg(heading_deg - self._heading_deg))
        self._idle_s += dt
        if self.follow and self._idle_s > self.recenter_delay_s:
            self.yaw_offset_deg *= math.exp(-self.recenter_rate_per_s * dt)

    def azimuth_deg(self, heading_deg: float) -> float:
        base = self._heading(heading_deg) if self.follow else 0.0
        return wrap_deg(base + self.yaw_offset_deg)

    def pose(self, vessel_position, heading_deg: float, ray: Ray | None = None) -> CameraPose:
        """Camera pose around the vessel, pulled in front of the first obstacle that `ray` reports."""
        pivot = np.asarray(vessel_position, dtype=float) + np.array([0.0, 0.0, self.pivot_height_m])
        azimuth, elevation = self.azimuth_deg(heading_deg), -self.pitch_deg
        distance = pulled_in_distance(pivot, -view_direction(azimuth, elevation), self.distance, ray,
                                      self.pull_in_margin_m, self.min_distance)  # fmt: skip
        return CameraPose(pivot, distance, azimuth, elevation)


def above_water(pose: CameraPose, elevation: Callable[[float, float], float], clearance_m: float = 0.5) -> CameraPose:
    """`pose` with its eye at least `clearance_m` above the water surface under it (`elevation(x, y)`: world z of
    the surface, m), by looking down more steeply from the same distance. In a rough sea at a low pitch the eye
    went under the waves and the view was black below a slanted line (sea state 7, pitch 1 deg: 0.19 m under)."""
    for _ in range(4):  # the surface under the eye moves as the eye does: a few rounds settle it
        eye = pose.eye
        target = elevation(float(eye[0]), float(eye[1])) + clearance_m
        if eye[2] >= target - 1e-3:
            return pose
        sin_el = min(max((float(pose.lookat[2]) - target) / pose.distance, -1.0), 1.0)
        elevation_deg = max(math.degrees(math.asin(sin_el)), -89.0)
        pose = CameraPose(pose.lookat, pose.distance, pose.azimuth_deg, min(elevation_deg, pose.elevation_deg))
    return pose


def pulled_in_distance(
    pivot, toward_eye, distance: float, ray: Ray | None, margin: float, minimum: float
) -> float:
    """The distance along `toward_eye` the camera may sit: in front of a hit, never under `minimum`."""
    if ray is None:
        return distance
    hit = ray(np.asarray(pivot, dtype=float), np.asarray(toward_eye, dtype=float), distance + margin)
    if hit is None or hit < 0 or hit > distance + margin:
        return distance
    return max(min(distance, hit - margin), minimum)


def mujoco_ray(model, data, exclude_body: int, groups=(1,)) -> Ray:
    """A `Ray` against a MuJoCo world's solid objects, ignoring the followed body's own geoms. `mj_ray` skips
    fully transparent geoms, so it casts against the visual pieces (group 1), which match the invisible
    collision pieces (group 3) of static obstacles, vessels and buoys; water (group 2) is not an obstacle."""
    import mujoco

    geomgroup = np.zeros(6, dtype=np.uint8)
    geomgroup[list(groups)] = 1
    hit_id = np.zeros(1, dtype=np.int32)

    def cast(origin: np.ndarray, direction: np.ndarray, max_dist: float) -> float | None:
        dist = mujoco.mj_ray(model, data, origin, direction, geomgroup, 1, exclude_body, hit_id)
        return None if dist < 0 or dist > max_dist else float(dist)

    return cast
