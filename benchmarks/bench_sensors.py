"""Sensor performance on this machine, each with a baseline measured in the same run.

1. LiDAR: OS1-128 (128 x 2048 = 262,144 rays) on the harbour WAM-V; usvsim (Embree, 2 threads, full
   pipeline: rays, cast static + moving scenes, water filter, noise, intensity) vs MuJoCo `mj_multiRay` on the
   same rays and geoms (visual group); plus the time per scan against beam count (16 channels x 250..8000
   columns), the seed's Figure 27, written as a PNG.
2. Camera 640x480 RGB + depth + segmentation (two render passes, MuJoCo EGL on llvmpipe) in frames/s,
   against the default `mujoco.Renderer` (three passes, MSAA) on the same scene.
3. The seed's demo sensor set on the harbour WAM-V (2D LiDAR 8000 beams 5 Hz, 3D LiDAR 500x16 10 Hz,
   512x512 RGB-D camera 10 Hz, IMU and odometry 50 Hz): real-time factor headless, vs no sensors.

    MUJOCO_GL=egl python benchmarks/bench_sensors.py [--repeats 5] [--seconds 10]
Writes benchmarks/results/sensors.json and benchmarks/results/sensors_beams.png. Timings are medians (and
minima) of `--repeats` runs after one warm-up.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import time
from pathlib import Path

os.environ.setdefault("MUJOCO_GL", "egl")

import mujoco
import numpy as np
from pydantic import TypeAdapter

from usvsim import Simulation
from usvsim.config.sensors import Sensor
from usvsim.sensors import SensorSuite

RESULTS = Path(__file__).parent / "results"
LIDAR_MOUNT = {"position": [0.7, 0.0, 1.03]}
CAMERA_MOUNT = {"position": [0.3, 0.0, 1.3], "pitch_deg": 5.0}
DEMO = [
    {"type": "lidar", "name": "scan", "preset": "seed_2d", "rate_hz": 5, "mount": LIDAR_MOUNT},
    {"type": "lidar", "name": "lidar", "preset": "seed_3d", "rate_hz": 10, "mount": LIDAR_MOUNT},
    {"type": "camera", "name": "camera", "width": 512, "height": 512, "horizontal_fov_deg": 60.0, "rate_hz": 10,
     "near_m": 0.01, "far_m": 100.0, "streams": ["rgb", "depth"], "mount": CAMERA_MOUNT},
    {"type": "imu", "name": "imu", "rate_hz": 50, "mount": {"position": [0.0, 0.0, 0.944]}},
    {"type": "odometry", "name": "odometry", "rate_hz": 50},
]  # fmt: skip


def configs(*dicts):
    adapter = TypeAdapter(Sensor)
    return [adapter.validate_python(d) for d in dicts]


def timed(fn, repeats: int) -> tuple[float, float]:
    fn()
    times = []
    for _ in range(repeats):
        t = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t)
    return float(np.median(times)), float(min(times))


def lidar(repeats: int) -> dict:
    sim = Simulation.from_scenario("harbor")
    sim.run(1.0)
    suite = SensorSuite(sim, {"wamv": configs({"type": "lidar", "name": "os1", "preset": "os1_128", "mount": LIDAR_MOUNT})})
    os1 = suite["wamv/os1"]
    world = os1.world

    def scan():
        world._dynamic_step = -1  # rebuild the moving scene every scan, as in a run
        os1.measure(sim)

    med, best = timed(scan, repeats)
    n = len(os1.dirs_local)
    origins, dirs, _, _ = os1._rays(sim)
    pnt, vec = origins[0].astype(float), np.ascontiguousarray(dirs, float).ravel()
    geomid, dist = np.zeros(n, np.int32), np.zeros(n)
    group = np.array([0, 1, 0, 0, 0, 0], np.uint8)
    mujoco.mj_forward(sim.model, sim.data)
    base_med, base_best = timed(lambda: mujoco.mj_multiRay(sim.model, sim.data, pnt, vec, group, 1, -1, geomid, dist,
                                                           None, n, os1.pattern.range_max_m), max(2, repeats // 2))  # fmt: skip
    sweep = []
    for columns in (250, 500, 1000, 2000, 4000, 8000):
        s = SensorSuite(sim, {"wamv": configs({"type": "lidar", "name": "l", "preset": "vlp16", "columns": columns,
                                               "mount": LIDAR_MOUNT})})  # fmt: skip
        sensor = s["wamv/l"]
        sensor.world = world
        t, _ = timed(lambda: (setattr(world, "_dynamic_step", -1), sensor.measure(sim)), repeats)  # noqa: B023
        sweep.append({"beams": 16 * columns, "seconds_per_scan": round(t, 5)})
        s.close()
    suite.close()
    return {"rays_per_scan": n, "scan_s_median": round(med, 4), "scan_s_min": round(best, 4),
            "mrays_per_s_median": round(n / med / 1e6, 2), "mrays_per_s_best": round(n / best / 1e6, 2),
            "os1_128_2048_10hz_realtime_factor": round(0.1 / med, 2),
            "baseline_mj_multiRay_s": round(base_med, 4), "baseline_mrays_per_s": round(n / base_med / 1e6, 2),
            "speedup_vs_mj_multiRay": round(base_med / med, 1), "beam_sweep_vlp16_rows": sweep}  # fmt: skip


def camera(repeats: int) -> dict:
    sim = Simulation.from_scenario("harbor")
    sim.run(0.5)
    cam_cfg = {"type": "camera", "name": "cam", "width": 640, "height": 480, "streams": ["rgb", "depth", "segmentation"],
               "mount": CAMERA_MOUNT}  # fmt: skip
    suite = SensorSuite(sim, {"wamv": configs(cam_cfg)})
    cam = suite["wamv/cam"]
    med, best = timed(lambda: cam.sample(sim, sim.clock_ns), repeats * 4)
    renderer = mujoco.Renderer(sim.model, 480, 640)

    def baseline():
        renderer.update_scene(sim.data)
        renderer.render()
        renderer.enable_depth_rendering()
        renderer.render()
        renderer.disable_depth_rendering()
        renderer.enable_segmentation_rendering()
        renderer.render()
        renderer.disable_segmentation_rendering()

    base_med, _ = timed(baseline, repeats * 2)
    renderer.close()
    suite.close()
    return {"fps_median": round(1 / med, 1), "fps_best": round(1 / best, 1), "includes": "render, water surface, "
            "readback, depth linearization, segmentation ids, ROS messages (no CDR)",
            "baseline_mujoco_Renderer_default_fps": round(1 / base_med, 1), "speedup": round(base_med / med, 2)}  # fmt: skip


def demo(seconds: float) -> dict:
    out = {}
    for label, sensors in (("no_sensors", []), ("demo_sensors", DEMO)):
        sim = Simulation.from_scenario("harbor")
        suite = SensorSuite(sim, {"wamv": configs(*sensors)})
        count = [0]
        sim.run(0.5, on_step=lambda s: suite.on_step(s))  # noqa: B023
        t = time.perf_counter()
        sim.run(seconds, on_step=lambda s: count.__setitem__(0, count[0] + len(suite.on_step(s))))  # noqa: B023
        wall = time.perf_counter() - t
        suite.close()
        out[label] = {"realtime_factor": round(seconds / wall, 2), "messages": count[0]}
    return out


def plot(sweep: list[dict], path: Path) -> None:
    from PIL import Image, ImageDraw

    img = Image.new("RGB", (640, 400), "white")
    d = ImageDraw.Draw(img)
    xs, ys = [s["beams"] for s in sweep], [s["seconds_per_scan"] * 1e3 for s in sweep]
    px = lambda x: 60 + 540 * x / max(xs)  # noqa: E731
    py = lambda y: 360 - 320 * y / max(ys)  # noqa: E731
    d.line([(60, 360), (600, 360)], fill="black")
    d.line([(60, 40), (60, 360)], fill="black")
    d.line([(px(x), py(y)) for x, y in zip(xs, ys)], fill="blue", width=2)
    for x, y in zip(xs, ys):
        d.ellipse([px(x) - 3, py(y) - 3, px(x) + 3, py(y) + 3], fill="blue")
        d.text((px(x) - 20, py(y) - 16), f"{y:.1f} ms", fill="black")
    d.text((250, 375), "beams per scan (16 channels)", fill="black")
    d.text((5, 20), f"ms per scan (max {max(xs)} beams)", fill="black")
    img.save(path)


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--seconds", type=float, default=10.0)
    args = ap.parse_args()
    result = {"machine": f"{platform.machine()}, {os.cpu_count()} cores, load {os.getloadavg()[0]:.1f} at start",
              "lidar": lidar(args.repeats), "camera_640x480_rgb_depth_seg": camera(args.repeats),
              "demo_sensor_set_harbor": demo(args.seconds)}  # fmt: skip
    RESULTS.mkdir(exist_ok=True)
    (RESULTS / "sensors.json").write_text(json.dumps(result, indent=2) + "\n")
    plot(result["lidar"]["beam_sweep_vlp16_rows"], RESULTS / "sensors_beams.png")
    print(json.dumps(result, indent=2))


if __name__ == "__main__":
    main()
