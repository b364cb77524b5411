"""VRX's perception task places each object at its offset from the WAM-V where the boat is when the object
appears (PerceptionScoringPlugin::StartTrial: the boat's position and yaw), and moves it out of sight after its
window (EndTrial). usvsim placed them at fixed world positions, offsets from the boat's start pose (QA)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from usvsim.simulation import Simulation
from usvsim.tasks.library import PERCEPTION_STASH_M, Perception
from usvsim.tasks.timing import TaskTiming


class QuickPerception(Perception):
    schedule = [(0.5, "mb_marker_buoy_red", (7.8, 2.1), "red"), (1.5, "mb_marker_buoy_green", (8.3, 0.1), "green"),
                (2.5, "mb_marker_buoy_white", (4.9, -2.32), "white")]  # fmt: skip
    duration_s = 0.5


# where the boat is put before each object appears: x, y (world ENU, m), yaw (rad, CCW from east)
POSES = [(30.0, -20.0, math.radians(60.0)), (-12.0, 40.0, math.radians(-135.0)), (5.0, 5.0, math.radians(180.0))]


def test_each_object_appears_at_its_body_frame_offset_from_the_boat_then_leaves():
    task = QuickPerception(0, 0, TaskTiming(running_s=3.5))
    sim = Simulation(task.scenario())
    try:
        task.bind(sim)
        boat, placed, reported = sim.vessels["wamv"], {}, set()
        while not task.finished:
            upcoming = next((i for i, o in enumerate(task.scorer.objects) if not o.active and not o.done), None)
            if upcoming is not None and task.elapsed_s < task.schedule[upcoming][0] and upcoming not in placed:
                boat.teleport((*POSES[upcoming][:2], 0.0, 0.0, 0.0, POSES[upcoming][2]))
                placed[upcoming] = None
            sim.step()
            task.update()
            for i, o in enumerate(task.scorer.objects):
                if o.active and placed.get(i) is None:
                    x, y, yaw = task.pose()  # the boat as the object appeared (it drifts a few mm after a teleport)
                    placed[i] = ((x, y, yaw), task.object_xy(f"object_{i}"))
                if o.active and i not in reported:  # a perfect report while it is shown
                    task.scorer.report(o.kind, *task.object_xy(f"object_{i}"))
                    reported.add(i)
        for i, ((x, y, yaw), xy) in placed.items():
            assert abs(x - POSES[i][0]) < 0.05 and abs(y - POSES[i][1]) < 0.05  # the pose set before it appeared
            forward, left = task.schedule[i][2]
            rot = np.array([[math.cos(yaw), -math.sin(yaw)], [math.sin(yaw), math.cos(yaw)]])  # FLU → ENU, by yaw
            assert np.allclose(xy, np.array([x, y]) + rot @ [forward, left], atol=1e-9), (i, xy)
            # out of sight again after its window
            assert math.hypot(*task.object_xy(f"object_{i}")) > PERCEPTION_STASH_M - 1.0
        assert len(placed) == 3
        # scored as VRX does against where each object was: perfect reports, error ~0 each
        assert task.score == pytest.approx(0.0, abs=1e-3)
        assert all(o.done for o in task.scorer.objects)
    finally:
        sim.close()


def test_reset_takes_a_shown_object_out_of_sight():
    task = QuickPerception(0, 0, TaskTiming(running_s=3.5))
    sim = Simulation(task.scenario())
    try:
        task.bind(sim)
        while not task.scorer.objects[0].active:
            sim.step()
            task.update()
        assert math.hypot(*task.object_xy("object_0")) < 10.0
        task.reset(seed=1)
        assert math.hypot(*task.object_xy("object_0")) > PERCEPTION_STASH_M - 1.0
        assert not any(o.active for o in task.scorer.objects)
    finally:
        sim.close()
