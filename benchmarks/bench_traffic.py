"""Traffic and radar performance, each against a baseline measured in the same run.

1. 50 kinematic traffic ships (constant course and routes, ground-truth situation at 1 Hz, AIS on) in the calm
   `harbor`: wall time per physics step vs the same harbour without traffic. Target: <= +10 %.
2. X-band radar at 24 rpm, 1024 spokes x 512 range bins (the defaults: 10 sectors/s, 16 elevation rays, 2x
   azimuth oversampling, sea state 3 clutter, ARPA on) on the harbour WAM-V among the 50 ships: the radar's own
   real-time factor (simulated seconds / wall seconds spent in the radar) and the whole simulation's, vs the
   same simulation without radar. Target: radar >= 10x real time.

    python benchmarks/bench_traffic.py [--repeats 5] [--seconds 10]
Writes benchmarks/results/traffic.json. Medians (and bests) over `--repeats` interleaved runs after a warm-up;
the 1-minute load average is recorded beside each figure, since the machine is shared.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import platform
import time
from pathlib import Path

import numpy as np
import yaml

from usvsim import Simulation
from usvsim.config.loader import parse_scenario, resolve

RESULTS = Path(__file__).parent / "results"
RADAR = {"type": "radar", "name": "radar", "rpm": 24, "spokes": 1024, "range_bins": 512, "range_max_m": 1500.0,
         "mount": {"position": [0.0, 0.0, 2.5]}, "sea_clutter": {"sea_state": 3}}  # fmt: skip


def ships(n: int = 50) -> list[dict]:
    """n ships on a ring 250-900 m out: half at constant course and speed, half on square routes."""
    rng = np.random.default_rng(7)
    out = []
    for k in range(n):
        r, a = rng.uniform(250, 900), 2 * math.pi * k / n
        x, y = r * math.cos(a), r * math.sin(a)
        if k % 2:
            motion = {"type": "constant", "position": [x, y], "course_deg": float(rng.uniform(0, 360)),
                      "speed_mps": float(rng.uniform(1, 8))}  # fmt: skip
        else:
            side = float(rng.uniform(40, 120))
            pts = [[x, y], [x + side, y], [x + side, y + side], [x, y + side]]
            motion = {"type": "route", "loop": True, "waypoints": [{"position": p, "speed_mps": 4.0} for p in pts]}
        out.append({"name": f"ship_{k}", "mmsi": 257100000 + k, "length_m": float(rng.uniform(10, 60)),
                    "beam_m": float(rng.uniform(3, 12)), "motion": motion})  # fmt: skip
    return out


def harbor(traffic: bool, radar: bool):
    data = yaml.safe_load(resolve("harbor")[0])
    if traffic:
        data["traffic"] = {"ships": ships()}
    if radar:
        data["vessels"][0]["sensors"] = [RADAR]
    return parse_scenario(data, "bench")


def run_once(scenario, seconds: float) -> dict:
    sim = Simulation(scenario)
    sim.run(1.0)  # warm-up: numba, first sectors
    radar = sim.sensors.sensors.get("wamv/radar")
    spent = [0.0]
    if radar is not None:
        sample = radar.sample

        def timed_sample(s, stamp_ns):
            t = time.perf_counter()
            out = sample(s, stamp_ns)
            spent[0] += time.perf_counter() - t
            return out

        radar.sample = timed_sample
    start = time.perf_counter()
    sim.run(seconds)
    wall = time.perf_counter() - start
    steps = round(seconds * 1e9 / sim.clock.step_ns)
    sim.close()
    return {"wall_s": wall, "step_us": wall / steps * 1e6, "radar_s": spent[0]}


def median(values):
    return float(np.median(values))


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--seconds", type=float, default=10.0)
    args = ap.parse_args()
    cases = {"harbor": harbor(False, False), "harbor_50_ships": harbor(True, False),
             "harbor_50_ships_radar": harbor(True, True)}  # fmt: skip
    runs: dict[str, list[dict]] = {k: [] for k in cases}
    loads = []
    for _ in range(args.repeats):  # interleaved, so load changes hit every case alike
        for name, sc in cases.items():
            runs[name].append(run_once(sc, args.seconds))
        loads.append(os.getloadavg()[0])
    step = {k: median([r["step_us"] for r in v]) for k, v in runs.items()}
    radar_s = median([r["radar_s"] for r in runs["harbor_50_ships_radar"]])
    result = {
        "machine": platform.processor() or platform.machine(), "cpus": os.cpu_count(),
        "load_average_1min": {"median": median(loads), "max": max(loads)}, "seconds": args.seconds,
        "repeats": args.repeats,
        "step_us_median": step,
        "step_us_best": {k: min(r["step_us"] for r in v) for k, v in runs.items()},
        "traffic_50_ships_overhead": step["harbor_50_ships"] / step["harbor"] - 1.0,
        "radar_realtime_factor": args.seconds / radar_s,
        "radar_ms_per_simulated_s": radar_s / args.seconds * 1e3,
        "sim_realtime_factor": {k: 1e6 / (v * 100.0) for k, v in step.items()},  # harbor runs at 100 Hz
    }  # fmt: skip
    RESULTS.mkdir(exist_ok=True)
    (RESULTS / "traffic.json").write_text(json.dumps(result, indent=2) + "\n")
    print(json.dumps(result, indent=2))


if __name__ == "__main__":
    main()
