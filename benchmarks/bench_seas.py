"""Cost of a sea: calm vs sea state 4, against bare MuJoCo on the same model, and fleets (same-run ratios).

Figures are medians over interleaved repeats of the mean µs per physics step (100 Hz), wall clock and process
CPU time (which leaves out what other jobs took on a loaded machine), each with the median 1-minute load average
of its repeats beside it; every ratio divides two figures of this run (wall by wall, CPU by CPU). Bare MuJoCo:
`mj_step` alone on the same model and its own MjData (no marine forces), interleaved with the others. Sea state 4
runs twice: with the FFT snapshots all made on the simulation thread (the default) and made ahead on a worker thread
(`USVSIM_FFT_AHEAD=1`; the same sea bit for bit); besides wall and process CPU time (both threads), the simulation
thread's own CPU time is reported. Also:
serial vs parallel builds of the wave-query kernels per call (points per call), both real since the
dispatch fix. Run: python benchmarks/bench_seas.py [--quick] [--fused-ab] (the latter: only the wavy fleets with and
without the fused hull pass, hydro/fused.py, in one process)

(Until 2026-11-24 the bare baseline stepped a fresh MjData from the model's reference pose with no forces: the
bodies fell through the harbour and its cost depended on what they met on the way, 15-75 µs a step.)
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


def harbor(code: int, ahead: bool | None = None) -> Simulation:
    """The harbor scenario in sea state `code` (0 = calm); `ahead` True/False: FFT snapshots made ahead on a worker
    thread or all on the simulation's thread (`FFTWaveField.AHEAD`, the same sea bit for bit; None: the default)."""
    import yaml

    from usvsim.ocean.fft import FFTWaveField

    data = yaml.safe_load(resolve("harbor")[0])
    if code:
        data.setdefault("environment", {})["sea"] = {"type": "sea_state", "code": code}
    before = getattr(FFTWaveField, "AHEAD", None)
    if before is not None and ahead is not None:
        FFTWaveField.AHEAD = ahead
    try:
        return Simulation(parse_scenario(data, "harbor"))
    finally:
        if before is not None:
            FFTWaveField.AHEAD = before


