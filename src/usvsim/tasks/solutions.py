"""Built-in reference solutions: the station-keeping controller (`usvsim.control`) steered by each task's
`reference_target()` at 10 Hz; for perception a ground-truth oracle that reports every shown object once a
second (it exercises the scoring path; it is not a detector)."""

from __future__ import annotations

import time

from usvsim.config import control as cfg
from usvsim.control.factory import build_controller
from usvsim.core.clock import steps_per_period
from usvsim.simulation import Simulation
from usvsim.tasks.library import TASKS, Perception
from usvsim.tasks.timing import TaskTiming

CONTROL_RATE_HZ = 10.0


def reference_controller(world, hold: dict | None = None):
    """The station-keeping controller of the WAM-V at 10 Hz; `hold` overrides `config.control.Hold` keys."""
    config = cfg.StationKeeping(rate_hz=CONTROL_RATE_HZ, hold=cfg.Hold(**({"max_speed_mps": 2.0} | (hold or {}))))
    return build_controller(config, world.vessels["wamv"].model)


def run_trial(name: str, difficulty: int = 0, seed: int = 0, timing: TaskTiming | None = None,
              sea_state: int | None = None, mass_kg: float | None = None, hold: dict | None = None,
              trace: list | None = None, after_step=None) -> dict:  # fmt: skip
    """One trial of a task with its reference solution; returns the trial's report (JSON-ready).
    `mass_kg` overrides the WAM-V's mass; `hold` the controller's hold gains (`config.control.Hold` keys);
    `trace`, if given, receives (t s, x m, y m, yaw rad) at every control step; `after_step()` runs after every
    step (the CLI's stop check: an exception from it ends the trial, the simulation closed)."""
    task = TASKS[name](difficulty, seed, timing, sea_state)
    sim = Simulation(task.scenario({"mass": {"mass_kg": mass_kg}} if mass_kg else None), seed=seed)
    try:
        return drive(task, sim, reference_controller(sim, hold), trace, after_step)
    finally:
        sim.close()


def drive(task, sim, controller, trace=None, after_step=None, realtime: bool = False) -> dict:
    """Step `sim` until the task finishes. `controller` None: the boat is left to commands arriving through
    the bridges (an external stack); `after_step()` runs after every scored step; `realtime` paces to the wall
    clock (what a stack on the other side of a bridge lives by)."""
    task.bind(sim)
    vessel = sim.vessels["wamv"]
    every = steps_per_period(CONTROL_RATE_HZ, sim.clock.step_ns)
    dt, wall = every * sim.clock.dt, time.perf_counter()
    while not task.finished:
        if controller is not None and sim.clock.steps % every == 0 and task.state == "running":
            target = task.reference_target()
            if trace is not None:
                trace.append((sim.time, *task.pose()))
            if target is None:
                vessel.command(0.0)
            else:
                controller.apply(vessel, target, dt)
            if isinstance(task, Perception) and sim.clock.steps % (10 * every) == 0:
                for i, o in enumerate(task.scorer.objects):
                    if o.active:
                        task.scorer.report(o.kind, *task.object_xy(f"object_{i}"))
        sim.step()
        task.update()
        if after_step is not None:
            after_step()
        if realtime and (ahead := sim.time - (time.perf_counter() - wall)) > 0:
            time.sleep(ahead)
    return {"task": task.name, "difficulty": task.difficulty, "seed": task.seed, "score": task.score,
            "higher_is_better": task.higher_is_better, "sim_time_s": sim.time,
            "elapsed_time_s": task.elapsed_s, "num_collisions": task.collisions.count,
            "collision_times_s": task.collisions.times_s, "environment": task.environment,
            "wall_time_s": time.perf_counter() - wall, "details": details(task)}  # fmt: skip


def details(task) -> dict:
    s = task.scorer
    if task.name == "station_keeping":
        return {"goal": list(task.goal), "samples": s.samples}
    if task.name == "wayfinding":
        return {"waypoints": [list(w) for w in task.waypoints], "min_errors": s.min_errors}
    if task.name in ("follow_path", "gymkhana"):
        return {"gates_crossed": s.gates_crossed, "gates": len(task.gates), "channel_completed": s.finished}
    if task.name == "wildlife":
        return {"animals": {a.name: {"goal": a.goal, "state": a.state} for a in s.animals}}
    return {"errors_m": {o.kind: o.error_m for o in s.objects}}
