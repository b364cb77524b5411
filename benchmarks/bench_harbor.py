"""Real-time factor of the `harbor` scenario, headless, without sensors.

Figures: usvsim's full step (marine forces + thrusters + MuJoCo), with and without MCAP recording,
against a baseline measured in the same run: MuJoCo stepping the same compiled model with no marine
forces (the floor any MuJoCo-based simulator pays), on its own copy of the simulation's data taken from the
settled state before each repeat (bare stepping lets the hull sink: it must not disturb the simulation, whose
divergence guard would stop it). The three take turns in each of REPEATS rounds; medians by the wall clock and
by the process's CPU time (the less disturbed figure on a shared machine), with the 1-minute load average.
Run: python benchmarks/bench_harbor.py   (→ results/harbor.json)
"""

from __future__ import annotations

import json
import os
import statistics
import tempfile
import time
from pathlib import Path

import mujoco

from usvsim import Simulation
from usvsim.io.mcap_recorder import McapRecorder

SIM_SECONDS = 20.0
REPEATS = 5


def make_cases(sim: Simulation, steps: int) -> dict:
    """The three timed callables, each `steps` physics steps; the bare baseline steps a copy of sim's data."""
    bare = mujoco.MjData(sim.model)

    def usvsim_headless():
        for _ in range(steps):
            sim.vessels["wamv"].command(0.5, 0.1)
            sim.step()

    def mujoco_only():
        mujoco.mj_copyData(bare, sim.model, sim.data)
        for _ in range(steps):
            mujoco.mj_step(sim.model, bare)

    def usvsim_recording():
        with tempfile.TemporaryDirectory() as tmp, McapRecorder(Path(tmp) / "bench.mcap") as rec:
            unsubscribe = sim.subscribe(rec.write)
            usvsim_headless()
            unsubscribe()

    return {"mujoco_only": mujoco_only, "usvsim": usvsim_headless, "usvsim_recording": usvsim_recording}


def main() -> dict:
    sim = Simulation.from_scenario("harbor")
    sim.run(1.0)  # JIT warm-up, hull settled
    cases = make_cases(sim, round(SIM_SECONDS / sim.clock.dt))
    wall: dict = {name: [] for name in cases}
    cpu: dict = {name: [] for name in cases}
    loads = [os.getloadavg()[0]]
    for _ in range(REPEATS):
        for name, run_once in cases.items():
            start, cpu_start = time.perf_counter(), time.process_time()
            run_once()
            wall[name].append(SIM_SECONDS / (time.perf_counter() - start))
            cpu[name].append(SIM_SECONDS / (time.process_time() - cpu_start))
        loads.append(os.getloadavg()[0])
    figures: dict = {}
    for name in cases:
        figures[f"{name}_rtf"] = statistics.median(wall[name])
        figures[f"{name}_rtf_cpu"] = statistics.median(cpu[name])
    figures["usvsim_step_us"] = 1e6 * sim.clock.dt / figures["usvsim_rtf"]
    figures["usvsim_step_cpu_us"] = 1e6 * sim.clock.dt / figures["usvsim_rtf_cpu"]
    figures["ratio_usvsim_vs_mujoco_only"] = figures["usvsim_rtf"] / figures["mujoco_only_rtf"]
    figures["ratio_usvsim_vs_mujoco_only_cpu"] = figures["usvsim_rtf_cpu"] / figures["mujoco_only_rtf_cpu"]
    figures["target_rtf"] = 100.0
    figures["bodies"] = len(sim.bodies)
    figures["hull_triangles"] = int(len(sim.hulls.faces))
    figures["repeats"] = REPEATS
    figures["sim_seconds_per_repeat"] = SIM_SECONDS
    figures["load_1min_median"] = statistics.median(loads)
    for key, value in figures.items():
        print(f"{key:32s} {value:10.2f}" if isinstance(value, float) else f"{key:32s} {value:10d}")
    out = Path(__file__).parent / "results" / "harbor.json"
    out.parent.mkdir(exist_ok=True)
    out.write_text(json.dumps(figures, indent=2))
    return figures


if __name__ == "__main__":
    main()
