"""Costs of the Python API (docs/python-api.md), each beside a baseline measured in the same run.

- `reset()` of `harbor` (target <= 20 ms) vs building a fresh `Simulation` of it (what a reset avoids);
  the same in sea state 4 (FFT waves: each reset draws new amplitudes; the seed-independent tables are kept);
- `observe()` after every step of `harbor_sensors` (target <= 5 % of a step): the time in `observe()`
  (each new sample converted once) against the time of the steps it follows, timed separately.
Medians over repeats; the load average is written beside the figures (the machine may be shared).
Run: python benchmarks/bench_api.py
"""

from __future__ import annotations

import json
import os
import time
from pathlib import Path

import numpy as np
import yaml

from usvsim import Simulation
from usvsim.config.loader import load_scenario, parse_scenario, resolve

RESETS, BUILDS, STEPS = 30, 3, 300


def median_s(fn, repeats: int) -> float:
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        fn()
        times.append(time.perf_counter() - start)
    return float(np.median(times))


def reset_figures(label: str, scenario) -> dict:
    sim = Simulation(scenario)
    sim.run(1.0)  # JIT warm-up
    seeds = iter(range(1, RESETS + 1))
    reset_s = median_s(lambda: sim.reset(seed=next(seeds)), RESETS)
    build_s = median_s(lambda: Simulation(scenario).close(), BUILDS)
    sim.close()
    return {f"{label}_reset_ms": 1e3 * reset_s, f"{label}_build_ms": 1e3 * build_s,
            f"{label}_ratio_reset_vs_build": reset_s / build_s}  # fmt: skip


def rough_harbor():
    """`harbor` in sea state 4 (FFT waves, redrawn at every reset), gusting wind, a Gauss–Markov current."""
    data = yaml.safe_load(resolve("harbor")[0])
    data["environment"] = {"sea": {"type": "sea_state", "code": 4}, "wind": {"speed_mps": 8.0, "gust_gain": 3.0},
                           "current": {"speed_mps": 0.3, "speed_std_mps": 0.1, "time_constant_s": 5.0}}  # fmt: skip
    return parse_scenario(data, "harbor_rough")


def observe_figures() -> dict:
    """Time in `observe()` (converting each new sample once) against the step it follows, same steps."""
    sim = Simulation.from_scenario("harbor_sensors")
    sim.vessels["wamv"].command(0.5)
    sim.run(1.0)  # warm-up: JIT, GL context, ray scenes
    step_s, observe_s = np.empty(STEPS), np.empty(STEPS)
    for k in range(STEPS):
        t0 = time.perf_counter()
        sim.step()
        t1 = time.perf_counter()
        sim.observe()
        step_s[k], observe_s[k] = t1 - t0, time.perf_counter() - t1
    sim.close()
    return {"harbor_sensors_step_ms_median": 1e3 * float(np.median(step_s)),
            "harbor_sensors_step_ms_mean": 1e3 * float(step_s.mean()),
            "observe_us_median": 1e6 * float(np.median(observe_s)),
            "observe_us_mean": 1e6 * float(observe_s.mean()),
            "observe_overhead_percent_of_mean_step": 100.0 * float(observe_s.sum() / step_s.sum()),
            "target_observe_overhead_percent": 5.0}  # fmt: skip


def main() -> dict:
    figures = {"load_average_1min_before": os.getloadavg()[0]}
    figures |= reset_figures("harbor", load_scenario("harbor")) | {"target_reset_ms": 20.0}
    figures |= reset_figures("harbor_sea_state_4", rough_harbor())
    figures |= observe_figures()
    figures["load_average_1min_after"] = os.getloadavg()[0]
    for key, value in figures.items():
        print(f"{key:40s} {value:12.4g}")
    out = Path(__file__).parent / "results" / "api.json"
    out.parent.mkdir(exist_ok=True)
    out.write_text(json.dumps(figures, indent=2))
    return figures


if __name__ == "__main__":
    main()
