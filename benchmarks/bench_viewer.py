"""Viewer frames per second at 1280 x 720 on this machine (CPU, Mesa llvmpipe).

Figures, all measured in this run on the `harbor` scenario with a JONSWAP sea (Hs 0.6 m, Tp 4 s):
- baseline: the bare `mujoco.Renderer` drawing the same scene (visual + water groups, no wave refresh, no HUD,
  its defaults: 4x multisampling, shadows) — what a user of MuJoCo's renderer gets out of the box;
- viewer_offscreen: one full viewer frame offscreen (EGL): wave surface re-sampled from the ocean and
  uploaded, follow camera with its ray cast, HUD, then pixels read back;
- viewer_offscreen_with_layers: the same plus 2000 LiDAR-like points and a 320 x 240 camera inset;
- viewer_window: the real GLFW window under Xvfb (if Xvfb is installed), frames per second over a few
  seconds of driving, physics included (the simulation paced to the wall clock); viewer_window_calm: the
  same in the calm harbour, where physics is cheap and the figure is the viewer's own rate.
Rendering only (no physics) unless stated. Run: python benchmarks/bench_viewer.py  (→ results/viewer.json)
`python benchmarks/bench_viewer.py --window-target N`: only issue 17's target (the window in sea state 4 with the
shader look, MuJoCo's look as the baseline, N alternating repeats; → results/viewer_window_target.json)
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

WIDTH, HEIGHT, FRAMES = 1280, 720, 30
ROOT = Path(__file__).resolve().parents[1]


def fps_of(render, frames: int = FRAMES) -> float:
    render()  # warm-up
    start = time.perf_counter()
    for _ in range(frames):
        render()
    return frames / (time.perf_counter() - start)


def offscreen_figures() -> dict:
    import mujoco
    import numpy as np

    from usvsim.simulation import Simulation
    from usvsim.viewer.demo import harbor_with_waves
    from usvsim.viewer.offscreen import OffscreenViewer

    sim = Simulation(harbor_with_waves())
    sim.run(1.0)
    baseline = mujoco.Renderer(sim.model, HEIGHT, WIDTH)
    option = mujoco.MjvOption()
    option.geomgroup[:] = [0, 1, 1, 0, 0, 0]
    camera = mujoco.MjvCamera()
    camera.lookat[:], camera.distance, camera.azimuth, camera.elevation = (
        sim.vessels["wamv"].position,
        14.0,
        0.0,
        -18.0,
    )

    def bare():
        baseline.update_scene(sim.data, camera, option)
        baseline.render()

    out = {"baseline_mujoco_renderer_fps": fps_of(bare)}
    baseline.close()
    viewer = OffscreenViewer(sim, WIDTH, HEIGHT)
    out["viewer_offscreen_fps"] = fps_of(lambda: viewer.render(dt=1 / 30))
    rng = np.random.default_rng(0)
    viewer.view.points = sim.vessels["wamv"].position + rng.normal(size=(2000, 3)) * [10.0, 10.0, 1.0]
    viewer.view.inset = rng.integers(0, 255, size=(240, 320, 3), dtype=np.uint8)
    out["viewer_offscreen_with_layers_fps"] = fps_of(lambda: viewer.render(dt=1 / 30))
    viewer.close()
    out["ratio_viewer_vs_baseline"] = out["viewer_offscreen_fps"] / out["baseline_mujoco_renderer_fps"]
    return out


def window_figures(seconds: float = 6.0, waves: bool = True) -> dict:
    """The GLFW window under a private Xvfb, in a child process (its own GL platform)."""
    if shutil.which("Xvfb") is None:
        return {"viewer_window_fps": None, "viewer_window_note": "Xvfb not installed"}
    display = f":{os.getpid() % 800 + 100}"
    xvfb = subprocess.Popen(["Xvfb", display, "-screen", "0", "1280x800x24", "-nolisten", "tcp"],
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)  # fmt: skip
    time.sleep(1.0)
    code = (
        "import json; from usvsim.simulation import Simulation; from usvsim.viewer.app import run_viewer;"
        "from usvsim.viewer.demo import harbor_with_waves, HARBOR_LAP;"
        f"sim = Simulation(harbor_with_waves()) if {waves} else Simulation.from_scenario('harbor'); sim.run(1.0);"
        f"s = run_viewer(sim, script=[(t + 1.0, k, a) for t, k, a in HARBOR_LAP], max_seconds=1.0 + {seconds});"
        "print(json.dumps(s))"
    )
    env = {k: v for k, v in os.environ.items() if k not in ("MUJOCO_GL", "PYOPENGL_PLATFORM")}
    env["DISPLAY"] = display
    try:
        proc = subprocess.run(
            [sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=600
        )
    finally:
        xvfb.terminate()
        xvfb.wait()
    stats = json.loads(proc.stdout.strip().splitlines()[-1])
    tag = "viewer_window" if waves else "viewer_window_calm"
    return {f"{tag}_fps": stats["fps"], f"{tag}_rtf": stats["sim_s"] / stats["wall_s"]}


TARGET_CHILD = """
import json, os, time, yaml
from importlib import resources
from usvsim.config.loader import parse_scenario
from usvsim.simulation import Simulation
from usvsim.viewer.app import run_viewer
from usvsim.viewer.demo import HARBOR_LAP
data = yaml.safe_load((resources.files("usvsim.scenarios") / "harbor.yaml").read_text())
data["environment"] = {{"sea": {{"type": "sea_state", "code": 4}}}}
data["rendering"] = {{"renderer": "{renderer}"}}
sim = Simulation(parse_scenario(data, "harbor_ss4")); sim.run(1.0)
run_viewer(sim, max_seconds=2.5)  # warm-up: shader compilation (a few seconds of llvmpipe), first uploads
cpu = time.process_time()
s = run_viewer(sim, script=[(t + 2.5, k, a) for t, k, a in HARBOR_LAP], max_seconds=2.5 + {seconds})
s["cpu_ms_per_frame"] = 1e3 * (time.process_time() - cpu) / s["frames"]
print(json.dumps(s))
"""


def window_target(repeats: int, seconds: float = 8.0) -> dict:
    """Issue 17's target: the GLFW window at 1280 x 720 under Xvfb, `harbor` in sea state 4, the shader look,
    driving the benchmark lap with physics paced to the wall clock, HUD on; MuJoCo's plain look in the same window
    as the same-run baseline. Each repeat a fresh process per look, the looks alternating; medians and the load."""
    if shutil.which("Xvfb") is None:
        return {"note": "Xvfb not installed"}
    display = f":{os.getpid() % 800 + 100}"
    xvfb = subprocess.Popen(["Xvfb", display, "-screen", "0", "1280x800x24", "-nolisten", "tcp"],
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)  # fmt: skip
    time.sleep(1.0)
    env = {k: v for k, v in os.environ.items() if k not in ("MUJOCO_GL", "PYOPENGL_PLATFORM")}
    env["DISPLAY"] = display
    runs: dict[str, list] = {"shader": [], "mujoco": []}
    try:
        for i in range(repeats):
            for renderer in ("shader", "mujoco")[:: 1 if i % 2 == 0 else -1]:
                code = TARGET_CHILD.format(renderer=renderer, seconds=seconds)
                proc = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True,
                                      timeout=600, check=True)  # fmt: skip
                stats = json.loads(proc.stdout.strip().splitlines()[-1])
                runs[renderer].append({"fps": stats["fps"], "cpu_ms_per_frame": stats["cpu_ms_per_frame"],
                                       "load_1min": os.getloadavg()[0]})  # fmt: skip
                print(renderer, runs[renderer][-1], flush=True)
    finally:
        xvfb.terminate()
        xvfb.wait()
    median = {r: float(np.median([x["fps"] for x in v])) for r, v in runs.items()}
    return {
        "runs": runs,
        "median_fps": median,
        "target_fps": 20.0,
        "shader_over_mujoco_fps": median["shader"] / median["mujoco"],
    }


def main() -> dict:
    if len(sys.argv) > 2 and sys.argv[1] == "--window-target":
        figures = window_target(int(sys.argv[2]))
        path = ROOT / "benchmarks/results/viewer_window_target.json"
        path.write_text(json.dumps(figures, indent=2) + "\n")
        print(json.dumps(figures, indent=2))
        return figures
    os.environ.setdefault("MUJOCO_GL", "egl")
    figures = {
        "width": WIDTH,
        "height": HEIGHT,
        **offscreen_figures(),
        **window_figures(),
        **window_figures(waves=False),
    }
    figures["target_fps"] = 15.0
    figures["load_average_1min"] = os.getloadavg()[0]
    figures["note"] = ("2 shared CPU cores, Mesa llvmpipe; viewer renders without multisampling and shadows; "
                       "the load average shows how busy the machine was")  # fmt: skip
    path = ROOT / "benchmarks/results/viewer.json"
    path.write_text(json.dumps(figures, indent=2) + "\n")
    print(json.dumps(figures, indent=2))
    return figures


if __name__ == "__main__":
    main()
