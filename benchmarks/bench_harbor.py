"""Real-time factor of the `harbor` scenario, headless, without sensors.

Figures: usvsim's full step (marine forces + thrusters + MuJoCo), with and without MCAP recording,
against a baseline measured in the same run: MuJoCo stepping the same compiled model with no marine
forces (the floor any MuJoCo-based simulator pays). Run: python benchmarks/bench_harbor.py
"""

from __future__ import annotations

import json
import tempfile
import time
from pathlib import Path

import mujoco
import numpy as np

from usvsim import Simulation
from usvsim.io.mcap_recorder import McapRecorder

SIM_SECONDS = 60.0
REPEATS = 3


def rtf_of(run_once) -> float:
    """Best-of-REPEATS real-time factor of a callable that simulates SIM_SECONDS."""
    best = np.inf
    for _ in range(REPEATS):
        start = time.perf_counter()
        run_once()
        best = min(best, time.perf_counter() - start)
    return SIM_SECONDS / best


def main() -> dict:
    sim = Simulation.from_scenario("harbor")
    sim.run(1.0)  # JIT warm-up
    steps = round(SIM_SECONDS / sim.clock.dt)

    def usvsim_headless():
        for _ in range(steps):
            sim.vessels["wamv"].command(0.5, 0.1)
            sim.step()

    def mujoco_only():
        for _ in range(steps):
            mujoco.mj_step(sim.model, sim.data)

    def usvsim_recording():
        with tempfile.TemporaryDirectory() as tmp, McapRecorder(Path(tmp) / "bench.mcap") as rec:
            unsubscribe = sim.subscribe(rec.write)
            usvsim_headless()
            unsubscribe()

    figures = {
        "mujoco_only_rtf": rtf_of(mujoco_only),
        "usvsim_rtf": rtf_of(usvsim_headless),
        "usvsim_recording_rtf": rtf_of(usvsim_recording),
    }
    figures["usvsim_step_us"] = 1e6 * sim.clock.dt / figures["usvsim_rtf"]
    figures["ratio_usvsim_vs_mujoco_only"] = figures["usvsim_rtf"] / figures["mujoco_only_rtf"]
    figures["target_rtf"] = 100.0
    figures["bodies"] = len(sim.bodies)
    figures["hull_triangles"] = int(len(sim.hulls.faces))
    for key, value in figures.items():
        print(f"{key:32s} {value:10.2f}" if isinstance(value, float) else f"{key:32s} {value:10d}")
    out = Path(__file__).parent / "results" / "harbor.json"
    out.parent.mkdir(exist_ok=True)
    out.write_text(json.dumps(figures, indent=2))
    return figures


if __name__ == "__main__":
    main()
