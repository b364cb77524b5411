"""Tasks in a real simulation: a scripted trajectory (the boat held at known poses) scored by hand, and the
reference solutions."""

import math

import mujoco
import pytest

from usvsim.simulation import Simulation
from usvsim.tasks import TASKS, TaskTiming
from usvsim.tasks.solutions import run_trial


def hold(sim, index, x, y, yaw):
    """Put body `index` at (x, y, yaw) (world ENU) at rest: the scripted trajectory."""
    sim.world.teleport(index, ((x, y, 0.0), (math.cos(yaw / 2), 0.0, 0.0, math.sin(yaw / 2))))
    mujoco.mj_forward(sim.model, sim.data)


def test_station_keeping_scripted_offsets_give_vrx_formula():
    task = TASKS["station_keeping"](difficulty=0, seed=4, timing=TaskTiming(running_s=1.0))
    sim = Simulation(task.scenario(), seed=4)
    task.bind(sim)
    gx, gy, gyaw = task.goal
    poses = [(gx + 3.0, gy, gyaw + 0.5), (gx, gy - 4.0, gyaw - 1.0), (gx + 0.6, gy + 0.8, gyaw)]
    for k in range(30):
        sim.step()
        hold(sim, task.index, *poses[k % 3])
        task.update()
    hand = [3.0 + 0.75**3 * 0.5, 4.0 + 0.75**4 * 1.0, 1.0]
    assert task.scorer.samples == 30
    assert task.score == pytest.approx(sum(hand) / 3, abs=1e-9)
    sim.close()


def test_reference_solution_completes_the_channel_without_collisions():
    report = run_trial("follow_path", difficulty=0, seed=0, timing=TaskTiming(running_s=120.0))
    assert report["details"]["channel_completed"] and report["num_collisions"] == 0
    assert report["score"] == 3 * 10 + 2 + 1


def test_reference_station_keeping_holds_the_goal():
    report = run_trial("station_keeping", difficulty=0, seed=1, timing=TaskTiming(running_s=40.0))
    assert 0.0 < report["score"] < 6.0  # mean includes the transit from the start; the final error is small


def test_wildlife_task_at_its_time_limit_gets_the_bonus_of_goals_met():
    """The task calls the scorer's time_out() on its last scored step: the boat left adrift never nears the
    crocodile (21.6 m ahead), so its bonus (here 0.25 s, to fit a 1 s trial) comes off the 1 s elapsed."""
    task = TASKS["wildlife"](difficulty=0, seed=0, timing=TaskTiming(running_s=1.0))
    task.scorer.bonus = 0.25
    sim = Simulation(task.scenario(), seed=0)
    task.bind(sim)
    while not task.finished:
        sim.step()
        task.update()
    assert task.scorer.animals[0].state == "NEVER_ENGAGED"
    assert task.score == pytest.approx(1.0 - 0.25) and not task.completed
    sim.close()


def test_gymkhana_black_box_samples_the_whole_run_as_vrx():
    """VRX's gymkhana world runs the black box (a station-keeping plugin, no heading term) with the task's own
    timing, so its mean distance to the pinger includes the channel transit; the score is that mean once the
    channel is completed (200 before), + 1 per collision. It sampled only after the channel (3.0 here)."""
    task = TASKS["gymkhana"](difficulty=0, seed=0, timing=TaskTiming(running_s=1.0))
    sim = Simulation(task.scenario(), seed=0)
    task.bind(sim)
    px, py, _ = task.pinger
    # through the gates at 15, 45 and 75 m
    transit = [(px - d, py) for d in (80.0, 70.0, 50.0, 40.0, 20.0, 10.0)]
    scores = []
    for x, y in transit + [(px, py + 3.0)] * 4:  # then 3 m off the pinger
        sim.step()
        hold(sim, task.index, x, y, 0.0)
        task.update()
        scores.append(task.score)
    assert task.scorer.gates_crossed == 3 and task.collisions.count == 0
    assert scores[4] == 200.0  # the channel is not completed before the last gate
    assert task.score == pytest.approx((80 + 70 + 50 + 40 + 20 + 10 + 4 * 3.0) / 10, abs=1e-9)
    assert task.collision_buffer_s == 3.0 and task.collision_penalty == 1.0
    sim.close()


@pytest.mark.parametrize("name", ["follow_path", "gymkhana"])
def test_collisions_count_from_the_start_as_vrx_and_cost_only_while_running(name):
    """VRX counts a WAM-V contact in every task state (ScoringPlugin::OnContacts has no state check; vrx_gz and
    VRX classic alike): num_collisions includes the initial and ready states, and the gymkhana's penalty (its
    OnFinished: NumCollisions x obstacle_penalty) with it; follow the path's penalty applies while running
    (one before is taken off a score of 0 at the first running step, floored at 0). usvsim counted only while
    running (QA). The contact is simulated for 0.3 s of the ready state."""
    timing = TaskTiming(initial_s=0.5, ready_s=1.0, running_s=1.0)
    task = TASKS[name](difficulty=0, seed=0, timing=timing)
    sim = Simulation(task.scenario(), seed=0)
    try:
        task.bind(sim)
        task.in_contact = lambda: 0.8 <= sim.time <= 1.1  # in the ready state
        while not task.finished:
            sim.step()
            task.update()
        assert task.collisions.count == 1 and task.info()["num_collisions"] == 1
        assert timing.initial_s <= task.collisions.times_s[0] < timing.start_s
        if name == "gymkhana":
            assert task.score == 200.0 + 1.0  # the channel not completed, + 1 per collision
        else:
            assert task.score == 0.0 and task.scorer.collisions == 0  # no gate, no penalty while not running
    finally:
        sim.close()
