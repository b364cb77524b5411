"""Bad arguments and actions to the Gymnasium and PettingZoo envs: a clear exception naming the value.

Before: an action with 3 values for the WAM-V's 4 thrusters was taken (zip dropped the 4th thruster, which
kept its last command); time_limit_s=nan failed with 'cannot convert float NaN to integer', -1 gave an
episode that ended at once; difficulty=1.5 ran level 1; sea_state=12 raised pydantic's multi-line
ValidationError; a wrong action_type or observation listed the options without naming the bad one."""

import math
import re

import numpy as np
import pytest

gymnasium = pytest.importorskip("gymnasium")

import usvsim.tasks.gym  # noqa: E402
from usvsim.tasks.timing import TaskTiming  # noqa: E402


@pytest.fixture(scope="module")
def env():
    env = gymnasium.make("usvsim/StationKeeping-v0", time_limit_s=5.0).unwrapped
    env.reset(seed=0)
    yield env
    env.close()


@pytest.mark.parametrize(
    ("action", "words"),
    [
        (np.zeros(3, np.float32), r"shape \(4,\), got shape \(3,\)"),
        (np.zeros(5), r"shape \(4,\), got shape \(5,\)"),
        (np.zeros((1, 4)), r"shape \(4,\), got shape \(1, 4\)"),
        (0.5, r"shape \(4,\), got shape \(\)"),
        ([0.1, math.nan, 0.0, 0.0], "finite"),
        (["a", "b", "c", "d"], "4 numbers"),
    ],
)
def test_a_bad_action_is_refused_and_commands_nothing(env, action, words):
    env.step(np.full(4, 0.3, np.float32))
    clock = env.sim.clock.steps
    with pytest.raises(ValueError, match=words):
        env.step(action)
    assert env.sim.clock.steps == clock  # nothing stepped
    assert env.sim.thrusters.cmd_u[env._thruster_ids].tolist() == pytest.approx([0.3] * 4)  # nothing commanded


@pytest.mark.parametrize(
    ("kwargs", "words"),
    [
        ({"time_limit_s": math.nan}, "time_limit_s .* not nan"),
        ({"time_limit_s": -1.0}, "time_limit_s .* not -1.0"),
        ({"time_limit_s": 0}, "time_limit_s .* not 0"),
        ({"action_type": "thrust"}, "action_type .* not 'thrust'"),
        ({"observation": ("state", "radar")}, r"observation .* not \('state', 'radar'\)"),
        ({"task": "stationkeeping"}, "task must be one of .* not 'stationkeeping'"),
        ({"task": "perception"}, "perception has no env: its reports .* are not thruster actions"),  # ran, score 10
        ({"control_rate_hz": 0.0}, "rate .* not 0.0"),
        ({"control_rate_hz": math.nan}, "rate .* not nan"),
        ({"render_mode": "rgb_aray"}, "render_mode must be None or 'rgb_array', not 'rgb_aray'"),  # render(): None
    ],
)
def test_bad_env_arguments_name_the_value(kwargs, words):
    with pytest.raises(ValueError, match=words):
        usvsim.tasks.gym.TaskEnv(**({"time_limit_s": 1.0} | kwargs))


@pytest.mark.parametrize(
    ("kwargs", "words"),
    [
        ({"difficulty": 1.5}, "difficulty must be one of .* not 1.5"),
        ({"difficulty": True}, "difficulty must be one of .* not True"),  # was level 1
        ({"sea_state": 12}, "sea_state must be .* 0-9 .* not 12"),
        ({"sea_state": -1}, "sea_state must be .* not -1"),
    ],
)
def test_bad_levels_name_the_value(kwargs, words):
    with pytest.raises(ValueError, match=words):  # a UsvsimError before, unlike every other bad argument
        usvsim.tasks.gym.TaskEnv(time_limit_s=1.0, **kwargs)


def test_task_timing_refuses_non_finite_or_negative_durations():
    for kwargs in ({"running_s": math.nan}, {"running_s": 0.0}, {"ready_s": -1.0}, {"initial_s": math.inf}):
        with pytest.raises(ValueError, match=f"TaskTiming.{next(iter(kwargs))}"):
            TaskTiming(**kwargs)
    assert TaskTiming(ready_s=20.0, running_s=1.0).start_s == 20.0


