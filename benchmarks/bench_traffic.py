"""Traffic and radar performance, each against a baseline measured in the same run.

1. 50 kinematic traffic ships (constant course and routes, collidable, seen by sensors, ground-truth situation at
   1 Hz) in the calm `harbor`: wall and CPU time per physics step vs the same harbour without traffic. Target:
   <= +10 %. The same with AIS on (the default: ~5.7 position reports/s for 50 ships) is reported beside it.
2. X-band radar at 24 rpm, 1024 spokes x 512 range bins (the defaults: 10 sectors/s, 16 elevation rays, 2x
   azimuth oversampling, sea state 3 clutter, ARPA on) on the harbour WAM-V among the 50 ships: the radar's own
   real-time factor (simulated seconds / wall seconds spent in the radar) and the whole simulation's, vs the
   same simulation without radar. Target: radar >= 10x real time.
3. AIS position reports (types 1 and 18, 200 ships' reports): usvsim's packer (`ais.position_sentence`, what the
   publisher sends) vs pyais's `encode_dict` (`ais.position_sentences`) on the same reports, the sentences checked
   equal first; medians of 7 rounds, wall and CPU µs per report.

    python benchmarks/bench_traffic.py [--repeats 40] [--seconds 1]
Writes benchmarks/results/traffic.json. Each case is built and warmed up once (20 simulated s: past the first
round of AIS static reports, 50 pyais encodings in the first 15 s), then run in `--repeats` chunks
of `--seconds`, the cases' chunks interleaved in a shuffled order (a load change hits all alike); medians (and bests) over the
chunks, and the median of the per-chunk ratios to the baseline chunk beside them. CPU time (process_time: all
threads) is recorded beside wall time: on a shared, loaded machine wall time includes the time other processes
hold the cores, CPU time mostly does not. The 1-minute load average is recorded.
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
WARM_UP_S = 20.0  # simulated; the steady state after it (AIS static data recurs every 6 min: 0.14 reports/s)
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


def harbor(traffic: bool, radar: bool, ais: bool = True):
    data = yaml.safe_load(resolve("harbor")[0])
    if traffic:
        data["traffic"] = {"ships": ships(), "ais": {"enabled": ais}}
    if radar:
        data["vessels"][0]["sensors"] = [RADAR]
    return parse_scenario(data, "bench")


class Case:
    """One simulation, built and warmed up once, then run in chunks interleaved with the other cases'."""

    def __init__(self, scenario):
        self.sim = sim = Simulation(scenario)
        sim.run(WARM_UP_S)  # numba, first sectors, the first round of AIS reports (static data: t < 15 s)
        self.radar_s = 0.0
        radar = sim.sensors.sensors.get("wamv/radar")
        if radar is not None:
            sample = radar.sample

            def timed_sample(s, stamp_ns):
                t = time.perf_counter()
                out = sample(s, stamp_ns)
                self.radar_s += time.perf_counter() - t
                return out

            radar.sample = timed_sample

    def chunk(self, seconds: float) -> dict:
        radar0, start, cpu0 = self.radar_s, time.perf_counter(), time.process_time()
        self.sim.run(seconds)
        wall, cpu = time.perf_counter() - start, time.process_time() - cpu0
        steps = round(seconds * 1e9 / self.sim.clock.step_ns)
        return {"wall_s": wall, "step_us": wall / steps * 1e6, "cpu_step_us": cpu / steps * 1e6,
                "radar_s": self.radar_s - radar0}  # fmt: skip


def median(values):
    return float(np.median(values))


