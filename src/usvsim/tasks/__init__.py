"""VRX tasks and their scoring (`TASKS`), reference solutions, Gymnasium and PettingZoo environments (`gym`)."""

from usvsim.tasks.library import TASKS
from usvsim.tasks.timing import TaskTiming

__all__ = ["TASKS", "TaskTiming"]