def test_multi_env_refuses_bad_actions_and_steps_after_the_end():
    from usvsim.tasks.gym.multi import MultiStationKeeping

    with pytest.raises(ValueError, match="time_limit_s .* not nan"):
        MultiStationKeeping(vessels=2, time_limit_s=math.nan)
    with pytest.raises(ValueError, match="vessels .* not 0"):
        MultiStationKeeping(vessels=0)
    with pytest.raises(ValueError, match="vessels .* not True"):  # was one vessel
        MultiStationKeeping(vessels=True)
    env = MultiStationKeeping(vessels=2, time_limit_s=0.1)
    env.reset(seed=0)
    with pytest.raises(ValueError, match=r"shape \(4,\), got shape \(2,\)"):
        env.step({"wamv_0": np.zeros(2, np.float32)})
    with pytest.raises(ValueError, match="finite"):
        env.step({"wamv_1": np.full(4, np.nan, np.float32)})
    with pytest.raises(ValueError, match=r"unknown or finished agents \['wamv_7'\]"):
        env.step({"wamv_7": np.zeros(4, np.float32)})
    *_, truncs, _ = env.step({a: np.zeros(4, np.float32) for a in env.agents})
    assert all(truncs.values()) and env.agents == []
    with pytest.raises(RuntimeError, match="reset"):
        env.step({})
    env.close()


def test_numpy_numbers_are_taken():
    """The checks above must not refuse numpy scalars (np.float32(1.0) was refused by the first version)."""
    from usvsim.tasks.solutions import run_trial

    report = run_trial("station_keeping", difficulty=np.int64(0), seed=np.int64(2),
                       timing=TaskTiming(running_s=np.float32(0.5), ready_s=np.float64(0.0)))  # fmt: skip
    assert report["sim_time_s"] == pytest.approx(0.5)
    env = usvsim.tasks.gym.TaskEnv(time_limit_s=np.float32(0.5), control_rate_hz=np.float64(10.0))
    env.reset(seed=0)
    env.step(np.zeros(4, np.float32))
    env.close()


@pytest.mark.parametrize("threads", [0, -1, "abc", 1.5, True])
def test_numba_threads_must_be_a_positive_integer(threads):
    """0 gave numba's 'must be between 1 and 2' without naming the argument, 'abc' a TypeError."""
    with pytest.raises(ValueError, match=f"numba_threads must be a positive integer .*not {re.escape(repr(threads))}"):
        gymnasium.make("usvsim/StationKeeping-v0", numba_threads=threads)


def test_a_step_after_the_episode_ended_is_refused():
    """It advanced the simulation and returned rewards after truncation (Gymkhana: -15.96)."""
    env = gymnasium.make("usvsim/StationKeeping-v0", time_limit_s=0.2)
    env.reset(seed=0)
    *_, terminated, truncated, _ = env.step(np.zeros(4, np.float32))
    *_, terminated, truncated, _ = env.step(np.zeros(4, np.float32))
    assert terminated or truncated
    time = env.unwrapped.sim.time
    with pytest.raises(RuntimeError, match="call reset"):
        env.step(np.zeros(4, np.float32))
    assert env.unwrapped.sim.time == time
    env.reset(seed=1)
    env.step(np.zeros(4, np.float32))  # a new episode steps again
    env.close()


def test_multi_agent_actions_all_checked_first_and_no_step_past_the_time_limit():
    """A bad action of one agent commands nobody; a missing agent's action is an error (it kept its last
    command); a limit that is not a whole number of control periods ends the episode at the limit (0.15 s
    was scored over 0.2 s, 20 samples per agent), as TaskEnv does."""
    pytest.importorskip("pettingzoo")
    from usvsim.tasks.gym.multi import MultiStationKeeping

    env = MultiStationKeeping(vessels=2, time_limit_s=0.15)
    env.reset(seed=0)
    with pytest.raises(ValueError, match="finite"):
        env.step({"wamv_0": np.ones(4, np.float32), "wamv_1": np.full(4, np.nan, np.float32)})
    assert not env.sim.thrusters.cmd_u.any()  # wamv_0's valid action was not applied either
    with pytest.raises(ValueError, match=r"no action for agents \['wamv_1'\]"):
        env.step({"wamv_0": np.zeros(4, np.float32)})
    assert env.sim.clock.steps == 0
    steps = 0
    while env.agents:
        env.step({a: np.zeros(4, np.float32) for a in env.agents})
        steps += 1
    assert steps == 2 and env.sim.clock.steps == 15
    assert all(s.samples == 15 for s in env.scorers.values())
    env.close()


