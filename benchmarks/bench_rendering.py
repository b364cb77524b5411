"""The marine shader look against MuJoCo's plain look, measured in the same run on the same scene.

1. Camera 640x480 RGB + depth + segmentation on the harbour WAM-V in sea state 4: `rendering.renderer:
   shader` with sky, glint, foam and fog (visibility 2 km) vs `renderer: mujoco` (flat sky, height field).
2. Viewer 1280x720 (offscreen, HUD on) in sea state 4, shader vs mujoco.

    MUJOCO_GL=egl python benchmarks/bench_rendering.py [--frames 24]
Both looks of a case run side by side in one process, frame by frame in alternation, so that the shared
machine's changing load falls on both alike. Writes benchmarks/results/rendering.json: per case the median and
best frame time, the median CPU time of the process per frame (all threads; on a shared machine the least
disturbed figure), frames/s, the ratios shader / mujoco, and the 1-minute load average at the start and end
(the machine is shared: compare ratios and CPU times, not absolute frame rates).
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import time
from pathlib import Path

os.environ.setdefault("MUJOCO_GL", "egl")

import numpy as np

from usvsim.config.loader import load_scenario
from usvsim.rendering.gallery import scenario_dict

RESULTS = Path(__file__).parent / "results"
FOG = {"fog": {"visibility_m": 2000.0}}


def _sim(renderer: str, width: int = 640, height: int = 480, look: dict | None = None):
    import tempfile

    import yaml

    from usvsim.simulation import Simulation

    look = {"renderer": renderer, **FOG, **(look or {})}
    raw = scenario_dict(sea_state=4, look=look, width=width, height=height)
    path = Path(tempfile.mkdtemp()) / "bench.yaml"
    path.write_text(yaml.safe_dump(raw))
    sim = Simulation(load_scenario(path))
    sim.run(3.0)
    return sim


def _time(frame, sim, frames: int) -> dict:
    frame()  # warm-up: shader compilation, first uploads
    times, cpu = [], []
    for _ in range(frames):
        sim.step()  # the ocean moves: every frame uploads new wave tiles
        t0, c0 = time.perf_counter(), time.process_time()
        frame()
        times.append(time.perf_counter() - t0)
        cpu.append(time.process_time() - c0)
    median = float(np.median(times))
    return {
        "median_ms": 1000 * median,
        "cpu_median_ms": 1000 * float(np.median(cpu)),  # all threads (llvmpipe's too): robust to other load
        "best_ms": 1000 * min(times),
        "fps": 1 / median,
        "load_1min": os.getloadavg()[0],
    }


def _interleaved(cases: dict, frames: int) -> dict:
    """`_time` for several (frame, sim) cases at once, alternating frame by frame (the order flips every round),
    so that the machine's changing load falls on all of them alike."""
    for frame, _ in cases.values():
        frame()  # warm-up: shader compilation, first uploads
    times = {name: ([], []) for name in cases}
    load_start = os.getloadavg()[0]
    for i in range(frames):
        for name in list(cases)[:: 1 if i % 2 == 0 else -1]:
            frame, sim = cases[name]
            sim.step()  # the ocean moves: every frame uploads new wave tiles
            t0, c0 = time.perf_counter(), time.process_time()
            frame()
            times[name][0].append(time.perf_counter() - t0)
            times[name][1].append(time.process_time() - c0)
    out = {}
    for name, (wall, cpu) in times.items():
        median = float(np.median(wall))
        out[name] = {
            "median_ms": 1000 * median,
            "cpu_median_ms": 1000 * float(np.median(cpu)),  # all threads (llvmpipe's too): robust to other load
            "best_ms": 1000 * min(wall),
            "fps": 1 / median,
            "load_1min_start": load_start,
            "load_1min": os.getloadavg()[0],
        }
    return out


def camera_case(frames: int) -> dict:
    sims = {renderer: _sim(renderer) for renderer in ("shader", "mujoco")}
    cameras = {renderer: sim.sensors["wamv/camera"] for renderer, sim in sims.items()}
    try:
        return _interleaved({r: (lambda c=cameras[r], s=sims[r]: c.sample(s, s.clock_ns), sims[r]) for r in sims}, frames)
    finally:
        for sim in sims.values():
            sim.close()


