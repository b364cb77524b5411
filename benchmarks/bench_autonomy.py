"""The navigation demo's speed: real-time factor of harbor_navigate with the whole stack (physics, sensors,
LiDAR odometry, mapping, planning, guidance) and each part's share, against the same scenario without the
stack (physics and sensors only) measured in the same run.

    python benchmarks/bench_autonomy.py [--seconds 30] [--repeats 3]

Each repeat drives from the start toward the first two goals for `--seconds` of simulation time, after one
untimed warm-up of each (numba caches, Embree scenes). Medians; the 1-minute load average is recorded beside
every figure, since the machine is shared.
Writes benchmarks/results/autonomy.json.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import time
from pathlib import Path

from usvsim.autonomy.demo import DEFAULT_GOALS
from usvsim.autonomy.odometry import kiss_icp_available
from usvsim.autonomy.run import build_navigator, navigate
from usvsim.simulation import Simulation

RESULTS = Path(__file__).parent / "results"


def stack_run(seconds: float) -> dict:
    sim = Simulation.from_scenario("harbor_navigate")
    nav, tap = build_navigator(sim, "wamv", "lidar", DEFAULT_GOALS["harbor_navigate"][:2])
    start = time.perf_counter()
    trace = navigate(sim, nav, tap, "wamv", "lidar", seconds)
    wall = time.perf_counter() - start
    sim.close()
    return {"rtf": sim.time / wall, "wall_s": trace.wall_s, "load": os.getloadavg()[0]}


def baseline_run(seconds: float) -> dict:
    sim = Simulation.from_scenario("harbor_navigate")
    sim.subscribe(lambda env: None)  # messages are built as for the stack
    start = time.perf_counter()
    sim.run(seconds)
    wall = time.perf_counter() - start
    sim.close()
    return {"rtf": seconds / wall, "load": os.getloadavg()[0]}


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--seconds", type=float, default=30.0)
    ap.add_argument("--repeats", type=int, default=3)
    args = ap.parse_args()
    stack, base = [], []
    baseline_run(2.0), stack_run(2.0)  # warm-up
    for _ in range(args.repeats):
        base.append(baseline_run(args.seconds))
        stack.append(stack_run(args.seconds))
    parts = {k: statistics.median(r["wall_s"][k] for r in stack) for k in stack[0]["wall_s"]}
    total = sum(parts.values())
    out = {
        "seconds_simulated": args.seconds, "repeats": args.repeats, "kiss_icp": kiss_icp_available(),
        "stack_real_time_factor_median": round(statistics.median(r["rtf"] for r in stack), 3),
        "baseline_real_time_factor_median": round(statistics.median(r["rtf"] for r in base), 3),
        "stack_over_baseline_wall": round(statistics.median(b["rtf"] / s["rtf"] for b, s in zip(base, stack)), 3),
        "share_of_wall": {k: round(v / total, 3) for k, v in parts.items()},
        "wall_s_per_simulated_s": {k: round(v / args.seconds, 4) for k, v in parts.items()},
        "load_average_1min": [round(r["load"], 2) for r in base + stack], "cpus": os.cpu_count(),
    }  # fmt: skip
    RESULTS.mkdir(exist_ok=True)
    (RESULTS / "autonomy.json").write_text(json.dumps(out, indent=2))
    print(json.dumps(out, indent=2))


if __name__ == "__main__":
    main()
