"""Wildlife animals move as VRX's TrajectoryFollower moves them: turn, push, shuttle between their two
waypoints; the scorer follows them where they are; a reset puts them back exactly."""

import math

import numpy as np

from usvsim.simulation import Simulation
from usvsim.tasks import TaskTiming
from usvsim.tasks.animals import VRX_ANIMALS, task_frame
from usvsim.tasks.library import Wildlife


def _segment_distance(p, a, b) -> float:
    a, b, p = np.asarray(a), np.asarray(b), np.asarray(p)
    t = np.clip(np.dot(p - a, b - a) / np.dot(b - a, b - a), 0.0, 1.0)
    return float(np.linalg.norm(p - (a + t * (b - a))))


def test_animals_shuttle_between_their_waypoints_and_reset_exactly():
    task = Wildlife(0, 0, TaskTiming(running_s=300.0))
    sim = Simulation(task.scenario())
    task.bind(sim)
    tracks = {n: [] for n in VRX_ANIMALS}
    reached = dict.fromkeys(VRX_ANIMALS, 0)
    for step in range(6000):  # 60 s; the boat is left alone
        before = dict(task.motion.target)
        sim.step()
        task.update()
        for n in VRX_ANIMALS:
            reached[n] += task.motion.target[n] != before[n]
            if step % 50 == 0:
                tracks[n].append(task.object_xy(n))
    for n, (_, pose, waypoints, _, _) in VRX_ANIMALS.items():
        a, b = task_frame(*waypoints[0]), task_frame(*waypoints[1])
        track = np.array(tracks[n])
        assert reached[n] >= 2, f"{n} reached {reached[n]} waypoints in 60 s"  # there and back at least
        assert max(_segment_distance(p, a, b) for p in track) < 1.5  # stays on its path (overshoot < 1.5 m)
        start = task_frame(*pose)  # the second waypoint: it heads for the first, within 0.5 m, and back
        assert max(math.dist(p, start) for p in track) > math.dist(a, b) - 1.0
    first = task.object_xy("crocodile")
    sim.reset()
    task.reset()
    task.bind(sim)
    assert task.object_xy("crocodile") == task_frame(*VRX_ANIMALS["crocodile"][1])  # back at its pose
    assert task.motion.target["crocodile"] == 0 and first != task.object_xy("crocodile")
    sim.close()


def test_the_scorer_circles_an_animal_where_it_is_now():
    """Engagement follows the animal: the boat parked where the crocodile was is not engaged once it moved."""
    task = Wildlife(0, 0, TaskTiming(running_s=300.0))
    sim = Simulation(task.scenario())
    task.bind(sim)
    croc = task.scorer.animals[0]
    cx, cy = task.object_xy("crocodile")
    task.scorer.update(1.0, cx + 10.5, cy, [(cx, cy), (0.0, 0.0), (0.0, 0.0)])
    assert croc.state == "NEVER_ENGAGED"
    task.scorer.update(2.0, cx + 10.5, cy, [(cx + 1.0, cy), (0.0, 0.0), (0.0, 0.0)])  # it came 1 m closer
    assert croc.state == "ENGAGED"
    sim.close()