def viewer_case(frames: int) -> dict:
    from usvsim.viewer.offscreen import OffscreenViewer

    sims = {renderer: _sim(renderer) for renderer in ("shader", "mujoco")}
    viewers = {renderer: OffscreenViewer(sim, 1280, 720) for renderer, sim in sims.items()}
    try:
        return _interleaved({r: (viewers[r].render, sims[r]) for r in sims}, frames)
    finally:
        for renderer, sim in sims.items():
            viewers[renderer].close()
            sim.close()


EFFECTS = {  # name: the look's changes from the shader baseline (each effect alone, measured in the same run)
    "short_waves_off": {"water": {"short_waves": 0.0}},
    "navigation_lights_on": {"lights": {"navigation": "on"}},
    "rain_10mm_h": {"rain": {"rate_mm_h": 10.0}},
    "lens_droplets_0.5": {"camera": {"droplets": 0.5}},
    "motion_blur_30ms": {"camera": {"motion_blur_ms": 30.0}},
    "shadows_on": {"shadows": True},
    "materials_off": {"materials": False},
    "wake_off_moving": {"water": {"wake_s": 0.0}},  # the WAM-V under way (2.5 m/s) without and with its wake
    "wake_on_moving": {},
    "baseline_again": {},  # the baseline at the start and at the end: the ratios use their mean (drift, warm-up)
}


def effects(frames: int) -> dict:
    """The camera case with each optional effect against the shader baseline, interleaved in one run."""
    out = {}
    for name, look in (("baseline", {}), *EFFECTS.items()):
        sim = _sim("shader", look=look)
        camera = sim.sensors["wamv/camera"]
        if name.endswith("_moving"):  # under way for 6 s: the wake texture is drawn every frame (ahead: little seen)
            boat = sim.vessels["wamv"]
            for _ in range(600):
                boat.command(1.0, 0.0)
                sim.step()
        try:
            out[name] = _time(lambda camera=camera, sim=sim: camera.sample(sim, sim.clock_ns), sim, frames)
        finally:
            sim.close()
        print(name, json.dumps(out[name]))
    base = 0.5 * (out["baseline"]["cpu_median_ms"] + out["baseline_again"]["cpu_median_ms"])
    for name in EFFECTS:
        out[name]["over_baseline_cpu"] = out[name]["cpu_median_ms"] / base
        out[name]["extra_cpu_ms"] = out[name]["cpu_median_ms"] - base
    out["wake_on_moving"]["extra_cpu_ms_vs_wake_off"] = (
        out["wake_on_moving"]["cpu_median_ms"] - out["wake_off_moving"]["cpu_median_ms"]
    )
    print("extra CPU per frame (ms) over the mean baseline:",
          json.dumps({k: round(out[k]["extra_cpu_ms"], 2) for k in EFFECTS}))  # fmt: skip
    return out


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--frames", type=int, default=24)
    parser.add_argument("--effects", action="store_true", help="only the optional effects' cost (camera case)")
    args = parser.parse_args()
    if args.effects:
        out = {"frames": args.frames, "camera_640x480_ss4_effects": effects(args.frames)}
        RESULTS.mkdir(exist_ok=True)
        (RESULTS / "rendering_effects.json").write_text(json.dumps(out, indent=2) + "\n")
        return
    out = {
        "machine": platform.processor() or platform.machine(),
        "cpus": os.cpu_count(),
        "frames": args.frames,
    }
    for name, case in (
        ("camera_640x480_rgb_depth_seg_ss4", camera_case),
        ("viewer_1280x720_ss4", viewer_case),
    ):
        both = case(args.frames)
        shader, plain = both["shader"], both["mujoco"]
        out[name] = {
            "shader": shader,
            "mujoco": plain,
            "shader_over_mujoco_time": shader["median_ms"] / plain["median_ms"],
            "shader_over_mujoco_cpu": shader["cpu_median_ms"] / plain["cpu_median_ms"],
        }
        print(name, json.dumps(out[name]))
    RESULTS.mkdir(exist_ok=True)
    (RESULTS / "rendering.json").write_text(json.dumps(out, indent=2) + "\n")


if __name__ == "__main__":
    main()
