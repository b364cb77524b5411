"""Gymnasium envs: the checker for every registered env, deterministic reset(seed), sync == async vectors."""

import numpy as np
import pytest

gymnasium = pytest.importorskip("gymnasium")
from gymnasium.utils.env_checker import check_env  # noqa: E402

from usvsim.tasks.gym import ENV_IDS  # noqa: E402


@pytest.mark.parametrize("env_id", sorted(ENV_IDS.values()))
def test_check_env(env_id):
    env = gymnasium.make(env_id, time_limit_s=2.0)
    check_env(env.unwrapped, skip_render_check=True)
    env.close()


def _rollout(env, seed, steps=15):
    obs, _ = env.reset(seed=seed)
    rng = np.random.default_rng(seed)
    out = [obs]
    for _ in range(steps):
        obs, reward, terminated, truncated, _ = env.step(rng.uniform(-1, 1, env.action_space.shape))
        out.append(np.append(obs, reward))
        if terminated or truncated:
            break
    return out


def test_reset_seed_is_deterministic_and_changes_the_goal():
    env = gymnasium.make("usvsim/StationKeeping-v0", difficulty=1, time_limit_s=5.0)
    a, b = _rollout(env, 7), _rollout(env, 7)
    c = _rollout(env, 8)
    assert all(np.array_equal(x, y) for x, y in zip(a, b))
    assert not np.array_equal(a[0], c[0])
    env.close()


def test_velocity_actions():
    env = gymnasium.make("usvsim/StationKeeping-v0", action_type="velocity", time_limit_s=3.0)
    obs, _ = env.reset(seed=0)
    for _ in range(20):
        obs, *_ = env.step(np.array([1.0, 0.0, 0.0], dtype=np.float32))
    assert obs[0] > 0.3  # surging forward (u, m/s)
    env.close()


def test_sync_and_async_vector_envs_are_equal():
    kwargs = {"difficulty": 1, "time_limit_s": 3.0}
    results = []
    for mode in ("sync", "async"):
        envs = gymnasium.make_vec("usvsim/StationKeeping-v0", num_envs=2, vectorization_mode=mode, **kwargs)
        obs, _ = envs.reset(seed=[11, 12])
        trace = [obs]
        rng = np.random.default_rng(0)
        for _ in range(10):
            obs, reward, *_ = envs.step(rng.uniform(-1, 1, envs.action_space.shape).astype(np.float32))
            trace += [obs, reward]
        envs.close()
        results.append(trace)
    assert all(np.array_equal(x, y) for x, y in zip(*results))


class _Kicked(gymnasium.Wrapper):
    """A worker whose boat is thrown at 500 m/s before its step: the world's divergence check stops it."""

    def step(self, action):
        self.env.unwrapped.vessel.teleport((0.0, 0.0, 0.0, 0.0, 0.0, 0.0), twist=(500.0, 0.0, 0.0, 0.0, 0.0, 0.0))
        return self.env.step(action)


def _station_keeping(kicked: bool):
    from usvsim.tasks.gym import TaskEnv

    return lambda: _Kicked(TaskEnv("station_keeping", time_limit_s=2.0)) if kicked else TaskEnv("station_keeping",
                                                                                                time_limit_s=2.0)  # fmt: skip


def test_an_error_in_an_async_worker_reaches_the_user_as_itself():
    """Gymnasium's AsyncVectorEnv re-raises a worker's error in the main process as `type(err)(err)`, after
    logging "Received the following error from Worker-1" with its traceback. usvsim's DivergenceError and
    ScenarioError did not survive that (pickled with their message only, then built from one argument): the user
    got "TypeError: DivergenceError.__init__() missing 1 required positional argument: 'time_s'", and the vector
    env's close() then waited forever for the failed worker (QA)."""
    from usvsim.core.errors import DivergenceError

    envs = gymnasium.vector.AsyncVectorEnv([_station_keeping(False), _station_keeping(True)])
    try:
        envs.reset(seed=0)
        with pytest.raises(DivergenceError, match=r"^simulation diverged: body 'wamv' at t = 0\.010 s \(speed"):
            envs.step(np.zeros((2, 4), np.float32))
        envs.close()  # the failed worker is shut down: closing does not wait for it
        assert envs.closed
    finally:
        if not envs.closed:
            envs.close(terminate=True)


def test_usvsim_errors_cross_a_process_boundary_unchanged():
    """Pickled and rebuilt from one argument (what Gymnasium's async worker and multiprocessing do), every usvsim
    error keeps its type, text and fields."""
    import pickle

    from usvsim.core.errors import DivergenceError, InputError, ScenarioError, UnknownNameError

    errors = [DivergenceError("wamv", 1.5, "(speed 700 m/s)"), ScenarioError("s.yaml", "vessels[0].name", "bad"),
              ScenarioError("s.yaml", "", "not a mapping"), InputError("a pose has 6 numbers"),
              UnknownNameError("no body named 'x'")]  # fmt: skip
    for err in errors:
        for again in (pickle.loads(pickle.dumps(err)), type(err)(err), type(err)(pickle.loads(pickle.dumps(err)))):
            assert type(again) is type(err) and str(again) == str(err)
            assert vars(again) == vars(err)


