"""Cost of a sea: calm vs sea state 4, against bare MuJoCo on the same model, and fleets (same-run ratios).

Figures are medians of interleaved repeats (µs per physics step at 100 Hz), each with the 1-minute load average
beside it; every ratio divides two figures measured in this run. Also: the serial/parallel crossover of the
wave-query kernel (points per call). Run: python benchmarks/bench_seas.py [--quick]
"""

from __future__ import annotations

import argparse
import json
import os
import time
from pathlib import Path

import mujoco
import numpy as np

from usvsim import Simulation
from usvsim.config.loader import parse_scenario, resolve

RESULTS = Path(__file__).parent / "results" / "seas.json"


def load() -> float:
    return round(os.getloadavg()[0], 2)


def harbor(code: int) -> Simulation:
    import yaml

    data = yaml.safe_load(resolve("harbor")[0])
    if code:
        data.setdefault("environment", {})["sea"] = {"type": "sea_state", "code": code}
    return Simulation(parse_scenario(data, "harbor"))


def fleet(n: int, code: int) -> Simulation:
    """n WAM-Vs on a 15 m grid, in sea state `code` (0 = calm)."""
    side = int(np.ceil(np.sqrt(n)))
    vessels = [{"name": f"wamv{i}", "model": "wamv", "pose": {"position": [15.0 * (i % side), 15.0 * (i // side), 0.0]}}
               for i in range(n)]  # fmt: skip
    env = {"sea": {"type": "sea_state", "code": code}} if code else {}
    return Simulation(parse_scenario({"version": 1, "vessels": vessels, "environment": env}, "fleet"))


def step_us(sim, steps: int, bare: bool = False) -> float:
    """µs per step of `sim`; `bare`: MuJoCo alone on the same model, on its own MjData (no marine forces)."""
    start = time.perf_counter()
    if bare:
        data = sim.__dict__.setdefault("_bare_data", mujoco.MjData(sim.model))
        start = time.perf_counter()
        for _ in range(steps):
            mujoco.mj_step(sim.model, data)
    else:
        for _ in range(steps):
            sim.step()
    return 1e6 * (time.perf_counter() - start) / steps


def compare(cases: dict, steps: int, repeats: int) -> dict:
    """Median µs/step of each case over interleaved repeats, with the load average of each repeat."""
    times = {name: [] for name in cases}
    loads = []
    for _ in range(repeats):
        loads.append(load())
        for name, (sim, bare) in cases.items():
            times[name].append(step_us(sim, steps, bare))
    out = {name: round(float(np.median(t)), 1) for name, t in times.items()}
    out["load_average"] = [min(loads), max(loads)]
    return out


def crossover(points=(1_000, 4_000, 16_000, 64_000, 256_000)) -> dict:
    """Serial vs parallel wave-query kernel (height inversion, sea state 4 tiles) per call, µs."""
    from usvsim.ocean.fft_kernels import INVERT

    sim = harbor(4)
    waves = sim.ocean.waves
    wts = waves.update(10.0)
    rng = np.random.default_rng(0)
    out = {}
    for n in points:
        px, py = rng.uniform(0, 200, n), rng.uniform(0, 200, n)
        bufs = (np.empty(n), np.empty(n), np.empty(n), np.empty(n, np.int64))
        args = (
            px,
            py,
            waves.geometry.tiles,
            wts,
            waves.inv_cells,
            waves.choppiness,
            waves.tol,
            waves.max_iter,
        )
        row = {}
        for name, kernel in zip(("serial", "parallel"), INVERT):
            kernel(*args, *bufs)
            row[name] = float(np.median([_time(lambda k=kernel, a=args, b=bufs: k(*a, *b)) for _ in range(15)]) * 1e6)
        row["parallel_over_serial"] = round(row["parallel"] / row["serial"], 2)
        out[n] = {k: round(v, 1) for k, v in row.items()} | {"load_average": load()}
    return out


def _time(fn) -> float:
    start = time.perf_counter()
    fn()
    return time.perf_counter() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer steps and repeats (a smoke run)")
    args = parser.parse_args()
    steps, repeats = (50, 3) if args.quick else (300, 7)
    calm, wavy = harbor(0), harbor(4)
    for sim in (calm, wavy):
        sim.run(0.5)  # JIT and caches
    h = compare(
        {"calm": (calm, False), "sea_state_4": (wavy, False), "bare_mujoco": (calm, True)}, steps, repeats
    )
    h["sea_state_4_over_calm"] = round(h["sea_state_4"] / h["calm"], 2)
    h["calm_speed_over_bare_mujoco"] = round(h["bare_mujoco"] / h["calm"], 3)
    print("harbor", h, flush=True)
    fleets = {"calm_100": fleet(100, 0), "sea_state_4_100": fleet(100, 4), "sea_state_4_200": fleet(200, 4)}
    for sim in fleets.values():
        sim.run(0.05)
    f = compare({k: (s, False) for k, s in fleets.items()}, max(steps // 10, 5), repeats)
    f["calm_100_real_time_factor"] = round(1e4 / f["calm_100"], 2)
    f["sea_state_4_200_over_100"] = round(f["sea_state_4_200"] / f["sea_state_4_100"], 2)
    print("fleets", f, flush=True)
    report = {"us_per_step_median": {"harbor": h, "fleet_wamv": f}, "query_kernel_crossover_us": crossover(),
              "cpus": os.cpu_count()}  # fmt: skip
    print(json.dumps(report["query_kernel_crossover_us"], indent=1))
    RESULTS.parent.mkdir(parents=True, exist_ok=True)
    RESULTS.write_text(json.dumps(report, indent=2) + "\n")


if __name__ == "__main__":
    main()
