"""Sensor observations of the task envs: Dict spaces that pass Gymnasium's checker, a LiDAR that sees the
channel's buoys, a rendered camera image, and reset(seed) through the simulation's exact reset (no rebuild)."""

import numpy as np
import pytest

gymnasium = pytest.importorskip("gymnasium")
from gymnasium.utils.env_checker import check_env  # noqa: E402

import usvsim.tasks.gym  # noqa: E402, F401
from usvsim.tasks.gym.observations import LIDAR_RANGE_M  # noqa: E402


def test_state_lidar_camera_pass_the_checker_and_see_the_scene():
    env = gymnasium.make("usvsim/FollowPath-v0", observation=("state", "lidar", "camera"), time_limit_s=2.0)
    check_env(env.unwrapped, skip_render_check=True)
    space = env.observation_space
    assert isinstance(space, gymnasium.spaces.Dict) and set(space) == {"state", "lidar", "camera"}
    obs, _ = env.reset(seed=3)
    assert obs["lidar"].min() == LIDAR_RANGE_M and not obs["camera"].any()  # nothing sampled yet at t = 0
    model = env.unwrapped.sim.model
    obs, *_ = env.step(np.zeros(env.action_space.shape, np.float32))
    assert space.contains(obs)
    # the first gate's buoys, 15 m ahead of base_link and 10 m to each side, seen from the bow scanner (2.6 m
    # ahead): 15.9 m away at ±39° (column i looks at −180° + 2° i)
    hits = np.flatnonzero(obs["lidar"] < 20.0)
    bearings = -180.0 + hits * 360.0 / obs["lidar"].size
    assert obs["lidar"].min() == pytest.approx(np.hypot(12.4, 10.0), abs=1.0)
    assert np.any(np.abs(bearings - 39) < 4) and np.any(np.abs(bearings + 39) < 4)
    assert obs["camera"].std() > 5  # water, sky and buoys rendered, not a blank frame
    assert env.unwrapped.sim.model is model  # reset(seed) kept the compiled model
    env.close()


def test_sensor_only_observation_resets_exactly():
    env = gymnasium.make("usvsim/StationKeeping-v0", observation="lidar", time_limit_s=2.0)
    check_env(env.unwrapped, skip_render_check=True)
    runs = []
    for _ in range(2):
        env.reset(seed=5)
        runs.append([env.step(np.full(4, 0.5, np.float32))[0]["lidar"] for _ in range(3)])
    assert all(np.array_equal(a, b) for a, b in zip(*runs))
    env.close()


def test_async_camera_envs_spawned_match_sync():
    """Camera observations in async vector envs need the 'spawn' start method (OpenGL is not fork-safe, and
    Gymnasium makes an env in this process first); spawned, they give the same observations as sync envs."""
    kwargs = {"observation": ("state", "camera"), "time_limit_s": 3.0}
    results = []
    for mode, extra in (("sync", {}), ("async", {"vector_kwargs": {"context": "spawn"}})):
        envs = gymnasium.make_vec("usvsim/StationKeeping-v0", num_envs=2, vectorization_mode=mode, **kwargs, **extra)
        obs, _ = envs.reset(seed=[11, 12])
        trace = [obs["state"], obs["camera"]]
        rng = np.random.default_rng(0)
        for _ in range(4):
            obs, reward, *_ = envs.step(rng.uniform(-1, 1, envs.action_space.shape).astype(np.float32))
            trace += [obs["state"], obs["camera"], reward]
        envs.close()
        results.append(trace)
    assert results[0][-2].std() > 5  # rendered images, not blank frames
    assert all(np.array_equal(x, y) for x, y in zip(*results))