def test_a_time_limit_under_one_physics_step_is_refused():
    """0.004 s rounded to 0 steps of 10 ms: a trial ran no step and scored NaN (station keeping) or inf
    (wayfinding), written as NaN/Infinity into the JSON report, and an env was over at reset (its first
    step raised 'the episode is over')."""
    from usvsim.core.errors import UsvsimError
    from usvsim.tasks.solutions import run_trial

    for task in ("station_keeping", "wayfinding"):
        with pytest.raises(UsvsimError, match=r"running time 0.004 s is shorter than one physics step \(0.01 s\)"):
            run_trial(task, timing=TaskTiming(running_s=0.004))
    with pytest.raises(ValueError, match="shorter than one physics step"):
        usvsim.tasks.gym.TaskEnv(time_limit_s=0.004)
    pytest.importorskip("pettingzoo")
    from usvsim.tasks.gym.multi import MultiStationKeeping

    with pytest.raises(ValueError, match="time_limit_s 0.004 is shorter than one physics step"):
        MultiStationKeeping(vessels=1, time_limit_s=0.004)
    report = run_trial("station_keeping", timing=TaskTiming(running_s=0.01))  # one step is enough
    assert report["details"]["samples"] == 1 and math.isfinite(report["score"])


def test_render_fps_is_the_control_rate():
    """One rendered frame per env step: a video recorder playing the frames at metadata['render_fps'] shows
    real time. It was 10 whatever the control rate (5 Hz control played twice as fast)."""
    env = usvsim.tasks.gym.TaskEnv(control_rate_hz=5.0, time_limit_s=1.0)
    assert env.metadata["render_fps"] == 5.0
    assert usvsim.tasks.gym.TaskEnv.metadata["render_fps"] == 10  # the class default is left as it was
    env.close()


BAD_ENV_KWARGS = [{"time_limit_s": math.nan}, {"time_limit_s": 0.001}, {"action_type": "thrust"},
                  {"observation": ("state", "radar")}, {"task": "perception"}, {"control_rate_hz": 7.0},
                  {"render_mode": "rgb_aray"}, {"difficulty": 1.5}, {"sea_state": 12}, {"numba_threads": 0}]  # fmt: skip


@pytest.mark.parametrize("kwargs", BAD_ENV_KWARGS)
def test_the_arguments_check_says_what_the_env_says(kwargs):
    """`check_arguments` (no simulation built) refuses what `TaskEnv` refuses, in the same words."""
    with pytest.raises(ValueError) as made:
        usvsim.tasks.gym.TaskEnv(**({"time_limit_s": 1.0} | kwargs))
    with pytest.raises(ValueError) as checked:
        usvsim.tasks.gym.check_arguments(**({"time_limit_s": 1.0} | kwargs))
    assert str(checked.value) == str(made.value)


def test_vector_env_names_the_env_whose_arguments_are_bad():
    """Given to gymnasium's AsyncVectorEnv, an env that fails to build in its worker kills the worker: the user
    saw 'ConnectionResetError: [Errno 104] Connection reset by peer' (the worker's ValueError only on stderr).
    `usvsim.tasks.gym.vector_env` checks every env's arguments in the calling process first (QA)."""
    good = {"task": "station_keeping", "time_limit_s": 1.0}
    for bad, words in (({"difficulty": 7}, "difficulty must be one of [0, 1, 2], not 7"),
                       ({"dificulty": 1}, "got an unexpected keyword argument 'dificulty'; TaskEnv takes task, ")):  # fmt: skip
        with pytest.raises(ValueError) as info:
            usvsim.tasks.gym.vector_env([good, good | bad])
        assert str(info.value).startswith(f"env_kwargs[1]: {words}")
    with pytest.raises(ValueError, match="vectorization_mode must be 'async' or 'sync', not 'asnyc'"):
        usvsim.tasks.gym.vector_env([good], vectorization_mode="asnyc")
    for mode in ("sync", "async"):  # good arguments: the same vector env as gymnasium's own
        envs = usvsim.tasks.gym.vector_env([good, good | {"difficulty": 1}], vectorization_mode=mode)
        try:
            obs, _ = envs.reset(seed=[3, 4])
            obs, reward, *_ = envs.step(np.zeros((2, 4), np.float32))
            assert obs.shape == (2, envs.single_observation_space.shape[0]) and reward.shape == (2,)
        finally:
            envs.close()