def test_the_chase_view_draws_the_sea_of_now():
    """`render()` shows the waves at the current time of the current episode: the same frame whatever was
    rendered before (it drew the height field its GL context got when it was made, stale ever after)."""

    def frame(env, before: bool):
        env.reset(seed=3)
        if before:
            env.render()  # the first frame, at t = 0
        for _ in range(5):
            env.step(np.zeros(4, np.float32))
        return env.render()

    make = {"observation": ("state", "camera"), "sea_state": 4, "time_limit_s": 5.0, "render_mode": "rgb_array"}
    a, b = gymnasium.make("usvsim/StationKeeping-v0", **make), gymnasium.make("usvsim/StationKeeping-v0", **make)
    try:
        after_a_first_frame, only = frame(a, True), frame(b, False)
        assert np.array_equal(after_a_first_frame, only)
        a.reset(seed=4)  # another sea at the same time
        for _ in range(5):
            a.step(np.zeros(4, np.float32))
        assert (a.render() != only).any(axis=-1).mean() > 0.05
    finally:
        a.close()
        b.close()


def test_the_chase_view_right_after_reset_shows_the_scene():
    """The first frame of an episode (what a video wrapper records after `reset`) shows the vessel on the water:
    the view poses the bodies from the current qpos (it drew MuJoCo's data, which holds no poses before the
    first step: every geom vanished, the frame was all sky)."""
    env = gymnasium.make("usvsim/Wayfinding-v0", time_limit_s=5.0, render_mode="rgb_array")
    try:
        env.reset(seed=1)
        first = env.render()
        env.step(np.zeros(4, np.float32))  # calm water, no thrust: 0.1 s later the view has hardly changed
        assert (first != env.render()).any(axis=-1).mean() < 0.1
    finally:
        env.close()


def test_render_needs_no_display_nor_mujoco_gl():
    """A headless user's `render()` (no DISPLAY, MUJOCO_GL unset, `mujoco` imported first): the chase view makes its
    own EGL context like the cameras (it used `mujoco.Renderer`, whose backend `import mujoco` had already chosen:
    GLFW, which fails without a display)."""
    import os
    import subprocess
    import sys

    code = ("import mujoco, gymnasium, numpy as np, usvsim.tasks.gym\n"
            "env = gymnasium.make('usvsim/StationKeeping-v0', time_limit_s=2.0, render_mode='rgb_array')\n"
            "env.reset(seed=1)\n"
            "frame = env.render()\n"
            "env.close()\n"
            "print(frame.shape, int(frame.std() > 5))\n")  # fmt: skip
    env = {k: v for k, v in os.environ.items() if k not in ("MUJOCO_GL", "DISPLAY", "PYOPENGL_PLATFORM")}
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr[-2000:]
    assert out.stdout.strip().splitlines()[-1] == "(240, 320, 3) 1"


@pytest.mark.parametrize("env_id", sorted(ENV_IDS.values()))
def test_the_score_in_info_is_finite_at_reset(env_id):
    """Before the first scored step the info's score read nan (station keeping) or inf (wayfinding): json wrote
    NaN/Infinity and a vector env's auto-reset step put it in a logger's mean. VRX publishes 0 until scoring starts."""
    import json

    env = gymnasium.make(env_id)
    _, info = env.reset(seed=0)
    assert np.isfinite(info["score"]) and json.loads(json.dumps(info))["score"] == info["score"]
    env.close()


def test_every_physics_step_of_the_episode_is_scored():
    """The state at the time limit was never scored: 4 s of station keeping had 399 samples, and a wildlife run
    of 5 s scored 4.99 s. Now the return is exactly -score x control steps, as docs/tasks.md says."""
    env = gymnasium.make("usvsim/StationKeeping-v0", time_limit_s=4.0)
    env.reset(seed=2)
    rng, total, steps = np.random.default_rng(0), 0.0, 0
    while True:
        _, reward, terminated, truncated, info = env.step(rng.uniform(-1, 1, 4).astype(np.float32))
        total, steps = total + reward, steps + 1
        if terminated or truncated:
            break
    assert env.unwrapped.task.scorer.samples == 400
    assert total == pytest.approx(-info["score"] * steps, rel=1e-9)
    env.close()
    wildlife = gymnasium.make("usvsim/Wildlife-v0", time_limit_s=5.0)
    wildlife.reset(seed=0)
    for _ in range(50):
        *_, info = wildlife.step(np.zeros(wildlife.action_space.shape, np.float32))
    assert info["score"] == pytest.approx(info["elapsed_time"]) == pytest.approx(5.0)
    wildlife.close()


def test_the_chase_view_far_from_the_origin_shows_the_sea_to_the_top():
    """900 m from the origin the plain look's still-water plane (a 1 km square around the origin) was out of view:
    past the 120 m field the chase view showed sky below the horizon (top rows ~(194, 217, 245)). Now the plane
    follows the view: the top rows are water, in the field's colour."""
    env = gymnasium.make("usvsim/StationKeeping-v0", time_limit_s=5.0, render_mode="rgb_array")
    try:
        env.reset(seed=1)
        sim = env.unwrapped.sim
        sim.world.teleport(next(iter(sim.vessels.values())).index, {"position": [900.0, 0.0, 0.0]})
        env.step(np.zeros(4, np.float32))
        frame = env.render().astype(int)
        top, field = np.median(frame[:20].reshape(-1, 3), axis=0), np.median(frame[200:].reshape(-1, 3), axis=0)
        assert top[0] < 100 and np.abs(top - field).max() <= 4
    finally:
        env.close()