def fleet(n: int, code: int) -> Simulation:
    """n WAM-Vs on a 15 m grid, in sea state `code` (0 = calm)."""
    side = int(np.ceil(np.sqrt(n)))
    vessels = [{"name": f"wamv{i}", "model": "wamv", "pose": {"position": [15.0 * (i % side), 15.0 * (i // side), 0.0]}}
               for i in range(n)]  # fmt: skip
    env = {"sea": {"type": "sea_state", "code": code}} if code else {}
    return Simulation(parse_scenario({"version": 1, "vessels": vessels, "environment": env}, "fleet"))


def step_us(sim, steps: int, bare: bool = False) -> tuple[float, float, float]:
    """(wall, CPU, this thread's CPU) µs per step of `sim`; `bare`: `mj_step` alone on the same model, on its own MjData copied from
    the simulation's (state and the last marine wrenches in `xfrc_applied`, held constant), so MuJoCo integrates
    the same floating bodies with the same contacts and constraints, without anything of usvsim. CPU time is the
    process's (all threads): on a loaded machine it leaves out the time other jobs held the cores. The simulation
    thread's own CPU time leaves out what worker threads did (FFT snapshots made ahead, split hydrostatics)."""
    data = sim.__dict__.setdefault("_bare_data", mujoco.MjData(sim.model)) if bare else None
    if bare:
        mujoco.mj_copyData(data, sim.model, sim.data)
    wall, cpu, main = time.perf_counter(), time.process_time(), time.thread_time()
    if bare:
        for _ in range(steps):
            mujoco.mj_step(sim.model, data)
    else:
        for _ in range(steps):
            sim.step()
    return (1e6 * (time.perf_counter() - wall) / steps, 1e6 * (time.process_time() - cpu) / steps,
            1e6 * (time.thread_time() - main) / steps)  # fmt: skip


def compare(cases: dict, steps: int, repeats: int) -> dict:
    """Per case: medians over interleaved repeats of wall and CPU µs/step, with the median load average of
    those repeats."""
    times = {name: [] for name in cases}
    loads = {name: [] for name in cases}
    for _ in range(repeats):
        for name, (sim, bare) in cases.items():
            loads[name].append(load())
            times[name].append(step_us(sim, steps, bare))
    out = {}
    for name in cases:
        wall, cpu, main = np.median(np.array(times[name]), axis=0)
        out[name] = {
            "us": round(float(wall), 1),
            "cpu_us": round(float(cpu), 1),
            "main_thread_cpu_us": round(float(main), 1),
            "load": round(float(np.median(loads[name])), 2),
        }
    return out


def ratio(figures: dict, a: str, b: str) -> dict:
    """a / b of wall and of CPU time."""
    return {
        "wall": round(figures[a]["us"] / figures[b]["us"], 3),
        "cpu": round(figures[a]["cpu_us"] / figures[b]["cpu_us"], 3),
    }


def crossover(points=(1_000, 4_000, 16_000, 64_000, 256_000)) -> dict:
    """Serial vs parallel wave-query kernels per call (µs), sea state 4 tiles: heights without displacement
    (what physics queries: `HEIGHTS`) and the choppy Newton inversion (`INVERT`, choppiness 1)."""
    from usvsim.ocean import fft_kernels

    waves = harbor(4).ocean.waves
    wts = waves.update(10.0)
    rng = np.random.default_rng(0)
    out = {}
    for n in points:
        px, py = rng.uniform(0, 200, n), rng.uniform(0, 200, n)
        bufs = (np.empty(n), np.empty(n), np.empty(n), np.empty(n, np.int64))
        calls = {
            "heights": (getattr(fft_kernels, "HEIGHTS", None), (px, py, waves.geometry.tiles, wts, waves.inv_cells, bufs[2])),
            "choppy_inversion": (fft_kernels.INVERT, (px, py, waves.geometry.tiles, wts, waves.inv_cells, 1.0, waves.tol,
                                          waves.max_iter, *bufs)),
        }  # fmt: skip
        row = {}
        for kind, (kernels, args) in calls.items():
            if kernels is None:  # an older tree (before/after comparisons)
                continue
            for name, kernel in zip(("serial", "parallel"), kernels):
                kernel(*args)
                row[f"{kind}_{name}"] = round(
                    float(np.median([_time(lambda k=kernel, a=args: k(*a)) for _ in range(9)]) * 1e6), 1
                )
            row[f"{kind}_parallel_over_serial"] = round(row[f"{kind}_parallel"] / row[f"{kind}_serial"], 2)
        out[n] = row | {"load": load()}
    return out


def _time(fn) -> float:
    start = time.perf_counter()
    fn()
    return time.perf_counter() - start


def fused_ab(steps: int, repeats: int) -> dict:
    """100 and 200 WAM-Vs in sea state 4 with the hull pass a body at a time (hydro/fused.py) and with the three
    separate passes (`World._fused_hull_pass` answering None), the four fleets stepped in turn: same-run ratios
    200/100 of each (the two give the same motion bit for bit, checked at the end)."""
    sims = {}
    for n in (100, 200):
        for kind in ("fused", "three_passes"):
            sim = fleet(n, 4)
            if kind == "three_passes":
                sim.world._fused_hull_pass = lambda t: None
            sim.run(0.05)
            sims[f"{kind}_{n}"] = sim
    out = compare({k: (sim, False) for k, sim in sims.items()}, steps, repeats)
    for kind in ("fused", "three_passes"):
        out[f"{kind}_200_over_100"] = ratio(out, f"{kind}_200", f"{kind}_100")
    for n in (100, 200):
        assert np.array_equal(sims[f"fused_{n}"].data.qpos, sims[f"three_passes_{n}"].data.qpos)
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer steps and repeats (a smoke run)")
    parser.add_argument("--fused-ab", action="store_true", help="only the fleets with and without the fused hull pass")
    args = parser.parse_args()
    steps, repeats = (50, 3) if args.quick else (300, 7)
    if args.fused_ab:  # (prints only; results/seas.json is left as it is)
        print("fused_ab", fused_ab(10, 7 if args.quick else 21), "load", load(), flush=True)
        return
    calm, wavy, ahead = harbor(0), harbor(4, ahead=False), harbor(4, ahead=True)
    for sim in (calm, wavy, ahead):
        sim.run(0.5)  # JIT and caches
    cases = {"calm": (calm, False), "sea_state_4": (wavy, False), "sea_state_4_ahead": (ahead, False),
             "bare_mujoco": (calm, True)}  # fmt: skip
    h = compare(cases, steps, repeats)
    h["sea_state_4_over_calm"] = ratio(h, "sea_state_4", "calm")
    h["sea_state_4_ahead_over_calm"] = ratio(h, "sea_state_4_ahead", "calm")
    h["calm_speed_over_bare_mujoco"] = ratio(h, "bare_mujoco", "calm")
    print("harbor", h, flush=True)
    fleets = {"calm_100": fleet(100, 0), "sea_state_4_100": fleet(100, 4), "sea_state_4_200": fleet(200, 4)}
    for sim in fleets.values():
        sim.run(0.05)
    cases = {k: (sim, False) for k, sim in fleets.items()} | {"bare_mujoco_100": (fleets["calm_100"], True)}
    f = compare(cases, max(steps // 3, 5), repeats)  # blocks of 1 s of sea: 0.3 s blocks spread 200/100 over 1.9-2.3
    f["calm_100_real_time_factor"] = {
        "wall": round(1e4 / f["calm_100"]["us"], 2),
        "cpu": round(1e4 / f["calm_100"]["cpu_us"], 2),
    }
    f["calm_100_speed_over_bare_mujoco"] = ratio(f, "bare_mujoco_100", "calm_100")
    f["sea_state_4_200_over_100"] = ratio(f, "sea_state_4_200", "sea_state_4_100")
    print("fleets", f, flush=True)
    cross = crossover((1_000, 16_000, 64_000) if args.quick else (1_000, 4_000, 16_000, 64_000, 256_000))
    report = {"us_per_step_median": {"harbor": h, "fleet_wamv": f}, "query_kernel_crossover_us": cross,
              "cpus": os.cpu_count()}  # fmt: skip
    print(json.dumps(cross, indent=1))
    RESULTS.parent.mkdir(parents=True, exist_ok=True)
    RESULTS.write_text(json.dumps(report, indent=2) + "\n")


if __name__ == "__main__":
    main()
