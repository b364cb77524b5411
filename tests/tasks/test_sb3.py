"""SB3 PPO smoke test (extra rl-test): 5k steps of station keeping without error."""

import pytest

pytest.importorskip("stable_baselines3")
gymnasium = pytest.importorskip("gymnasium")

import usvsim.tasks.gym  # noqa: E402, F401 - registers the envs


def test_ppo_5k_steps():
    from stable_baselines3 import PPO

    env = gymnasium.make("usvsim/StationKeeping-v0", time_limit_s=20.0)
    model = PPO("MlpPolicy", env, n_steps=1024, batch_size=256, n_epochs=2, seed=0, device="cpu", verbose=0)
    model.learn(total_timesteps=5000)
    assert model.num_timesteps >= 5000
    env.close()
