"""Follow camera: orbit/zoom limits, heading tracking, and pull-in in front of obstacles."""

from __future__ import annotations

import math

import numpy as np
import pytest

from usvsim.simulation import Simulation
from usvsim.viewer.camera import FollowCamera, mujoco_ray, pulled_in_distance, view_direction


def wall_ray(x_wall: float):
    """Exact ray cast against the plane x = x_wall (the wall faces the pivot)."""

    def cast(origin, direction, max_dist):
        if direction[0] <= 0:
            return None
        d = (x_wall - origin[0]) / direction[0]
        return d if 0 <= d <= max_dist else None

    return cast


def test_camera_sits_behind_the_boat_in_follow_mode():
    cam = FollowCamera(distance=10.0, pitch_deg=20.0)
    pose = cam.pose([5.0, 2.0, 0.0], heading_deg=90.0)  # boat heading north
    eye = pose.eye
    assert eye[1] < 2.0 and abs(eye[0] - 5.0) < 1e-9  # south of the boat, i.e. behind it
    assert eye[2] > pose.lookat[2]  # looking down
    assert np.linalg.norm(eye - pose.lookat) == pytest.approx(10.0)


def test_pull_in_against_a_wall():
    cam = FollowCamera(distance=20.0, pitch_deg=10.0, follow=False, yaw_offset_deg=180.0)  # eye toward +x
    pose = cam.pose([0.0, 0.0, 0.0], 0.0, wall_ray(8.0))
    assert pose.eye[0] < 8.0  # never behind the wall
    hit = 8.0 / math.cos(math.radians(10.0))
    assert pose.distance == pytest.approx(hit - cam.pull_in_margin_m)
    assert cam.pose([0.0, 0.0, 0.0], 0.0, wall_ray(50.0)).distance == pytest.approx(
        20.0
    )  # wall too far: no change


def test_pull_in_never_below_minimum():
    assert pulled_in_distance(np.zeros(3), np.array([1.0, 0, 0]), 10.0, wall_ray(0.3), 0.25, 1.5) == 1.5


def test_orbit_zoom_limits_and_heading_smoothing():
    cam = FollowCamera(distance=10.0, pitch_deg=20.0)
    cam.orbit(0.0, 10_000.0)
    assert cam.pitch_deg == cam.max_pitch_deg
    cam.orbit(0.0, -10_000.0)
    assert cam.pitch_deg == cam.min_pitch_deg
    cam.zoom(1000)
    assert cam.distance == cam.min_distance
    cam.zoom(-1000)
    assert cam.distance == cam.max_distance
    cam = FollowCamera()
    cam.update(0.0, 0.0)
    cam.update(90.0, cam.heading_time_constant_s)  # one time constant: 63 % of the way
    assert cam.azimuth_deg(90.0) == pytest.approx(90.0 * (1 - math.exp(-1)))
    for _ in range(200):
        cam.update(90.0, 0.05)
    assert cam.azimuth_deg(90.0) == pytest.approx(90.0, abs=1e-3)


def test_toggle_follow_keeps_the_view():
    cam = FollowCamera()
    cam.update(40.0, 0.0)
    before = cam.azimuth_deg(40.0)
    cam.toggle_follow(40.0)
    assert not cam.follow and cam.azimuth_deg(40.0) == pytest.approx(before)


def test_mujoco_ray_pulls_in_before_a_dock(scenario_of):
    sc = scenario_of({"vessels": [{"name": "boat", "model": "wamv"}],
                      "objects": [{"type": "dock", "name": "wall", "position": [10.0, 0.0, 0.0], "size": [1.0, 30.0, 8.0]}]})  # fmt: skip
    sim = Simulation(sc)
    sim.step()
    boat = sim.vessels["boat"]
    cam = FollowCamera(
        distance=25.0, pitch_deg=5.0, follow=False, yaw_offset_deg=180.0
    )  # eye toward the dock
    pose = cam.pose(boat.position, 0.0, mujoco_ray(sim.model, sim.data, exclude_body=boat.index + 1))
    assert pose.distance < 25.0
    assert pose.eye[0] < 9.5  # in front of the dock's face at x = 9.5
    assert pose.eye[0] > 8.5
    free = FollowCamera(
        distance=25.0, pitch_deg=5.0, follow=False, yaw_offset_deg=0.0
    )  # eye toward open water
    assert free.pose(boat.position, 0.0, mujoco_ray(sim.model, sim.data, boat.index + 1)).distance == 25.0
    assert np.allclose(view_direction(0.0, 0.0), [1.0, 0.0, 0.0])


def test_the_eye_stays_above_the_waves():
    """At the lowest pitch (1 deg) in sea state 7 the eye went 0.19 m under the surface and the view was black below
    a slanted line. A surface 3 m up under the eye: the view looks down more steeply from the same distance until
    the eye is 0.5 m above it; a low surface leaves the pose alone."""
    from usvsim.viewer.camera import above_water

    camera = FollowCamera(distance=14.0, pitch_deg=1.0)
    pose = camera.pose(np.zeros(3), 0.0)
    assert pose.eye[2] < 3.0
    lifted = above_water(pose, lambda x, y: 3.0)
    assert lifted.eye[2] == pytest.approx(3.5, abs=2e-3)
    assert lifted.distance == pose.distance and lifted.azimuth_deg == pose.azimuth_deg
    assert np.array_equal(lifted.lookat, pose.lookat)
    assert above_water(pose, lambda x, y: -1.0) is pose
    sloped = above_water(pose, lambda x, y: 2.0 - 0.1 * x)  # the surface under the eye moves with it
    assert sloped.eye[2] >= 2.5 - 0.1 * sloped.eye[0] - 2e-3
