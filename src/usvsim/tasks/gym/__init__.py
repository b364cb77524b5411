"""Gymnasium and PettingZoo environments of the VRX tasks. Importing this module registers, in Gymnasium's
registry (the Gymnasium convention for third-party envs), one env per task:

    import gymnasium, usvsim.tasks.gym
    env = gymnasium.make("usvsim/StationKeeping-v0", difficulty=1, action_type="velocity")

or without the import: `gymnasium.make("usvsim.tasks.gym:usvsim/StationKeeping-v0")`. Needs the extra `rl`.
"""

from __future__ import annotations

import gymnasium

from usvsim.tasks.gym.env import TaskEnv

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

__all__ = ["ENV_IDS", "TaskEnv"]
