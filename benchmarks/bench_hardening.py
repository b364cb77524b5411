"""Cost of the hardening checks on the hot path: the per-step divergence guard (speed, turn rate and
acceleration of every floating body) in the harbour (2 vessels + 9 buoys), against the same run with the
guard's check replaced by a no-op, interleaved in one process. Medians of `REPEATS` runs; load average
recorded beside the figures. `python benchmarks/bench_hardening.py` writes results/hardening.json."""

from __future__ import annotations

import json
import os
import statistics
import time
from pathlib import Path

from usvsim.simulation import Simulation

STEPS, REPEATS = 1000, 5


def run(sim: Simulation, guarded: bool) -> float:
    guard = sim.world._guard
    original = type(guard).check
    if not guarded:
        guard.check = lambda *args: None
    start = time.perf_counter()
    for _ in range(STEPS):
        sim.step()
    elapsed = time.perf_counter() - start
    if not guarded:
        del guard.check
    assert type(guard).check is original
    return elapsed / STEPS


def main() -> dict:
    sim = Simulation.from_scenario("harbor")
    sim.run(1.0)  # warm up (numba kernels, caches)
    guard_s = {True: [], False: []}
    for _ in range(REPEATS):
        for guarded in (False, True):
            guard_s[guarded].append(run(sim, guarded))
    sim.close()
    on, off = statistics.median(guard_s[True]), statistics.median(guard_s[False])
    result = {"steps": STEPS, "repeats": REPEATS, "step_us_with_guard": on * 1e6, "step_us_without_guard": off * 1e6,
              "ratio_with_over_without": on / off, "loadavg_1min": os.getloadavg()[0]}  # fmt: skip
    out = Path(__file__).parent / "results" / "hardening.json"
    out.write_text(json.dumps(result, indent=2) + "\n")
    return result


if __name__ == "__main__":
    print(json.dumps(main(), indent=2))
