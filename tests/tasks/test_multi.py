"""PettingZoo ParallelEnv: the PettingZoo API test and seeding."""

import numpy as np
import pytest

pytest.importorskip("pettingzoo")
from pettingzoo.test import parallel_api_test, parallel_seed_test

from usvsim.tasks.gym.multi import MultiStationKeeping


def test_parallel_api():
    env = MultiStationKeeping(vessels=2, time_limit_s=2.0)
    parallel_api_test(env, num_cycles=25)
    env.close()


def test_parallel_seed():
    parallel_seed_test(lambda: MultiStationKeeping(vessels=2, difficulty=1, time_limit_s=1.0))


def test_agents_differ_and_rewards_are_pose_errors():
    env = MultiStationKeeping(vessels=3, time_limit_s=1.0)
    obs, _ = env.reset(seed=2)
    assert len(obs) == 3 and not np.array_equal(obs["wamv_0"], obs["wamv_1"])
    _, rewards, *_ = env.step({a: np.zeros(4, np.float32) for a in env.agents})
    assert all(r < 0 for r in rewards.values())
    env.close()
