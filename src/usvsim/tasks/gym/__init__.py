"""Gymnasium and PettingZoo environments of the VRX tasks. Importing this module registers, in Gymnasium's
registry (the Gymnasium convention for third-party envs), one env per task:

    import gymnasium, usvsim.tasks.gym
    env = gymnasium.make("usvsim/StationKeeping-v0", difficulty=1, action_type="velocity")

or without the import: `gymnasium.make("usvsim.tasks.gym:usvsim/StationKeeping-v0")`. Needs the extra `rl`.
"""

from __future__ import annotations

import gymnasium

from usvsim.tasks.gym.env import TaskEnv, check_arguments

ENV_IDS = {
    "station_keeping": "usvsim/StationKeeping-v0",
    "wayfinding": "usvsim/Wayfinding-v0",
    "follow_path": "usvsim/FollowPath-v0",
    "wildlife": "usvsim/Wildlife-v0",
    "gymkhana": "usvsim/Gymkhana-v0",
}

for _task, _id in ENV_IDS.items():
    if _id not in gymnasium.registry:
        gymnasium.register(_id, entry_point="usvsim.tasks.gym.env:TaskEnv", kwargs={"task": _task},
                           vector_entry_point=None, disable_env_checker=False)  # fmt: skip



def vector_env(env_kwargs, vectorization_mode: str = "async", **vector_kwargs) -> gymnasium.vector.VectorEnv:
    """A Gymnasium vector env of `TaskEnv(**kw)` for each `kw` in `env_kwargs` (one dict per env, e.g.
    `[{"task": "follow_path", "difficulty": d} for d in (0, 1, 2)]`), `vectorization_mode` "async"
    (AsyncVectorEnv, one process per env) or "sync"; `vector_kwargs` go to Gymnasium's class (e.g.
    `context="spawn"`). Every env's arguments are checked here first, in this process: a bad one is a ValueError
    naming its index ("env_kwargs[1]: difficulty must be one of [0, 1, 2], not 7"). Given to
    AsyncVectorEnv directly, an env that fails to build kills its worker, and Gymnasium's process reports only
    ConnectionResetError or EOFError (the worker's error goes to stderr)."""
    from functools import partial

    env_kwargs = [dict(kw) for kw in env_kwargs]
    if not env_kwargs:
        raise ValueError("env_kwargs must hold at least one env's arguments (a dict each)")
    if vectorization_mode not in ("async", "sync"):
        raise ValueError(f"vectorization_mode must be 'async' or 'sync', not {vectorization_mode!r}")
    for i, kw in enumerate(env_kwargs):
        try:
            check_arguments(**kw)
        except ValueError as exc:
            raise ValueError(f"env_kwargs[{i}]: {exc}") from None
    fns = [partial(TaskEnv, **kw) for kw in env_kwargs]
    if vectorization_mode == "sync":
        return gymnasium.vector.SyncVectorEnv(fns, **vector_kwargs)
    return gymnasium.vector.AsyncVectorEnv(fns, **vector_kwargs)


__all__ = ["ENV_IDS", "TaskEnv", "check_arguments", "vector_env"]
