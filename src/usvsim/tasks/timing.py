"""VRX task state machine (initial → ready → running → finished) and its collision counter."""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass


def check_seconds(name: str, value, positive: bool) -> None:
    """ValueError naming `name` unless `value` is a finite real number of seconds, > 0 if `positive` else >= 0."""
    if not isinstance(value, numbers.Real) or not math.isfinite(value) or float(value) < 0 or (positive and value == 0):
        raise ValueError(f"{name} must be a finite number of seconds {'> 0' if positive else '>= 0'}, not {value!r}")


@dataclass(frozen=True)
class TaskTiming:
    """Durations (s). VRX's 2023 worlds use initial 10, ready 10, running 300; episodes for learning start
    running at t = 0 (the default here)."""

    initial_s: float = 0.0
    ready_s: float = 0.0
    running_s: float = 300.0

    def __post_init__(self) -> None:
        for key in ("initial_s", "ready_s", "running_s"):
            check_seconds(f"TaskTiming.{key}", getattr(self, key), positive=key == "running_s")

    @property
    def start_s(self) -> float:
        return self.initial_s + self.ready_s

    def state(self, t_s: float, finished: bool = False) -> str:
        if finished or t_s >= self.start_s + self.running_s:
            return "finished"
        if t_s >= self.start_s:
            return "running"
        return "ready" if t_s >= self.initial_s else "initial"


class CollisionCounter:
    """VRX counting: a contact of the vessel counts when more than `buffer_s` passed since the last counted one."""

    def __init__(self, buffer_s: float = 3.0):
        self.buffer_s = buffer_s
        self.reset()

    def reset(self) -> None:
        self.count, self.last_s, self.times_s = 0, -math.inf, []

    def update(self, t_s: float, in_contact: bool) -> int:
        """New counted collisions (0 or 1) at time t_s."""
        if in_contact and t_s - self.last_s > self.buffer_s:
            self.count += 1
            self.last_s = t_s
            self.times_s.append(t_s)
            return 1
        return 0


def limit_numba_threads(threads: int | None) -> None:
    """One simulation per process (an env, a batch worker): numba's pool at `threads`, at most the cores numba
    has (None leaves it as it is); anything but a positive integer is a ValueError naming `numba_threads`."""
    if threads is not None:
        import numba

        if isinstance(threads, bool) or not isinstance(threads, int) or threads < 1:
            raise ValueError(f"numba_threads must be a positive integer (or None), not {threads!r}")
        # numba fills its config module from the environment at import: no static attribute to see
        numba.set_num_threads(min(threads, numba.config.NUMBA_NUM_THREADS))  # pyright: ignore
