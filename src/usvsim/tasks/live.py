"""A task live over ROS 2 (`usvsim task NAME --ros2`): its VRX topics go out through the simulation's bridges
and recorder (`Simulation.publish`), and a team's reports and thrust commands come in (tasks/ros_inputs.py).

    result = run_live("station_keeping", bridges=lambda sim: [DdsBridge(sim)], external=True)

Out, at 1 Hz of simulation time like VRX's scoring plugins, stamped with simulation time: `/vrx/task/info`
and the task's own topics (tasks/ros_topics.py), next to every simulation topic (`/clock`, sensors, TF).
`external=True`: no built-in solution; the boat moves only by what arrives over the bridges (VRX's
`/wamv/thrusters/left/thrust`..., usvsim's `/wamv/thrusters/<name>/thrust`, `/wamv/cmd_vel`), and the run is
paced to the wall clock. The score is VRX's, computed at every physics step, as in `run_trial`.
"""

from __future__ import annotations

from contextlib import ExitStack
from pathlib import Path

from usvsim.core.clock import steps_per_period
from usvsim.simulation import Simulation
from usvsim.tasks.base import Task
from usvsim.tasks.library import TASKS
from usvsim.tasks.ros_inputs import register_task_inputs
from usvsim.tasks.ros_topics import task_envelopes
from usvsim.tasks.solutions import drive, reference_controller
from usvsim.tasks.timing import TaskTiming

PUBLISH_RATE_HZ = 1.0


class TaskPublisher:
    """Calls `sim.publish(task_envelopes(...))` every 1/PUBLISH_RATE_HZ s of simulation time (call after each step)."""

    def __init__(self, task, sim: Simulation, rate_hz: float = PUBLISH_RATE_HZ):
        self.task, self.sim = task, sim
        self.every = steps_per_period(rate_hz, sim.clock.step_ns)

    def __call__(self) -> None:
        sim = self.sim
        if sim.clock.steps % self.every == 0:
            sim.publish(task_envelopes(self.task, sim.clock_ns))


def run_live(name: str | Task, difficulty: int = 0, seed: int = 0, timing: TaskTiming | None = None, *, bridges=None,
             external: bool = False, landmark_type: str = "pose", record: Path | None = None,
             realtime: bool | None = None, on_ready=None, after_step=None,
             record_epoch_ns: int | None = None) -> dict:  # fmt: skip
    """One trial with its topics live (`name`: a task name, or a `Task` made by the caller, whose difficulty,
    seed and timing then count). `bridges(sim)` opens the bridges (each with `close()` and `stats`; None:
    none, e.g. only `record`); `realtime` defaults to `external`; `on_ready(sim)` runs once they are open,
    before the first step; `after_step()` after every step (an exception from it, e.g. the CLI's stop on SIGTERM,
    ends the trial between two steps: the recording is closed complete, the bridges and the simulation closed);
    `record_epoch_ns`: the recording's log-time epoch (`Simulation.record`'s `epoch_ns`; None: the wall clock).
    Returns `run_trial`'s report plus the bridges' and the command inbox's counters."""
    task = TASKS[name](difficulty, seed, timing) if isinstance(name, str) else name
    sim = Simulation(task.scenario(), seed=task.seed)
    opened: list = []
    sim.commands.reset_allowed = False  # a /reset mid-trial restarted the clock under the task: the trial ran on
    # from t = 0 with the score kept (VRX has no reset); it is refused and counted `rejected` in report["commands"]
    try:
        register_task_inputs(sim, task, landmark_type)  # before the bridges open: they read the topic list
        if bridges is not None:
            opened = list(bridges(sim))
        with ExitStack() as stack:
            if record is not None:
                stack.enter_context(sim.record(record, epoch_ns=record_epoch_ns))
            if on_ready is not None:
                on_ready(sim)
            controller = None if external else reference_controller(sim)
            publisher = TaskPublisher(task, sim)

            def each_step() -> None:
                publisher()
                if after_step is not None:
                    after_step()

            report = drive(task, sim, controller, after_step=each_step,
                            realtime=external if realtime is None else realtime)  # fmt: skip
            sim.publish(task_envelopes(task, sim.clock_ns))  # the final state (finished, score)
        report["bridges"] = {type(b).__name__: dict(b.stats) for b in opened}
        report["commands"] = dict(sim.commands.stats)
        return report
    finally:
        for bridge in reversed(opened):
            bridge.close()
        sim.close()
