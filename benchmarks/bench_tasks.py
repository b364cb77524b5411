"""Task environments: env steps/s of StationKeeping (state observations, 10 Hz control, 100 Hz physics) in calm
water and in sea state 3, against baselines measured in the same run; batch scaling 1 → 2 workers.

    python benchmarks/bench_tasks.py [--steps 300] [--repeats 5] [--no-batch]

Per sea (median of --repeats timings of --steps env steps, one core: numba 1 thread, constant action):
- env:        gymnasium.make("usvsim/StationKeeping-v0").step (10 physics steps, scoring at each, observation);
- sim loop:   the same 10 `Simulation.step()` calls per env step without the env (the env's own overhead = ratio);
- bare MuJoCo: 10 `mujoco.mj_step` on the same model (a copy of its data) per env step, with the last applied
                wrenches held: MuJoCo's own share of the cost, an upper bound on speed.
Batch: a sweep (station keeping, 300 s, difficulty 0-2 x 4 seeds) and a small batch (8 calm runs) by
`usvsim.batch.run` on 1 and 2 workers, each a fresh process timed from outside; medians of --batch-repeats
turns (`--batch-only` for just this part).
The load average is recorded beside every figure, and the env figures also per second of process CPU time (the
machine is shared). Writes benchmarks/results/tasks.json.
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


def timed(fns: dict, steps: int, repeats: int) -> tuple[dict, dict]:
    """Median calls/s of each function over `repeats` rounds of `steps` calls, by the wall clock and by the
    process's CPU time (on a shared machine the less disturbed figure); the functions take turns within each
    round, so a change of machine load hits all of them alike."""
    rates: dict = {name: [] for name in fns}
    cpu_rates: dict = {name: [] for name in fns}
    for _ in range(repeats):
        for name, fn in fns.items():
            start, cpu = time.perf_counter(), time.process_time()
            for _ in range(steps):
                fn()
            rates[name].append(steps / (time.perf_counter() - start))
            cpu_rates[name].append(steps / max(time.process_time() - cpu, 1e-9))
    median = lambda d: {name: statistics.median(r) for name, r in d.items()}  # noqa: E731
    return median(rates), median(cpu_rates)


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
    r, c = timed({"env": lambda: env.step(action), "sim_loop": sim_loop, "bare": bare}, steps, repeats)
    env.close()
    return {"env_steps_per_s": r["env"], "sim_loop_env_steps_per_s": r["sim_loop"],
            "bare_mujoco_env_steps_per_s": r["bare"], "env_vs_sim_loop": r["env"] / r["sim_loop"],
            "env_vs_bare_mujoco": r["env"] / r["bare"], "env_steps_per_cpu_s": c["env"],
            "sim_loop_env_steps_per_cpu_s": c["sim_loop"], "bare_mujoco_env_steps_per_cpu_s": c["bare"],
            "load_avg_1min": [load_before, os.getloadavg()[0]]}  # fmt: skip


# the sweep: station keeping at VRX's three difficulty levels (calm, then sea states with wind and current) x 4
# seeds; the small batch: 8 calm runs, where the ~2 s a process needs to start (interpreter, imports, warm-up)
# is a third of the work and caps the speed-up (Amdahl)
BATCH_SPECS = {
    "sweep_difficulty_0_2": {"task": "station_keeping", "difficulty": [0, 1, 2], "seeds": {"start": 0, "count": 4},
                             "time_limit_s": 300.0},
    "small_calm_8": {"task": "station_keeping", "seeds": {"start": 0, "count": 8}, "time_limit_s": 300.0},
}


def batch_child(workers: int, name: str) -> None:
    """One `usvsim.batch.run` of BATCH_SPECS[name] in this fresh process (what `usvsim sweep` does); prints the
    scores."""
    from usvsim.batch import expand, run

    start = time.perf_counter()
    scores = [r["score"] for r in run(expand(BATCH_SPECS[name]), workers=workers)]
    print(json.dumps({"scores": scores, "run_s": time.perf_counter() - start}))


def bench_batch(repeats: int, name: str) -> dict:
    """The runs of BATCH_SPECS[name] by `usvsim.batch.run` on 1 and on 2 workers, each in a fresh process timed from outside
    (interpreter start, imports and warm-up included, as a user sees it); 1 and 2 take turns `repeats` times.
    Also the CPU seconds of the whole process tree: equal totals mean parallel work costs nothing extra."""
    import resource
    import subprocess
    import sys

    walls: dict = {1: [], 2: []}
    calls: dict = {1: [], 2: []}  # the `run()` call alone (imports done): what a script or notebook sees
    cpus: dict = {1: [], 2: []}
    loads, scores = [], {}
    for _ in range(repeats):
        for workers in (1, 2):
            loads.append(os.getloadavg()[0])
            before = resource.getrusage(resource.RUSAGE_CHILDREN)
            start = time.perf_counter()
            done = subprocess.run([sys.executable, __file__, "--batch-child", str(workers), "--batch-spec", name], capture_output=True,
                                  text=True, check=True)  # fmt: skip
            walls[workers].append(time.perf_counter() - start)
            after = resource.getrusage(resource.RUSAGE_CHILDREN)
            cpus[workers].append(after.ru_utime - before.ru_utime + after.ru_stime - before.ru_stime)
            child = json.loads(done.stdout.splitlines()[-1])
            scores[workers] = child["scores"]
            calls[workers].append(child["run_s"])
    w1, w2 = statistics.median(walls[1]), statistics.median(walls[2])
    c1, c2 = statistics.median(calls[1]), statistics.median(calls[2])
    return {"workers_1_s_median": w1, "workers_2_s_median": w2, "speedup_1_to_2": w1 / w2,
            "run_call_s": calls, "run_call_speedup_1_to_2": c1 / c2,
            "walls_s": walls, "cpu_s": cpus, "cpu_s_median": {k: statistics.median(v) for k, v in cpus.items()},
            "load_avg_1min": loads, "load_avg_median": statistics.median(loads),
            "identical": scores[1] == scores[2], "scores": scores[1], "spec": BATCH_SPECS[name]}  # fmt: skip


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--steps", type=int, default=300)
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--no-batch", action="store_true")
    parser.add_argument("--batch-only", action="store_true")
    parser.add_argument("--batch-repeats", type=int, default=3)
    parser.add_argument("--batch-child", type=int, help=argparse.SUPPRESS)
    parser.add_argument("--batch-spec", choices=sorted(BATCH_SPECS), help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.batch_child:
        return batch_child(args.batch_child, args.batch_spec)
    numba.set_num_threads(1)
    result = {"machine": platform.processor() or platform.machine(), "cpus": os.cpu_count(),
              "load_avg_start": os.getloadavg(), "steps": args.steps, "repeats": args.repeats}  # fmt: skip
    for label, sea_state in () if args.batch_only else (("calm", None), ("sea_state_3", 3)):
        result[label] = bench_sea(sea_state, args.steps, args.repeats)
        print(label, json.dumps(result[label], indent=1))
    if not args.no_batch:
        result["batch"] = {name: bench_batch(args.batch_repeats, name) for name in BATCH_SPECS}
        print("batch", json.dumps(result["batch"], indent=1))
    RESULTS.parent.mkdir(parents=True, exist_ok=True)
    if args.batch_only and RESULTS.is_file():  # keep the env figures of the last full run
        result = json.loads(RESULTS.read_text()) | {"batch": result["batch"], "batch_load_avg_start": result["load_avg_start"]}
    elif args.no_batch and RESULTS.is_file():  # keep the batch figures of the last run that measured them
        last = json.loads(RESULTS.read_text())
        result |= {k: last[k] for k in ("batch", "batch_load_avg_start") if k in last}
    RESULTS.write_text(json.dumps(result, indent=2))


if __name__ == "__main__":
    main()
