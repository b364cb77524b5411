"""Task environments: env steps/s of StationKeeping (state observations, 10 Hz control, 100 Hz physics) in calm
water and in sea state 3, against baselines measured in the same run; batch scaling 1 → 2 workers.

    python benchmarks/bench_tasks.py [--steps 300] [--repeats 5] [--no-batch]

Per sea (median of --repeats timings of --steps env steps, one core: numba 1 thread, constant action):
- env:        gymnasium.make("usvsim/StationKeeping-v0").step (10 physics steps, scoring at each, observation);
- sim loop:   the same 10 `Simulation.step()` calls per env step without the env (the env's own overhead = ratio);
- bare MuJoCo: 10 `mujoco.mj_step` on the same model (a copy of its data) per env step, with the last applied
                wrenches held: MuJoCo's own share of the cost, an upper bound on speed.
Batch: 8 station-keeping runs (300 s each) on a pool of 1 and of 2 worker processes (`usvsim.batch.run_one`).
The load average is recorded beside every figure (the machine is shared). Writes benchmarks/results/tasks.json.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import time
from pathlib import Path

import mujoco
import numba
import numpy as np

RESULTS = Path(__file__).parent / "results" / "tasks.json"


def timed(fns: dict, steps: int, repeats: int) -> dict:
    """Median calls/s of each function over `repeats` rounds of `steps` calls; the functions take turns
    within each round, so a change of machine load hits all of them alike."""
    rates: dict = {name: [] for name in fns}
    for _ in range(repeats):
        for name, fn in fns.items():
            start = time.perf_counter()
            for _ in range(steps):
                fn()
            rates[name].append(steps / (time.perf_counter() - start))
    return {name: statistics.median(r) for name, r in rates.items()}


def bench_sea(sea_state: int | None, steps: int, repeats: int) -> dict:
    import gymnasium

    import usvsim.tasks.gym  # noqa: F401

    env = gymnasium.make("usvsim/StationKeeping-v0", sea_state=sea_state, time_limit_s=1e6).unwrapped
    env.reset(seed=0)
    action = np.full(env.action_space.shape, 0.2, dtype=np.float32)
    for _ in range(20):  # warm-up: numba, caches, settled hull
        env.step(action)
    sim, every = env.sim, env._every

    def sim_loop():
        for _ in range(every):
            sim.step()

    bare_data = mujoco.MjData(sim.model)  # a copy: bare stepping must not disturb the env's state
    mujoco.mj_copyData(bare_data, sim.model, sim.data)

    def bare():
        for _ in range(every):
            mujoco.mj_step(sim.model, bare_data)

    load_before = os.getloadavg()[0]
    r = timed({"env": lambda: env.step(action), "sim_loop": sim_loop, "bare": bare}, steps, repeats)
    env.close()
    return {"env_steps_per_s": r["env"], "sim_loop_env_steps_per_s": r["sim_loop"],
            "bare_mujoco_env_steps_per_s": r["bare"], "env_vs_sim_loop": r["env"] / r["sim_loop"],
            "env_vs_bare_mujoco": r["env"] / r["bare"], "load_avg_1min": [load_before, os.getloadavg()[0]]}  # fmt: skip


def bench_batch() -> dict:
    """8 runs of 300 s on a pool of 1 and of 2 fresh worker processes (both pay the same start-up)."""
    from concurrent.futures import ProcessPoolExecutor

    from usvsim.batch import expand
    from usvsim.batch.runner import run_one

    runs = expand({"task": "station_keeping", "seeds": {"start": 0, "count": 8}, "time_limit_s": 300.0})
    out = {}
    for workers in (1, 2):
        start = time.perf_counter()
        with ProcessPoolExecutor(max_workers=workers) as pool:
            scores = [r["score"] for r in pool.map(run_one, runs)]
        out[f"workers_{workers}_s"] = time.perf_counter() - start
        out[f"load_avg_1min_{workers}"] = os.getloadavg()[0]
        out[f"scores_{workers}"] = scores
    out["identical"] = out["scores_1"] == out["scores_2"]
    out["speedup_1_to_2"] = out["workers_1_s"] / out["workers_2_s"]
    return out


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--steps", type=int, default=300)
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--no-batch", action="store_true")
    args = parser.parse_args()
    numba.set_num_threads(1)
    result = {"machine": platform.processor() or platform.machine(), "cpus": os.cpu_count(),
              "load_avg_start": os.getloadavg(), "steps": args.steps, "repeats": args.repeats}  # fmt: skip
    for label, sea_state in (("calm", None), ("sea_state_3", 3)):
        result[label] = bench_sea(sea_state, args.steps, args.repeats)
        print(label, json.dumps(result[label], indent=1))
    if not args.no_batch:
        result["batch"] = bench_batch()
        print("batch", json.dumps(result["batch"], indent=1))
    RESULTS.parent.mkdir(parents=True, exist_ok=True)
    RESULTS.write_text(json.dumps(result, indent=2))


if __name__ == "__main__":
    main()