def ais_packing(rounds: int = 7) -> dict:
    """µs per position report, usvsim's packer vs pyais on the same 200 reports (Class A and B), same run."""
    from usvsim.traffic.ais import Report, position_sentence, position_sentences

    reports = [Report(211000000 + i, 59.4 + i * 1e-4, 10.43 + i * 1e-4, 5.0 + i % 20, (13.7 * i) % 360, (13 * i) % 360,
                      i % 60) for i in range(200)]  # fmt: skip
    out: dict = {"load_1min_start": os.getloadavg()[0]}
    for cls in "AB":
        assert all([position_sentence(r, cls)] == position_sentences(r, cls) for r in reports)
        fns = {"pyais": lambda r: position_sentences(r, cls), "usvsim": lambda r: position_sentence(r, cls)}  # noqa: B023
        wall: dict = {k: [] for k in fns}
        cpu: dict = {k: [] for k in fns}
        for _ in range(rounds):
            for name, fn in fns.items():
                start, cpu_start = time.perf_counter(), time.process_time()
                for r in reports:
                    fn(r)
                wall[name].append((time.perf_counter() - start) / len(reports) * 1e6)
                cpu[name].append((time.process_time() - cpu_start) / len(reports) * 1e6)
        w, c = {k: median(v) for k, v in wall.items()}, {k: median(v) for k, v in cpu.items()}
        out[f"class_{cls}"] = {"us_per_report": w, "cpu_us_per_report": c, "pyais_over_usvsim": w["pyais"] / w["usvsim"],
                               "pyais_over_usvsim_cpu": c["pyais"] / c["usvsim"]}  # fmt: skip
    out["load_1min_end"] = os.getloadavg()[0]
    return out


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeats", type=int, default=40, help="chunks per case")
    ap.add_argument("--seconds", type=float, default=1.0, help="simulated seconds per chunk")
    args = ap.parse_args()
    cases = {"harbor": harbor(False, False), "harbor_50_ships": harbor(True, False, ais=False),
             "harbor_50_ships_ais": harbor(True, False), "harbor_50_ships_radar": harbor(True, True)}  # fmt: skip
    cases = {k: Case(sc) for k, sc in cases.items()}
    runs: dict[str, list[dict]] = {k: [] for k in cases}
    loads = [os.getloadavg()[0]]
    order = np.random.default_rng(1)
    for _ in range(args.repeats):  # short chunks, interleaved, so load changes hit every case alike; in a new order
        for name in order.permutation(list(cases)):  # each time, so no case always follows the radar's cache churn
            runs[name].append(cases[name].chunk(args.seconds))
        loads.append(os.getloadavg()[0])
    for case in cases.values():
        case.sim.close()
    step = {k: median([r["step_us"] for r in v]) for k, v in runs.items()}
    cpu = {k: median([r["cpu_step_us"] for r in v]) for k, v in runs.items()}

    def paired(case: str, key: str = "step_us") -> float:
        return median([a[key] / b[key] - 1.0 for a, b in zip(runs[case], runs["harbor"])])

    radar_s = median([r["radar_s"] for r in runs["harbor_50_ships_radar"]])
    result = {
        "machine": platform.processor() or platform.machine(), "cpus": os.cpu_count(), "warm_up_s": WARM_UP_S,
        "load_average_1min": {"median": median(loads), "max": max(loads)}, "seconds": args.seconds,
        "repeats": args.repeats,
        "step_us_median": step,
        "step_us_best": {k: min(r["step_us"] for r in v) for k, v in runs.items()},
        "cpu_step_us_median": cpu,
        "traffic_50_ships_overhead": step["harbor_50_ships"] / step["harbor"] - 1.0,
        "traffic_50_ships_ais_overhead": step["harbor_50_ships_ais"] / step["harbor"] - 1.0,
        "traffic_50_ships_overhead_median_of_paired_chunks": paired("harbor_50_ships"),
        "traffic_50_ships_ais_overhead_median_of_paired_chunks": paired("harbor_50_ships_ais"),
        "cpu_traffic_50_ships_overhead": cpu["harbor_50_ships"] / cpu["harbor"] - 1.0,
        "cpu_traffic_50_ships_ais_overhead": cpu["harbor_50_ships_ais"] / cpu["harbor"] - 1.0,
        "cpu_traffic_50_ships_overhead_median_of_paired_chunks": paired("harbor_50_ships", "cpu_step_us"),
        "cpu_traffic_50_ships_ais_overhead_median_of_paired_chunks": paired("harbor_50_ships_ais", "cpu_step_us"),
        "radar_realtime_factor": args.seconds / radar_s,
        "radar_ms_per_simulated_s": radar_s / args.seconds * 1e3,
        "sim_realtime_factor": {k: 1e6 / (v * 100.0) for k, v in step.items()},  # harbor runs at 100 Hz
        "ais_position_report_packing": ais_packing(),
    }  # fmt: skip
    RESULTS.mkdir(exist_ok=True)
    (RESULTS / "traffic.json").write_text(json.dumps(result, indent=2) + "\n")
    print(json.dumps(result, indent=2))


if __name__ == "__main__":
    main()
