"""VRX task topics: names, types, and CDR that the typestore (an independent rosbags deserializer) reads back."""

import math

import pytest

from usvsim.messages.ros import typestore
from usvsim.simulation import Simulation
from usvsim.tasks import TASKS, TaskTiming
from usvsim.tasks.ros_topics import task_envelopes


@pytest.mark.parametrize("name", ["station_keeping", "wayfinding"])
def test_task_topics_round_trip(name):
    task = TASKS[name](difficulty=0, seed=1, timing=TaskTiming(running_s=1.0))
    sim = Simulation(task.scenario(), seed=1)
    task.bind(sim)
    for _ in range(10):
        sim.step()
        task.update()
    envs = {e.topic: e for e in task_envelopes(task, sim.clock_ns)}
    store = typestore()
    info = store.deserialize_cdr(envs["/vrx/task/info"].cdr, "ros_gz_interfaces/msg/ParamVec")
    params = {p.name: p.value for p in info.params}
    assert params["state"].string_value == "running" and params["num_collisions"].integer_value == 0
    assert params["score"].double_value == pytest.approx(task.score)
    if name == "station_keeping":
        goal = store.deserialize_cdr(envs["/vrx/stationkeeping/goal"].cdr, "geometry_msgs/msg/PoseStamped")
        o = sim.scenario.world.origin
        north_m = (goal.pose.position.x - o.latitude_deg) * math.pi / 180 * 6_378_137.0
        assert north_m == pytest.approx(task.goal[1], abs=0.1)  # latitude carries the goal's northing
    else:
        minima = store.deserialize_cdr(envs["/vrx/wayfinding/min_errors"].cdr, "ros_gz_interfaces/msg/Float32Array")
        assert list(minima.data) == pytest.approx(task.scorer.min_errors, rel=1e-6)
    sim.close()
