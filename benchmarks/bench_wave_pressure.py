"""Cost of the wave pressure model (docs/vessel-dynamics.md): `harbor` in sea state 4 with the WAM-V's triangle
buoyancy at `wave_pressure: froude_krylov` (the default: each component's pressure decays with depth) against
`hydrostatic` (rho g times the depth below the displaced surface), both built in this process and stepped in
turn, 300 steps per turn, 9 turns after 1 s of warm-up: medians of wall and process CPU µs per physics step, with
the 1-minute load average. Run: python benchmarks/bench_wave_pressure.py   (→ results/wave_pressure.json)
"""

from __future__ import annotations

import json
import os
import statistics
import time
from pathlib import Path

import yaml

from usvsim import Simulation
from usvsim.config.loader import parse_scenario, resolve

STEPS, TURNS = 300, 9


def main() -> dict:
    base = yaml.safe_load(resolve("harbor")[0])
    base.setdefault("environment", {})["sea"] = {"type": "sea_state", "code": 4}
    sims = {}
    for mode in ("froude_krylov", "hydrostatic"):
        scenario = yaml.safe_load(yaml.safe_dump(base))
        for vessel in scenario["vessels"]:
            if vessel.get("model") == "wamv":
                vessel["buoyancy"] = {"type": "triangles", "wave_pressure": mode}
        sims[mode] = Simulation(parse_scenario(scenario, "bench_wave_pressure"))
        sims[mode].run(1.0)
    wall: dict = {m: [] for m in sims}
    cpu: dict = {m: [] for m in sims}
    loads = [os.getloadavg()[0]]
    for _ in range(TURNS):
        for mode, sim in sims.items():
            start, cpu_start = time.perf_counter(), time.process_time()
            for _ in range(STEPS):
                sim.step()
            wall[mode].append((time.perf_counter() - start) / STEPS * 1e6)
            cpu[mode].append((time.process_time() - cpu_start) / STEPS * 1e6)
        loads.append(os.getloadavg()[0])
    for sim in sims.values():
        sim.close()
    result = {
        "step_us_median": {m: statistics.median(v) for m, v in wall.items()},
        "cpu_step_us_median": {m: statistics.median(v) for m, v in cpu.items()},
        "load_1min_median": statistics.median(loads),
        "steps_per_turn": STEPS,
        "turns": TURNS,
    }
    result["hydrostatic_over_froude_krylov_cpu"] = (
        result["cpu_step_us_median"]["hydrostatic"] / result["cpu_step_us_median"]["froude_krylov"]
    )
    print(json.dumps(result, indent=2))
    out = Path(__file__).parent / "results" / "wave_pressure.json"
    out.parent.mkdir(exist_ok=True)
    out.write_text(json.dumps(result, indent=2) + "\n")
    return result


if __name__ == "__main__":
    main()
